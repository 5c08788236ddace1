//! Running a sweep: check everything before the first run, run this shard's unfinished points
//! in `--jobs` threads with a line per run and the overall progress on stderr, then gather the
//! outputs as `--collect` does.

use super::spec::{self, Point, Shard};
use super::table::{self, ERROR_FILE, Row};
use super::{Collected, SPEC_FILE, SweepError, SweepSpec, collect_with, io_error, read_spec};
use crate::case::{Case, CaseError};
use crate::output::run::{RunOptions, run};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// A sweep as the command line gives it.
#[derive(Debug, Clone)]
pub struct SweepOptions {
    pub case: PathBuf,
    /// `--vary KEY=...` arguments, in order.
    pub vary: Vec<String>,
    pub set: Vec<String>,
    pub until_s: Option<f64>,
    pub jobs: usize,
    /// Default `runs/sweep_<case name>/`.
    pub out: Option<PathBuf>,
    pub shard: Shard,
    /// Write each run's `run.rrd`.
    pub rrd: bool,
}

/// What a sweep did.
pub struct SweepOutcome {
    pub dir: PathBuf,
    pub collected: Collected,
    /// Points this process ran, and this shard's points found finished before.
    pub ran: usize,
    pub skipped: usize,
}

/// Checks the sweep, runs this shard's unfinished points, and writes the outputs.
pub fn run_sweep(opts: &SweepOptions) -> Result<SweepOutcome, SweepError> {
    if let Some(t) = opts.until_s
        && !(t.is_finite() && t > 0.0)
    {
        return Err(SweepError::BadUntil(t));
    }
    if opts.jobs == 0 {
        return Err(SweepError::NoJobs);
    }
    let axes = opts
        .vary
        .iter()
        .map(|v| spec::parse_vary(v))
        .collect::<Result<Vec<_>, _>>()?;
    let points = spec::points(&axes)?;
    let mut shared = opts.set.clone();
    if let Some(t) = opts.until_s {
        shared.push(format!("time.end_s={t}"));
    }
    let base = Case::load(&opts.case, &shared)?;
    let spec = SweepSpec {
        case: opts.case.clone(),
        case_name: base.name.clone(),
        vary: axes,
        set: opts.set.clone(),
        until_s: opts.until_s,
    };
    let fields = serde_json::to_value(&base).unwrap_or(Value::Null);
    for axis in &spec.vary {
        check_key(&opts.case, &fields, &shared, &axis.key, &axis.values[0])?;
    }
    let dir = opts
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("runs").join(format!("sweep_{}", base.name)));
    std::fs::create_dir_all(&dir).map_err(io_error(&dir))?;
    if dir.join(SPEC_FILE).exists() {
        let before = read_spec(&dir)?;
        if before != spec {
            return Err(SweepError::Mismatch {
                path: dir.join(SPEC_FILE),
                what: differences(&before, &spec),
            });
        }
    } else {
        let rows: Vec<Row> = points
            .iter()
            .map(|p| table::read_row(p, &dir.join(&p.dir_name)))
            .collect();
        super::write_spec(&dir, &spec, &rows)?;
    }

    // This shard's points, each with its case (or why the case refuses the point's values).
    let mine: Vec<&Point> = points.iter().filter(|p| opts.shard.owns(p.index)).collect();
    let mut todo: Vec<(&Point, Result<Case, CaseError>)> = Vec::new();
    let mut skipped = 0;
    for &p in &mine {
        if dir.join(&p.dir_name).join("summary.json").exists() {
            skipped += 1;
        } else {
            todo.push((p, Case::load(&opts.case, &spec.overrides(p))));
        }
    }
    let jobs = opts.jobs.min(todo.len()).max(1);
    let one_core = runs_on_one_core(jobs);
    eprintln!(
        "surflab sweep: {} — {} point{}{}; {} finished before, {} to run in {} thread{}{}; output to {}",
        spec.case_name,
        points.len(),
        if points.len() == 1 { "" } else { "s" },
        if opts.shard.count > 1 {
            format!(
                " (shard {}/{}: {} of them)",
                opts.shard.index,
                opts.shard.count,
                mine.len()
            )
        } else {
            String::new()
        },
        skipped,
        todo.len(),
        jobs,
        if jobs == 1 { "" } else { "s" },
        if one_core { ", one core a run" } else { "" },
        dir.display()
    );
    let progress = Mutex::new(Progress::new(todo.len()));
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    let Some((point, case)) = todo.get(k) else {
                        break;
                    };
                    let started = Instant::now();
                    let status = run_point(&dir.join(&point.dir_name), case, opts.rrd, one_core);
                    let wall_s = started.elapsed().as_secs_f64();
                    if let Ok(mut p) = progress.lock() {
                        p.done(point, &status, wall_s);
                    }
                }
            });
        }
    });
    let collected = collect_with(&dir, &spec)?;
    let rows = &collected.rows;
    let count = |f: &dyn Fn(&Row) -> bool| rows.iter().filter(|r| f(r)).count();
    eprintln!(
        "surflab sweep: {} of {} points ok, {} failed, {} not run yet{}; wrote {}",
        count(&Row::ok),
        rows.len(),
        count(&|r: &Row| !r.ok() && r.status != table::NOT_RUN),
        count(&|r: &Row| r.status == table::NOT_RUN),
        if opts.shard.count > 1 {
            " (other shards' points count as not run until they finish)"
        } else {
            ""
        },
        collected.written_list()
    );
    Ok(SweepOutcome {
        dir,
        ran: todo.len(),
        skipped,
        collected,
    })
}

/// Refuses a varied key that is not a field of the case: one that is neither in the resolved
/// case nor accepted when the case is loaded with it set to its first value.
fn check_key(
    file: &Path,
    fields: &Value,
    shared: &[String],
    key: &str,
    first_value: &str,
) -> Result<(), SweepError> {
    let present = key
        .split('.')
        .try_fold(fields, |v, seg| match v {
            Value::Object(m) => m.get(seg),
            Value::Array(a) => seg.parse::<usize>().ok().and_then(|i| a.get(i)),
            _ => None,
        })
        .is_some();
    if present {
        return Ok(());
    }
    let mut overrides = shared.to_vec();
    overrides.push(format!("{key}={first_value}"));
    match Case::load(file, &overrides) {
        Ok(_) => Ok(()),
        Err(e) => Err(SweepError::BadKey {
            key: key.to_owned(),
            file: file.to_owned(),
            message: match e {
                CaseError::Field { field, message, .. } => format!("field `{field}`: {message}"),
                CaseError::Override { message, .. } => message,
                other => other.to_string(),
            },
        }),
    }
}

fn differences(a: &SweepSpec, b: &SweepSpec) -> String {
    let mut what = Vec::new();
    if a.case != b.case || a.case_name != b.case_name {
        what.push("the case");
    }
    if a.vary != b.vary {
        what.push("the --vary lists");
    }
    if a.set != b.set {
        what.push("the --set overrides");
    }
    if a.until_s != b.until_s {
        what.push("--until");
    }
    what.join(", ")
}

/// Whether each of `jobs` runs at a time steps on one core: when the runs with their
/// solvers' second-core threads would ask for more cores than the machine has. The results are
/// the same to the last digit; the 1:4 sweep's twelve points at `--jobs 2` on two cores took
/// 45.5 min against 48.2 min with two threads a run (docs/sweep.md).
fn runs_on_one_core(jobs: usize) -> bool {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    jobs > 1 && 2 * jobs > cores
}

/// Runs one point into `dir`; the status for its progress line. A point that cannot start
/// leaves its reason in `dir/error.txt` (its row's status).
fn run_point(dir: &Path, case: &Result<Case, CaseError>, rrd: bool, one_core: bool) -> String {
    let error_file = dir.join(ERROR_FILE);
    let fail = |message: String| {
        let _ = std::fs::create_dir_all(dir);
        let _ = std::fs::write(&error_file, format!("{message}\n"));
        format!("error: {message}")
    };
    let case = match case {
        Ok(case) => case,
        Err(e) => return fail(e.to_string()),
    };
    let _ = std::fs::remove_file(&error_file);
    let options = RunOptions {
        out_dir: dir.to_owned(),
        rrd,
        progress: false,
        one_core,
    };
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run(case, &options))) {
        Ok(Ok(outcome)) => outcome.summary.status,
        Ok(Err(e)) => fail(e.to_string()),
        Err(panic) => {
            let message = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .unwrap_or_else(|| "unknown".into());
            fail(format!("the run panicked: {message}"))
        }
    }
}

/// The overall progress: runs done of this process's, and the time left at the pace so far
/// (the wall time since the start over the runs done, so parallel jobs count).
struct Progress {
    total: usize,
    done: usize,
    started: Instant,
}

impl Progress {
    fn new(total: usize) -> Self {
        Self {
            total,
            done: 0,
            started: Instant::now(),
        }
    }

    fn done(&mut self, point: &Point, status: &str, wall_s: f64) {
        self.done += 1;
        let elapsed = self.started.elapsed().as_secs_f64();
        let left = self.total - self.done;
        let eta = if left == 0 {
            "done".to_owned()
        } else {
            format!("ETA {}", duration(elapsed / self.done as f64 * left as f64))
        };
        eprintln!(
            "surflab sweep: [{}/{}] {}: {status} ({wall_s:.1} s wall) — {} of {} run, {eta}",
            self.done,
            self.total,
            point.overrides.join(" "),
            self.done,
            self.total
        );
    }
}

fn duration(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TANK: &str = "[flume]\nlength_m = 1.0\nheight_m = 0.7\n[[water]]\nx_end_m = 1.0\n\
                        depth_m = 0.5\n[particles]\nspacing_m = 0.05\n[time]\nend_s = 0.01\n";

    fn options(name: &str, vary: &[&str]) -> SweepOptions {
        let dir = std::env::temp_dir().join(format!("surflab-sweep-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let case = dir.join("tank.toml");
        std::fs::write(&case, TANK).unwrap();
        SweepOptions {
            case,
            vary: vary.iter().map(|s| s.to_string()).collect(),
            set: Vec::new(),
            until_s: None,
            jobs: 1,
            out: Some(dir.join("out")),
            shard: Shard::ALL,
            rrd: false,
        }
    }

    #[test]
    fn bad_keys_ranges_and_files_stop_the_sweep_before_any_run() {
        let error = |o: &SweepOptions| run_sweep(o).err().map(|e| e.to_string()).unwrap();
        let o = options("badkey", &["solver.alpah=1.2,1.3"]);
        let e = error(&o);
        assert!(
            e.contains("solver.alpah") && e.contains("not a field"),
            "{e}"
        );
        assert!(!o.out.as_ref().unwrap().exists(), "nothing was written");
        let e = error(&options("badrange", &["solver.alpha=1.3:1.2:0.1"]));
        assert!(
            e.contains("solver.alpha") && e.contains("below START"),
            "{e}"
        );
        let mut o = options("nofile", &["solver.alpha=1.2"]);
        o.case = o.case.with_file_name("missing.toml");
        assert!(error(&o).contains("missing.toml"));
        // A value the case refuses is not a bad key: it is checked per point.
        let fields =
            serde_json::to_value(Case::load(&options("ok", &[]).case, &[]).unwrap()).unwrap();
        let case = options("ok2", &[]).case;
        assert!(check_key(&case, &fields, &[], "solver.alpha", "0.9").is_ok());
        assert!(check_key(&case, &fields, &[], "water.0.depth_m", "0.4").is_ok());
        assert!(check_key(&case, &fields, &[], "water.3.depth_m", "0.4").is_err());
    }
}
