//! The 3D recording (issue 26): the particles as 3D points coloured by u1, the free surface as
//! a mesh, the wetted wall nodes, the tank's edges and bed, the planes z = const as 2D views
//! (with the bed's profile), and the run's scalars, for a headless run's `run.rrd` and for the
//! lab's viewer alike.

use super::colormap::ColorScale;
use super::rrd::{RrdError, SIM_TIMELINE, send_with_bounds};
use super::run3d::Row3;
use crate::case::Case;
use crate::geometry::bed3d::{Bed3, lattice_through};
use crate::solver3d::Flow3;
use rerun::{RecordingStream, RecordingStreamBuilder};
use std::path::Path;

/// The layout: the tank in 3D over two thirds of the height; below it the planes z = const,
/// one 2D view each, opened on the whole tank's side `window_m` ([x0, x1, y0, y1], m), and the
/// plots in tabs; the viewer's side panels collapsed.
fn send_blueprint(
    rec: &RecordingStream,
    planes_z_m: &[f64],
    window_m: [f64; 4],
) -> Result<(), RrdError> {
    use rerun::blueprint::components::PanelState;
    use rerun::blueprint::{
        Blueprint, BlueprintPanel, ContainerLike, Horizontal, SelectionPanel, Spatial2DView,
        Spatial3DView, Tabs, TimePanel, TimeSeriesView, Vertical,
    };
    let tank: ContainerLike = Spatial3DView::new("tank (x along, y up, z across)")
        .with_origin("/world")
        .into();
    // Each plane's view is rooted at `planes`, whose children `z=<z>` are y-flipped so that
    // physical y points up (Rerun's 2D views draw +y downwards).
    let mut bounded = Vec::new();
    let mut below: Vec<ContainerLike> = planes_z_m
        .iter()
        .map(|z| {
            let view: ContainerLike = Spatial2DView::new(format!("plane z = {z:.3} m"))
                .with_origin("/planes")
                .with_contents([format!("/planes/z={z:.3}/**")])
                .into();
            if let ContainerLike::View(v) = &view {
                bounded.push((v.blueprint_path(), window_m));
            }
            view
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
    let blueprint = Blueprint::new(root)
        .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
        .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
        .with_time_panel(
            TimePanel::new()
                .with_timeline(SIM_TIMELINE)
                .with_state(PanelState::Collapsed),
        );
    send_with_bounds(rec, &blueprint, &bounded)
}

/// The 3D recording: `world/particles` (fluid, coloured by u1 with the case's range),
/// `world/walls` (the wall nodes in the mesh), `world/free_surface` (the α-shape's surface
/// triangles), the tank's edges (static), `planes/z=<z>/particles` (the fluid particles within
/// h/2 of each plane of `output.planes_z_m`, as x, y points coloured by u1), and the scalars
/// `plots/volume_ratio`, `plots/front_x_m` and `plots/max_speed_m_s`, on the `sim_time`
/// timeline.
pub struct Recorder3 {
    rec: RecordingStream,
    scale: ColorScale,
    radius_m: f32,
    planes_z_m: Vec<f64>,
}

impl Recorder3 {
    /// A recording saved to `path`.
    pub fn create(path: &Path, case: &Case, flow: &Flow3) -> Result<Self, String> {
        let rec = RecordingStreamBuilder::new("surflab")
            .save(path)
            .map_err(|e| e.to_string())?;
        Self::to_stream(rec, case, flow)
    }

    /// The recording on `rec` (the lab's stream to its viewer): the tank's edges, the view
    /// coordinates and the layout first.
    pub fn to_stream(rec: RecordingStream, case: &Case, flow: &Flow3) -> Result<Self, String> {
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
        log_bed(&rec, case).map_err(|e| e.to_string())?;
        for z in &case.output.planes_z_m {
            rec.log_static(
                format!("planes/z={z:.3}"),
                &rerun::Transform3D::from_scale((1.0, -1.0, 1.0)),
            )
            .map_err(|e| e.to_string())?;
        }
        let (l, ht) = (f.length_m, f.height_m);
        let window = [-0.02 * l, 1.02 * l, -0.05 * ht, 1.05 * ht];
        send_blueprint(&rec, &case.output.planes_z_m, window).map_err(|e| e.to_string())?;
        Ok(Self {
            rec,
            scale: ColorScale::new(lo, hi),
            radius_m: (0.4 * flow.h_m) as f32,
            planes_z_m: case.output.planes_z_m.clone(),
        })
    }

    /// One frame of `flow` at `row`'s time; `v0` the initial volume, m³.
    pub fn log(&mut self, flow: &Flow3, row: &Row3, v0: f64) -> Result<(), String> {
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
    pub fn log_gauges(&mut self, columns: &[String], eta: &[Option<f64>]) -> Result<(), String> {
        for (name, v) in columns.iter().zip(eta) {
            if let Some(v) = v {
                self.rec
                    .log(format!("gauges/{name}"), &rerun::Scalars::single(*v))
                    .map_err(|e| e.to_string())?;
            }
        }
        Ok(())
    }

    pub fn flush(&self) {
        if let Err(e) = self.rec.flush_blocking() {
            eprintln!("warning: flushing the rerun recording failed: {e}");
        }
    }
}

/// The bed's colour, sand.
const BED_COLOUR: [u8; 3] = [194, 178, 128];

/// The bed (static): `world/bed`, a mesh of the height field on a grid through its creases
/// (about 200 × 50 cells), and `planes/z=<z>/bed`, its profile in each plane z = const.
fn log_bed(rec: &RecordingStream, case: &Case) -> Result<(), rerun::RecordingStreamError> {
    let f = &case.flume;
    let (length, width) = (f.length_m, f.width_m.unwrap_or(0.0));
    let bed = Bed3::from_flume(f);
    let xs = lattice_through(0.0, length, &bed.x_breaks(0.0, length), |_, _| {
        length / 200.0
    });
    let zs = lattice_through(0.0, width, &bed.z_breaks(0.0, width), |_, _| width / 50.0);
    let vertices: Vec<[f32; 3]> = xs
        .iter()
        .flat_map(|&x| zs.iter().map(move |&z| (x, z)))
        .map(|(x, z)| [x as f32, bed.height(x, z) as f32, z as f32])
        .collect();
    let nz = zs.len() as u32;
    let triangles: Vec<[u32; 3]> = (0..xs.len() as u32 - 1)
        .flat_map(|i| (0..nz - 1).map(move |k| i * nz + k))
        .flat_map(|a| [[a, a + nz, a + 1], [a + 1, a + nz, a + nz + 1]])
        .collect();
    let [r, g, b] = BED_COLOUR;
    rec.log_static(
        "world/bed",
        &rerun::Mesh3D::new(vertices)
            .with_triangle_indices(triangles)
            .with_albedo_factor(rerun::Rgba32::from_rgb(r, g, b)),
    )?;
    for &z in &case.output.planes_z_m {
        let profile: Vec<[f32; 2]> = xs
            .iter()
            .map(|&x| [x as f32, bed.height(x, z) as f32])
            .collect();
        rec.log_static(
            format!("planes/z={z:.3}/bed"),
            &rerun::LineStrips2D::new([profile]).with_colors([BED_COLOUR]),
        )?;
    }
    Ok(())
}
