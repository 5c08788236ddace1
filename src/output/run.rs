//! A headless run: advance the simulation to the end time, and at every output interval record
//! a frame to `run.rrd`, a row to `timeseries.csv`; write `summary.json` at the end, whatever the
//! end was. Numerical trouble ends the run with a status; what was recorded stays readable.

use super::recorder::{Frame, FrameRecorder, StageStats};
use super::summary::{GaugeSummary, RunFigures, Summary, median};
use super::surf::{SurfRecorder, log_profiles, write_profiles};
use super::timeseries::{GaugeWriter, TimeseriesWriter, gauge_columns};
use crate::case::Case;
use crate::diagnostics::{self, Integrals};
use crate::simulation::Simulation;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Clone)]
pub struct RunOptions {
    pub out_dir: PathBuf,
    pub rrd: bool,
    /// Show a progress bar on stderr.
    pub progress: bool,
    /// Step on one core (the solver's second-core thread off): for runs that share the
    /// machine's cores with each other, as a sweep's jobs do. The results are the same.
    pub one_core: bool,
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

pub(super) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> RunError + '_ {
    move |source| RunError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Runs `case` to `case.time.end_s`.
pub fn run(case: &Case, opts: &RunOptions) -> Result<RunOutcome, RunError> {
    std::fs::create_dir_all(&opts.out_dir).map_err(io_err(&opts.out_dir))?;
    let mut sim = Simulation::new(case).map_err(|e| RunError::Setup(e.to_string()))?;
    if opts.one_core {
        sim.use_one_core();
    }
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
    let rrd_err = |e: super::rrd::RrdError| RunError::Rrd {
        path: rrd_path.clone(),
        message: e.to_string(),
    };
    let mut rrd = if opts.rrd {
        Some(FrameRecorder::to_file(&rrd_path, "surflab", &sim).map_err(rrd_err)?)
    } else {
        None
    };

    let end_s = case.time.end_s;
    let interval = case.output.interval_s;
    let mut series = Vec::new();
    let mut timings = StageStats::default();
    let mut logging_ms: Vec<f64> = Vec::new();
    let mut iterations: Vec<f64> = Vec::new();
    // The longest step since the previous row: the Δt the policy set (the steps that land on
    // an output time are shorter), written as `dt_s`.
    let mut longest_dt = 0.0f64;
    // Insertion and removal change the particle count: particle-steps are summed per step.
    let mut particle_steps = 0.0;
    let mut progress = Progress::new(opts.progress, end_s);
    let started = Instant::now();

    let mut surf = SurfRecorder::new(&sim);
    let mut record = |sim: &Simulation,
                      surf: &mut SurfRecorder,
                      last: Option<&crate::solver::StageTimings>,
                      dt_s: f64|
     -> Result<(), RunError> {
        let t0 = Instant::now();
        let frame = Frame::of(sim);
        let events = surf.record(sim, frame.integrals.volume_m2);
        csv.row(&frame.integrals, sim.initial_volume_m2, sim.steps, dt_s)
            .map_err(io_err(&csv_path))?;
        if let Some(g) = gauge_csv.as_mut() {
            g.row(sim.time_s, &frame.gauges)
                .map_err(io_err(&gauge_path))?;
        }
        if let Some(rrd) = rrd.as_mut() {
            rrd.log(sim, &frame, last, &events).map_err(rrd_err)?;
            rrd.log_breaking(sim, &surf.detector).map_err(rrd_err)?;
        }
        gauge_records.push((sim.time_s, frame.gauges));
        series.push(frame.integrals);
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
                    longest_dt = longest_dt.max(report.dt_s);
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
        record(&sim, &mut surf, timings.last(), longest_dt)?;
        longest_dt = 0.0;
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
            let _ = rrd.log_stop(sim.time_s, &status);
        }
        let logger = rrd.logger();
        if let Some(s) = &surf_summary {
            log_profiles(logger, s);
        }
        let height = case.wavemaker.as_ref().map_or(0.0, |w| w.height_m);
        surf.log_space_time(logger, height, logger.scale());
        if surf.active() {
            let _ = logger.add_surf_views();
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

/// What the run loop measured, step by step.
struct Measured {
    timings: StageStats,
    logging_ms: Vec<f64>,
    iterations: Vec<f64>,
    particle_steps: f64,
    wall_s: f64,
}

fn summarize(sim: &Simulation, series: &[Integrals], m: &Measured, status: String) -> Summary {
    let wall_s = m.wall_s;
    let v0 = sim.initial_volume_m2;
    let drift = series
        .iter()
        .map(|m| (m.volume_m2 / v0 - 1.0).abs())
        .fold(0.0, f64::max);
    let mut stages = m.timings.stage_medians();
    stages.insert("logging_per_output".into(), median(&m.logging_ms));
    Summary {
        case: sim.case.name.clone(),
        parameters: sim.case.clone(),
        run: RunFigures::new(
            sim.particles.len(),
            sim.particles.fluid_count(),
            sim.steps,
            sim.time_s,
            wall_s,
            m.particle_steps,
            m.timings.median_total_ms(),
        ),
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
        paddle_arriving_amplitude_m: sim
            .wavemaker
            .as_ref()
            .and_then(|w| w.arriving_amplitude_m()),
        paddle_reflection_gauges_x_m: sim
            .wavemaker
            .as_ref()
            .and_then(|w| w.reflection_gauges_x_m()),
    }
}

/// A one-line progress bar on stderr: simulated time, steps per second, ETA.
pub(super) struct Progress {
    enabled: bool,
    end_s: f64,
    started: Instant,
    last_draw: Instant,
}

impl Progress {
    pub(super) fn new(enabled: bool, end_s: f64) -> Self {
        let now = Instant::now();
        Self {
            enabled,
            end_s,
            started: now,
            last_draw: now,
        }
    }

    pub(super) fn update(&mut self, t_s: f64, steps: u64) {
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

    pub(super) fn finish(&self) {
        if self.enabled {
            eprintln!();
        }
    }
}
