//! The `surflab sweep` command line.

use super::spec::Shard;
use super::{SweepError, SweepOptions, collect, run_sweep};
use std::path::PathBuf;

/// `surflab sweep CASE --vary KEY=... [...]` or `surflab sweep --collect DIR`.
#[derive(Debug, clap::Args)]
#[command(after_help = "\
Each point runs as `surflab run CASE --set <shared sets> --set <its values> --until S --out \
DIR/<key>=<value>,.../` would, and writes DIR/sweep.csv, DIR/sweep.json, DIR/breaker_map.svg, \
DIR/breaker_map.png and DIR/sweep.rrd. A run directory that holds a summary.json is not run \
again: run the same command to resume. See docs/sweep.md.")]
pub struct SweepArgs {
    /// The case file (TOML) every point starts from.
    #[arg(required_unless_present = "collect")]
    pub case: Option<PathBuf>,
    /// A case field and its values, KEY=V1,V2,... (TOML values, as --set takes them) or
    /// KEY=START:STOP:STEP (STOP included), e.g. wavemaker.period_s=1.0:4.0:0.25. Repeatable:
    /// the sweep runs the product, the first --vary changing slowest.
    #[arg(long, value_name = "KEY=VALUES", required_unless_present = "collect")]
    pub vary: Vec<String>,
    /// Override a case field at every point, e.g. --set particles.spacing_m=0.03 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Stop every run at this simulated time instead of the case's time.end_s.
    #[arg(long, value_name = "SECONDS")]
    pub until: Option<f64>,
    /// Runs at a time, each in its own thread (default 1). A run uses two cores when it may,
    /// one when the jobs would ask for more cores than the machine has; on two cores --jobs 2
    /// ran the 12-point 1:4 sweep in 45.5 min.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub jobs: usize,
    /// Output folder (default runs/sweep_<case name>/).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Run only the points whose index % N == I (I from 0, in product order), e.g. one task of
    /// a Slurm job array: --shard $SLURM_ARRAY_TASK_ID/4. Shards share --out.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Do not write each run's run.rrd.
    #[arg(long)]
    pub no_rrd: bool,
    /// Rebuild sweep.csv, the rows of sweep.json, the map and sweep.rrd in DIR from its run
    /// directories and DIR/sweep.json, running nothing.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["case", "vary", "set", "until", "out", "shard", "no_rrd"])]
    pub collect: Option<PathBuf>,
}

/// Runs the command.
pub fn main(args: SweepArgs) -> Result<(), SweepError> {
    if let Some(dir) = args.collect {
        let collected = collect(&dir)?;
        let ok = collected.rows.iter().filter(|r| r.ok()).count();
        eprintln!(
            "surflab sweep: collected {} point{} ({ok} ok) from {}; wrote {}",
            collected.rows.len(),
            if collected.rows.len() == 1 { "" } else { "s" },
            dir.display(),
            collected.written_list()
        );
        return Ok(());
    }
    let shard = match &args.shard {
        Some(s) => Shard::parse(s)?,
        None => Shard::ALL,
    };
    let case = args.case.ok_or_else(|| SweepError::BadVary {
        given: String::new(),
        message: "a sweep needs a case file".into(),
    })?;
    run_sweep(&SweepOptions {
        case,
        vary: args.vary,
        set: args.set,
        until_s: args.until,
        jobs: args.jobs,
        out: args.out,
        shard,
        rrd: !args.no_rrd,
    })?;
    Ok(())
}
