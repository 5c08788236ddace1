//! `surflab sweep` end to end on a tiny still-water tank: two shards into one directory, each
//! point run exactly once, `--collect` rebuilding the table, a second call running nothing
//! (resume), the map and the recording written; the errors that stop a sweep before it
//! runs anything; and `surflab study` gathering a sweep's runs over α and δ.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::SystemTime;

const TANK: &str = "description = \"a still tank for the sweep test\"\n\
                    [flume]\nlength_m = 1.0\nheight_m = 0.7\n\
                    [[water]]\nx_start_m = 0.0\nx_end_m = 1.0\ndepth_m = 0.5\n\
                    [particles]\nspacing_m = 0.05\n\
                    [time]\nend_s = 1.0\n\
                    [output]\ninterval_s = 0.01\n";

const VARY: [&str; 4] = [
    "--vary",
    "solver.alpha=1.2,1.3",
    "--vary",
    "particles.spacing_m=0.05,0.04",
];

fn workspace(name: &str) -> (PathBuf, PathBuf) {
    let dir = std::env::temp_dir().join(format!("surflab-sweep-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let case = dir.join("tank.toml");
    std::fs::write(&case, TANK).unwrap();
    (dir, case)
}

fn surflab(args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_surflab"));
    c.args(args);
    c
}

fn finish(out: Output, what: &str) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    println!("--- {what}: exit {:?}\n{stderr}", out.status.code());
    assert!(out.status.success(), "{what} failed: {stderr}");
    stderr
}

/// The cells of a CSV line (quoted cells may hold commas; quotes doubled inside).
fn cells(line: &str) -> Vec<String> {
    let (mut out, mut cell, mut quoted) = (Vec::new(), String::new(), false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cell.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cell)),
            _ => cell.push(c),
        }
    }
    out.push(cell);
    out
}

/// The points a sweep's stderr reports as run: its `[k/n] <point>: <status>` lines.
fn points_run(stderr: &str) -> Vec<String> {
    stderr
        .lines()
        .filter_map(|l| l.strip_prefix("surflab sweep: ["))
        .filter_map(|l| {
            l.split_once("] ")?
                .1
                .split_once(": ")
                .map(|p| p.0.to_owned())
        })
        .collect()
}

fn summaries(out: &Path) -> BTreeMap<String, SystemTime> {
    std::fs::read_dir(out)
        .unwrap()
        .filter_map(|e| {
            let path = e.ok()?.path().join("summary.json");
            let modified = std::fs::metadata(&path).ok()?.modified().ok()?;
            Some((path.display().to_string(), modified))
        })
        .collect()
}

#[test]
fn two_shards_collect_and_resume() {
    let (dir, case) = workspace("shards");
    let out = dir.join("out");
    let (case, out_s) = (case.to_str().unwrap(), out.to_str().unwrap());
    let common = |shard: Option<&str>| {
        let mut c = surflab(&["sweep", case]);
        c.args(VARY).args(["--until", "0.05", "--out", out_s]);
        if let Some(s) = shard {
            c.args(["--shard", s]);
        }
        c.stdout(Stdio::piped()).stderr(Stdio::piped());
        c
    };
    // The two shards at once, as two tasks of a job array would run.
    let first = common(Some("0/2")).spawn().unwrap();
    let second = common(Some("1/2")).spawn().unwrap();
    let (first, second) = (
        first.wait_with_output().unwrap(),
        second.wait_with_output().unwrap(),
    );
    let mut run: Vec<String> = points_run(&finish(first, "shard 0/2"));
    let shard_one = points_run(&finish(second, "shard 1/2"));
    assert_eq!(run.len(), 2, "shard 0/2 runs points 0 and 2");
    assert_eq!(shard_one.len(), 2, "shard 1/2 runs points 1 and 3");
    run.extend(shard_one);
    run.sort();
    run.dedup();
    assert_eq!(run.len(), 4, "each point ran exactly once: {run:?}");
    let before = summaries(&out);
    assert_eq!(before.len(), 4);

    std::fs::remove_file(out.join("sweep.csv")).unwrap();
    finish(
        surflab(&["sweep", "--collect", out_s]).output().unwrap(),
        "collect",
    );
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    println!("sweep.csv:\n{csv}");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 5, "a header and 4 rows");
    assert!(lines[0].starts_with("solver.alpha,particles.spacing_m,status,iribarren,"));
    let columns = lines[0].split(',').count();
    for (row, expected) in
        lines[1..]
            .iter()
            .zip(["1.2,0.05,", "1.2,0.04,", "1.3,0.05,", "1.3,0.04,"])
    {
        assert!(row.starts_with(&format!("{expected}ok,")), "{row}");
        let row = cells(row);
        assert_eq!(row.len(), columns, "{row:?}");
        assert!(row[columns - 1].starts_with("solver.alpha="), "{row:?}");
        let particles: usize = row[columns - 4].parse().unwrap();
        assert!(particles > 100, "{row:?}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sweep.json")).unwrap()).unwrap();
    assert_eq!(json["points"].as_array().map(Vec::len), Some(4));
    assert_eq!(json["until_s"], 0.05);
    assert_eq!(json["vary"][1]["key"], "particles.spacing_m");

    // Again, without a shard: everything is finished, nothing runs.
    let stderr = finish(common(None).output().unwrap(), "resume");
    assert!(stderr.contains("4 finished before, 0 to run"), "{stderr}");
    assert!(points_run(&stderr).is_empty());
    assert_eq!(summaries(&out), before, "no summary.json was rewritten");

    for (file, min_bytes) in [
        ("breaker_map.png", 10_000),
        ("breaker_map.svg", 5_000),
        ("sweep.rrd", 1_000),
    ] {
        let bytes = std::fs::read(out.join(file)).unwrap();
        assert!(bytes.len() > min_bytes, "{file}: {} bytes", bytes.len());
    }
    let png = std::fs::read(out.join("breaker_map.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"));
    let svg = std::fs::read_to_string(out.join("breaker_map.svg")).unwrap();
    assert!(svg.contains("Breaker-type map: tank"));
}

#[test]
fn a_point_the_case_refuses_keeps_its_row() {
    let (dir, case) = workspace("refused");
    let out = dir.join("out");
    let stderr = finish(
        surflab(&[
            "sweep",
            case.to_str().unwrap(),
            "--vary",
            "solver.alpha=0.9,1.2",
            "--until",
            "0.02",
            "--no-rrd",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap(),
        "refused point",
    );
    assert!(stderr.contains("1 of 2 points ok, 1 failed"), "{stderr}");
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert!(
        rows[0].starts_with("0.9,error: ") || rows[0].starts_with("0.9,\"error: "),
        "{}",
        rows[0]
    );
    assert!(rows[0].contains("solver.alpha"), "{}", rows[0]);
    assert!(rows[1].starts_with("1.2,ok,"), "{}", rows[1]);
}

#[test]
fn bad_sweeps_stop_before_any_run() {
    let (dir, case) = workspace("bad");
    let case = case.to_str().unwrap();
    let out = dir.join("out");
    let out_s = out.to_str().unwrap();
    let missing = dir.join("missing.toml");
    let cases: [(&str, Vec<&str>, &[&str]); 6] = [
        (
            "bad key",
            vec!["sweep", case, "--vary", "solver.alpah=1.2,1.3"],
            &["solver.alpah", "not a field"],
        ),
        (
            "backwards range",
            vec!["sweep", case, "--vary", "wavemaker.period_s=4.0:1.0:0.5"],
            &["wavemaker.period_s", "below START"],
        ),
        (
            "zero step",
            vec!["sweep", case, "--vary", "solver.alpha=1.2:1.4:0"],
            &["solver.alpha", "step must be positive"],
        ),
        (
            "non-numeric range",
            vec!["sweep", case, "--vary", "solver.alpha=1.2:x:0.1"],
            &["solver.alpha", "`x` is not a number"],
        ),
        (
            "too many points",
            vec!["sweep", case, "--vary", "solver.alpha=1.1:3.1:0.001"],
            &["solver.alpha", "more than 1000"],
        ),
        (
            "unknown case",
            vec![
                "sweep",
                missing.to_str().unwrap(),
                "--vary",
                "solver.alpha=1.2",
            ],
            &["missing.toml"],
        ),
    ];
    for (what, args, needles) in cases {
        let output = surflab(&args).args(["--out", out_s]).output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        println!("{what}: exit {:?}: {}", output.status.code(), stderr.trim());
        let code = output.status.code().unwrap_or(-1);
        assert!(code != 0 && code != 101, "{what}: exit code {code}");
        for n in needles {
            assert!(stderr.contains(n), "{what}: message lacks `{n}`: {stderr}");
        }
        assert!(
            !out.exists(),
            "{what}: nothing is written before the checks pass"
        );
    }
}

/// `surflab study` on a sweep's folder: a row per run, the figure, and the refusals (no runs;
/// runs that differ in more than α and δ).
#[test]
fn a_study_of_alpha_and_delta() {
    let (dir, case) = workspace("study");
    let out = dir.join("out");
    let (case, out_s) = (case.to_str().unwrap(), out.to_str().unwrap());
    finish(
        surflab(&["sweep", case])
            .args([
                "--vary",
                "solver.alpha=1.2,1.4",
                "--vary",
                "solver.delta=0,0.03",
            ])
            .args(["--until", "0.05", "--no-rrd", "--out", out_s])
            .output()
            .unwrap(),
        "sweep",
    );
    let study = surflab(&["study", out_s]).output().unwrap();
    let stdout = String::from_utf8_lossy(&study.stdout).into_owned();
    finish(study, "study");
    println!("{stdout}");
    // The still tank has no wavemaker and no dam to validate: each run says why it has no check.
    assert_eq!(stdout.matches("no checks (").count(), 4, "{stdout}");
    let csv = std::fs::read_to_string(out.join("study.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 5, "{csv}");
    for (row, expected) in
        lines[1..]
            .iter()
            .zip(["1.2,0,ok,", "1.2,0.03,ok,", "1.4,0,ok,", "1.4,0.03,ok,"])
    {
        assert!(row.starts_with(expected), "{row}");
    }
    let md = std::fs::read_to_string(out.join("study.md")).unwrap();
    assert!(md.contains("| 1.4 | 0.03 |"), "{md}");
    let png = std::fs::read(out.join("study.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n") && png.len() > 10_000);
    let svg = std::fs::read_to_string(out.join("study.svg")).unwrap();
    assert!(svg.contains("δ = 0.03"), "a line per δ");

    // A folder without runs, and runs that differ in the spacing too, are refused.
    let empty = dir.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let refused = surflab(&["study", empty.to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && stderr.contains("no run directory"),
        "{stderr}"
    );
    let other = dir.join("other");
    finish(
        surflab(&["sweep", case])
            .args(["--vary", "particles.spacing_m=0.04"])
            .args([
                "--until",
                "0.05",
                "--no-rrd",
                "--out",
                other.to_str().unwrap(),
            ])
            .output()
            .unwrap(),
        "sweep of another spacing",
    );
    let refused = surflab(&["study", out_s, other.to_str().unwrap()])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert!(
        !refused.status.success() && stderr.contains("particles.spacing_m"),
        "{stderr}"
    );
}
