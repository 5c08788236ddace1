//! A headless 3D run (a case with `flume.width_m`, issue 26): step the [`Flow3`] to the end
//! time and at every output interval write a row of `timeseries.csv` and a frame of `run.rrd`
//! (the particles as 3D points coloured by u1, the free surface as a mesh, the wetted wall
//! nodes); `summary.json` (and with a wavemaker `surface_u1.csv`) at the end, whatever the end
//! was. Numerical trouble ends the run with a status; what was recorded stays readable.

use super::rrd3d::Recorder3;
use super::run::{Progress, RunError, RunOptions, io_err};
use super::summary::{RunFigures, median};
use super::timeseries::{GaugeWriter, gauge_columns};
use crate::case::Case;
use crate::diagnostics::surface_u1::{BarsU1, SurfaceU1Map};
use crate::diagnostics::undertow::{Stations, UndertowSummary};
use crate::geometry::bed3d::Bed3;
use crate::simulation3d::Simulation3;
use crate::solver3d::{Flow3, Integrals3, STAGES_3D};
use serde::Serialize;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

/// One output time of a 3D run.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Row3 {
    pub t_s: f64,
    /// The longest step since the previous row, s: the Δt the policy set, where the steps that
    /// land on the output time are shorter (0 in the first row).
    pub dt_s: f64,
    pub steps: u64,
    /// Volume of the kept tetrahedra, m³ (at the start of the last step: one Δt behind `t_s`).
    pub volume_m3: f64,
    pub tetrahedra: usize,
    pub slivers_kept: usize,
    /// Fluid nodes the walls' guard put back since the previous row.
    pub guarded: usize,
    /// Fluid nodes inserted and removed since the previous row (the `nodes` stage).
    pub inserted: usize,
    pub removed: usize,
    /// What the moves changed of the volume since the start, m³ (Σ moved − start of step).
    pub moves_m3: f64,
    /// What the remeshes changed since the start, m³ (Σ next start − moved).
    pub remeshes_m3: f64,
    #[serde(flatten)]
    pub integrals: Integrals3,
}

impl Row3 {
    /// The row of `sim` as it stands; the counters since the previous row are taken from it.
    pub fn of(sim: &mut Simulation3) -> Row3 {
        let l = sim.take_counts();
        let last = sim.last;
        Row3 {
            t_s: sim.time_s,
            dt_s: l.longest_dt_s,
            steps: sim.steps,
            volume_m3: sim.volume_m3(),
            tetrahedra: last.map_or(0, |s| s.tetrahedra),
            slivers_kept: last.map_or(0, |s| s.slivers_kept),
            guarded: l.guarded,
            inserted: l.inserted,
            removed: l.removed,
            moves_m3: l.moves_m3,
            remeshes_m3: l.remeshes_m3,
            integrals: sim.flow.integrals(),
        }
    }
}

/// `summary.json` of a 3D run.
#[derive(Debug, Clone, Serialize)]
pub struct Summary3 {
    /// The case as run (the key the 2D summary uses too).
    pub parameters: Case,
    /// "ok", or why the run stopped.
    pub status: String,
    /// Particles, steps and speed, with the 2D summary's keys.
    #[serde(flatten)]
    pub run: RunFigures,
    /// Median ms per step of each stage, in the order of `stages`.
    pub median_stage_ms: Vec<f64>,
    pub stages: Vec<String>,
    pub initial_volume_m3: f64,
    /// Largest |V/V₀ − 1| over the rows.
    pub volume_drift_max: f64,
    pub max_tetrahedra: usize,
    pub max_slivers_kept: usize,
    /// The undertow stations (`surf.stations_x_m` at `stations_z_m`), averaged over whole
    /// periods after the spin-up, as in 2D (no station budget's ledger in 3D).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub undertow: Option<UndertowSummary>,
    /// The free surface's largest u1 over the bars' crests against the channel
    /// (`surface_u1.csv`, from the spin-up on; a tank with raised bars).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface_u1_over_bars: Option<BarsU1>,
}

impl Summary3 {
    /// The one line `surflab run` prints at the end of a 3D run.
    pub fn line(&self) -> String {
        let mut line = format!(
            "3D, {}, volume drift max {:.3e}, up to {} tetrahedra ({} slivers kept)",
            self.run.line(),
            self.volume_drift_max,
            self.max_tetrahedra,
            self.max_slivers_kept
        );
        if let Some(u) = &self.undertow {
            line += &format!(
                "; undertow over {} periods from {} s, mean u1 below the trough (m/s):",
                u.periods, u.averaged_from_s
            );
            for s in &u.stations {
                line += &format!(" ({}, {}) {:+.4}", s.x_m, s.across_m, s.undertow_mean_m_s);
            }
        }
        line
    }
}

/// What a finished (or stopped) 3D run produced.
pub struct Run3Outcome {
    pub summary: Summary3,
    pub rows: Vec<Row3>,
}

impl Run3Outcome {
    pub fn ok(&self) -> bool {
        self.summary.status == "ok"
    }
}

const CSV_HEADER: &str = "t_s,dt_s,steps,volume_m3,volume_m2,volume_ratio,fluid_particles,\
isolated_particles,max_speed_m_s,kinetic_energy_j,front_x_m,left_wall_height_m,tetrahedra,\
slivers_kept,guarded,inserted,removed,moves_m3,remeshes_m3";

/// η at each of the case's elevation gauges (`output.gauges_x_m`), m above the still-water
/// level there, on the tank's centre line z = width / 2: the highest crossing of the free
/// surface, `None` where the line meets no water.
pub fn gauge_values(case: &Case, flow: &Flow3) -> Vec<Option<f64>> {
    let z = 0.5 * case.flume.width_m.unwrap_or(0.0);
    case.output
        .gauges_x_m
        .iter()
        .map(|&x| {
            let level = case.still_level_at(x).unwrap_or(0.0);
            flow.surface_heights_at(x, z).first().map(|y| y - level)
        })
        .collect()
}

/// Runs the 3D `case` to `case.time.end_s` (Δt: [`Simulation3::dt_for`], cut to land on every
/// output time).
pub fn run3d(case: &Case, opts: &RunOptions) -> Result<Run3Outcome, RunError> {
    std::fs::create_dir_all(&opts.out_dir).map_err(io_err(&opts.out_dir))?;
    let mut sim = Simulation3::new(case).map_err(|e| RunError::Setup(e.to_string()))?;
    let csv_path = opts.out_dir.join("timeseries.csv");
    let mut csv =
        std::io::BufWriter::new(std::fs::File::create(&csv_path).map_err(io_err(&csv_path))?);
    writeln!(csv, "{CSV_HEADER}").map_err(io_err(&csv_path))?;
    let rrd_path = opts.out_dir.join("run.rrd");
    let rrd_err = |e: String| RunError::Rrd {
        path: rrd_path.clone(),
        message: e,
    };
    let mut rrd = if opts.rrd {
        Some(Recorder3::create(&rrd_path, case, &sim.flow).map_err(rrd_err)?)
    } else {
        None
    };

    // Elevation gauges on the tank's centre line (the case's probes are refused in 3D).
    let gauge_columns = gauge_columns(&case.output.gauges_x_m, &[]);
    let gauge_path = opts.out_dir.join("gauges.csv");
    let mut gauges = if gauge_columns.is_empty() {
        None
    } else {
        Some(GaugeWriter::create(&gauge_path, &gauge_columns).map_err(io_err(&gauge_path))?)
    };
    // Undertow stations: the flow through them integrated over every step.
    let bed = Bed3::from_flume(&case.flume);
    let mut stations = Stations::new(case, |x, z| bed.height(x, z));
    let flow_width = case.flume.width_m.unwrap_or(1.0);
    // The free surface's u1 seen from above, from the spin-up on (a wavemaker's tanks).
    let mut surface_u1 = case.wavemaker.as_ref().map(|w| {
        SurfaceU1Map::new(
            case.flume.length_m,
            flow_width,
            case.particles.spacing_m,
            case.surf.spin_up_periods * w.period_s,
        )
    });
    let end_s = case.time.end_s;
    let interval = case.output.interval_s;
    let initial_volume = sim.initial_volume_m3;
    let mut rows = Vec::new();
    let mut stage_ms: Vec<Vec<f64>> = vec![Vec::new(); STAGES_3D.len()];
    let mut step_ms = Vec::new();
    let mut particle_steps = 0.0f64;
    let mut progress = Progress::new(opts.progress, end_s);
    let started = Instant::now();
    let mut status = "ok".to_owned();
    let mut k = 0u64;
    loop {
        // Record the row of this output time.
        let row = Row3::of(&mut sim);
        write_row(&mut csv, &row, initial_volume, flow_width)
            .and_then(|()| csv.flush())
            .map_err(io_err(&csv_path))?;
        stations.record(&sim);
        if let Some(map) = surface_u1.as_mut() {
            let f = &sim.flow;
            let u1: Vec<f64> = f.u.iter().map(|u| u[0]).collect();
            let on_surface: Vec<bool> = (0..f.x.len())
                .map(|i| f.walls[i] == 0 && f.in_mesh[i] && f.was_free.get(i) == Some(&true))
                .collect();
            map.record(sim.time_s, &f.x, &u1, &on_surface);
        }
        let eta = gauge_values(case, &sim.flow);
        if let Some(g) = gauges.as_mut() {
            g.row(row.t_s, &eta).map_err(io_err(&gauge_path))?;
        }
        if let Some(r) = rrd.as_mut() {
            r.log(&sim.flow, &row, initial_volume).map_err(rrd_err)?;
            r.log_gauges(&gauge_columns, &eta).map_err(rrd_err)?;
        }
        rows.push(row);
        if sim.time_s >= end_s - 1e-12 || status != "ok" {
            break;
        }
        k += 1;
        let target = (k as f64 * interval).min(end_s);
        while sim.time_s < target - 1e-12 {
            match sim.step_towards(target) {
                Ok(s) => {
                    stations.accumulate(&sim, sim.last_dt_s);
                    particle_steps += sim.flow.x.len() as f64;
                    for (k, ms) in s.stage_ms.iter().enumerate() {
                        stage_ms[k].push(*ms);
                    }
                    step_ms.push(s.stage_ms.iter().sum());
                    progress.update(sim.time_s, sim.steps);
                }
                Err(e) => {
                    status = e;
                    break;
                }
            }
        }
        // After trouble the loop records one last row, of the state the trouble left.
    }
    progress.finish();
    csv.flush().map_err(io_err(&csv_path))?;
    if let Some(r) = rrd.as_ref() {
        r.flush();
    }
    let wall_s = started.elapsed().as_secs_f64();
    let mut summary = Summary3 {
        parameters: case.clone(),
        status,
        run: RunFigures::new(
            sim.flow.x.len(),
            sim.fluid_count(),
            sim.steps,
            sim.time_s,
            wall_s,
            particle_steps,
            median(&step_ms),
        ),
        median_stage_ms: stage_ms.iter().map(|v| median(v)).collect(),
        stages: STAGES_3D.iter().map(|s| s.to_string()).collect(),
        initial_volume_m3: initial_volume,
        volume_drift_max: rows
            .iter()
            .map(|r| (r.volume_m3 / initial_volume - 1.0).abs())
            .fold(0.0, f64::max),
        max_tetrahedra: rows.iter().map(|r| r.tetrahedra).max().unwrap_or(0),
        max_slivers_kept: rows.iter().map(|r| r.slivers_kept).max().unwrap_or(0),
        undertow: case.wavemaker.as_ref().and_then(|w| {
            stations.summary(
                w.period_s,
                case.surf.spin_up_periods * w.period_s,
                case.surf.x_origin_m,
            )
        }),
        surface_u1_over_bars: None,
    };
    if let Some(map) = surface_u1.as_ref() {
        let path = opts.out_dir.join("surface_u1.csv");
        write_surface_u1(&path, map).map_err(io_err(&path))?;
        summary.surface_u1_over_bars = map.over_bars(&case.flume.bars);
    }
    let summary_path = opts.out_dir.join("summary.json");
    let text = serde_json::to_string_pretty(&summary).expect("a summary serialises");
    std::fs::write(&summary_path, text).map_err(io_err(&summary_path))?;
    Ok(Run3Outcome { summary, rows })
}

/// `surface_u1.csv`: each counted cell's centre and the largest and smallest u1 of the free
/// surface there, with the number of nodes counted.
fn write_surface_u1(path: &Path, map: &SurfaceU1Map) -> std::io::Result<()> {
    let mut out = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(out, "x_m,z_m,u1_max_m_s,u1_min_m_s,samples")?;
    for c in (0..map.samples.len()).filter(|&c| map.samples[c] > 0) {
        let (x, z) = map.centre(c);
        writeln!(
            out,
            "{x},{z},{},{},{}",
            map.max_m_s[c], map.min_m_s[c], map.samples[c]
        )?;
    }
    out.flush()
}

/// One row; `volume_m2` is the volume per metre of width (m³ / width), the 2D series' unit.
fn write_row(out: &mut impl Write, r: &Row3, v0: f64, width_m: f64) -> std::io::Result<()> {
    let i = &r.integrals;
    writeln!(
        out,
        "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
        r.t_s,
        r.dt_s,
        r.steps,
        r.volume_m3,
        r.volume_m3 / width_m,
        r.volume_m3 / v0,
        i.fluid_particles,
        i.isolated_particles,
        i.max_speed_m_s,
        i.kinetic_energy_j,
        i.front_x_m,
        i.left_wall_height_m,
        r.tetrahedra,
        r.slivers_kept,
        r.guarded,
        r.inserted,
        r.removed,
        r.moves_m3,
        r.remeshes_m3
    )
}
