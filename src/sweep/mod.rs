//! `surflab sweep`: one case run over the product of `--vary` lists, one run directory per
//! point, and the rows gathered into `sweep.csv`, `sweep.json`, the breaker-type map
//! (`breaker_map.svg`, `.png`) and `sweep.rrd`. Resumable (a run directory holding a
//! `summary.json` is not run again) and shardable (`--shard I/N`) over machines sharing the
//! sweep's directory; `--collect DIR` rebuilds the outputs from the run directories alone.
//! See docs/sweep.md.

pub mod cli;
pub mod figure;
mod record;
pub mod reflection;
mod runner;
pub mod spec;
pub mod table;

use crate::case::CaseError;
use serde::{Deserialize, Serialize};
use spec::{Point, VaryAxis};
use std::path::{Path, PathBuf};
use table::Row;

pub use cli::SweepArgs;
pub use runner::{SweepOptions, SweepOutcome, run_sweep};

/// Everything that stops a sweep before or after its runs (a failing run is a row, not an
/// error).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    #[error("--vary {given}: {message}")]
    BadVary { given: String, message: String },
    #[error("--vary {key}: bad range `{range}`: {message}")]
    BadRange {
        key: String,
        range: String,
        message: String,
    },
    #[error("{what} has {points} points, more than {max}", max = spec::MAX_POINTS)]
    TooManyPoints { what: String, points: usize },
    #[error("--vary {key}: `{key}` is not a field of the case {file}: {message}")]
    BadKey {
        key: String,
        file: PathBuf,
        message: String,
    },
    #[error("--shard {given}: {message}")]
    BadShard { given: String, message: String },
    #[error("--until must be a positive number of seconds, got {0}")]
    BadUntil(f64),
    #[error("--jobs must be at least 1")]
    NoJobs,
    #[error(transparent)]
    Case(#[from] CaseError),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}: {message}")]
    Unreadable { path: PathBuf, message: String },
    #[error(
        "{path} describes another sweep ({what} differ); choose another --out, or delete it to start over"
    )]
    Mismatch { path: PathBuf, what: String },
    #[error("{path}: {message}")]
    Output { path: PathBuf, message: String },
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> SweepError + '_ {
    move |source| SweepError::Io {
        path: path.to_owned(),
        source,
    }
}

/// What a sweep is: enough to rebuild its points and to tell it from another sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepSpec {
    /// The case file, as given on the command line.
    pub case: PathBuf,
    pub case_name: String,
    pub vary: Vec<VaryAxis>,
    /// The `--set` overrides every point shares.
    pub set: Vec<String>,
    /// `--until`: the simulated end time of every run, s (the case's `time.end_s` if null).
    pub until_s: Option<f64>,
}

impl SweepSpec {
    pub fn keys(&self) -> Vec<String> {
        self.vary.iter().map(|a| a.key.clone()).collect()
    }

    pub fn points(&self) -> Result<Vec<Point>, SweepError> {
        spec::points(&self.vary)
    }

    /// The overrides of one point's run: the shared sets, `time.end_s`, then the point's.
    pub fn overrides(&self, point: &Point) -> Vec<String> {
        let mut o = self.set.clone();
        if let Some(t) = self.until_s {
            o.push(format!("time.end_s={t}"));
        }
        o.extend(point.overrides.iter().cloned());
        o
    }
}

/// `sweep.json`: the spec and one object per point.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct SweepFile {
    #[serde(flatten)]
    spec: SweepSpec,
    points: Vec<Row>,
}

pub const SPEC_FILE: &str = "sweep.json";

/// Reads the spec of the sweep in `dir`.
pub fn read_spec(dir: &Path) -> Result<SweepSpec, SweepError> {
    let path = dir.join(SPEC_FILE);
    let text = std::fs::read_to_string(&path).map_err(io_error(&path))?;
    let file: SweepFile = serde_json::from_str(&text).map_err(|e| SweepError::Unreadable {
        path: path.clone(),
        message: format!("not a sweep's {SPEC_FILE}: {e}"),
    })?;
    Ok(file.spec)
}

/// Writes `sweep.json` with `rows` (a new sweep's rows are all `not run`).
fn write_spec(dir: &Path, spec: &SweepSpec, rows: &[Row]) -> Result<(), SweepError> {
    let file = SweepFile {
        spec: spec.clone(),
        points: rows.to_vec(),
    };
    let path = dir.join(SPEC_FILE);
    let text = serde_json::to_string_pretty(&file).map_err(|e| SweepError::Output {
        path: path.clone(),
        message: e.to_string(),
    })?;
    write_atomically(&path, (text + "\n").as_bytes())
}

/// Writes through a temporary file renamed into place, so that shards finishing together on a
/// shared file system never leave a half-written file.
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), SweepError> {
    let tmp = temporary_beside(path);
    std::fs::write(&tmp, bytes).map_err(io_error(&tmp))?;
    std::fs::rename(&tmp, path).map_err(io_error(path))
}

fn temporary_beside(path: &Path) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    path.with_file_name(format!(".{name}.{}.{nanos}.tmp", std::process::id()))
}

/// The outputs rebuilt from the run directories.
pub struct Collected {
    pub rows: Vec<Row>,
    pub written: Vec<PathBuf>,
}

impl Collected {
    /// The files written, as one comma-separated line.
    pub fn written_list(&self) -> String {
        self.written
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Rebuilds `sweep.csv`, the rows of `sweep.json`, the map and `sweep.rrd` in `dir` from its
/// run directories and the spec, running nothing.
pub fn collect(dir: &Path) -> Result<Collected, SweepError> {
    let spec = read_spec(dir)?;
    collect_with(dir, &spec)
}

fn collect_with(dir: &Path, spec: &SweepSpec) -> Result<Collected, SweepError> {
    let rows: Vec<Row> = spec
        .points()?
        .iter()
        .map(|p| table::read_row(p, &dir.join(&p.dir_name)))
        .collect();
    let keys = spec.keys();
    let mut written = Vec::new();
    let csv = dir.join("sweep.csv");
    write_atomically(&csv, table::csv(&keys, &rows).as_bytes())?;
    written.push(csv);
    write_spec(dir, spec, &rows)?;
    written.push(dir.join(SPEC_FILE));
    let output = |path: &Path| {
        let path = path.to_owned();
        move |message: String| SweepError::Output { path, message }
    };
    let svg = dir.join("breaker_map.svg");
    let text = figure::svg(&spec.case_name, &rows).map_err(output(&svg))?;
    write_atomically(&svg, text.as_bytes())?;
    written.push(svg);
    let png = dir.join("breaker_map.png");
    let bytes = figure::png(&spec.case_name, &rows).map_err(output(&png))?;
    write_atomically(&png, &bytes)?;
    written.push(png);
    let rrd = dir.join("sweep.rrd");
    let tmp = temporary_beside(&rrd);
    record::write(&tmp, &spec.case_name, &keys, &rows).map_err(output(&rrd))?;
    std::fs::rename(&tmp, &rrd).map_err(io_error(&rrd))?;
    written.push(rrd);
    Ok(Collected { rows, written })
}
