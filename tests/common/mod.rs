//! Helpers shared by the integration tests: loading cases, running them headless into a
//! temporary folder, and reading what the runs wrote.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use surflab::case::Case;
use surflab::output::run::{RunOptions, RunOutcome, run};

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn case(name: &str, overrides: &[&str]) -> Case {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Case::load(&root().join("cases").join(name), &o).expect("case loads")
}

/// A fresh, empty output folder for one test.
pub fn out_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("surflab-test-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

pub fn run_case(case: &Case, test: &str, rrd: bool) -> RunOutcome {
    run(
        case,
        &RunOptions {
            out_dir: out_dir(test),
            rrd,
            progress: false,
            one_core: false,
        },
    )
    .expect("run completes its files")
}

pub fn exists(path: &Path) -> bool {
    path.metadata().map(|m| m.len() > 0).unwrap_or(false)
}

/// Decodes a whole .rrd file and returns the number of messages in it.
pub fn rrd_messages(path: &Path) -> Result<usize, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let decoder = re_log_encoding::DecoderApp::decode_eager(std::io::BufReader::new(file))
        .map_err(|e| e.to_string())?;
    let mut count = 0;
    for msg in decoder {
        let _message = msg.map_err(|e| e.to_string())?;
        count += 1;
    }
    Ok(count)
}

/// What a run stopped by trouble must leave in `dir`: a `summary.json` whose status says where
/// it stopped, a `timeseries.csv` with at least the t = 0 row, and a readable `run.rrd`.
pub fn assert_stopped_and_kept(dir: &Path) {
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let status = summary["status"].as_str().unwrap();
    println!("status: {status}");
    assert!(status.starts_with("stopped at t = "), "{status}");
    let csv = std::fs::read_to_string(dir.join("timeseries.csv")).unwrap();
    assert!(csv.lines().count() >= 2, "header and the t = 0 row");
    let messages = rrd_messages(&dir.join("run.rrd")).expect("run.rrd decodes");
    println!("run.rrd: {messages} messages");
    assert!(messages > 0);
}

/// Distinct colours and the luminance standard deviation of a PNG screenshot: a blank or
/// single-colour window has a handful of colours and no contrast.
#[cfg(feature = "lab")]
pub fn screenshot_contrast(path: &Path) -> (usize, f64) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    let mut colors = std::collections::HashSet::new();
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for p in img.pixels() {
        colors.insert(p.0);
        let l = 0.299 * p.0[0] as f64 + 0.587 * p.0[1] as f64 + 0.114 * p.0[2] as f64;
        sum += l;
        sum2 += l * l;
    }
    let n = f64::from(img.width() * img.height());
    (colors.len(), (sum2 / n - (sum / n).powi(2)).max(0.0).sqrt())
}

/// An oscillating record (t, η): its mean period from the downward zero crossings, and the
/// growth rate σ of its amplitude, a(t) = a₀ e^(σ t), fitted by least squares on ln a, with a
/// the half range between successive crossings. `None` with fewer than four crossings.
pub struct Oscillation {
    pub period_s: f64,
    pub growth_per_s: f64,
    /// (mid time, amplitude) per period, s and m.
    pub amplitudes: Vec<(f64, f64)>,
}

pub fn fit_oscillation(record: &[(f64, f64)]) -> Option<Oscillation> {
    let crossings: Vec<f64> = record
        .windows(2)
        .filter(|w| w[0].1 > 0.0 && w[1].1 <= 0.0)
        .map(|w| w[0].0 + w[0].1 / (w[0].1 - w[1].1) * (w[1].0 - w[0].0))
        .collect();
    if crossings.len() < 4 {
        return None;
    }
    let n = crossings.len() - 1;
    let period_s = (crossings[n] - crossings[0]) / n as f64;
    let amplitudes: Vec<(f64, f64)> = crossings
        .windows(2)
        .map(|w| {
            let (lo, hi) = record
                .iter()
                .filter(|(t, _)| (w[0]..w[1]).contains(t))
                .fold((f64::MAX, f64::MIN), |(lo, hi), &(_, e)| {
                    (lo.min(e), hi.max(e))
                });
            (0.5 * (w[0] + w[1]), 0.5 * (hi - lo))
        })
        .collect();
    let m = amplitudes.len() as f64;
    let (st, sl) = amplitudes
        .iter()
        .fold((0.0, 0.0), |(a, b), &(t, y)| (a + t, b + y.ln()));
    let (tm, lm) = (st / m, sl / m);
    let (num, den) = amplitudes.iter().fold((0.0, 0.0), |(n, d), &(t, y)| {
        (n + (t - tm) * (y.ln() - lm), d + (t - tm) * (t - tm))
    });
    Some(Oscillation {
        period_s,
        growth_per_s: num / den,
        amplitudes,
    })
}
