//! `surflab study`: finished runs of one case that differ in the remeshing parameters α and δ
//! (issue 24's sensitivity study), gathered into one table and one figure. Each run is read
//! from its directory (`summary.json`, and `gauges.csv` or `timeseries.csv` for the check
//! `surflab validate` would make of it); each check is reported as the fraction of its bar it
//! uses (1 = on the bar), the worst over the checks of one kind (the seven wave heights of a
//! flap run are one kind). Writes `study.csv`, `study.md`, `study.svg` and `study.png`.
//! See docs/alpha_delta.md.

pub mod figure;

use crate::case::Case;
use crate::validation::{Check, CheckError, Report};
use std::path::{Path, PathBuf};

#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Unreadable { path: PathBuf, message: String },
    #[error("the run in {dir} did not finish ({status}); nothing to validate")]
    NotFinished { dir: PathBuf, status: String },
    #[error("validating {case}: {source}")]
    Check { case: String, source: CheckError },
    #[error(
        "no run directory (a folder holding summary.json) in {0}: give the folders of a sweep or of `surflab run --out`"
    )]
    NoRuns(String),
    #[error(
        "a study compares runs of one case; {first} is {first_case} but {other} is {other_case}"
    )]
    MixedCases {
        first: PathBuf,
        first_case: String,
        other: PathBuf,
        other_case: String,
    },
    #[error(
        "a study compares runs that differ only in α and δ; {first} and {other} differ in {key} as well"
    )]
    OtherDifference {
        first: PathBuf,
        other: PathBuf,
        key: String,
    },
    #[error("{first} and {other} are both α = {alpha}, δ = {delta}")]
    SamePoint {
        first: PathBuf,
        other: PathBuf,
        alpha: f64,
        delta: f64,
    },
    #[error("{path}: {message}")]
    Output { path: PathBuf, message: String },
}

/// The first key (dotted path) where two JSON values differ; keys that only one of them has
/// are passed over (the summary of an older build lacks the fields added since).
fn first_difference(a: &serde_json::Value, b: &serde_json::Value, path: &str) -> Option<String> {
    use serde_json::Value;
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            keys.into_iter().find_map(|k| {
                let (u, v) = (&x.get(k), &y.get(k));
                let here = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                // A key only one side has is a field newer than the other run's build.
                first_difference((*u)?, (*v)?, &here)
            })
        }
        _ if a == b => None,
        _ => Some(if path.is_empty() {
            "the parameters".to_owned()
        } else {
            path.to_owned()
        }),
    }
}

/// The run's parameters without the two a study varies.
fn fixed_parameters(run: &FinishedRun) -> serde_json::Value {
    let mut p = run.summary["parameters"].clone();
    if let Some(solver) = p.get_mut("solver").and_then(|s| s.as_object_mut()) {
        solver.remove("alpha");
        solver.remove("delta");
    }
    p
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> StudyError + '_ {
    move |source| StudyError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Where a 3D narrow tank's run keeps its 2D twin's run (`validation::against_2d`).
pub const TWIN_2D_DIR: &str = "2d";

/// Validates the outputs a run of `case` wrote in `dir`, as `surflab validate` does: a surf
/// case (a wavemaker and a beach) reads `summary.json` for Ting & Kirby's bars, a 3D narrow
/// tank with a linear piston its `gauges.csv` and its 2D twin's (in [`TWIN_2D_DIR`]), another
/// wavemaker's checks read `gauges.csv`, the dam break's (no wavemaker) `timeseries.csv`.
pub fn validate_outputs(
    dir: &Path,
    case: &Case,
    volume_drift_max: f64,
    simulated_s: f64,
    particles: Option<usize>,
) -> Result<Report, StudyError> {
    let check_error = |source| StudyError::Check {
        case: case.name.clone(),
        source,
    };
    if case.wavemaker.is_some() && case.flume.beach.is_some() {
        let file = dir.join("summary.json");
        let text = std::fs::read_to_string(&file).map_err(io_error(&file))?;
        let summary: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| StudyError::Unreadable {
                path: file.clone(),
                message: format!("not JSON: {e}"),
            })?;
        return crate::validation::ting_kirby(case, &summary).map_err(check_error);
    }
    if crate::validation::against_2d::applies(case) {
        let read =
            |file: PathBuf| crate::output::timeseries::read_gauges(&file).map_err(io_error(&file));
        let record_3d = read(dir.join("gauges.csv"))?;
        let record_2d = read(dir.join(TWIN_2D_DIR).join("gauges.csv"))?;
        return crate::validation::against_2d::against_2d(
            case,
            &record_3d,
            &record_2d,
            volume_drift_max,
        )
        .map_err(check_error);
    }
    let (record, series) = if case.wavemaker.is_some() {
        let file = dir.join("gauges.csv");
        let record = crate::output::timeseries::read_gauges(&file).map_err(io_error(&file))?;
        (record, None)
    } else {
        let file = dir.join("timeseries.csv");
        let mut series =
            crate::output::timeseries::read_dam_break_series(&file).map_err(io_error(&file))?;
        series.particles = particles;
        (Default::default(), Some(series))
    };
    crate::validation::check_case(
        case,
        &record,
        series.as_ref(),
        volume_drift_max,
        simulated_s,
    )
    .map_err(check_error)
}

/// A run directory's `summary.json`, and the case it was run with.
#[derive(Debug, Clone)]
pub struct FinishedRun {
    pub dir: PathBuf,
    pub summary: serde_json::Value,
    pub case: Case,
}

impl FinishedRun {
    pub fn read(dir: &Path) -> Result<Self, StudyError> {
        let file = dir.join("summary.json");
        let text = std::fs::read_to_string(&file).map_err(io_error(&file))?;
        let unreadable = |message: String| StudyError::Unreadable {
            path: file.clone(),
            message,
        };
        let summary: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| unreadable(format!("not JSON: {e}")))?;
        let case = Case::from_summary(summary["parameters"].clone())
            .map_err(|e| unreadable(format!("parameters: {e}")))?;
        Ok(Self {
            dir: dir.to_owned(),
            summary,
            case,
        })
    }

    pub fn status(&self) -> &str {
        self.summary["status"].as_str().unwrap_or("unknown")
    }

    fn number(&self, key: &str) -> Option<f64> {
        self.summary[key].as_f64()
    }

    /// The check `surflab validate --from DIR` makes.
    pub fn validate(&self) -> Result<Report, StudyError> {
        if self.status() != "ok" {
            return Err(StudyError::NotFinished {
                dir: self.dir.clone(),
                status: self.status().to_owned(),
            });
        }
        let number = |key: &str| {
            self.number(key).ok_or_else(|| StudyError::Unreadable {
                path: self.dir.join("summary.json"),
                message: format!("no number {key}"),
            })
        };
        validate_outputs(
            &self.dir,
            &self.case,
            number("volume_drift_max")?,
            number("simulated_s")?,
            self.summary["particles"].as_u64().map(|n| n as usize),
        )
    }
}

/// The fraction of its bar a check uses: |measured/target − 1| over the tolerance, or the
/// measured figure over its upper bound. At most 1 passes (below 1 for a strict bound).
/// A yes/no check (no tolerance) is 0 when it holds and infinite when it does not.
pub fn bar_fraction(check: &Check) -> f64 {
    match check.relative_tolerance {
        Some(0.0) => {
            if check.passed {
                0.0
            } else {
                f64::INFINITY
            }
        }
        Some(tol) => check.error().abs() / tol,
        None => check.measured / check.target,
    }
}

/// The kind a check belongs to: its description up to a colon or to " at x = ", so that the
/// heights at each gauge, or the worst of the u1 probes, are one kind.
pub fn check_kind(what: &str) -> &str {
    let what = what.split(':').next().unwrap_or(what);
    what.split(" at x = ").next().unwrap_or(what).trim()
}

/// One kind of check in one run: the worst fraction of the bar, and whether all passed.
#[derive(Debug, Clone, PartialEq)]
pub struct KindResult {
    pub kind: String,
    pub worst_fraction: f64,
    pub passed: bool,
    /// The bar as `surflab validate` prints it (of the worst check).
    pub bar: String,
}

/// The checks grouped by kind, in the order they come.
pub fn by_kind(checks: &[Check]) -> Vec<KindResult> {
    let mut kinds: Vec<KindResult> = Vec::new();
    for c in checks {
        let kind = check_kind(&c.what);
        let f = bar_fraction(c);
        let f = if f.is_finite() { f } else { f64::INFINITY };
        match kinds.iter_mut().find(|k| k.kind == kind) {
            Some(k) => {
                if f > k.worst_fraction {
                    k.worst_fraction = f;
                    k.bar = c.bar();
                }
                k.passed &= c.passed;
            }
            None => kinds.push(KindResult {
                kind: kind.to_owned(),
                worst_fraction: f,
                passed: c.passed,
                bar: c.bar(),
            }),
        }
    }
    kinds
}

/// One run of the study.
#[derive(Debug, Clone)]
pub struct StudyRun {
    /// The run's folder, as found.
    pub dir: PathBuf,
    pub case_name: String,
    pub alpha: f64,
    pub delta: f64,
    pub status: String,
    pub kinds: Vec<KindResult>,
    /// Why there are no checks (the case has none, or the run did not finish).
    pub note: Option<String>,
    pub volume_drift_max: Option<f64>,
    pub observed: Option<String>,
    /// The breaking point, in the data's frame where the case has one ([surf] x_origin_m), m.
    pub x_b_m: Option<f64>,
    /// The set-up at the case's set-up gauge, m.
    pub setup_m: Option<f64>,
    pub median_ms_per_step: Option<f64>,
    pub particles: Option<u64>,
}

impl StudyRun {
    pub fn from_run(run: &FinishedRun) -> StudyRun {
        let s = &run.summary;
        let (kinds, note) = match run.validate() {
            Ok(report) => (by_kind(&report.checks), None),
            Err(e) => (Vec::new(), Some(e.to_string())),
        };
        let breaking = &s["breaking"];
        StudyRun {
            dir: run.dir.clone(),
            case_name: run.case.name.clone(),
            alpha: run.case.solver.alpha,
            delta: run.case.solver.delta,
            status: run.status().to_owned(),
            kinds,
            note,
            volume_drift_max: run.number("volume_drift_max"),
            observed: breaking["observed"].as_str().map(str::to_owned),
            x_b_m: breaking["x_b_data_frame_m"]
                .as_f64()
                .or(breaking["x_b_m"].as_f64()),
            setup_m: s["surf"]["setup_m"].as_f64(),
            median_ms_per_step: run.number("median_ms_per_step"),
            particles: s["particles"].as_u64(),
        }
    }

    /// All checks passed (false when there were none).
    pub fn all_passed(&self) -> bool {
        !self.kinds.is_empty() && self.kinds.iter().all(|k| k.passed)
    }
}

/// The run directories in `dirs`: each one that holds a `summary.json`, and each of their
/// sub-folders that does (a sweep's points), sorted by path.
pub fn find_runs(dirs: &[PathBuf]) -> Result<Vec<PathBuf>, StudyError> {
    let mut found = Vec::new();
    for dir in dirs {
        if dir.join("summary.json").is_file() {
            found.push(dir.clone());
            continue;
        }
        let entries = std::fs::read_dir(dir).map_err(io_error(dir))?;
        for entry in entries {
            let path = entry.map_err(io_error(dir))?.path();
            if path.join("summary.json").is_file() {
                found.push(path);
            }
        }
    }
    found.sort();
    found.dedup();
    if found.is_empty() {
        let names: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
        return Err(StudyError::NoRuns(names.join(", ")));
    }
    Ok(found)
}

/// Reads and checks every run, sorted by (α, δ); refuses runs of different cases.
pub fn read_study(dirs: &[PathBuf]) -> Result<Vec<StudyRun>, StudyError> {
    let mut runs: Vec<StudyRun> = Vec::new();
    let mut fixed: Option<serde_json::Value> = None;
    for dir in find_runs(dirs)? {
        let finished = FinishedRun::read(&dir)?;
        let run = StudyRun::from_run(&finished);
        if let Some(first) = runs.first() {
            if first.case_name != run.case_name {
                return Err(StudyError::MixedCases {
                    first: first.dir.clone(),
                    first_case: first.case_name.clone(),
                    other: run.dir.clone(),
                    other_case: run.case_name.clone(),
                });
            }
            let params = fixed_parameters(&finished);
            if let Some(key) = fixed
                .as_ref()
                .and_then(|f| first_difference(f, &params, ""))
            {
                return Err(StudyError::OtherDifference {
                    first: first.dir.clone(),
                    other: run.dir.clone(),
                    key,
                });
            }
            if let Some(same) = runs
                .iter()
                .find(|r| r.alpha == run.alpha && r.delta == run.delta)
            {
                return Err(StudyError::SamePoint {
                    first: same.dir.clone(),
                    other: run.dir.clone(),
                    alpha: run.alpha,
                    delta: run.delta,
                });
            }
        } else {
            fixed = Some(fixed_parameters(&finished));
        }
        runs.push(run);
    }
    runs.sort_by(|a, b| {
        (a.alpha, a.delta)
            .partial_cmp(&(b.alpha, b.delta))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    Ok(runs)
}

/// The kinds of check over all runs, in the order they first come.
pub fn kinds(runs: &[StudyRun]) -> Vec<String> {
    let mut kinds: Vec<String> = Vec::new();
    for k in runs.iter().flat_map(|r| &r.kinds) {
        if !kinds.contains(&k.kind) {
            kinds.push(k.kind.clone());
        }
    }
    kinds
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or(String::new(), |v| format!("{v:.digits$}"))
}

/// `study.csv`: one row per run; a column per kind of check with the worst fraction of its bar.
pub fn csv(runs: &[StudyRun]) -> String {
    let kinds = kinds(runs);
    let mut out = String::from("alpha,delta,status");
    for k in &kinds {
        out.push_str(&format!(",\"{} (fraction of bar)\"", k.replace('"', "'")));
    }
    out.push_str(
        ",all_checks_passed,volume_drift_max,observed,x_b_m,setup_m,median_ms_per_step,particles,dir\n",
    );
    for r in runs {
        out.push_str(&format!("{},{},{}", r.alpha, r.delta, r.status));
        for k in &kinds {
            let f = r.kinds.iter().find(|x| &x.kind == k);
            out.push_str(&format!(",{}", opt(f.map(|f| f.worst_fraction), 4)));
        }
        out.push_str(&format!(
            ",{},{},{},{},{},{},{},\"{}\"\n",
            if r.kinds.is_empty() {
                String::new()
            } else {
                r.all_passed().to_string()
            },
            opt(r.volume_drift_max, 6),
            r.observed.as_deref().unwrap_or(""),
            opt(r.x_b_m, 4),
            opt(r.setup_m, 5),
            opt(r.median_ms_per_step, 2),
            r.particles.map_or(String::new(), |n| n.to_string()),
            r.dir.display()
        ));
    }
    out
}

/// `study.md`: the same table in Markdown, with each kind's bar in its header.
pub fn markdown(runs: &[StudyRun]) -> String {
    let kinds = kinds(runs);
    let bar_of = |kind: &str| {
        runs.iter()
            .flat_map(|r| &r.kinds)
            .find(|k| k.kind == kind)
            .map(|k| k.bar.clone())
            .unwrap_or_default()
    };
    let case = runs.first().map_or("", |r| r.case_name.as_str());
    let mut out = format!(
        "# α/δ study of `{case}`: {} runs\n\nEach check as the fraction of its bar it uses \
         (1 = on the bar; the worst over the checks of one kind).\n\n| α | δ |",
        runs.len()
    );
    // A `|` inside a cell would end it.
    let cell = |text: &str| text.replace('|', "\\|");
    for k in &kinds {
        out.push_str(&format!(" {} ({}) |", cell(k), cell(&bar_of(k))));
    }
    let surf = runs.iter().any(|r| r.observed.is_some());
    if surf {
        out.push_str(" observed type | x_b (m) | set-up (m) |");
    }
    out.push_str(" volume drift | ms/step | all checks |\n|---|---|");
    for _ in 0..kinds.len() + if surf { 3 } else { 0 } + 3 {
        out.push_str("---|");
    }
    out.push('\n');
    for r in runs {
        out.push_str(&format!("| {} | {} |", r.alpha, r.delta));
        for k in &kinds {
            match r.kinds.iter().find(|x| &x.kind == k) {
                Some(f) if f.worst_fraction.is_infinite() => out.push_str(" ✗ |"),
                Some(f) => out.push_str(&format!(
                    " {:.2}{} |",
                    f.worst_fraction,
                    if f.passed { "" } else { " ✗" }
                )),
                None => out.push_str(" – |"),
            }
        }
        if surf {
            out.push_str(&format!(
                " {} | {} | {} |",
                r.observed.as_deref().unwrap_or("–"),
                opt(r.x_b_m, 3),
                opt(r.setup_m, 4)
            ));
        }
        out.push_str(&format!(
            " {} | {} | {} |\n",
            r.volume_drift_max
                .map_or("–".to_owned(), |v| format!("{:.3} %", 100.0 * v)),
            opt(r.median_ms_per_step, 1),
            match (r.status == "ok", r.kinds.is_empty(), r.all_passed()) {
                (false, _, _) => "✗ did not finish",
                (true, true, _) => "none",
                (true, false, true) => "✓",
                (true, false, false) => "✗",
            }
        ));
    }
    // Why runs have no checks, once per reason.
    let mut notes: Vec<(&str, usize)> = Vec::new();
    for n in runs
        .iter()
        .filter(|r| r.kinds.is_empty())
        .filter_map(|r| r.note.as_deref())
    {
        match notes.iter_mut().find(|(m, _)| *m == n) {
            Some((_, count)) => *count += 1,
            None => notes.push((n, 1)),
        }
    }
    for (note, count) in notes {
        out.push_str(&format!("\nNo checks in {count} of the runs: {note}.\n"));
    }
    out
}

/// Writes `study.csv`, `study.md`, `study.svg` and `study.png` into `out`; returns their paths.
pub fn write_study(runs: &[StudyRun], out: &Path) -> Result<Vec<PathBuf>, StudyError> {
    std::fs::create_dir_all(out).map_err(io_error(out))?;
    let svg = figure::svg(runs).map_err(|message| StudyError::Output {
        path: out.join("study.svg"),
        message,
    })?;
    let png = figure::png(runs).map_err(|message| StudyError::Output {
        path: out.join("study.png"),
        message,
    })?;
    let files: [(&str, Vec<u8>); 4] = [
        ("study.csv", csv(runs).into_bytes()),
        ("study.md", markdown(runs).into_bytes()),
        ("study.svg", svg.into_bytes()),
        ("study.png", png),
    ];
    let mut written = Vec::new();
    for (name, bytes) in files {
        let path = out.join(name);
        std::fs::write(&path, bytes).map_err(io_error(&path))?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(what: &str, measured: f64, target: f64, tol: Option<f64>, passed: bool) -> Check {
        Check {
            what: what.into(),
            measured,
            target,
            relative_tolerance: tol,
            inclusive: false,
            unit: "m".into(),
            passed,
        }
    }

    #[test]
    fn kinds_group_the_gauges_and_the_probes() {
        assert_eq!(
            check_kind("wave height at x = 1.468 m (0.98 L)"),
            "wave height"
        );
        assert_eq!(
            check_kind("u1(z) under a crest, worst probe: u1 amplitude at x = 4.638 m"),
            "u1(z) under a crest, worst probe"
        );
        assert_eq!(
            check_kind("front mean |ΔZ| on T ≤ 3, Lethe's shift ΔT = 0.175"),
            "front mean |ΔZ| on T ≤ 3, Lethe's shift ΔT = 0.175"
        );
    }

    #[test]
    fn the_first_difference_names_its_key() {
        let a = serde_json::json!({"solver": {"gamma": 1.0, "theta": 0.0}, "time": {"end_s": 30}});
        let b = serde_json::json!({"solver": {"gamma": 1.0, "theta": 0.5}, "time": {"end_s": 30}});
        assert_eq!(first_difference(&a, &a, ""), None);
        assert_eq!(
            first_difference(&a, &b, "").as_deref(),
            Some("solver.theta")
        );
        let c = serde_json::json!({"solver": {"gamma": 1.0}, "time": {"end_s": 30}});
        assert_eq!(first_difference(&a, &c, ""), None);
    }

    #[test]
    fn the_worst_fraction_of_each_bar() {
        let checks = [
            check("wave height at x = 1 m", 0.0597, 0.06, Some(0.05), true),
            check("wave height at x = 2 m", 0.0627, 0.06, Some(0.05), true),
            check("volume drift", 0.0055, 0.005, None, false),
        ];
        let kinds = by_kind(&checks);
        assert_eq!(kinds.len(), 2);
        // 0.0627/0.06 − 1 = 4.5 %, 0.9 of the 5 % bar; 0.0055 is 1.1 of its bound.
        assert!((kinds[0].worst_fraction - 0.9).abs() < 1e-12, "{kinds:?}");
        assert!(kinds[0].passed);
        assert!((kinds[1].worst_fraction - 1.1).abs() < 1e-12);
        assert!(!kinds[1].passed);
    }
}
