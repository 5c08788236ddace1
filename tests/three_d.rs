//! The 3D path from a case file (issue 26): `surflab run` takes a case with `flume.width_m` to
//! the 3D solver and writes the same three files as a 2D run; trouble stops it with a status
//! and keeps them.

mod common;

use std::process::Command;

fn run(dir: &std::path::Path, extra: &[&str]) -> (Option<i32>, String) {
    run_case("cases/tank3d_still.toml", dir, extra)
}

/// `surflab run CASE --quiet --out DIR EXTRA…`: the exit code and stderr (printed).
fn run_case(case: &str, dir: &std::path::Path, extra: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_surflab"))
        .current_dir(common::root())
        .args(["run", case, "--quiet", "--out"])
        .arg(dir)
        .args(extra)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    println!("exit {:?}: {stderr}", out.status.code());
    (out.status.code(), stderr)
}

#[test]
fn a_3d_case_runs_and_records_its_three_files() {
    let dir = common::out_dir("three_d_run");
    let (code, stderr) = run(&dir, &["--until", "0.1"]);
    assert_eq!(code, Some(0));
    assert!(stderr.contains("3D"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "ok");
    assert_eq!(summary["parameters"]["flume"]["width_m"], 0.2);
    let drift = summary["volume_drift_max"].as_f64().unwrap();
    let particles = summary["particles"].as_u64().unwrap();
    let csv = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for column in [
        "t_s",
        "volume_m3",
        "volume_m2",
        "front_x_m",
        "max_speed_m_s",
    ] {
        assert!(
            header.split(',').any(|c| c == column),
            "{column} in {header}"
        );
    }
    // Rows at t = 0, 0.05 and 0.1 s.
    assert_eq!(csv.lines().count(), 4, "{csv}");
    let messages = common::rrd_messages(&dir.join("run.rrd")).expect("run.rrd decodes");
    println!("{particles} nodes, volume drift {drift:.1e}, run.rrd: {messages} messages");
    assert!(messages > 0);
    assert!(drift < 1e-6);
}

#[test]
fn trouble_stops_a_3d_run_and_keeps_what_was_recorded() {
    // A subnormal density makes Δt/ρ infinite: the first pressure is not finite.
    let dir = common::out_dir("three_d_nan");
    let (code, stderr) = run(
        &dir,
        &["--until", "0.05", "--set", "fluid.density_kg_m3=1e-310"],
    );
    assert_eq!(code, Some(1));
    assert!(stderr.contains("did not finish"), "{stderr}");
    common::assert_stopped_and_kept(&dir);
}

/// A 2D-only remedy asked of a 3D case is refused with its field, by `check` and by `run`,
/// before anything is written (the 3D step would silently ignore it).
#[test]
fn a_2d_only_setting_in_a_3d_case_is_refused_with_its_field() {
    let dir = common::out_dir("three_d_refused");
    let (code, stderr) = run(&dir, &["--set", "solver.geometry_theta=1"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("solver.geometry_theta"), "{stderr}");
    assert!(!dir.join("summary.json").exists());
    let out = Command::new(env!("CARGO_BIN_EXE_surflab"))
        .current_dir(common::root())
        .args([
            "check",
            "cases/tank3d_still.toml",
            "--set",
            "solver.midpoint_move=true",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("check: exit {:?}: {stderr}", out.status.code());
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("solver.midpoint_move"), "{stderr}");
}

/// Elevation gauges in a 3D case: `gauges.csv` with one column per gauge, read on the tank's
/// centre line, and η = 0 in still water; velocity probes are refused with their field.
#[test]
fn a_3d_case_records_its_elevation_gauges() {
    let dir = common::out_dir("three_d_gauges");
    let (code, stderr) = run(
        &dir,
        &[
            "--until",
            "0.1",
            "--set",
            "output.gauges_x_m=[0.05, 0.15, 0.25]",
        ],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let csv = std::fs::read_to_string(dir.join("gauges.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("t_s,eta_0.050,eta_0.150,eta_0.250"));
    let mut rows = 0;
    for line in lines {
        rows += 1;
        for cell in line.split(',').skip(1) {
            let eta: f64 = cell
                .parse()
                .unwrap_or_else(|_| panic!("a dry gauge: {line}"));
            assert!(eta.abs() < 1e-9, "{line}");
        }
    }
    assert_eq!(rows, 3, "{csv}");
    let dir = common::out_dir("three_d_probes");
    let (code, stderr) = run(&dir, &["--set", "output.probes_m=[[0.1, 0.05]]"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("output.probes_m"), "{stderr}");
}

/// Undertow stations in 3D (`surf.stations_x_m` at `stations_z_m`): the vertical line at each
/// station cuts the kept tetrahedra, and with the water all moving at U along the tank the
/// section holds U times the water's depth there, over a bar and beside it, at every bin
/// height; the surface is at the still level.
#[test]
fn a_3d_station_integrates_the_flow_from_the_bed_to_the_surface() {
    use surflab::diagnostics::undertow::{Station, StationFlow};
    let case = common::case(
        "tank3d_piston.toml",
        &[
            "output.planes_z_m=[]",
            "flume.bars=[{x_m = [0.8, 0.9, 1.1, 1.2], z_m = [-1.0, -0.5, 0.2, 0.3], height_m = 0.05}]",
            "surf.stations_x_m=[1.0, 2.0]",
            "surf.stations_z_m=[0.05, 0.05]",
        ],
    );
    let mut sim = surflab::simulation3d::Simulation3::new(&case).unwrap();
    let speed = 0.3;
    for u in &mut sim.flow.u {
        u.x = speed;
    }
    let dz = 0.0125;
    // Over the bar's crest (the bed 5 cm up) and on the flat bed.
    let stations: Vec<Station> = [(1.0, 0.05), (2.0, 0.0)]
        .map(|(x_m, bottom_m)| Station {
            x_m,
            z_m: 0.05,
            bottom_m,
            bins: 24,
        })
        .to_vec();
    let sections = sim.sections(&stations, dz);
    for (s, (flux, wet)) in stations.iter().zip(&sections) {
        let depth = 0.25 - s.bottom_m;
        let (f, w): (f64, f64) = (flux.iter().sum(), wet.iter().sum());
        println!(
            "station x = {} m over a bed at {} m: ∫u dy {f:.6} m²/s, wet {w:.6} m (depth {depth} m), \
             η {:?}",
            s.x_m,
            s.bottom_m,
            sim.elevation_m(s)
        );
        assert!((w - depth).abs() < 1e-9, "{w}");
        assert!((f - speed * depth).abs() < 1e-9, "{f}");
        for (b, (&fb, &wb)) in flux.iter().zip(wet).enumerate() {
            assert!((fb - speed * wb).abs() < 1e-12, "bin {b}");
        }
        assert!(sim.elevation_m(s).unwrap().abs() < 1e-9);
    }
    // A 2D case has no stations across a tank.
    let mut two_d =
        std::fs::read_to_string(common::root().join("cases/tank3d_still.toml")).unwrap();
    two_d = two_d.replace("width_m = 0.2", "");
    let err = surflab::case::Case::from_toml_str(
        &two_d,
        std::path::Path::new("t.toml"),
        "t",
        &["surf.stations_z_m=[0.1]".to_owned()],
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("surf.stations_z_m"), "{err}");
}

/// `surflab run` of a 3D piston case with stations writes their period averages into
/// `summary.json` and names them in its last line.
#[test]
fn a_3d_run_averages_its_undertow_stations_over_whole_periods() {
    let dir = common::out_dir("three_d_stations");
    let mut extra = vec!["--no-rrd"];
    // The tank at 2.5 cm and 4 h wide, as this test was written (the case now runs at 2 cm).
    for set in [
        "particles.spacing_m=0.025",
        "flume.width_m=0.1",
        "flume.length_m=1.2",
        "water.0.x_end_m=1.2",
        "wavemaker.period_s=0.4",
        "wavemaker.height_m=0.005",
        "wavemaker.ramp_periods=0.5",
        "time.end_s=0.45",
        "output.gauges_x_m=[]",
        "output.planes_z_m=[]",
        "surf.stations_x_m=[0.6, 0.9]",
        "surf.stations_z_m=[0.05, 0.05]",
        "surf.spin_up_periods=0",
    ] {
        extra.extend(["--set", set]);
    }
    let (code, stderr) = run_case("cases/tank3d_piston.toml", &dir, &extra);
    assert_eq!(code, Some(0), "{stderr}");
    assert!(stderr.contains("undertow over 1 periods"), "{stderr}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let u = &summary["undertow"];
    assert_eq!(u["periods"], 1);
    let stations = u["stations"].as_array().unwrap();
    assert_eq!(stations.len(), 2);
    for s in stations {
        assert_eq!(s["across_m"], 0.05);
        // Still water 0.25 m deep under the trough, a wave of 5 mm: the mean flow is small.
        let depth = s["depth_m"].as_f64().unwrap();
        let mean = s["undertow_mean_m_s"].as_f64().unwrap();
        assert!((depth - 0.25).abs() < 1e-12 && mean.abs() < 0.05, "{s}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
