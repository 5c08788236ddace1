//! A headless 3D run (a case with `flume.width_m`, issue 26): step the [`Flow3`] to the end
//! time and at every output interval write a row of `timeseries.csv` and a frame of `run.rrd`
//! (the particles as 3D points coloured by u1, the free surface as a mesh, the wetted wall
//! nodes); `summary.json` at the end, whatever the end was. Numerical trouble ends the run with
//! a status; what was recorded stays readable.

use super::colormap::ColorScale;
use super::rrd::SIM_TIMELINE;
use super::run::{Progress, RunError, RunOptions, io_err};
use super::summary::{RunFigures, median};
use super::timeseries::{GaugeWriter, gauge_columns};
use crate::case::Case;
use crate::solver3d::{Flow3, Integrals3, STAGES_3D, setup};
use crate::waves::paddle::PaddleMotion;
use rerun::{RecordingStream, RecordingStreamBuilder};
use serde::Serialize;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

/// One output time of a 3D run.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Row3 {
    pub t_s: f64,
    /// The last step's Δt, s (0 in the first row).
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
}

impl Summary3 {
    /// The one line `surflab run` prints at the end of a 3D run.
    pub fn line(&self) -> String {
        format!(
            "3D, {}, volume drift max {:.3e}, up to {} tetrahedra ({} slivers kept)",
            self.run.line(),
            self.volume_drift_max,
            self.max_tetrahedra,
            self.max_slivers_kept
        )
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

/// Runs the 3D `case` to `case.time.end_s` (Δt: the CFL policy's bound on the fastest fluid
/// particle, `time.dt_max_s` and the surface-wave bound, as in 2D, cut to land on every output
/// time).
pub fn run3d(case: &Case, opts: &RunOptions) -> Result<Run3Outcome, RunError> {
    std::fs::create_dir_all(&opts.out_dir).map_err(io_err(&opts.out_dir))?;
    let mut flow = setup::from_case(case).map_err(|e| RunError::Setup(e.to_string()))?;
    // The piston's path (the case was validated, so its motion exists); the solver is told
    // one step ahead where the face is to be.
    let paddle = match (case.wavemaker.as_ref(), PaddleMotion::from_case(case)) {
        (Some(w), Some(Ok(motion))) => Some((w.x_m, motion)),
        (_, Some(Err(e))) => return Err(RunError::Setup(e.to_string())),
        _ => None,
    };
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
        Some(Recorder3::create(&rrd_path, case, &flow).map_err(rrd_err)?)
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
    let flow_width = case.flume.width_m.unwrap_or(1.0);
    let end_s = case.time.end_s;
    let interval = case.output.interval_s;
    let initial_volume = flow
        .mesh_now()
        .map_err(|e| RunError::Setup(e.to_string()))?;
    let mut rows = Vec::new();
    let mut stage_ms: Vec<Vec<f64>> = vec![Vec::new(); STAGES_3D.len()];
    let mut step_ms = Vec::new();
    let (mut t, mut steps, mut particle_steps) = (0.0f64, 0u64, 0.0f64);
    let mut progress = Progress::new(opts.progress, end_s);
    let started = Instant::now();
    let mut row = Row3 {
        t_s: 0.0,
        dt_s: 0.0,
        steps: 0,
        volume_m3: initial_volume,
        tetrahedra: 0,
        slivers_kept: 0,
        guarded: 0,
        inserted: 0,
        removed: 0,
        moves_m3: 0.0,
        remeshes_m3: 0.0,
        integrals: flow.integrals(),
    };
    let mut last_moved = initial_volume;
    let mut status = "ok".to_owned();
    let mut k = 0u64;
    loop {
        // Record the row of this output time.
        row.t_s = t;
        row.steps = steps;
        row.integrals = flow.integrals();
        write_row(&mut csv, &row, initial_volume, flow_width)
            .and_then(|()| csv.flush())
            .map_err(io_err(&csv_path))?;
        let eta = gauge_values(case, &flow);
        if let Some(g) = gauges.as_mut() {
            g.row(t, &eta).map_err(io_err(&gauge_path))?;
        }
        if let Some(r) = rrd.as_mut() {
            r.log(&flow, &row, initial_volume).map_err(rrd_err)?;
            r.log_gauges(&gauge_columns, &eta).map_err(rrd_err)?;
        }
        rows.push(row);
        row.guarded = 0;
        row.inserted = 0;
        row.removed = 0;
        if t >= end_s - 1e-12 || status != "ok" {
            break;
        }
        k += 1;
        let target = (k as f64 * interval).min(end_s);
        while t < target - 1e-12 {
            let speed = flow.max_fluid_speed();
            if !speed.is_finite() {
                status = format!(
                    "stopped at t = {t:.5} s (step {steps}): the flow diverged (a particle's speed \
                     is {speed})"
                );
                break;
            }
            let mut dt = step_for(case, &flow);
            if dt < case.time.dt_min_s {
                status = format!(
                    "stopped at t = {t:.5} s (step {steps}): Δt = {dt:.2e} s is below \
                     time.dt_min_s = {} s (the fastest particle moves at {speed:.3} m/s)",
                    case.time.dt_min_s
                );
                break;
            }
            // Land on the output time rather than step a sliver past it.
            let left = target - t;
            if dt >= left || left < 1.5 * dt {
                dt = if dt >= left { left } else { 0.5 * left };
            }
            let t_next = if dt == left { target } else { t + dt };
            if let Some((x_rest, motion)) = &paddle {
                flow.drive_piston(x_rest + motion.displacement_m(t_next));
            }
            match flow.step(dt) {
                Ok(s) => {
                    t = t_next;
                    steps += 1;
                    particle_steps += flow.x.len() as f64;
                    for (k, ms) in s.stage_ms.iter().enumerate() {
                        stage_ms[k].push(*ms);
                    }
                    step_ms.push(s.stage_ms.iter().sum());
                    row.dt_s = dt;
                    row.remeshes_m3 += s.volume_m3 - last_moved;
                    row.moves_m3 += s.moved_volume_m3 - s.volume_m3;
                    last_moved = s.moved_volume_m3;
                    row.volume_m3 = s.volume_m3;
                    row.tetrahedra = s.tetrahedra;
                    row.slivers_kept = s.slivers_kept;
                    row.guarded += s.guarded;
                    row.inserted += s.nodes.inserted;
                    row.removed += s.nodes.removed;
                    progress.update(t, steps);
                }
                Err(e) => {
                    status = format!("stopped at t = {t:.5} s (step {steps}): {e}");
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
    let fluid = flow.walls.iter().filter(|&&w| w == 0).count();
    let summary = Summary3 {
        parameters: case.clone(),
        status,
        run: RunFigures::new(
            flow.x.len(),
            fluid,
            steps,
            t,
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
    };
    let summary_path = opts.out_dir.join("summary.json");
    let text = serde_json::to_string_pretty(&summary).expect("a summary serialises");
    std::fs::write(&summary_path, text).map_err(io_err(&summary_path))?;
    Ok(Run3Outcome { summary, rows })
}

/// One row; `volume_m2` is the volume per metre of width (m³ / width), the 2D series' unit.
/// The 3D run's Δt for the flow's state, s: `time.dt_max_s`, the CFL bound
/// `time.cfl · h / (fastest fluid particle or moving wall)` and the surface-wave bound, as in
/// 2D.
pub fn step_for(case: &Case, flow: &Flow3) -> f64 {
    let h = case.particles.spacing_m;
    let speed = flow.max_fluid_speed().max(flow.wall_speed());
    let cfl_dt = if speed > 0.0 {
        case.time.cfl * h / speed
    } else {
        f64::INFINITY
    };
    let surface_dt = case.time.surface_wave_dt_s(h, case.fluid.gravity_m_s2);
    case.time.dt_max_s.min(cfl_dt).min(surface_dt)
}

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

/// The layout: the tank in 3D over two thirds of the height; below it the planes z = const,
/// one 2D view each, and the plots in tabs; the viewer's side panels collapsed.
fn send_blueprint(
    rec: &RecordingStream,
    planes_z_m: &[f64],
) -> Result<(), rerun::RecordingStreamError> {
    use rerun::blueprint::components::PanelState;
    use rerun::blueprint::{
        Blueprint, BlueprintActivation, BlueprintPanel, ContainerLike, Horizontal, SelectionPanel,
        Spatial2DView, Spatial3DView, Tabs, TimePanel, TimeSeriesView, Vertical,
    };
    let tank: ContainerLike = Spatial3DView::new("tank (x along, y up, z across)")
        .with_origin("/world")
        .into();
    let mut below: Vec<ContainerLike> = planes_z_m
        .iter()
        .map(|z| {
            Spatial2DView::new(format!("plane z = {z:.3} m"))
                .with_origin(format!("/planes/z={z:.3}"))
                .into()
        })
        .collect();
    below.push(
        Tabs::new([
            TimeSeriesView::new("volume V/V₀")
                .with_origin("/plots/volume_ratio")
                .into(),
            TimeSeriesView::new("front x (m)")
                .with_origin("/plots/front_x_m")
                .into(),
            TimeSeriesView::new("max speed (m/s)")
                .with_origin("/plots/max_speed_m_s")
                .into(),
        ])
        .into(),
    );
    let root = Vertical::new([tank, Horizontal::new(below).into()]).with_row_shares([2.0, 1.0]);
    Blueprint::new(root)
        .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
        .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
        .with_time_panel(
            TimePanel::new()
                .with_timeline(SIM_TIMELINE)
                .with_state(PanelState::Collapsed),
        )
        .send(rec, BlueprintActivation::default())
}

/// The 3D recording: `world/particles` (fluid, coloured by u1 with the case's range),
/// `world/walls` (the wall nodes in the mesh), `world/free_surface` (the α-shape's surface
/// triangles), the tank's edges (static), `planes/z=<z>/particles` (the fluid particles within
/// h/2 of each plane of `output.planes_z_m`, as x, y points coloured by u1), and the scalars
/// `plots/volume_ratio`, `plots/front_x_m` and `plots/max_speed_m_s`, on the `sim_time`
/// timeline.
struct Recorder3 {
    rec: RecordingStream,
    scale: ColorScale,
    radius_m: f32,
    planes_z_m: Vec<f64>,
}

impl Recorder3 {
    fn create(path: &Path, case: &Case, flow: &Flow3) -> Result<Self, String> {
        let rec = RecordingStreamBuilder::new("surflab")
            .save(path)
            .map_err(|e| e.to_string())?;
        rec.set_log_time_enabled(false);
        let (lo, hi) = case.u1_range();
        let f = &case.flume;
        let (l, ht, w) = (
            f.length_m as f32,
            f.height_m as f32,
            f.width_m.unwrap_or(0.0) as f32,
        );
        let c = |x: f32, y: f32, z: f32| [x, y, z];
        let edges = vec![
            vec![
                c(0., 0., 0.),
                c(l, 0., 0.),
                c(l, 0., w),
                c(0., 0., w),
                c(0., 0., 0.),
            ],
            vec![
                c(0., ht, 0.),
                c(l, ht, 0.),
                c(l, ht, w),
                c(0., ht, w),
                c(0., ht, 0.),
            ],
            vec![c(0., 0., 0.), c(0., ht, 0.)],
            vec![c(l, 0., 0.), c(l, ht, 0.)],
            vec![c(l, 0., w), c(l, ht, w)],
            vec![c(0., 0., w), c(0., ht, w)],
        ];
        rec.log_static(
            "world/tank",
            &rerun::LineStrips3D::new(edges).with_colors([[120u8, 120, 120]]),
        )
        .map_err(|e| e.to_string())?;
        rec.log_static("world", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())
            .map_err(|e| e.to_string())?;
        send_blueprint(&rec, &case.output.planes_z_m).map_err(|e| e.to_string())?;
        Ok(Self {
            rec,
            scale: ColorScale::new(lo, hi),
            radius_m: (0.4 * flow.h_m) as f32,
            planes_z_m: case.output.planes_z_m.clone(),
        })
    }

    fn log(&mut self, flow: &Flow3, row: &Row3, v0: f64) -> Result<(), String> {
        let e = |err: rerun::RecordingStreamError| err.to_string();
        self.rec.set_duration_secs(SIM_TIMELINE, row.t_s);
        let to32 = |p: &[f64; 3]| p.map(|c| c as f32);
        let (mut fluid, mut colours, mut walls) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..flow.x.len() {
            if flow.walls[i] == 0 {
                fluid.push(to32(&flow.x[i]));
                colours.push(self.scale.color(flow.u[i][0]));
            } else if flow.in_mesh.get(i).copied().unwrap_or(false) {
                walls.push(to32(&flow.x[i]));
            }
        }
        self.rec
            .log(
                "world/particles",
                &rerun::Points3D::new(fluid)
                    .with_colors(colours)
                    .with_radii([rerun::Radius::new_scene_units(self.radius_m)]),
            )
            .map_err(e)?;
        self.rec
            .log(
                "world/walls",
                &rerun::Points3D::new(walls)
                    .with_colors([[150u8, 150, 150]])
                    .with_radii([rerun::Radius::new_scene_units(0.5 * self.radius_m)]),
            )
            .map_err(e)?;
        // The surface as its own small vertex list.
        let mut index = std::collections::HashMap::new();
        let (mut vertices, mut vertex_colours) = (Vec::new(), Vec::new());
        let triangles: Vec<[u32; 3]> = flow
            .surface
            .iter()
            .map(|f| {
                f.map(|i| {
                    *index.entry(i).or_insert_with(|| {
                        vertices.push(to32(&flow.x[i as usize]));
                        vertex_colours.push(self.scale.color(flow.u[i as usize][0]));
                        (vertices.len() - 1) as u32
                    })
                })
            })
            .collect();
        self.rec
            .log(
                "world/free_surface",
                &rerun::Mesh3D::new(vertices)
                    .with_triangle_indices(triangles)
                    .with_vertex_colors(vertex_colours),
            )
            .map_err(e)?;
        // The planes z = const: the particles within h/2 of each, seen from the side.
        for &z in &self.planes_z_m {
            let (mut xy, mut colours) = (Vec::new(), Vec::new());
            for i in 0..flow.x.len() {
                if flow.walls[i] == 0 && (flow.x[i][2] - z).abs() <= 0.5 * flow.h_m {
                    xy.push([flow.x[i][0] as f32, flow.x[i][1] as f32]);
                    colours.push(self.scale.color(flow.u[i][0]));
                }
            }
            self.rec
                .log(
                    format!("planes/z={z:.3}/particles"),
                    &rerun::Points2D::new(xy)
                        .with_colors(colours)
                        .with_radii([rerun::Radius::new_scene_units(self.radius_m)]),
                )
                .map_err(e)?;
        }
        let i = &row.integrals;
        for (path, v) in [
            ("plots/volume_ratio", row.volume_m3 / v0),
            ("plots/front_x_m", i.front_x_m),
            ("plots/max_speed_m_s", i.max_speed_m_s),
        ] {
            if v.is_finite() {
                self.rec.log(path, &rerun::Scalars::single(v)).map_err(e)?;
            }
        }
        Ok(())
    }

    /// The gauges' η as scalar plots `gauges/<column>` (nothing for a dry gauge).
    fn log_gauges(&mut self, columns: &[String], eta: &[Option<f64>]) -> Result<(), String> {
        for (name, v) in columns.iter().zip(eta) {
            if let Some(v) = v {
                self.rec
                    .log(format!("gauges/{name}"), &rerun::Scalars::single(*v))
                    .map_err(|e| e.to_string())?;
            }
        }
        Ok(())
    }

    fn flush(&self) {
        if let Err(e) = self.rec.flush_blocking() {
            eprintln!("warning: flushing the rerun recording failed: {e}");
        }
    }
}
