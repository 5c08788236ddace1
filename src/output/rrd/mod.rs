//! Rerun (.rrd) logging of the flume state.
//!
//! Entity layout (all lengths in metres):
//! - `world`: a static y-flip (`Transform3D` scale (1, -1, 1)). Rerun's 2D
//!   views draw +y downwards; the flip makes the physical +y (up) point up on
//!   screen. Everything spatial lives below this entity.
//! - `world/flume`: static grey polyline of the solid walls and bed.
//! - `world/particles`: fluid particles, coloured by the horizontal velocity
//!   u1 through a [`ColorScale`] (viridis), radius in scene units.
//! - `world/walls`: wall nodes, small grey points, logged every frame because
//!   a paddle may move them.
//! - `world/boundary`: the alpha-shape boundary as blue 2-point segments.
//! - `world/polygons`: the outlines of the EDT polygon elements (δ > 0), orange; their inner
//!   diagonals are left out of `world/mesh`.
//! - `world/mesh`: triangle edges (each once), thin, only on frames that
//!   carry triangles; cleared on the next frame without them so that an old
//!   mesh is never drawn over newer particles.
//! - `world/breaker`: the breaking point of the newest breaker, labelled with its type.
//! - `breaker_map`: Battjes's bands against ξ₀, one row per type (static, `breaker_map.rs`),
//!   and `breaker_map/run`, the run's point on it (its ξ₀ and observed type).
//! - `scalars/<group>`: one entity per plot. A scalar named `group/series` is instance
//!   `series` of `scalars/group`; a name without a group belongs to `scalars/diagnostics`.
//!   The series names are logged statically as `SeriesLines` names, in the order first seen;
//!   a series missing from a frame (a dry gauge, the timings before the first step) is NaN
//!   there, a gap in its line. One entity per plot rather than per series: the viewer takes in
//!   and queries 3 chunks a frame instead of 33 (the lab's plots cost about a fifth of its
//!   window's frame time on a software renderer).
//! - `legend`: static markdown stating the colour map and its range.
//!
//! Time is the duration timeline `sim_time` (seconds of simulated time).

use std::cell::Cell;
use std::collections::HashMap;
use std::fmt;
use std::path::Path;

use nalgebra::Vector2;
use rerun::archetypes::{
    Clear, LineStrips2D, Points2D, Scalars, SeriesLines, TextDocument, TextLog, Transform3D,
};
use rerun::components::Radius;
use rerun::{
    ApplicationId, EntityPath, RecordingStream, RecordingStreamBuilder, RecordingStreamError,
};

use super::colormap::ColorScale;

/// Name of the timeline carrying simulated time.
pub const SIM_TIMELINE: &str = "sim_time";

const FLUME_COLOR: [u8; 3] = [150, 150, 150];
const WALL_COLOR: [u8; 3] = [110, 110, 110];
const BOUNDARY_COLOR: [u8; 3] = [30, 110, 255];
const MESH_COLOR: [u8; 4] = [40, 40, 40, 150];
/// EDT polygon outlines: orange, apart from the triangles' grey.
const POLYGON_COLOR: [u8; 4] = [230, 120, 20, 220];

// Draw order in 2D views: larger is drawn on top.
const ORDER_PARTICLES: f32 = 30.0;
const ORDER_WALLS: f32 = 31.0;
const ORDER_MESH: f32 = 35.0;
const ORDER_BOUNDARY: f32 = 40.0;
const ORDER_FLUME: f32 = 50.0;
const ORDER_BREAKER: f32 = 60.0;

/// One output frame, borrowed from the solver state.
#[derive(Debug, Clone, Copy)]
pub struct FrameView<'a> {
    /// Simulated time in seconds (finite, >= 0).
    pub t_s: f64,
    /// All nodes, fluid and wall.
    pub positions: &'a [Vector2<f64>],
    /// Velocities of all nodes (same length as `positions`).
    pub velocities: &'a [Vector2<f64>],
    /// True for fluid particles, false for wall nodes (same length as `positions`).
    pub is_fluid: &'a [bool],
    /// Alpha-shape boundary (free surface and wetted walls) as node index pairs.
    pub boundary_edges: &'a [[u32; 2]],
    /// Kept mesh triangles; logged only when `Some`.
    pub triangles: Option<&'a [[u32; 3]]>,
    /// The EDT polygons among them (`triangles` indices): drawn as outlines of their own
    /// colour at `world/polygons`, with their inner diagonals left out of `world/mesh`.
    pub polygons: &'a [crate::mesh::MeshPolygon],
    /// Named scalars, e.g. `("volume_m2", v)` or `("timing_ms/remesh", 1.2)`.
    pub scalars: &'a [(&'a str, f64)],
}

/// Failure while setting up or writing the recording.
#[derive(Debug)]
pub enum RrdError {
    /// Error reported by the Rerun SDK (sink creation, serialisation, ...).
    Rerun(RecordingStreamError),
    /// Inconsistent input: frame lengths, node indices, time or radius.
    InvalidInput(String),
}

impl fmt::Display for RrdError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Rerun(e) => write!(f, "rerun logging failed: {e}"),
            Self::InvalidInput(msg) => write!(f, "invalid input for rerun logging: {msg}"),
        }
    }
}

impl std::error::Error for RrdError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Rerun(e) => Some(e),
            Self::InvalidInput(_) => None,
        }
    }
}

impl From<RecordingStreamError> for RrdError {
    fn from(e: RecordingStreamError) -> Self {
        Self::Rerun(e)
    }
}

/// The series of one plot: one entity, one instance per series.
#[derive(Debug)]
struct ScalarGroup {
    path: EntityPath,
    names: Vec<String>,
    /// This frame's values, NaN where a series has none.
    values: Vec<f64>,
    /// How many names the last static `SeriesLines` carried.
    names_logged: usize,
    /// Whether any series of the group has a value this frame.
    touched: bool,
}

/// Who the recording's blueprint is laid out for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Viewing {
    /// A file reviewed later: the time panel starts collapsed, with its play controls.
    Review,
    /// The lab's live window: the time panel starts hidden (the toggle in the viewer's top bar
    /// opens it). Collapsed, it still redraws its density graph of every entity each frame,
    /// about 5 % of the window's time on a software renderer.
    Live,
}

/// Writes flume frames to a Rerun recording stream.
///
/// The per-frame conversion buffers are kept between calls, so after the first
/// few frames logging allocates nothing on our side beyond what the SDK needs
/// to serialise the batches.
#[derive(Debug)]
pub struct RrdLogger {
    rec: RecordingStream,
    scale: ColorScale,
    radius_m: f32,
    /// Fluid particle positions in f32.
    fluid_pos: Vec<[f32; 2]>,
    /// Fluid particle colours.
    fluid_rgb: Vec<[u8; 3]>,
    /// Wall node positions in f32.
    wall_pos: Vec<[f32; 2]>,
    /// Boundary segments.
    boundary_segs: Vec<[[f32; 2]; 2]>,
    /// Sorted, deduplicated mesh edges (index pairs with a < b).
    mesh_edges: Vec<[u32; 2]>,
    /// Mesh edge segments.
    mesh_segs: Vec<[[f32; 2]; 2]>,
    polygon_segs: Vec<[[f32; 2]; 2]>,
    /// Whether `world/polygons` shows outlines that must be cleared.
    polygons_shown: bool,
    /// Whether `world/mesh` currently shows a mesh that must be cleared
    /// when a frame arrives without triangles.
    mesh_shown: bool,
    /// The plots' scalar groups, in the order first seen, and where each is by name.
    scalar_groups: Vec<ScalarGroup>,
    group_index: HashMap<String, usize>,
    viewing: Viewing,
    /// Which optional tabs the blueprint has: the surf-zone views, the breaker map.
    surf_views: Cell<bool>,
    breaker_map: Cell<bool>,
    /// The part of the flume the flume view opens on, [x_min, x_max, y_min, y_max] in m (the
    /// whole flume when `None`).
    flume_window_m: Cell<Option<[f64; 4]>>,
}

impl RrdLogger {
    /// Opens `path` as an .rrd file sink and writes the static scene.
    ///
    /// `flume_outline`: the solid boundary polyline (walls + bed) in metres,
    /// logged once statically. The wall-clock `log_time` timeline is turned
    /// off for the file so that it only carries `sim_time`.
    pub fn create(
        path: &Path,
        app_id: &str,
        flume_outline: &[[f64; 2]],
        scale: ColorScale,
        particle_radius_m: f64,
    ) -> Result<Self, RrdError> {
        check_radius(particle_radius_m)?;
        // Only `&'static str` converts directly; a runtime string needs the
        // fallible constructor (it rejects e.g. an empty id).
        let app = ApplicationId::try_new(app_id)
            .map_err(|e| RrdError::InvalidInput(format!("bad application id {app_id:?}: {e}")))?;
        let rec = RecordingStreamBuilder::new(app).save(path)?;
        rec.set_log_time_enabled(false);
        Self::from_stream(
            rec,
            flume_outline,
            scale,
            particle_radius_m,
            Viewing::Review,
        )
    }

    /// Same as [`Self::create`], but logs into an existing stream (which may
    /// fan out to several sinks), with the blueprint laid out for `viewing`. The stream's
    /// settings are left as they are.
    pub fn from_stream(
        rec: RecordingStream,
        flume_outline: &[[f64; 2]],
        scale: ColorScale,
        particle_radius_m: f64,
        viewing: Viewing,
    ) -> Result<Self, RrdError> {
        check_radius(particle_radius_m)?;
        let logger = Self {
            rec,
            scale,
            radius_m: particle_radius_m as f32,
            fluid_pos: Vec::new(),
            fluid_rgb: Vec::new(),
            wall_pos: Vec::new(),
            boundary_segs: Vec::new(),
            mesh_edges: Vec::new(),
            mesh_segs: Vec::new(),
            polygon_segs: Vec::new(),
            polygons_shown: false,
            mesh_shown: false,
            scalar_groups: Vec::new(),
            group_index: HashMap::new(),
            viewing,
            surf_views: Cell::new(false),
            breaker_map: Cell::new(false),
            flume_window_m: Cell::new(None),
        };
        logger.log_static_scene(flume_outline)?;
        logger.send_blueprint()?;
        Ok(logger)
    }

    /// The underlying stream, for logging extra entities.
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// The colour scale used for the particles.
    pub fn scale(&self) -> ColorScale {
        self.scale
    }

    fn log_static_scene(&self, flume_outline: &[[f64; 2]]) -> Result<(), RrdError> {
        let rec = &self.rec;
        rec.log_static("world", &Transform3D::from_scale((1.0, -1.0, 1.0)))?;

        let outline: Vec<[f32; 2]> = flume_outline.iter().map(|p| to_f32(*p)).collect();
        rec.log_static(
            "world/flume",
            &LineStrips2D::new([outline])
                .with_colors([FLUME_COLOR])
                .with_radii([Radius::new_ui_points(1.5)])
                .with_draw_order(ORDER_FLUME),
        )?;

        let legend = format!(
            "## Legend\n\n\
             - **Particles** (`world/particles`): colour = {}.\n\
             - **Blue lines** (`world/boundary`): alpha-shape boundary (free surface and wetted walls).\n\
             - **Thin dark lines** (`world/mesh`): kept mesh triangles, on frames where they were logged.\n\
             - **Orange outlines** (`world/polygons`): EDT polygon elements (δ > 0).\n\
             - **Grey points** (`world/walls`): wall nodes. **Grey polyline** (`world/flume`): walls and bed.\n\
             - Axes: x along the flume, y up, metres. Time: `{SIM_TIMELINE}` (simulated seconds).\n",
            self.scale.describe("u1", "m/s")
        );
        rec.log_static("legend", &TextDocument::from_markdown(legend))?;
        Ok(())
    }

    /// Sends the blueprint again with the surf-zone views as tabs beside the flume: the
    /// undertow profiles (`/profiles`) and the space–time images (`/space_time`). A run calls
    /// it once these are logged.
    pub fn add_surf_views(&self) -> Result<(), RrdError> {
        self.surf_views.set(true);
        self.send_blueprint()
    }

    /// Draws the frame of the breaker-type map (`/breaker_map`: Battjes's bands against ξ₀,
    /// one row per type) and adds its tab beside the flume. The run's point on it comes with
    /// [`Self::log_breaker`].
    pub fn add_breaker_map(&self) -> Result<(), RrdError> {
        super::breaker_map::log_axes(
            &self.rec,
            "breaker_map",
            super::breaker_map::DEEP_WATER_LIMITS,
        )?;
        self.breaker_map.set(true);
        self.send_blueprint()
    }

    /// At `t_s`: the run's point on the breaker map, at its Iribarren number `iribarren` and
    /// the row of the `observed` type (before any breaker, a hollow grey ring on the row of
    /// the `predicted` one), and on the flume the breaking point `at` (x, y in m) labelled
    /// with its type, when there is one.
    pub fn log_breaker(
        &self,
        t_s: f64,
        iribarren: f64,
        observed: Option<&str>,
        predicted: &str,
        at: Option<[f64; 2]>,
    ) -> Result<(), RrdError> {
        use super::breaker_map::{TYPE_COLORS, type_index};
        self.set_time(t_s)?;
        let (row, colour, label) = match observed.and_then(|o| Some((o, type_index(o)?))) {
            Some((name, k)) => (
                k,
                TYPE_COLORS[k],
                format!("this run: ξ₀ = {iribarren:.2}, {name}"),
            ),
            None => (
                type_index(predicted).unwrap_or(TYPE_COLORS.len() - 1),
                TYPE_COLORS[TYPE_COLORS.len() - 1],
                format!("this run: ξ₀ = {iribarren:.2}, no breaker yet (predicted {predicted})"),
            ),
        };
        if iribarren.is_finite() {
            self.rec.log(
                "breaker_map/run",
                &Points2D::new([[iribarren as f32, row as f32]])
                    .with_colors([colour])
                    .with_labels([label])
                    .with_radii([Radius::new_scene_units(0.08)])
                    .with_draw_order(20.0),
            )?;
        }
        match (observed, at) {
            (Some(name), Some([x, y])) => {
                let k = type_index(name).unwrap_or(TYPE_COLORS.len() - 1);
                self.rec.log(
                    "world/breaker",
                    &Points2D::new([to_f32([x, y])])
                        .with_colors([TYPE_COLORS[k]])
                        .with_labels([format!("breaking: {name}")])
                        .with_radii([Radius::new_ui_points(6.0)])
                        .with_draw_order(ORDER_BREAKER),
                )?;
            }
            // A new wave (the lab's panel): the old wave's mark goes.
            _ => self.rec.log("world/breaker", &Clear::flat())?,
        }
        Ok(())
    }

    /// Opens the flume view on `window_m` = [x_min, x_max, y_min, y_max], m (the surf zone of
    /// a beach); the view zooms out to the whole flume as usual (scroll, or double-click).
    pub fn open_on(&self, window_m: [f64; 4]) -> Result<(), RrdError> {
        self.flume_window_m.set(Some(window_m));
        self.send_blueprint()
    }

    /// Logs one frame at simulated time `frame.t_s`.
    ///
    /// NOTE: Rerun keeps the time cursor per thread; this call sets
    /// `sim_time` itself, so it may be called from any thread.
    pub fn log_frame(&mut self, frame: &FrameView) -> Result<(), RrdError> {
        let n = frame.positions.len();
        if frame.velocities.len() != n || frame.is_fluid.len() != n {
            return Err(RrdError::InvalidInput(format!(
                "length mismatch: {n} positions, {} velocities, {} fluid flags",
                frame.velocities.len(),
                frame.is_fluid.len()
            )));
        }
        self.set_time(frame.t_s)?;

        // Particles and wall nodes.
        self.fluid_pos.clear();
        self.fluid_rgb.clear();
        self.wall_pos.clear();
        for ((p, v), &fluid) in frame
            .positions
            .iter()
            .zip(frame.velocities)
            .zip(frame.is_fluid)
        {
            let q = [p.x as f32, p.y as f32];
            if fluid {
                self.fluid_pos.push(q);
                self.fluid_rgb.push(self.scale.color(v.x));
            } else {
                self.wall_pos.push(q);
            }
        }
        self.rec.log(
            "world/particles",
            &Points2D::new(self.fluid_pos.iter().copied())
                .with_colors(self.fluid_rgb.iter().copied())
                .with_radii([Radius::new_scene_units(self.radius_m)])
                .with_draw_order(ORDER_PARTICLES),
        )?;
        self.rec.log(
            "world/walls",
            &Points2D::new(self.wall_pos.iter().copied())
                .with_colors([WALL_COLOR])
                .with_radii([Radius::new_scene_units(0.5 * self.radius_m)])
                .with_draw_order(ORDER_WALLS),
        )?;

        // Boundary segments.
        self.boundary_segs.clear();
        for &[a, b] in frame.boundary_edges {
            let pa = node(frame.positions, a, "boundary edge")?;
            let pb = node(frame.positions, b, "boundary edge")?;
            self.boundary_segs.push([pa, pb]);
        }
        self.rec.log(
            "world/boundary",
            &LineStrips2D::new(self.boundary_segs.iter().copied())
                .with_colors([BOUNDARY_COLOR])
                .with_radii([Radius::new_ui_points(1.0)])
                .with_draw_order(ORDER_BOUNDARY),
        )?;

        // Mesh edges, each shared edge once; the triangles of a polygon give its outline only.
        if let Some(tris) = frame.triangles {
            self.mesh_edges.clear();
            let flagged = if frame.polygons.is_empty() {
                0
            } else {
                tris.len()
            };
            let mut in_polygon = vec![false; flagged];
            self.polygon_segs.clear();
            for poly in frame.polygons {
                for (k, &a) in poly.nodes.iter().enumerate() {
                    let b = poly.nodes[(k + 1) % poly.nodes.len()];
                    let pa = node(frame.positions, a, "polygon")?;
                    let pb = node(frame.positions, b, "polygon")?;
                    self.polygon_segs.push([pa, pb]);
                    self.mesh_edges.push([a.min(b), a.max(b)]);
                }
                for &t in &poly.triangles {
                    if let Some(flag) = in_polygon.get_mut(t as usize) {
                        *flag = true;
                    }
                }
            }
            for (k, t) in tris.iter().enumerate() {
                if in_polygon.get(k).copied().unwrap_or(false) {
                    continue;
                }
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    if a as usize >= n || b as usize >= n {
                        return Err(RrdError::InvalidInput(format!(
                            "triangle {t:?} refers to a node >= {n}"
                        )));
                    }
                    self.mesh_edges.push([a.min(b), a.max(b)]);
                }
            }
            self.mesh_edges.sort_unstable();
            self.mesh_edges.dedup();
            self.mesh_segs.clear();
            for &[a, b] in &self.mesh_edges {
                self.mesh_segs.push([
                    vec_f32(frame.positions[a as usize]),
                    vec_f32(frame.positions[b as usize]),
                ]);
            }
            self.rec.log(
                "world/mesh",
                &LineStrips2D::new(self.mesh_segs.iter().copied())
                    .with_colors([MESH_COLOR])
                    .with_radii([Radius::new_ui_points(0.35)])
                    .with_draw_order(ORDER_MESH),
            )?;
            if !self.polygon_segs.is_empty() || self.polygons_shown {
                self.rec.log(
                    "world/polygons",
                    &LineStrips2D::new(self.polygon_segs.iter().copied())
                        .with_colors([POLYGON_COLOR])
                        .with_radii([Radius::new_ui_points(0.8)])
                        .with_draw_order(ORDER_MESH + 1.0),
                )?;
                self.polygons_shown = !self.polygon_segs.is_empty();
            }
            self.mesh_shown = true;
        } else if self.mesh_shown {
            self.rec.log("world/mesh", &Clear::flat())?;
            if self.polygons_shown {
                self.rec.log("world/polygons", &Clear::flat())?;
                self.polygons_shown = false;
            }
            self.mesh_shown = false;
        }

        // Scalars: one entity per group.
        for g in &mut self.scalar_groups {
            g.values.fill(f64::NAN);
            g.touched = false;
        }
        for &(name, value) in frame.scalars {
            let (group, series) = name.rsplit_once('/').unwrap_or(("diagnostics", name));
            if group.is_empty() || series.is_empty() {
                return Err(RrdError::InvalidInput(format!(
                    "scalar name {name:?} needs a group and a series name"
                )));
            }
            let gi = match self.group_index.get(group) {
                Some(&gi) => gi,
                None => {
                    self.scalar_groups.push(ScalarGroup {
                        path: EntityPath::from(format!("scalars/{group}")),
                        names: Vec::new(),
                        values: Vec::new(),
                        names_logged: 0,
                        touched: false,
                    });
                    self.group_index
                        .insert(group.to_owned(), self.scalar_groups.len() - 1);
                    self.scalar_groups.len() - 1
                }
            };
            let g = &mut self.scalar_groups[gi];
            let k = match g.names.iter().position(|n| n == series) {
                Some(k) => k,
                None => {
                    g.names.push(series.to_owned());
                    g.values.push(f64::NAN);
                    g.names.len() - 1
                }
            };
            g.values[k] = value;
            g.touched = true;
        }
        for g in &mut self.scalar_groups {
            if !g.touched {
                continue;
            }
            if g.names_logged != g.names.len() {
                self.rec.log_static(
                    g.path.clone(),
                    &SeriesLines::new().with_names(g.names.iter().map(String::as_str)),
                )?;
                g.names_logged = g.names.len();
            }
            self.rec
                .log(g.path.clone(), &Scalars::new(g.values.iter().copied()))?;
        }
        Ok(())
    }

    /// Logs a text event at `entity` and simulated time `t_s` (shown in the
    /// text-log view).
    pub fn log_text(&mut self, t_s: f64, entity: &str, text: &str) -> Result<(), RrdError> {
        self.set_time(t_s)?;
        self.rec.log(entity, &TextLog::new(text))?;
        Ok(())
    }

    /// Blocks until everything logged so far has reached the sinks. A flush
    /// failure is reported on stderr and otherwise ignored.
    pub fn flush(&self) {
        if let Err(e) = self.rec.flush_blocking() {
            eprintln!("warning: flushing the rerun recording failed: {e}");
        }
    }

    fn set_time(&self, t_s: f64) -> Result<(), RrdError> {
        if !(t_s.is_finite() && t_s >= 0.0) {
            return Err(RrdError::InvalidInput(format!(
                "simulated time must be finite and >= 0, got {t_s}"
            )));
        }
        self.rec.set_duration_secs(SIM_TIMELINE, t_s);
        Ok(())
    }
}

fn check_radius(r: f64) -> Result<(), RrdError> {
    if r.is_finite() && r > 0.0 {
        Ok(())
    } else {
        Err(RrdError::InvalidInput(format!(
            "particle radius must be positive and finite, got {r}"
        )))
    }
}

fn to_f32(p: [f64; 2]) -> [f32; 2] {
    [p[0] as f32, p[1] as f32]
}

fn vec_f32(p: Vector2<f64>) -> [f32; 2] {
    [p.x as f32, p.y as f32]
}

fn node(positions: &[Vector2<f64>], i: u32, what: &str) -> Result<[f32; 2], RrdError> {
    positions
        .get(i as usize)
        .map(|p| vec_f32(*p))
        .ok_or_else(|| {
            RrdError::InvalidInput(format!(
                "{what} refers to node {i}, but there are {} nodes",
                positions.len()
            ))
        })
}

mod blueprint;
pub(crate) use blueprint::send_with_bounds;
#[cfg(test)]
mod tests;
