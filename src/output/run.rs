//! A headless run: advance the simulation to the end time, and at every output interval record
//! a frame to `run.rrd`, a row to `timeseries.csv`; write `summary.json` at the end, whatever the
//! end was. Numerical trouble ends the run with a status; what was recorded stays readable.

use super::colormap::ColorScale;
use super::rrd::{FrameView, RrdLogger};
use super::summary::{GaugeSummary, Summary, median};
use super::surf::{SurfRecorder, log_profiles, write_profiles};
use super::timeseries::{GaugeWriter, TimeseriesWriter, gauge_columns};
use crate::case::Case;
use crate::diagnostics::{self, Integrals};
use crate::simulation::Simulation;
use crate::solver::StageTimings;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Clone)]
pub struct RunOptions {
    pub out_dir: PathBuf,
    pub rrd: bool,
    /// Show a progress bar on stderr.
    pub progress: bool,
}

/// Failures of the run's set-up or files (not of the numerics, which end in a status).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("cannot seed or mesh the initial state: {0}")]
    Setup(String),
    #[error("{path}: cannot record: {message}")]
    Rrd { path: PathBuf, message: String },
}

/// What a finished (or stopped) run produced.
pub struct RunOutcome {
    pub summary: Summary,
    pub series: Vec<Integrals>,
    pub out_dir: PathBuf,
}

impl RunOutcome {
    pub fn ok(&self) -> bool {
        self.summary.status == "ok"
    }
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Runs `case` to `case.time.end_s`.
pub fn run(case: &Case, opts: &RunOptions) -> Result<RunOutcome, RunError> {
    std::fs::create_dir_all(&opts.out_dir).map_err(io_err(&opts.out_dir))?;
    let mut sim = Simulation::new(case).map_err(|e| RunError::Setup(e.to_string()))?;
    let csv_path = opts.out_dir.join("timeseries.csv");
    let mut csv = TimeseriesWriter::create(&csv_path).map_err(io_err(&csv_path))?;
    let gauge_path = opts.out_dir.join("gauges.csv");
    let gauge_columns = gauge_columns(&case.output.gauges_x_m, &case.output.probes_m);
    let mut gauge_csv = if gauge_columns.is_empty() {
        None
    } else {
        Some(GaugeWriter::create(&gauge_path, &gauge_columns).map_err(io_err(&gauge_path))?)
    };
    let mut gauge_records: Vec<(f64, Vec<Option<f64>>)> = Vec::new();
    let rrd_path = opts.out_dir.join("run.rrd");
    let mut rrd = if opts.rrd {
        let (lo, hi) = case.u1_range();
        let outline: Vec<[f64; 2]> = sim.flume.outline.iter().map(|p| [p.x, p.y]).collect();
        Some(
            RrdLogger::create(
                &rrd_path,
                "surflab",
                &outline,
                ColorScale { min: lo, max: hi },
                0.5 * case.particles.spacing_m,
            )
            .map_err(|e| RunError::Rrd {
                path: rrd_path.clone(),
                message: e.to_string(),
            })?,
        )
    } else {
        None
    };

    let end_s = case.time.end_s;
    let interval = case.output.interval_s;
    let mut series = Vec::new();
    let mut timings: Vec<StageTimings> = Vec::new();
    let mut logging_ms: Vec<f64> = Vec::new();
    let mut iterations: Vec<f64> = Vec::new();
    let mut last_dt = 0.0;
    // Insertion and removal change the particle count: particle-steps are summed per step.
    let mut particle_steps = 0.0;
    let mut progress = Progress::new(opts.progress, end_s);
    let started = Instant::now();

    let mut surf = SurfRecorder::new(&sim);
    let mut record = |sim: &Simulation,
                      surf: &mut SurfRecorder,
                      last: Option<&StageTimings>,
                      last_dt: f64|
     -> Result<(), RunError> {
        let t0 = Instant::now();
        let m = diagnostics::integrals(sim);
        let events = surf.record(sim, m.volume_m2);
        csv.row(&m, sim.initial_volume_m2, sim.steps, last_dt)
            .map_err(io_err(&csv_path))?;
        let values = gauge_values(sim);
        if let Some(g) = gauge_csv.as_mut() {
            g.row(sim.time_s, &values).map_err(io_err(&gauge_path))?;
        }
        if let Some(rrd) = rrd.as_mut() {
            for e in &events {
                rrd.log_text(sim.time_s, "events/breaking", e)
                    .map_err(|e| RunError::Rrd {
                        path: rrd_path.clone(),
                        message: e.to_string(),
                    })?;
            }
            let gauges: Vec<(&str, Option<f64>)> = gauge_columns
                .iter()
                .map(String::as_str)
                .zip(values.iter().copied())
                .collect();
            log_frame(rrd, sim, &m, last, &gauges, case.output.mesh).map_err(|message| {
                RunError::Rrd {
                    path: rrd_path.clone(),
                    message,
                }
            })?;
        }
        gauge_records.push((sim.time_s, values));
        series.push(m);
        logging_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        Ok(())
    };

    record(&sim, &mut surf, None, 0.0)?;
    let mut status = "ok".to_owned();
    let mut k = 1u64;
    while sim.time_s < end_s - 1e-12 {
        let target = (k as f64 * interval).min(end_s);
        let mut failure = None;
        while sim.time_s < target - 1e-12 {
            match sim.step_towards(target) {
                Ok(report) => {
                    timings.push(report.timings);
                    iterations.push(report.pressure_iterations as f64);
                    last_dt = report.dt_s;
                    surf.step(&sim, report.dt_s);
                    particle_steps += sim.particles.len() as f64;
                    progress.update(sim.time_s, sim.steps);
                }
                Err(e) => {
                    failure = Some(format!(
                        "stopped at t = {:.5} s (step {}): {e}",
                        sim.time_s, sim.steps
                    ));
                    break;
                }
            }
        }
        if let Some(f) = failure {
            status = f;
            break;
        }
        record(&sim, &mut surf, timings.last(), last_dt)?;
        k += 1;
    }
    let wall_s = started.elapsed().as_secs_f64();
    progress.finish();
    let (breaking, surf_summary) = surf.finish(&sim, &gauge_records);
    if let Some(s) = &surf_summary {
        let path = opts.out_dir.join("profiles.csv");
        write_profiles(&path, s).map_err(io_err(&path))?;
    }
    if let Some(rrd) = rrd.as_mut() {
        if status != "ok" {
            let _ = rrd.log_text(sim.time_s, "events", &status);
        }
        if let Some(s) = &surf_summary {
            log_profiles(rrd, s);
        }
        let height = case.wavemaker.as_ref().map_or(0.0, |w| w.height_m);
        surf.log_space_time(rrd, height, rrd.scale());
        if surf.active() {
            let _ = rrd.add_surf_views();
        }
        rrd.flush();
    }

    let measured = Measured {
        timings,
        logging_ms,
        iterations,
        particle_steps,
        wall_s,
    };
    let mut summary = summarize(&sim, &series, &measured, status);
    summary.gauges = gauge_summary(case, &gauge_records);
    summary.breaking = breaking;
    summary.surf = surf_summary;
    let json_path = opts.out_dir.join("summary.json");
    let json = serde_json::to_string_pretty(&summary).expect("summary serialises");
    std::fs::write(&json_path, json + "\n").map_err(io_err(&json_path))?;
    Ok(RunOutcome {
        summary,
        series,
        out_dir: opts.out_dir.clone(),
    })
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

/// Wave height and period at each elevation gauge over the last (up to) five whole waves,
/// counted after the paddle's ramp (or over the whole record without a wavemaker).
fn gauge_summary(case: &Case, records: &[(f64, Vec<Option<f64>>)]) -> Vec<GaugeSummary> {
    let from_s = case
        .wavemaker
        .as_ref()
        .map_or(0.0, |w| w.ramp_periods * w.period_s);
    let t: Vec<f64> = records.iter().map(|r| r.0).collect();
    case.output
        .gauges_x_m
        .iter()
        .enumerate()
        .map(|(k, &x)| {
            let eta: Vec<Option<f64>> = records.iter().map(|r| r.1[k]).collect();
            GaugeSummary {
                x_m: x,
                stats: diagnostics::wave_stats(&t, &eta, from_s, 5),
            }
        })
        .collect()
}

/// Logs one frame of `sim` with the integrals `m`, the stage timings of the last step and the
/// gauge readings (`(column name, value)`; dry ones are skipped).
pub fn log_frame(
    rrd: &mut RrdLogger,
    sim: &Simulation,
    m: &Integrals,
    last: Option<&StageTimings>,
    gauges: &[(&str, Option<f64>)],
    with_mesh: bool,
) -> Result<(), String> {
    let p = &sim.particles;
    let is_fluid: Vec<bool> = (0..p.len()).map(|i| p.is_fluid(i)).collect();
    let mut scalars: Vec<(String, f64)> = vec![
        ("volume_m2".into(), m.volume_m2),
        ("volume_ratio".into(), m.volume_m2 / sim.initial_volume_m2),
        ("kinetic_energy_j_per_m".into(), m.kinetic_energy_j_per_m),
        ("max_speed_m_s".into(), m.max_speed_m_s),
        ("front_x_m".into(), m.front_x_m),
    ];
    if let Some(t) = last {
        scalars.extend(
            t.named()
                .iter()
                .map(|(name, ms)| (format!("timing_ms/{name}"), *ms)),
        );
    }
    scalars.extend(
        gauges
            .iter()
            .filter_map(|(name, v)| v.map(|v| (format!("gauges/{name}"), v))),
    );
    let named: Vec<(&str, f64)> = scalars.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    let frame = FrameView {
        t_s: sim.time_s,
        positions: &p.position,
        velocities: &p.velocity,
        is_fluid: &is_fluid,
        boundary_edges: &sim.solver.mesh.boundary_edges,
        triangles: with_mesh.then_some(sim.solver.mesh.triangles.as_slice()),
        scalars: &named,
    };
    rrd.log_frame(&frame).map_err(|e| e.to_string())
}

/// What the run loop measured, step by step.
struct Measured {
    timings: Vec<StageTimings>,
    logging_ms: Vec<f64>,
    iterations: Vec<f64>,
    particle_steps: f64,
    wall_s: f64,
}

fn summarize(sim: &Simulation, series: &[Integrals], m: &Measured, status: String) -> Summary {
    let (timings, wall_s) = (&m.timings, m.wall_s);
    let v0 = sim.initial_volume_m2;
    let drift = series
        .iter()
        .map(|m| (m.volume_m2 / v0 - 1.0).abs())
        .fold(0.0, f64::max);
    let mut stages = std::collections::BTreeMap::new();
    if !timings.is_empty() {
        for (k, (name, _)) in timings[0].named().iter().enumerate() {
            let v: Vec<f64> = timings.iter().map(|t| t.named()[k].1).collect();
            stages.insert(name.to_string(), median(&v));
        }
    }
    stages.insert("logging_per_output".into(), median(&m.logging_ms));
    let totals: Vec<f64> = timings.iter().map(StageTimings::total_ms).collect();
    let n = sim.particles.len();
    let fluid = sim.particles.fluid_count();
    Summary {
        case: sim.case.name.clone(),
        parameters: sim.case.clone(),
        particles: n,
        fluid_particles: fluid,
        wall_nodes: n - fluid,
        steps: sim.steps,
        simulated_s: sim.time_s,
        wall_s,
        real_time_factor: sim.time_s / wall_s.max(1e-9),
        particle_steps_per_s: m.particle_steps / wall_s.max(1e-9),
        median_ms_per_step: median(&totals),
        median_stage_ms: stages,
        median_pressure_iterations: median(&m.iterations),
        initial_volume_m2: v0,
        volume_drift_max: drift,
        final_volume_ratio: series.last().map_or(f64::NAN, |m| m.volume_m2 / v0),
        status,
        gauges: Vec::new(),
        breaking: None,
        surf: None,
        paddle_absorbed_m: sim
            .wavemaker
            .as_ref()
            .filter(|w| w.absorbs())
            .map(|w| w.absorbed_offset_m(sim.time_s)),
    }
}

/// A one-line progress bar on stderr: simulated time, steps per second, ETA.
struct Progress {
    enabled: bool,
    end_s: f64,
    started: Instant,
    last_draw: Instant,
}

impl Progress {
    fn new(enabled: bool, end_s: f64) -> Self {
        let now = Instant::now();
        Self {
            enabled,
            end_s,
            started: now,
            last_draw: now,
        }
    }

    fn update(&mut self, t_s: f64, steps: u64) {
        if !self.enabled || self.last_draw.elapsed().as_secs_f64() < 0.25 {
            return;
        }
        self.last_draw = Instant::now();
        let elapsed = self.started.elapsed().as_secs_f64();
        let frac = (t_s / self.end_s).clamp(0.0, 1.0);
        let width = 30;
        let filled = (frac * width as f64) as usize;
        let eta = if frac > 0.0 {
            elapsed * (1.0 - frac) / frac
        } else {
            f64::NAN
        };
        eprint!(
            "\r[{}{}] t = {:.3}/{:.3} s  {:.0} steps/s  ETA {:.0} s   ",
            "#".repeat(filled),
            " ".repeat(width - filled),
            t_s,
            self.end_s,
            steps as f64 / elapsed.max(1e-9),
            eta
        );
        let _ = std::io::stderr().flush();
    }

    fn finish(&self) {
        if self.enabled {
            eprintln!();
        }
    }
}
