//! Bad input: every malformed case must make `surflab run` exit non-zero with a message that
//! names the problem, and never panic (a panic exits with 101).

use std::process::Command;

const GOOD: &str = "[flume]\nlength_m = 1.0\nheight_m = 0.7\n[[water]]\nx_end_m = 1.0\ndepth_m = 0.5\n[particles]\nspacing_m = 0.05\n[time]\nend_s = 0.01\n";

fn run_with(name: &str, text: &str, extra: &[&str]) -> (i32, String) {
    let dir = std::env::temp_dir().join(format!("surflab-bad-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_surflab"))
        .arg("run")
        .arg(&path)
        .args([
            "--out",
            dir.join("out").to_str().unwrap(),
            "--no-rrd",
            "--quiet",
        ])
        .args(extra)
        .output()
        .expect("surflab runs");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code().unwrap_or(-1), stderr)
}

#[test]
fn each_bad_case_is_refused_with_its_reason() {
    let cases: [(&str, String, &[&str], &[&str]); 14] = [
        (
            "unknown_field",
            format!("{GOOD}[solver]\nalpah = 1.3\n"),
            &[],
            &["alpah", "unknown field"],
        ),
        (
            "not_toml",
            "this is { not toml".into(),
            &[],
            &["not valid TOML"],
        ),
        ("empty", String::new(), &[], &["empty"]),
        (
            "negative_depth",
            GOOD.replace("depth_m = 0.5", "depth_m = -0.5"),
            &[],
            &["water[0].depth_m", "positive"],
        ),
        (
            "alpha_one",
            format!("{GOOD}[solver]\nalpha = 1.0\n"),
            &[],
            &["solver.alpha", "greater than 1"],
        ),
        (
            "delta_negative",
            format!("{GOOD}[solver]\ndelta = -0.01\n"),
            &[],
            &["solver.delta", "[0, 1]"],
        ),
        (
            "delta_nan",
            format!("{GOOD}[solver]\ndelta = nan\n"),
            &[],
            &["solver.delta", "[0, 1]"],
        ),
        (
            "delta_large",
            GOOD.into(),
            &["--set", "solver.delta=1.5"],
            &["solver.delta", "[0, 1]"],
        ),
        (
            "water_outside",
            GOOD.replace("x_end_m = 1.0", "x_end_m = 1.5"),
            &[],
            &["outside the flume"],
        ),
        (
            "bad_override",
            GOOD.into(),
            &["--set", "solver.alpha=0.9"],
            &["solver.alpha"],
        ),
        (
            "refine_coarser",
            format!("{GOOD}[particles.refine]\nx_m = 0.6\nspacing_m = 0.05\n"),
            &[],
            &["particles.refine.spacing_m", "not finer"],
        ),
        (
            "refine_outside",
            format!("{GOOD}[particles.refine]\nx_m = 1.5\nspacing_m = 0.02\n"),
            &[],
            &["particles.refine.x_m", "inside the flume"],
        ),
        (
            "refine_unknown_field",
            format!("{GOOD}[particles.refine]\nx_m = 0.6\nspacing = 0.02\n"),
            &[],
            &["spacing", "unknown field"],
        ),
        (
            "refine_sharp",
            format!("{GOOD}[particles.refine]\nx_m = 0.6\nspacing_m = 0.03\ntransition_m = 0.01\n"),
            &[],
            &["particles.refine.transition_m", "two coarse spacings"],
        ),
    ];
    for (name, text, extra, needles) in cases {
        let (code, stderr) = run_with(name, &text, extra);
        println!("{name}: exit {code}: {}", stderr.trim());
        assert!(code != 0 && code != 101, "{name}: exit code {code}");
        assert!(!stderr.contains("panicked"), "{name} panicked: {stderr}");
        for n in needles {
            assert!(stderr.contains(n), "{name}: message lacks `{n}`: {stderr}");
        }
        assert!(
            stderr.contains(&format!("{name}.toml")),
            "{name}: message does not name the file"
        );
    }
}

#[test]
fn a_good_case_runs() {
    let (code, stderr) = run_with("good", GOOD, &[]);
    assert_eq!(code, 0, "{stderr}");
}
