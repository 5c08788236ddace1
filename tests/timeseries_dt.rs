//! `timeseries.csv`'s `dt_s` is the Δt the policy set over the interval before the row, not
//! the shortened step that landed on the output time. (It was the last step's until
//! 2026-12-05: with the landing halved every interval, a 3D piston tank stepping at 2.85 ms
//! wrote 1.46 ms in every row, and docs/three_d.md quoted it.)

mod common;

use std::process::Command;

/// `surflab run CASE --quiet --no-rrd --out DIR --until T --set …`, then the `dt_s` column
/// after the first row, and the case's surface-wave bound (the step the policy sets when the
/// water is nearly at rest and `time.dt_max_s` is above it), s.
fn dt_column(case: &str, test: &str, until: &str, sets: &[&str]) -> (Vec<f64>, f64) {
    let dir = common::out_dir(test);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_surflab"));
    cmd.current_dir(common::root())
        .args([
            "run", case, "--quiet", "--no-rrd", "--until", until, "--out",
        ])
        .arg(&dir);
    for s in sets {
        cmd.args(["--set", s]);
    }
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|c| *c == "dt_s")
        .expect("a dt_s column");
    let dts: Vec<f64> = lines
        .skip(1)
        .map(|l| l.split(',').nth(col).unwrap().trim().parse().unwrap())
        .collect();
    let c = common::case(case.trim_start_matches("cases/"), sets);
    let bound = c
        .time
        .surface_wave_dt_s(c.particles.spacing_m, c.fluid.gravity_m_s2)
        .min(c.time.dt_max_s);
    (dts, bound)
}

/// Each `dt_s` within `tolerance` (relative) of the policy's step; a landing step is shorter
/// by a large fraction of it (45 % and 37 % in the two runs here).
fn assert_policy_step(dts: &[f64], bound: f64, tolerance: f64, what: &str) {
    println!("{what}: dt_s column {dts:?}, the policy's step {bound:.6e} s");
    assert!(!dts.is_empty());
    for dt in dts {
        assert!(
            (dt / bound - 1.0).abs() < tolerance,
            "{what}: {dt} s against {bound} s"
        );
    }
}

#[test]
fn the_2d_timeseries_writes_the_policys_step() {
    // h = 1 cm: the surface-wave bound 1.80 ms, five full steps and a landing in 0.01 s.
    let (dts, bound) = dt_column("cases/sloshing.toml", "dt_2d", "0.05", &[]);
    assert!(
        0.01 % bound > 1e-6,
        "the interval must not be a multiple of the step"
    );
    // The 2D file writes Δt to five significant digits.
    assert_policy_step(&dts, bound, 1e-4, "2D sloshing");
}

#[test]
fn the_3d_timeseries_writes_the_policys_step() {
    // h = 2 cm: the surface-wave bound 2.55 ms under a dt_max of 3 ms; 0.05 s is 19.6 steps.
    let sets = ["time.dt_max_s=0.003"];
    let (dts, bound) = dt_column("cases/tank3d_still.toml", "dt_3d", "0.1", &sets);
    assert!(
        0.05 % bound > 1e-6,
        "the interval must not be a multiple of the step"
    );
    assert_policy_step(&dts, bound, 1e-12, "3D still tank");
}
