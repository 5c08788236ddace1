//! The sweep's rows: one per point, read back from its run directory (`summary.json`, and
//! `gauges.csv` for the reflection coefficient), and written as `sweep.csv`.

use super::reflection::reflection;
use super::spec::Point;
use crate::case::Case;
use crate::diagnostics::breaking::SWEEP_FILM_M;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::Path;

/// The file a run that could not start leaves in its directory: the reason, one line.
pub const ERROR_FILE: &str = "error.txt";

/// Status of a point whose run directory holds neither a summary nor an error.
pub const NOT_RUN: &str = "not run";

/// What one point of the sweep gave. Units in the names; numbers are `None` where the run has
/// none (no breaking, no summary, gauges that do not allow a reflection coefficient).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The point's index in product order.
    pub index: usize,
    /// Its run directory, relative to the sweep's.
    pub dir: String,
    /// `key=value` of each varied field.
    pub set: Vec<String>,
    /// `ok`, why the run stopped (from `summary.json`), `error: ...` when it could not start, or
    /// `not run`.
    pub status: String,
    /// I_r = ξ₀ = tan β / sqrt(H₀/L₀) of the case's wave.
    pub iribarren: Option<f64>,
    /// ξ_b = tan β / sqrt(H_b/L₀) with the height the waves broke at.
    pub iribarren_b: Option<f64>,
    /// The thesis table's type for I_r.
    pub predicted: Option<String>,
    /// The type the surface showed (`none` when nothing broke or ran up).
    pub observed: Option<String>,
    pub x_b_m: Option<f64>,
    pub h_b_m: Option<f64>,
    #[serde(rename = "H_b_m")]
    pub height_b_m: Option<f64>,
    pub run_up_m: Option<f64>,
    /// The run-up read where the water on the bed is `SWEEP_FILM_M` (2 cm) deep
    /// (`breaking.run_up_films`).
    pub run_up_2cm_film_m: Option<f64>,
    /// |reflected| / |incident| first harmonic from two gauges (see `reflection.rs`).
    pub reflection_coefficient: Option<f64>,
    /// The two gauges it was computed from, m.
    pub reflection_gauges_x_m: Option<[f64; 2]>,
    /// Why there is no reflection coefficient.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reflection_note: Option<String>,
    pub volume_drift_max: Option<f64>,
    pub particles: Option<u64>,
    pub median_ms_per_step: Option<f64>,
    pub wall_s: Option<f64>,
}

impl Row {
    fn empty(point: &Point, status: String) -> Row {
        Row {
            index: point.index,
            dir: point.dir_name.clone(),
            set: point.overrides.clone(),
            status,
            iribarren: None,
            iribarren_b: None,
            predicted: None,
            observed: None,
            x_b_m: None,
            h_b_m: None,
            height_b_m: None,
            run_up_m: None,
            run_up_2cm_film_m: None,
            reflection_coefficient: None,
            reflection_gauges_x_m: None,
            reflection_note: None,
            volume_drift_max: None,
            particles: None,
            median_ms_per_step: None,
            wall_s: None,
        }
    }

    /// Whether the run finished with status `ok`.
    pub fn ok(&self) -> bool {
        self.status == "ok"
    }

    /// Whether the point has a finished run (a summary, whatever its status): a resumed sweep
    /// does not run it again.
    pub fn finished(&self) -> bool {
        self.status != NOT_RUN && !self.status.starts_with("error: ")
    }
}

/// The row of `point` from its directory `run_dir`.
pub fn read_row(point: &Point, run_dir: &Path) -> Row {
    let summary = run_dir.join("summary.json");
    match std::fs::read_to_string(&summary) {
        Ok(text) => match serde_json::from_str::<Value>(&text) {
            Ok(json) => row_from_summary(point, &json, run_dir),
            Err(e) => Row::empty(
                point,
                format!("error: {}: not JSON: {e}", summary.display()),
            ),
        },
        Err(_) => match std::fs::read_to_string(run_dir.join(ERROR_FILE)) {
            Ok(text) => Row::empty(point, format!("error: {}", text.trim())),
            Err(_) => Row::empty(point, NOT_RUN.to_owned()),
        },
    }
}

/// The row from a parsed `summary.json` (keys as `output/summary.rs` writes them).
pub fn row_from_summary(point: &Point, json: &Value, run_dir: &Path) -> Row {
    let number = |path: &str| -> Option<f64> {
        path.split('.')
            .try_fold(json, |v, key| v.get(key))
            .and_then(Value::as_f64)
            .filter(|v| v.is_finite())
    };
    let text = |path: &str| -> Option<String> {
        path.split('.')
            .try_fold(json, |v, key| v.get(key))
            .and_then(Value::as_str)
            .map(str::to_owned)
    };
    let mut row = Row::empty(
        point,
        text("status").unwrap_or_else(|| "error: summary.json has no status".into()),
    );
    row.iribarren = number("breaking.iribarren");
    row.iribarren_b = number("breaking.iribarren_b");
    row.predicted = text("breaking.predicted");
    row.observed = text("breaking.observed");
    row.x_b_m = number("breaking.x_b_m");
    row.h_b_m = number("breaking.h_b_m");
    row.height_b_m = number("breaking.H_b_m");
    row.run_up_m = number("breaking.run_up_m");
    row.run_up_2cm_film_m = json
        .pointer("/breaking/run_up_films")
        .and_then(Value::as_array)
        .and_then(|films| {
            films
                .iter()
                .find(|f| f.get("film_m").and_then(Value::as_f64) == Some(SWEEP_FILM_M))
        })
        .and_then(|f| f.get("run_up_m").and_then(Value::as_f64));
    row.volume_drift_max = number("volume_drift_max");
    row.particles = json.get("particles").and_then(Value::as_u64);
    row.median_ms_per_step = number("median_ms_per_step");
    row.wall_s = number("wall_s");
    match reflection_of(json, run_dir) {
        Ok(r) => {
            row.reflection_coefficient = Some(r.coefficient);
            row.reflection_gauges_x_m = Some(r.gauges_x_m);
        }
        Err(note) => row.reflection_note = Some(note),
    }
    row
}

fn reflection_of(json: &Value, run_dir: &Path) -> Result<super::reflection::Reflection, String> {
    let case: Case = json
        .get("parameters")
        .cloned()
        .ok_or("summary.json has no parameters")
        .and_then(|p| {
            serde_json::from_value(p).map_err(|_| "summary.json: unreadable parameters")
        })?;
    if case.wavemaker.is_none() {
        return Err("the case has no wavemaker".into());
    }
    let gauges = run_dir.join("gauges.csv");
    if !gauges.exists() {
        return Err("no gauges.csv".into());
    }
    let record = crate::output::timeseries::read_gauges(&gauges).map_err(|e| e.to_string())?;
    reflection(&case, &record)
}

/// The fixed columns of `sweep.csv` after the varied fields, with their units.
pub const COLUMNS: [(&str, &str); 16] = [
    (
        "status",
        "ok, why the run stopped, error: ... (could not start) or not run",
    ),
    ("iribarren", "ξ₀ = tan β / sqrt(H₀/L₀), dimensionless"),
    ("iribarren_b", "ξ_b = tan β / sqrt(H_b/L₀), dimensionless"),
    ("predicted", "the thesis table's type for ξ₀"),
    (
        "observed",
        "spilling, plunging, collapsing, surging or none",
    ),
    ("x_b_m", "breaking point, flume x, m"),
    ("h_b_m", "still depth at the breaking point, m"),
    ("H_b_m", "wave height at breaking, m"),
    (
        "run_up_m",
        "run-up: the shoreline tip's highest elevation above still water over the waves, m",
    ),
    (
        "run_up_2cm_film_m",
        "the same read at the edge of the water on the bed 2 cm deep, m",
    ),
    (
        "reflection_coefficient",
        "K_r = |reflected| / |incident|, dimensionless",
    ),
    ("volume_drift_max", "max |V/V₀ − 1|, dimensionless"),
    ("particles", "particles at the end, count"),
    ("median_ms_per_step", "ms of wall time per step, median"),
    ("wall_s", "wall time of the run, s"),
    ("dir", "the run directory, relative to the sweep's"),
];

/// `sweep.csv`: a header (the varied keys, then [`COLUMNS`]) and one line per row.
pub fn csv(keys: &[String], rows: &[Row]) -> String {
    let mut out = String::new();
    let header: Vec<String> = keys
        .iter()
        .map(|k| cell(k))
        .chain(COLUMNS.iter().map(|(c, _)| (*c).to_owned()))
        .collect();
    out.push_str(&header.join(","));
    out.push('\n');
    let num = |v: Option<f64>| v.map_or(String::new(), significant);
    for r in rows {
        let values = r
            .set
            .iter()
            .map(|s| s.split_once('=').map_or(s.as_str(), |(_, v)| v))
            .map(cell);
        let text = |v: &Option<String>| cell(v.as_deref().unwrap_or(""));
        let fields: Vec<String> = values
            .chain([
                cell(&r.status),
                num(r.iribarren),
                num(r.iribarren_b),
                text(&r.predicted),
                text(&r.observed),
                num(r.x_b_m),
                num(r.h_b_m),
                num(r.height_b_m),
                num(r.run_up_m),
                num(r.run_up_2cm_film_m),
                num(r.reflection_coefficient),
                num(r.volume_drift_max),
                r.particles.map_or(String::new(), |n| n.to_string()),
                num(r.median_ms_per_step),
                num(r.wall_s),
                cell(&r.dir),
            ])
            .collect();
        out.push_str(&fields.join(","));
        out.push('\n');
    }
    out
}

/// `v` rounded to six significant digits, in its shortest form (3.14404, 0.000012345, 239).
fn significant(v: f64) -> String {
    let rounded: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    format!("{rounded}")
}

/// A CSV cell: quoted (quotes doubled) when it holds a comma, a quote or a line break.
fn cell(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// The rows as a markdown table (for the recording's text view).
pub fn markdown(case_name: &str, keys: &[String], rows: &[Row]) -> String {
    let fmt =
        |v: Option<f64>, digits: usize| v.map_or("–".to_owned(), |v| format!("{v:.digits$}"));
    let mut out = format!(
        "# Sweep of {case_name}: {} points\n\nξ₀ and ξ_b dimensionless; x_b, h_b, H_b, run-up in m; \
         K_r the reflection coefficient; wall in s.\n\n",
        rows.len()
    );
    let mut header: Vec<String> = keys.to_vec();
    header.extend(
        [
            "status",
            "ξ₀",
            "ξ_b",
            "predicted",
            "observed",
            "x_b",
            "h_b",
            "H_b",
            "run-up",
            "K_r",
            "wall",
        ]
        .map(str::to_owned),
    );
    out += &format!("| {} |\n", header.join(" | "));
    out += &format!("|{}\n", "---|".repeat(header.len()));
    for r in rows {
        let mut cells: Vec<String> = r
            .set
            .iter()
            .map(|s| s.split_once('=').map_or(s.clone(), |(_, v)| v.to_owned()))
            .collect();
        cells.extend([
            r.status.clone(),
            fmt(r.iribarren, 2),
            fmt(r.iribarren_b, 2),
            r.predicted.clone().unwrap_or_else(|| "–".into()),
            r.observed.clone().unwrap_or_else(|| "–".into()),
            fmt(r.x_b_m, 2),
            fmt(r.h_b_m, 3),
            fmt(r.height_b_m, 3),
            fmt(r.run_up_m, 3),
            fmt(r.reflection_coefficient, 2),
            fmt(r.wall_s, 1),
        ]);
        let cells: Vec<String> = cells.iter().map(|c| c.replace('|', "\\|")).collect();
        out += &format!("| {} |\n", cells.join(" | "));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point() -> Point {
        Point {
            index: 2,
            overrides: vec!["wavemaker.period_s=2.5".into(), "solver.tau=\"a,b\"".into()],
            values: vec!["2.5".into(), "\"a,b\"".into()],
            dir_name: "wavemaker.period_s=2.5,solver.tau=a_b".into(),
        }
    }

    #[test]
    fn a_summary_gives_its_row_and_csv_line() {
        let json: Value = serde_json::json!({
            "status": "stopped at t = 1.2 s (step 40): diverged, badly",
            "particles": 1234,
            "wall_s": 12.500000004,
            "median_ms_per_step": 3.25,
            "volume_drift_max": 0.004,
            "breaking": {
                "iribarren": 1.94, "iribarren_b": 1.8, "predicted": "collapsing",
                "observed": "plunging", "x_b_m": 7.6, "h_b_m": 0.2, "H_b_m": 0.15,
                "run_up_m": 0.21,
                "run_up_films": [{"film_m": 0.01, "run_up_m": 0.2, "run_ups_m": [0.2]},
                                 {"film_m": 0.02, "run_up_m": 0.19, "run_ups_m": [0.19]}]
            }
        });
        let row = row_from_summary(&point(), &json, Path::new("/nonexistent"));
        assert_eq!(row.iribarren, Some(1.94));
        assert_eq!(row.height_b_m, Some(0.15));
        assert_eq!(row.observed.as_deref(), Some("plunging"));
        assert_eq!(row.particles, Some(1234));
        assert_eq!(row.run_up_2cm_film_m, Some(0.19));
        assert!(row.finished() && !row.ok());
        assert_eq!(row.reflection_coefficient, None);
        let keys = vec!["wavemaker.period_s".to_owned(), "solver.tau".to_owned()];
        let text = csv(&keys, &[row]);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("wavemaker.period_s,solver.tau,status,iribarren,"));
        assert_eq!(lines[0].split(',').count(), 2 + COLUMNS.len());
        assert_eq!(
            lines[1],
            "2.5,\"\"\"a,b\"\"\",\"stopped at t = 1.2 s (step 40): diverged, badly\",1.94,1.8,\
             collapsing,plunging,7.6,0.2,0.15,0.21,0.19,,0.004,1234,3.25,12.5,\
             \"wavemaker.period_s=2.5,solver.tau=a_b\""
        );
    }

    #[test]
    fn a_directory_without_a_summary_is_not_run_or_an_error() {
        let dir = std::env::temp_dir().join(format!("surflab-sweep-row-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let row = read_row(&point(), &dir);
        assert_eq!(row.status, NOT_RUN);
        assert!(!row.finished());
        std::fs::write(
            dir.join(ERROR_FILE),
            "solver.alpha must be greater than 1\n",
        )
        .unwrap();
        let row = read_row(&point(), &dir);
        assert_eq!(row.status, "error: solver.alpha must be greater than 1");
        assert!(!row.finished());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
