//! The one frame recorder: what `surflab run`, the lab's worker and `surflab bench` log at each
//! output. A frame is the integrals and the gauge readings of the simulation at that instant
//! ([`Frame`]); the recorder logs it to Rerun with the particles, the boundary, the stage
//! timings and the breaking events ([`FrameRecorder`]). Stage medians over a run are kept by
//! [`StageStats`].

use super::colormap::ColorScale;
use super::rrd::{FrameView, RrdError, RrdLogger, Viewing};
use super::summary::median;
use super::timeseries::gauge_columns;
use crate::diagnostics::{self, Integrals};
use crate::simulation::Simulation;
use crate::solver::StageTimings;
use rerun::RecordingStream;
use std::collections::BTreeMap;
use std::path::Path;

/// What is measured at an output: the integrals, and the gauges in the order of
/// [`gauge_columns`] (η at each elevation gauge, then u and w at each probe; `None` where dry).
#[derive(Debug, Clone)]
pub struct Frame {
    pub integrals: Integrals,
    pub gauges: Vec<Option<f64>>,
}

impl Frame {
    pub fn of(sim: &Simulation) -> Frame {
        Frame {
            integrals: diagnostics::integrals(sim),
            gauges: gauge_values(sim),
        }
    }
}

/// The gauge readings of `sim`, in the order of [`gauge_columns`]: η at each elevation gauge,
/// then (u, w) at each velocity probe; `None` where dry.
pub fn gauge_values(sim: &Simulation) -> Vec<Option<f64>> {
    let out = &sim.case.output;
    let mut values: Vec<Option<f64>> = out
        .gauges_x_m
        .iter()
        .map(|&x| diagnostics::surface_elevation(sim, x))
        .collect();
    for [x, y] in &out.probes_m {
        let u = diagnostics::velocity_at(sim, nalgebra::Vector2::new(*x, *y));
        values.push(u.map(|u| u.x));
        values.push(u.map(|u| u.y));
    }
    values
}

/// Logs frames of one simulation to a Rerun stream.
pub struct FrameRecorder {
    logger: RrdLogger,
    columns: Vec<String>,
    with_mesh: bool,
}

impl FrameRecorder {
    /// Records to the .rrd file `path` (laid out for review), under the application id `app`.
    pub fn to_file(path: &Path, app: &str, sim: &Simulation) -> Result<Self, RrdError> {
        let (outline, scale, radius) = scene(sim);
        Ok(Self::with_logger(
            RrdLogger::create(path, app, &outline, scale, radius)?,
            sim,
        ))
    }

    /// Records into an existing stream (the lab's, which feeds the viewer and maybe a file),
    /// laid out for `viewing`.
    pub fn to_stream(
        stream: RecordingStream,
        sim: &Simulation,
        viewing: Viewing,
    ) -> Result<Self, RrdError> {
        let (outline, scale, radius) = scene(sim);
        Ok(Self::with_logger(
            RrdLogger::from_stream(stream, &outline, scale, radius, viewing)?,
            sim,
        ))
    }

    fn with_logger(logger: RrdLogger, sim: &Simulation) -> Self {
        let out = &sim.case.output;
        FrameRecorder {
            logger,
            columns: gauge_columns(&out.gauges_x_m, &out.probes_m),
            with_mesh: out.mesh,
        }
    }

    /// The logger, for what is logged beside the frames (surf views, profiles).
    pub fn logger(&self) -> &RrdLogger {
        &self.logger
    }

    /// Logs one frame of `sim` (measured as `frame`), the stage timings of the last step (or
    /// their mean over the steps since the last frame), and the breaking `events` seen since.
    pub fn log(
        &mut self,
        sim: &Simulation,
        frame: &Frame,
        timings: Option<&StageTimings>,
        events: &[String],
    ) -> Result<(), RrdError> {
        for e in events {
            self.logger.log_text(sim.time_s, "events/breaking", e)?;
        }
        let m = &frame.integrals;
        let mut scalars: Vec<(String, f64)> = vec![
            ("volume_m2".into(), m.volume_m2),
            ("volume_ratio".into(), m.volume_m2 / sim.initial_volume_m2),
            ("kinetic_energy_j_per_m".into(), m.kinetic_energy_j_per_m),
            ("max_speed_m_s".into(), m.max_speed_m_s),
            ("front_x_m".into(), m.front_x_m),
        ];
        if let Some(t) = timings {
            scalars.extend(
                t.named()
                    .iter()
                    .map(|(name, ms)| (format!("timing_ms/{name}"), *ms)),
            );
        }
        scalars.extend(
            self.columns
                .iter()
                .zip(&frame.gauges)
                .filter_map(|(name, v)| v.map(|v| (format!("gauges/{name}"), v))),
        );
        let named: Vec<(&str, f64)> = scalars.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let p = &sim.particles;
        let is_fluid: Vec<bool> = (0..p.len()).map(|i| p.is_fluid(i)).collect();
        self.logger.log_frame(&FrameView {
            t_s: sim.time_s,
            positions: &p.position,
            velocities: &p.velocity,
            is_fluid: &is_fluid,
            boundary_edges: &sim.solver.mesh.boundary_edges,
            triangles: self
                .with_mesh
                .then_some(sim.solver.mesh.triangles.as_slice()),
            scalars: &named,
        })
    }

    /// Says in the recording why the run stopped (`events`).
    pub fn log_stop(&mut self, t_s: f64, status: &str) -> Result<(), RrdError> {
        self.logger.log_text(t_s, "events", status)
    }

    pub fn flush(&self) {
        self.logger.flush();
    }
}

/// The static scene of a simulation's recording: the flume's outline, the u1 colour scale and
/// the particle radius (h/2).
fn scene(sim: &Simulation) -> (Vec<[f64; 2]>, ColorScale, f64) {
    let (lo, hi) = sim.case.u1_range();
    let outline = sim.flume.outline.iter().map(|p| [p.x, p.y]).collect();
    (
        outline,
        ColorScale { min: lo, max: hi },
        0.5 * sim.case.particles.spacing_m,
    )
}

/// Stage timings step by step, for their medians over a run.
#[derive(Debug, Clone, Default)]
pub struct StageStats {
    steps: Vec<StageTimings>,
}

impl StageStats {
    pub fn push(&mut self, t: StageTimings) {
        self.steps.push(t);
    }

    pub fn last(&self) -> Option<&StageTimings> {
        self.steps.last()
    }

    /// The median ms per step of each stage, by stage name (empty before the first step).
    pub fn stage_medians(&self) -> BTreeMap<String, f64> {
        let mut out = BTreeMap::new();
        if let Some(first) = self.steps.first() {
            for (k, (name, _)) in first.named().iter().enumerate() {
                let v: Vec<f64> = self.steps.iter().map(|t| t.named()[k].1).collect();
                out.insert(name.to_string(), median(&v));
            }
        }
        out
    }

    /// The median ms of a whole step.
    pub fn median_total_ms(&self) -> f64 {
        let totals: Vec<f64> = self.steps.iter().map(StageTimings::total_ms).collect();
        median(&totals)
    }
}
