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
//! - `world/mesh`: triangle edges (each once), thin, only on frames that
//!   carry triangles; cleared on the next frame without them so that an old
//!   mesh is never drawn over newer particles.
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

use std::collections::HashMap;
use std::fmt;
use std::path::Path;

use nalgebra::Vector2;
use rerun::archetypes::{
    Clear, LineStrips2D, Points2D, Scalars, SeriesLines, TextDocument, TextLog, Transform3D,
};
use rerun::blueprint::components::PanelState;
use rerun::blueprint::{
    Blueprint, BlueprintActivation, BlueprintPanel, Horizontal, SelectionPanel, Spatial2DView,
    Tabs, TextDocumentView, TextLogView, TimePanel, TimeSeriesView, Vertical,
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

// Draw order in 2D views: larger is drawn on top.
const ORDER_PARTICLES: f32 = 30.0;
const ORDER_WALLS: f32 = 31.0;
const ORDER_MESH: f32 = 35.0;
const ORDER_BOUNDARY: f32 = 40.0;
const ORDER_FLUME: f32 = 50.0;

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
    /// Whether `world/mesh` currently shows a mesh that must be cleared
    /// when a frame arrives without triangles.
    mesh_shown: bool,
    /// The plots' scalar groups, in the order first seen, and where each is by name.
    scalar_groups: Vec<ScalarGroup>,
    group_index: HashMap<String, usize>,
    viewing: Viewing,
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
            mesh_shown: false,
            scalar_groups: Vec::new(),
            group_index: HashMap::new(),
            viewing,
        };
        logger.log_static_scene(flume_outline)?;
        logger.send_blueprint(false)?;
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
             - **Grey points** (`world/walls`): wall nodes. **Grey polyline** (`world/flume`): walls and bed.\n\
             - Axes: x along the flume, y up, metres. Time: `{SIM_TIMELINE}` (simulated seconds).\n",
            self.scale.describe("u1", "m/s")
        );
        rec.log_static("legend", &TextDocument::from_markdown(legend))?;
        Ok(())
    }

    /// Sends the blueprint again with the surf-zone views beside the flume: the undertow
    /// profiles (`/profiles`) and the space–time images (`/space_time`). A run calls it once
    /// these are logged; the viewer then shows them as tabs of the left column.
    pub fn add_surf_views(&self) -> Result<(), RrdError> {
        self.send_blueprint(true)
    }

    fn send_blueprint(&self, surf_views: bool) -> Result<(), RrdError> {
        let flume = Spatial2DView::new("flume")
            .with_origin("/")
            .with_contents(["/world/**"]);
        let left: rerun::blueprint::ContainerLike = if surf_views {
            // Each picture with its legend below it.
            let with_legend = |title: &str, origin: &str| -> rerun::blueprint::ContainerLike {
                Vertical::new([
                    Spatial2DView::new(title).with_origin(origin).into(),
                    TextDocumentView::new("legend")
                        .with_origin(format!("{origin}_legend"))
                        .into(),
                ])
                .with_row_shares([6.0, 1.0])
                .with_name(title)
                .into()
            };
            Tabs::new([
                flume.into(),
                with_legend("undertow ū(z)", "/profiles"),
                with_legend("η(x, t)", "/space_time/eta"),
                with_legend("u1(x, t)", "/space_time/u1"),
            ])
            .into()
        } else {
            flume.into()
        };
        // Physical series and per-stage timings have different units: one view each.
        let scalars = TimeSeriesView::new("diagnostics").with_origin("/scalars/diagnostics");
        let gauges =
            TimeSeriesView::new("gauges: η (m), u and w (m/s)").with_origin("/scalars/gauges");
        let timings = TimeSeriesView::new("ms per stage").with_origin("/scalars/timing_ms");
        let info = Tabs::new([
            scalars.into(),
            timings.into(),
            TextDocumentView::new("legend")
                .with_origin("/legend")
                .into(),
            TextLogView::new("log").with_origin("/").into(),
        ]);
        let side = Vertical::new([gauges.into(), info.into()]).with_row_shares([1.0, 1.0]);
        let root = Horizontal::new([left, side.into()]).with_column_shares([3.0, 2.0]);
        // The viewer's own side panels start collapsed: the flume and the plots get the room.
        let blueprint = Blueprint::new(root)
            .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
            .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
            .with_time_panel(TimePanel::new().with_timeline(SIM_TIMELINE).with_state(
                match self.viewing {
                    Viewing::Review => PanelState::Collapsed,
                    Viewing::Live => PanelState::Hidden,
                },
            ));
        blueprint.send(&self.rec, BlueprintActivation::default())?;
        Ok(())
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

        // Mesh edges, each shared edge once.
        if let Some(tris) = frame.triangles {
            self.mesh_edges.clear();
            for t in tris {
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
            self.mesh_shown = true;
        } else if self.mesh_shown {
            self.rec.log("world/mesh", &Clear::flat())?;
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

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};
    use std::io::BufReader;
    use std::path::PathBuf;

    use rerun::StoreKind;
    use rerun::log::{Chunk, LogMsg};

    use super::*;

    fn temp_rrd(tag: &str) -> PathBuf {
        std::env::temp_dir().join(format!("surflab_rrd_{tag}_{}.rrd", std::process::id()))
    }

    /// Reads every message of an .rrd file; panics on any decoding error.
    fn read_rrd(path: &Path) -> Vec<LogMsg> {
        let file = std::fs::File::open(path).expect("open rrd");
        re_log_encoding::DecoderApp::decode_eager(BufReader::new(file))
            .expect("not an rrd stream")
            .collect::<Result<Vec<_>, _>>()
            .expect("rrd decoding failed")
    }

    /// Rows per entity path in the recording (not the blueprint), plus the
    /// set of timelines seen.
    struct Summary {
        rows: BTreeMap<String, usize>,
        timelines: BTreeSet<String>,
        blueprint_msgs: usize,
    }

    fn summarize(msgs: &[LogMsg]) -> Summary {
        let mut s = Summary {
            rows: BTreeMap::new(),
            timelines: BTreeSet::new(),
            blueprint_msgs: 0,
        };
        for msg in msgs {
            if msg.store_id().kind() == StoreKind::Blueprint {
                s.blueprint_msgs += 1;
                continue;
            }
            if let LogMsg::ArrowMsg(_, arrow) = msg {
                let chunk = Chunk::from_arrow_msg(arrow).expect("chunk");
                *s.rows.entry(chunk.entity_path().to_string()).or_default() += chunk.num_rows();
                for name in chunk.timelines().keys() {
                    s.timelines.insert(name.to_string());
                }
            }
        }
        s
    }

    #[test]
    fn error_and_logger_can_cross_threads() {
        // `anyhow` and worker threads need these bounds.
        fn bounds<T: Send + Sync + 'static>() {}
        fn send<T: Send + 'static>() {}
        bounds::<RrdError>();
        send::<RrdLogger>();
    }

    const OUTLINE: [[f64; 2]; 4] = [[0.0, 1.0], [0.0, 0.0], [4.0, 0.0], [4.0, 1.0]];

    /// Ten fluid particles on a 5 x 2 grid plus four wall nodes.
    fn small_state(shift: f64) -> (Vec<Vector2<f64>>, Vec<Vector2<f64>>, Vec<bool>) {
        let mut pos = Vec::new();
        let mut vel = Vec::new();
        let mut fluid = Vec::new();
        for j in 0..2 {
            for i in 0..5 {
                pos.push(Vector2::new(
                    0.5 + 0.1 * f64::from(i) + shift,
                    0.1 * f64::from(j),
                ));
                vel.push(Vector2::new(f64::from(i) - 2.0, 0.0));
                fluid.push(true);
            }
        }
        for k in 0..4 {
            pos.push(Vector2::new(0.4 + 0.2 * f64::from(k), -0.05));
            vel.push(Vector2::zeros());
            fluid.push(false);
        }
        (pos, vel, fluid)
    }

    /// A logger writing to `path`, u1 coloured over ±1 m/s, particles of radius 2 cm.
    fn test_logger(path: &Path) -> RrdLogger {
        RrdLogger::create(
            path,
            "surflab_test",
            &OUTLINE,
            ColorScale::new(-1.0, 1.0),
            0.02,
        )
        .expect("create")
    }

    fn write_small_run(logger: &mut RrdLogger) {
        let edges = [[5u32, 6], [6, 7], [7, 8], [8, 9]];
        // Two triangles sharing the edge 1-5: five distinct edges.
        let tris = [[0u32, 1, 5], [1, 6, 5]];
        for f in 0..3 {
            let (pos, vel, fluid) = small_state(0.01 * f64::from(f));
            let frame = FrameView {
                t_s: 0.05 * f64::from(f),
                positions: &pos,
                velocities: &vel,
                is_fluid: &fluid,
                boundary_edges: &edges,
                triangles: (f == 1).then_some(&tris[..]),
                scalars: &[("volume_m2", 0.2), ("timing_ms/remesh", 1.25)],
            };
            logger.log_frame(&frame).expect("log_frame");
            if f == 1 {
                assert_eq!(logger.mesh_segs.len(), 5, "shared edge logged twice");
                assert_eq!(logger.fluid_pos.len(), 10);
                assert_eq!(logger.wall_pos.len(), 4);
            }
        }
        logger
            .log_text(0.1, "events", "paddle started")
            .expect("log_text");
    }

    #[test]
    fn written_file_decodes_with_expected_entities() {
        let path = temp_rrd("roundtrip");
        let scale = ColorScale::new(-1.5, 1.5);
        let mut logger =
            RrdLogger::create(&path, "surflab_test", &OUTLINE, scale, 0.02).expect("create");
        write_small_run(&mut logger);
        logger.flush();
        drop(logger);

        let msgs = read_rrd(&path);
        assert!(!msgs.is_empty());
        let s = summarize(&msgs);
        assert!(s.blueprint_msgs > 0, "no blueprint in the file");
        for (entity, rows) in [
            ("/world", 1),
            ("/world/flume", 1),
            ("/legend", 1),
            ("/world/particles", 3),
            ("/world/walls", 3),
            ("/world/boundary", 3),
            // Triangles on frame 1, then a clear on frame 2.
            ("/world/mesh", 2),
            // Three frames and the static series names.
            ("/scalars/diagnostics", 4),
            ("/scalars/timing_ms", 4),
            ("/events", 1),
        ] {
            assert_eq!(
                s.rows.get(entity).copied(),
                Some(rows),
                "{entity}: {:?}",
                s.rows
            );
        }
        assert!(s.timelines.contains(SIM_TIMELINE), "{:?}", s.timelines);
        assert!(!s.timelines.contains("log_time"), "{:?}", s.timelines);
        std::fs::remove_file(&path).ok();
    }

    #[test]
    fn scalars_are_grouped_one_entity_per_plot_with_nan_gaps() {
        let path = temp_rrd("groups");
        let mut logger = test_logger(&path);
        let (pos, vel, fluid) = small_state(0.0);
        let frames: [&[(&str, f64)]; 3] = [
            &[("volume_m2", 0.2), ("gauges/eta_1.0", 0.01)],
            // The first gauge dry, a second one wet: the first is a gap.
            &[("volume_m2", 0.3), ("gauges/eta_2.0", 0.02)],
            &[("gauges/eta_1.0", 0.03), ("gauges/eta_2.0", 0.04)],
        ];
        for (f, scalars) in frames.iter().enumerate() {
            let frame = FrameView {
                t_s: 0.1 * f as f64,
                positions: &pos,
                velocities: &vel,
                is_fluid: &fluid,
                boundary_edges: &[],
                triangles: None,
                scalars,
            };
            logger.log_frame(&frame).expect("log_frame");
            let g = &logger.scalar_groups[logger.group_index["gauges"]];
            match f {
                0 => assert_eq!(g.names, ["eta_1.0"]),
                1 => {
                    assert_eq!(g.names, ["eta_1.0", "eta_2.0"]);
                    assert!(g.values[0].is_nan() && g.values[1] == 0.02);
                }
                _ => assert_eq!(g.values, [0.03, 0.04]),
            }
        }
        let d = &logger.scalar_groups[logger.group_index["diagnostics"]];
        assert_eq!(d.path, EntityPath::from("scalars/diagnostics"));
        assert_eq!(d.names, ["volume_m2"]);
        assert!(!d.touched, "diagnostics logged on a frame without them");
        for bad in ["gauges/", "/eta"] {
            let frame = FrameView {
                t_s: 0.5,
                positions: &pos,
                velocities: &vel,
                is_fluid: &fluid,
                boundary_edges: &[],
                triangles: None,
                scalars: &[(bad, 1.0)],
            };
            assert!(logger.log_frame(&frame).is_err(), "{bad:?} accepted");
        }
        logger.flush();
        drop(logger);
        let s = summarize(&read_rrd(&path));
        // The gauges: three frames, plus the static names logged twice (each time a name came).
        assert_eq!(s.rows.get("/scalars/gauges"), Some(&5), "{:?}", s.rows);
        // The diagnostics: two frames and their names once.
        assert_eq!(s.rows.get("/scalars/diagnostics"), Some(&3), "{:?}", s.rows);
        let _ = std::fs::remove_file(&path);
    }

    #[test]
    fn dropped_without_flush_is_decodable() {
        let path = temp_rrd("dropped");
        let mut logger = test_logger(&path);
        write_small_run(&mut logger);
        drop(logger);

        let s = summarize(&read_rrd(&path));
        assert_eq!(
            s.rows.get("/world/particles").copied(),
            Some(3),
            "{:?}",
            s.rows
        );
        std::fs::remove_file(&path).ok();
    }

    #[test]
    fn open_file_is_readable_as_after_a_crash() {
        // A killed process leaves a file without the end-of-stream marker and
        // footer; what was flushed before must still decode.
        let path = temp_rrd("open");
        let mut logger = test_logger(&path);
        write_small_run(&mut logger);
        logger.flush();
        let s = summarize(&read_rrd(&path));
        assert_eq!(
            s.rows.get("/world/particles").copied(),
            Some(3),
            "{:?}",
            s.rows
        );
        drop(logger);
        std::fs::remove_file(&path).ok();
    }

    #[test]
    fn bad_frames_are_rejected_and_the_logger_stays_usable() {
        let path = temp_rrd("bad");
        let mut logger = test_logger(&path);
        let (pos, vel, fluid) = small_state(0.0);
        let good = FrameView {
            t_s: 0.0,
            positions: &pos,
            velocities: &vel,
            is_fluid: &fluid,
            boundary_edges: &[[0, 1]],
            triangles: None,
            scalars: &[],
        };
        let short = FrameView {
            velocities: &vel[1..],
            ..good
        };
        assert!(matches!(
            logger.log_frame(&short),
            Err(RrdError::InvalidInput(_))
        ));
        let bad_edge = FrameView {
            boundary_edges: &[[0, 99]],
            ..good
        };
        assert!(matches!(
            logger.log_frame(&bad_edge),
            Err(RrdError::InvalidInput(_))
        ));
        let tris = [[0u32, 1, 99]];
        let bad_tri = FrameView {
            triangles: Some(&tris),
            ..good
        };
        assert!(matches!(
            logger.log_frame(&bad_tri),
            Err(RrdError::InvalidInput(_))
        ));
        for t in [-1.0, f64::NAN, f64::INFINITY] {
            let bad_t = FrameView { t_s: t, ..good };
            assert!(matches!(
                logger.log_frame(&bad_t),
                Err(RrdError::InvalidInput(_))
            ));
        }
        assert!(logger.log_text(-0.5, "events", "x").is_err());
        let neg_zero = FrameView { t_s: -0.0, ..good };
        logger.log_frame(&neg_zero).expect("-0.0 is a valid time");
        logger.log_frame(&good).expect("good frame");
        let unused = temp_rrd("bad_radius");
        let r = RrdLogger::create(&unused, "x", &OUTLINE, ColorScale::new(0.0, 1.0), 0.0);
        assert!(matches!(r, Err(RrdError::InvalidInput(_))));
        assert!(
            !unused.exists(),
            "the sink must not be opened for a bad radius"
        );
        let msg = RrdError::InvalidInput("abc".into()).to_string();
        assert!(msg.contains("abc"));
        drop(logger);
        std::fs::remove_file(&path).ok();
    }

    /// Prints the .rrd size per frame for 5000 particles (run with
    /// `cargo test --release rrd_size -- --nocapture`).
    #[test]
    fn rrd_size_per_frame_5000_particles() {
        let (nx, ny) = (100u32, 50u32);
        let h = 0.01;
        let mut pos = Vec::new();
        let mut vel = Vec::new();
        let mut fluid = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = (f64::from(i) * h, f64::from(j) * h);
                pos.push(Vector2::new(x, y));
                vel.push(Vector2::new((7.0 * x).sin(), (3.0 * y).cos()));
                fluid.push(true);
            }
        }
        let n_fluid = pos.len();
        for k in 0..300 {
            pos.push(Vector2::new(f64::from(k) * h / 3.0, -h));
            vel.push(Vector2::zeros());
            fluid.push(false);
        }
        let id = |i: u32, j: u32| j * nx + i;
        let mut edges = Vec::new();
        for i in 0..nx - 1 {
            edges.push([id(i, ny - 1), id(i + 1, ny - 1)]);
        }
        let mut tris = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let scalars = [
            ("volume_m2", 0.5),
            ("timing_ms/remesh", 1.0),
            ("timing_ms/solve", 2.0),
        ];

        let size = |p: &Path| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0);
        let mut report = Vec::new();
        for with_mesh in [false, true] {
            let path = temp_rrd(if with_mesh { "size_mesh" } else { "size" });
            let mut logger = RrdLogger::create(
                &path,
                "surflab_size",
                &OUTLINE,
                ColorScale::new(-1.0, 1.0),
                0.005,
            )
            .expect("create");
            logger.flush();
            let base = size(&path);
            let frames: u32 = 10;
            let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
            let mut jitter = move || {
                // xorshift64*: cheap noise in [-0.5, 0.5) so that the data
                // does not compress better than a real particle cloud would.
                seed ^= seed >> 12;
                seed ^= seed << 25;
                seed ^= seed >> 27;
                (seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            };
            let mut p_f = pos.clone();
            let mut v_f = vel.clone();
            let total_start = std::time::Instant::now();
            let mut log_time = std::time::Duration::ZERO;
            for f in 0..frames {
                for i in 0..n_fluid {
                    p_f[i] = pos[i] + Vector2::new(0.3 * h * jitter(), 0.3 * h * jitter());
                    v_f[i] = vel[i] + Vector2::new(0.2 * jitter(), 0.2 * jitter());
                }
                let frame = FrameView {
                    t_s: 0.01 * f64::from(f),
                    positions: &p_f,
                    velocities: &v_f,
                    is_fluid: &fluid,
                    boundary_edges: &edges,
                    triangles: with_mesh.then_some(&tris[..]),
                    scalars: &scalars,
                };
                let t0 = std::time::Instant::now();
                logger.log_frame(&frame).expect("log_frame");
                log_time += t0.elapsed();
            }
            logger.flush();
            let elapsed = total_start.elapsed();
            let per_frame = (size(&path) - base) / u64::from(frames);
            drop(logger);
            let s = summarize(&read_rrd(&path));
            assert_eq!(
                s.rows.get("/world/particles").copied(),
                Some(frames as usize)
            );
            report.push(format!(
                "{} fluid + 300 wall nodes, {} boundary edges, mesh: {}: {} bytes/frame; \
                 log_frame {:.2} ms/frame, with noise generation and final flush {:.2} ms/frame",
                n_fluid,
                edges.len(),
                if with_mesh {
                    format!("{} triangles", tris.len())
                } else {
                    "no".into()
                },
                per_frame,
                log_time.as_secs_f64() * 1e3 / f64::from(frames),
                elapsed.as_secs_f64() * 1e3 / f64::from(frames)
            ));
            std::fs::remove_file(&path).ok();
        }
        for line in report {
            println!("rrd size: {line}");
        }
    }
}
