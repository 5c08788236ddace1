//! The one frame recorder: what `surflab run`, the lab's worker and `surflab bench` log at each
//! output. A frame is the integrals and the gauge readings of the simulation at that instant
//! ([`Frame`]); the recorder logs it to Rerun with the particles, the boundary, the stage
//! timings and the breaking events ([`FrameRecorder`]). Stage medians over a run are kept by
//! [`StageStats`].

use super::colormap::ColorScale;
use super::rrd::{FrameView, RrdError, RrdLogger, Viewing};
use super::summary::median;
use super::timeseries::gauge_columns;
use crate::case::WaveTheory;
use crate::diagnostics::breaking::BreakingDetector;
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
    /// What the breaker map and the breaking mark last showed: the number of breakers and
    /// the Iribarren number (the lab's panel changes it).
    breaking_shown: Option<(usize, f64)>,
}

impl FrameRecorder {
    /// Records to the .rrd file `path` (laid out for review), under the application id `app`.
    pub fn to_file(path: &Path, app: &str, sim: &Simulation) -> Result<Self, RrdError> {
        let (outline, scale, radius) = scene(sim);
        Self::with_logger(RrdLogger::create(path, app, &outline, scale, radius)?, sim)
    }

    /// Records into an existing stream (the lab's, which feeds the viewer and maybe a file),
    /// laid out for `viewing`.
    pub fn to_stream(
        stream: RecordingStream,
        sim: &Simulation,
        viewing: Viewing,
    ) -> Result<Self, RrdError> {
        let (outline, scale, radius) = scene(sim);
        Self::with_logger(
            RrdLogger::from_stream(stream, &outline, scale, radius, viewing)?,
            sim,
        )
    }

    fn with_logger(logger: RrdLogger, sim: &Simulation) -> Result<Self, RrdError> {
        let out = &sim.case.output;
        if has_breaker_map(sim) {
            logger.add_breaker_map()?;
        }
        if let Some(window) = surf_zone_window_m(sim) {
            logger.open_on(window)?;
        }
        Ok(FrameRecorder {
            logger,
            columns: gauge_columns(&out.gauges_x_m, &out.probes_m),
            with_mesh: out.mesh,
            breaking_shown: None,
        })
    }

    /// The run's breaking on the breaker map and the flume ([`RrdLogger::log_breaker`]): its
    /// Iribarren number, the newest breaker's type and where it broke. Logged when a breaker
    /// has been classified since the last call, or the wave changed (the lab's panel).
    pub fn log_breaking(
        &mut self,
        sim: &Simulation,
        detector: &BreakingDetector,
    ) -> Result<(), RrdError> {
        let Some(predicted) = detector.predicted else {
            return Ok(());
        };
        let iribarren = if has_breaker_map(sim) {
            detector.iribarren
        } else {
            f64::NAN
        };
        let now = (detector.breakers.len(), iribarren);
        let same = self
            .breaking_shown
            .is_some_and(|(n, xi)| n == now.0 && (xi == now.1 || (xi.is_nan() && now.1.is_nan())));
        if same {
            return Ok(());
        }
        self.breaking_shown = Some(now);
        let newest = detector.breakers.last();
        // At the still water line over the breaking point (h_b is the still depth there).
        let at = newest.map(|b| [b.x_b_m, sim.case.bed_y_at(b.x_b_m) + b.h_b_m]);
        self.logger.log_breaker(
            sim.time_s,
            iribarren,
            newest.map(|b| b.observed.name()),
            predicted.name(),
            at,
        )
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
        // One plot per unit (the group before the slash); volume_m2 is timeseries.csv's.
        let mut scalars: Vec<(String, f64)> = vec![
            (
                "volume/V_over_V0".into(),
                m.volume_m2 / sim.initial_volume_m2,
            ),
            ("energy/kinetic_j_per_m".into(), m.kinetic_energy_j_per_m),
            ("speed/max_m_s".into(), m.max_speed_m_s),
            ("front/x_m".into(), m.front_x_m),
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
            polygons: &sim.solver.mesh.polygons,
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

/// Whether the run's recording gets the breaker map: a beach and a periodic wave (Battjes's
/// bands are drawn for periodic waves; a solitary wave's breaking point is still marked).
fn has_breaker_map(sim: &Simulation) -> bool {
    sim.case.flume.beach.is_some()
        && sim
            .case
            .wavemaker
            .as_ref()
            .is_some_and(|w| w.theory != WaveTheory::Solitary && w.period_s > 0.0)
}

/// The surf zone of a flume with a beach and a wavemaker, [x_min, x_max, y_min, y_max] in m:
/// from twice the distance from the still shoreline at which a wave of the case's height H
/// breaks (in about 1.5 H of water: H_b ≈ 1.2 H at H_b/h_b ≈ 0.8) to a run-up of 2 H, and from
/// the bed there to 2 H above still water, within the flume.
fn surf_zone_window_m(sim: &Simulation) -> Option<[f64; 4]> {
    let case = &sim.case;
    let (beach, w) = (case.flume.beach.as_ref()?, case.wavemaker.as_ref()?);
    let shoreline = crate::diagnostics::surface::still_shoreline_x_m(case);
    let level = case.still_level_at(beach.toe_x_m)?;
    if !(shoreline.is_finite() && beach.slope > 0.0 && w.height_m > 0.0) {
        return None;
    }
    let x0 = (shoreline - 3.0 * w.height_m / beach.slope).max(w.x_m);
    let x1 = (shoreline + 2.0 * w.height_m / beach.slope).min(case.flume.length_m);
    let margin = 0.25 * w.height_m;
    let y0 = case.bed_y_at(x0) - margin;
    let y1 = level + 2.0 * w.height_m;
    (x1 > x0 && y1 > y0).then_some([x0, x1, y0, y1])
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
