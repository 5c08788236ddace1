//! `surflab view`: a recording made by `surflab run` opens in the embedded viewer, alone and
//! merged with a second run on one timeline. The real window runs (under Xvfb when there is no
//! display), waits for the data, saves a PNG and exits; the PNG must not be blank and the
//! viewer must report the run's entities (under each run's name when merged).
#![cfg(feature = "lab")]

mod common;

use common::screenshot_contrast as contrast;
use std::path::PathBuf;
use std::process::Command;

const TANK: &str = "[flume]\nlength_m = 1.0\nheight_m = 0.7\n[[water]]\nx_end_m = 0.5\n\
depth_m = 0.4\n[particles]\nspacing_m = 0.04\n[time]\nend_s = 0.2\n";

fn surflab(args: &[&str], window: bool) -> (bool, String) {
    let exe = env!("CARGO_BIN_EXE_surflab");
    let has_display = std::env::var_os("DISPLAY").is_some_and(|d| !d.is_empty());
    let mut cmd = if window && !has_display {
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "-s", "-screen 0 1600x1000x24", exe]);
        c
    } else {
        Command::new(exe)
    };
    let out = cmd
        .args(args)
        .output()
        .expect("run surflab (without a display this needs xvfb-run: bash .ci/setup)");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    println!("surflab {} → {}\n{stderr}", args.join(" "), out.status);
    (out.status.success(), stderr)
}

#[test]
fn a_run_recording_opens_alone_and_merged_with_another() {
    let dir = std::env::temp_dir().join(format!("surflab-view-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join("tank.toml");
    std::fs::write(&case, TANK).unwrap();
    let mut recordings: Vec<PathBuf> = Vec::new();
    for (name, alpha) in [("alpha12", "1.2"), ("alpha14", "1.4")] {
        let out = dir.join(name);
        let (ok, stderr) = surflab(
            &[
                "run",
                case.to_str().unwrap(),
                "--quiet",
                "--set",
                &format!("solver.alpha={alpha}"),
                "--out",
                out.to_str().unwrap(),
            ],
            false,
        );
        assert!(ok, "the run failed: {stderr}");
        recordings.push(out.join("run.rrd"));
    }

    let shot = dir.join("one.png");
    let (ok, stderr) = surflab(
        &[
            "view",
            recordings[0].to_str().unwrap(),
            "--screenshot",
            shot.to_str().unwrap(),
        ],
        true,
    );
    assert!(ok, "view failed: {stderr}");
    assert!(stderr.contains("viewing 1 recording"), "{stderr}");
    assert!(
        stderr.contains("/world/particles"),
        "no particle entity: {stderr}"
    );
    let (colors, std) = contrast(&shot);
    println!("one recording: {colors} colours, luminance std {std:.1}");
    assert!(colors >= 50 && std >= 5.0, "blank window");

    let shot = dir.join("two.png");
    let (ok, stderr) = surflab(
        &[
            "view",
            recordings[0].to_str().unwrap(),
            recordings[1].to_str().unwrap(),
            "--screenshot",
            shot.to_str().unwrap(),
        ],
        true,
    );
    assert!(ok, "view failed: {stderr}");
    assert!(
        stderr.contains("merged on one timeline under alpha12, alpha14"),
        "{stderr}"
    );
    for run in ["/alpha12/world/particles", "/alpha14/world/particles"] {
        assert!(stderr.contains(run), "no {run}: {stderr}");
    }
    let (colors, std) = contrast(&shot);
    println!("two recordings: {colors} colours, luminance std {std:.1}");
    assert!(colors >= 50 && std >= 5.0, "blank window");

    // A file that is not a recording is refused with its name, before any window opens.
    let bad = dir.join("not.rrd");
    std::fs::write(&bad, "not a recording").unwrap();
    let (ok, stderr) = surflab(&["view", bad.to_str().unwrap()], false);
    assert!(!ok && stderr.contains("not.rrd"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}
