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

/// The blueprint paths at which 2D views' bounds were logged.
fn visual_bounds_paths(msgs: &[LogMsg]) -> Vec<String> {
    msgs.iter()
        .filter(|m| m.store_id().kind() == StoreKind::Blueprint)
        .filter_map(|m| match m {
            LogMsg::ArrowMsg(_, arrow) => Some(Chunk::from_arrow_msg(arrow).expect("chunk")),
            _ => None,
        })
        .map(|c| c.entity_path().to_string())
        .filter(|p| p.ends_with("/VisualBounds2D"))
        .collect()
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
            polygons: &[],
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
            polygons: &[],
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
            polygons: &[],
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
        polygons: &[],
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
        polygons: &[],
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
                polygons: &[],
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

/// The breaker map, the run's point on it, the breaking mark on the flume, and the flume view
/// opened on a window: the entities are in the recording and the bounds in its blueprint.
#[test]
fn the_breaker_map_and_the_surf_zone_window_are_recorded() {
    let path = temp_rrd("breaker_map");
    let logger = RrdLogger::create(
        &path,
        "surflab-test",
        &OUTLINE,
        ColorScale::symmetric(1.0),
        0.01,
    )
    .expect("create");
    logger.add_breaker_map().expect("map");
    logger.open_on([1.0, 3.0, 0.0, 0.8]).expect("window");
    logger
        .log_breaker(0.5, 1.2, None, "plunging", None)
        .expect("before breaking");
    logger
        .log_breaker(1.0, 1.2, Some("plunging"), "plunging", Some([2.5, 0.6]))
        .expect("after breaking");
    logger.flush();
    drop(logger);
    let msgs = read_rrd(&path);
    let s = summarize(&msgs);
    for static_part in [
        "/breaker_map/bands",
        "/breaker_map/battjes",
        "/breaker_map/rows",
    ] {
        assert_eq!(
            s.rows.get(static_part),
            Some(&1),
            "{static_part}: {:?}",
            s.rows
        );
    }
    assert_eq!(s.rows.get("/breaker_map/run"), Some(&2), "{:?}", s.rows);
    // A clear before the first breaker (a new wave has no mark), then the mark.
    assert_eq!(s.rows.get("/world/breaker"), Some(&2), "{:?}", s.rows);
    let bounds = visual_bounds_paths(&msgs);
    println!("bounds logged at {bounds:?}");
    // Sent with the map's tab and again with the window: the second blueprint carries them.
    assert_eq!(bounds.len(), 1, "{bounds:?}");
    assert!(bounds[0].starts_with("/view/"), "{bounds:?}");
    let _ = std::fs::remove_file(&path);
}

/// An EDT polygon is drawn as its outline at `world/polygons`, and its inner diagonal is left
/// out of `world/mesh`; a frame without polygons clears the outlines.
#[test]
fn polygons_are_outlined_and_their_diagonals_left_out() {
    let path = temp_rrd("polygons");
    let mut logger = test_logger(&path);
    let edges = [[5u32, 6], [6, 7], [7, 8], [8, 9]];
    let tris = [[0u32, 1, 5], [1, 6, 5]];
    let quad = [crate::mesh::MeshPolygon {
        nodes: vec![0, 1, 6, 5],
        triangles: vec![0, 1],
    }];
    for f in 0..2 {
        let (pos, vel, fluid) = small_state(0.0);
        let frame = FrameView {
            t_s: 0.05 * f64::from(f),
            positions: &pos,
            velocities: &vel,
            is_fluid: &fluid,
            boundary_edges: &edges,
            triangles: Some(&tris[..]),
            polygons: if f == 0 { &quad[..] } else { &[] },
            scalars: &[],
        };
        logger.log_frame(&frame).expect("log_frame");
        if f == 0 {
            assert_eq!(logger.polygon_segs.len(), 4);
            assert_eq!(logger.mesh_segs.len(), 4, "the diagonal 1–5 was drawn");
        } else {
            assert_eq!(logger.mesh_segs.len(), 5);
        }
    }
    logger.flush();
    drop(logger);
    let s = summarize(&read_rrd(&path));
    // The outline on frame 0, then a clear (an empty list) on frame 1.
    assert_eq!(
        s.rows.get("/world/polygons").copied(),
        Some(2),
        "{:?}",
        s.rows
    );
    std::fs::remove_file(&path).ok();
}

/// The 3D recording's planes z = const: each plane's particles under a y-flip (physical y up in
/// a 2D view), and each plane's view opened on the whole side of the tank (its bounds in the
/// blueprint), as the 2D flume's view is.
#[test]
fn the_3d_planes_are_upright_and_opened_on_the_tank() {
    let case_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/tank3d_still.toml");
    let case = crate::case::Case::load(&case_path, &["output.planes_z_m=[0.05, 0.1]".into()])
        .expect("the still tank with two planes");
    let mut sim = crate::simulation3d::Simulation3::new(&case).expect("set up");
    let path = temp_rrd("planes3d");
    let mut rec = crate::output::rrd3d::Recorder3::create(&path, &case, &sim.flow).expect("create");
    let v0 = sim.initial_volume_m3;
    let row = crate::output::run3d::Row3::of(&mut sim);
    rec.log(&sim.flow, &row, v0).expect("frame");
    rec.flush();
    drop(rec);
    let msgs = read_rrd(&path);
    let s = summarize(&msgs);
    for z in ["0.050", "0.100"] {
        assert_eq!(
            // The entity path escapes the `=`.
            s.rows.get(&format!("/planes/z\\={z}")),
            Some(&1),
            "the flip of plane {z}: {:?}",
            s.rows
        );
        assert_eq!(
            s.rows.get(&format!("/planes/z\\={z}/particles")),
            Some(&1),
            "{:?}",
            s.rows
        );
        // The bed's profile in the plane, under the particles.
        assert_eq!(
            s.rows.get(&format!("/planes/z\\={z}/bed")),
            Some(&1),
            "{:?}",
            s.rows
        );
    }
    assert_eq!(s.rows.get("/world/bed"), Some(&1), "{:?}", s.rows);
    let bounds = visual_bounds_paths(&msgs);
    println!("3D planes: bounds logged at {bounds:?}");
    assert_eq!(bounds.len(), 2, "{bounds:?}");
    let _ = std::fs::remove_file(&path);
}
