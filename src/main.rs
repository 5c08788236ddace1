//! `surflab`: open the lab window, run a case headless, or benchmark the time step.

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::time::Instant;
use surflab::case::Case;
use surflab::output::recorder::{Frame, FrameRecorder, StageStats};
use surflab::output::run::{RunOptions, run};
use surflab::output::summary::median;
use surflab::simulation::Simulation;

/// With the window (the default build), mimalloc, as Rerun's own viewer uses: the viewer
/// allocates and frees many small blocks every frame.
#[cfg(feature = "lab")]
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[derive(Parser)]
#[command(
    name = "surflab",
    version,
    about = "A 2D PFEM wave flume: still water, dam breaks, waves and surf"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Refuse a case whose fluid particles plus wall nodes would exceed N (estimated before
    /// seeding). The default suits a 24 GiB machine; raise it on a bigger one.
    #[arg(long, global = true, value_name = "N", default_value_t = surflab::case::DEFAULT_MAX_NODES)]
    max_particles: usize,
}

#[derive(Subcommand)]
enum Command {
    /// Run a case to its end time; write run.rrd, timeseries.csv and summary.json.
    Run {
        /// The case file (TOML), e.g. cases/dam_break.toml.
        case: PathBuf,
        /// Stop at this simulated time instead of the case's time.end_s.
        #[arg(long, value_name = "SECONDS")]
        until: Option<f64>,
        /// Output folder (default runs/<case name>/).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Do not write run.rrd.
        #[arg(long)]
        no_rrd: bool,
        /// Override a case field by its dotted path, e.g. --set solver.alpha=1.3 (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
    },
    /// Open the lab: the Rerun viewer with the control panel, the solver in a worker thread.
    #[cfg(feature = "lab")]
    Lab {
        /// The case to open (default cases/teaching_beach.toml); the presets are the cases in
        /// its folder.
        case: Option<PathBuf>,
        /// Save a PNG of the window and exit, once the solver has run --after seconds.
        #[arg(long, value_name = "PATH")]
        screenshot: Option<PathBuf>,
        /// Simulated seconds to run before the screenshot.
        #[arg(long, value_name = "SECONDS", default_value_t = 1.0)]
        after: f64,
        /// Where the panel's "record" checkbox writes the .rrd.
        #[arg(long, value_name = "PATH", default_value = "runs/lab.rrd")]
        record_to: PathBuf,
    },
    /// Run a case and check it: a wavemaker's waves against theory (issue 3): a flap or piston
    /// into an absorbing end, a standing wave at a wall, or a cnoidal piston; a dam break
    /// against Martin & Moyce (1952); a Ting & Kirby surf case against its breaking point,
    /// type, undertow balance and volume; a narrow 3D tank with a linear piston against its 2D
    /// twin (run too, into DIR/2d), wave height by wave height. Prints each figure against its
    /// bar, writes validation.json beside the run, exits non-zero if one fails.
    Validate {
        /// The case file, e.g. cases/flap_deep_water.toml.
        case: PathBuf,
        /// Check the outputs of an earlier `surflab run` in DIR instead of running again (the
        /// case is then taken from DIR/summary.json).
        #[arg(long, value_name = "DIR")]
        from: Option<PathBuf>,
        /// Output folder (default runs/<case name>/).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Stop at this simulated time instead of the case's time.end_s.
        #[arg(long, value_name = "SECONDS")]
        until: Option<f64>,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Check a case without running it: validate every field and print the sizes it would
    /// take (particles, wall nodes, frames, steps).
    Check {
        case: PathBuf,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Open recordings (.rrd) in the embedded viewer; several are merged on one timeline, each
    /// run's entities under its folder's name, to compare runs side by side.
    #[cfg(feature = "lab")]
    View {
        #[arg(required = true, value_name = "FILE.rrd")]
        files: Vec<PathBuf>,
        /// Save a PNG of the window once the recordings are shown, and exit.
        #[arg(long, value_name = "PATH")]
        screenshot: Option<PathBuf>,
    },
    /// Run a case over the product of --vary lists, one run directory per point; write
    /// sweep.csv, sweep.json, the breaker-type map (PNG, SVG) and sweep.rrd (docs/sweep.md).
    Sweep(surflab::sweep::SweepArgs),
    /// Gather finished runs of one case that differ in α and δ (docs/alpha_delta.md): validate
    /// each as `surflab validate --from` does, and write study.csv, study.md, study.svg and
    /// study.png with each kind of check as the fraction of its bar it uses, against α, one
    /// line per δ.
    Study {
        /// Run folders, or folders holding them (a sweep's, or runs/study_flap).
        #[arg(required = true, value_name = "DIR")]
        dirs: Vec<PathBuf>,
        /// Output folder (default: the first DIR).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Time the 3D mesher alone (issue 26): the Delaunay tetrahedralisation of a random or
    /// lattice cloud, µs per point over several repeats.
    BenchTetra {
        /// Number of points.
        #[arg(long, default_value_t = 100_000)]
        points: usize,
        /// A cubic lattice of about that many nodes instead of random points.
        #[arg(long)]
        lattice: bool,
        /// Number of timed repeats.
        #[arg(long, default_value_t = 5)]
        repeat: u32,
    },
    /// Time the 3D loop (issue 26) on a tank of still water (jittered interior, h = 2 cm, twice
    /// as long and wide as deep): ms per step by stage, particle-steps per second.
    Bench3d {
        /// About this many nodes (walls included).
        #[arg(long, default_value_t = 20_000)]
        nodes: usize,
        /// Number of steps to time (Δt = 10 ms).
        #[arg(long, default_value_t = 5)]
        steps: u64,
        /// The pressure solver: cholesky, cg, or auto (Cholesky up to 10 000 unknowns).
        #[arg(long, default_value = "auto")]
        solver: String,
    },
    /// Time the step: ms per step by stage, particles and particle-steps per second.
    Bench {
        case: PathBuf,
        /// Number of steps to time.
        #[arg(long, default_value_t = 200)]
        steps: u64,
        /// Print one JSON object instead of a table.
        #[arg(long)]
        json: bool,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
}

fn main() {
    let cli = Cli::parse();
    surflab::case::set_max_nodes(cli.max_particles);
    let result = match cli.command {
        Some(Command::Run {
            case,
            until,
            out,
            no_rrd,
            set,
            quiet,
        }) => cmd_run(&case, until, out, !no_rrd, &set, !quiet),
        Some(Command::Bench {
            case,
            steps,
            json,
            set,
        }) => cmd_bench(&case, steps, json, &set),
        Some(Command::Validate {
            case,
            from,
            out,
            until,
            set,
        }) => cmd_validate(&case, from, out, until, &set),
        Some(Command::Check { case, set }) => cmd_check(&case, &set),
        #[cfg(feature = "lab")]
        Some(Command::View { files, screenshot }) => {
            surflab::lab::view(surflab::lab::ViewOptions { files, screenshot })
        }
        Some(Command::Sweep(args)) => surflab::sweep::cli::main(args).map_err(Into::into),
        Some(Command::Study { dirs, out }) => cmd_study(&dirs, out),
        Some(Command::BenchTetra {
            points,
            lattice,
            repeat,
        }) => surflab::output::bench3d::bench_tetra(points, lattice, repeat),
        Some(Command::Bench3d {
            nodes,
            steps,
            solver,
        }) => surflab::output::bench3d::bench_still_tank(nodes, steps, &solver),
        #[cfg(feature = "lab")]
        Some(Command::Lab {
            case,
            screenshot,
            after,
            record_to,
        }) => cmd_lab(case, screenshot, after, record_to),
        None => default_job(),
    };
    if let Err(e) = result {
        eprintln!("surflab: error: {e:#}");
        std::process::exit(1);
    }
}

/// No arguments: the lab when there is a display to open it on, else the default case headless.
fn default_job() -> Result<()> {
    let display = ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()));
    #[cfg(feature = "lab")]
    if display {
        return cmd_lab(None, None, 1.0, PathBuf::from("runs/lab.rrd"));
    }
    eprintln!(
        "surflab: {}; running cases/teaching_beach.toml headless",
        if display {
            "built without the lab feature"
        } else {
            "no display (DISPLAY/WAYLAND_DISPLAY unset)"
        }
    );
    cmd_run(
        Path::new("cases/teaching_beach.toml"),
        None,
        None,
        true,
        &[],
        true,
    )
}

#[cfg(feature = "lab")]
fn cmd_lab(
    case: Option<PathBuf>,
    screenshot: Option<PathBuf>,
    after: f64,
    record_to: PathBuf,
) -> Result<()> {
    if !(after.is_finite() && after >= 0.0) {
        bail!("--after must be a non-negative number of seconds, got {after}");
    }
    if let Some(dir) = record_to.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    surflab::lab::run(surflab::lab::LabOptions {
        case,
        screenshot,
        screenshot_after_s: after,
        record_path: record_to,
    })
}

fn load(path: &Path, set: &[String], until: Option<f64>) -> Result<Case> {
    let mut overrides = set.to_vec();
    if let Some(t) = until {
        if !(t.is_finite() && t > 0.0) {
            bail!("--until must be a positive number of seconds, got {t}");
        }
        overrides.push(format!("time.end_s={t}"));
    }
    Ok(Case::load(path, &overrides)?)
}

fn cmd_check(path: &Path, set: &[String]) -> Result<()> {
    let case = load(path, set, None)?;
    if case.flume.width_m.is_some() {
        // What the 3D path cannot run yet is refused here too, with its field.
        surflab::solver3d::setup::from_case(&case)?;
    }
    let e = case.size_estimate();
    println!(
        "{}: valid; about {:.0} fluid particles and {:.0} wall nodes at h = {} (limit {} in all), \
         {:.0} frames every {} s to t = {} s, at least {:.0} steps (Δt ≤ {} s)",
        case.name,
        e.fluid,
        e.walls,
        spacing_label(&case),
        surflab::case::max_nodes(),
        e.frames,
        case.output.interval_s,
        case.time.end_s,
        e.min_steps,
        case.time.dt_max_s
    );
    Ok(())
}

/// "0.02 m", or "0.02 m, 0.01 m from x = 6 m" with `particles.refine`.
fn spacing_label(case: &Case) -> String {
    let h = case.particles.spacing_m;
    match &case.particles.refine {
        None => format!("{h} m"),
        Some(r) => format!("{h} m, {} m from x = {} m", r.spacing_m, r.x_m),
    }
}

fn cmd_run(
    path: &Path,
    until: Option<f64>,
    out: Option<PathBuf>,
    rrd: bool,
    set: &[String],
    progress: bool,
) -> Result<()> {
    let case = load(path, set, until)?;
    let out_dir = out.unwrap_or_else(|| PathBuf::from("runs").join(&case.name));
    eprintln!(
        "surflab: {} — {} to t = {} s, h = {}, output to {}",
        case.name,
        path.display(),
        case.time.end_s,
        spacing_label(&case),
        out_dir.display()
    );
    let opts = RunOptions {
        out_dir: out_dir.clone(),
        rrd,
        progress,
        one_core: false,
    };
    if case.flume.width_m.is_some() {
        return run_3d(&case, &opts);
    }
    let outcome = run(&case, &opts)?;
    let s = &outcome.summary;
    eprintln!(
        "surflab: {}, volume drift max {:.3e}",
        s.run.line(),
        s.volume_drift_max
    );
    finished(outcome.ok(), &s.status, &out_dir)
}

/// The end of `surflab run`: an error naming the status when the run stopped early.
fn finished(ok: bool, status: &str, out_dir: &Path) -> Result<()> {
    if !ok {
        bail!(
            "run did not finish: {status} (what was recorded is in {})",
            out_dir.display()
        );
    }
    eprintln!("surflab: status ok; wrote {}", out_dir.display());
    Ok(())
}

/// `surflab run` of a 3D case (one with `flume.width_m`).
fn run_3d(case: &surflab::case::Case, opts: &RunOptions) -> Result<()> {
    let outcome = surflab::output::run3d::run3d(case, opts)?;
    let s = &outcome.summary;
    eprintln!("surflab: {}", s.line());
    finished(outcome.ok(), &s.status, &opts.out_dir)
}

fn cmd_validate(
    path: &Path,
    from: Option<PathBuf>,
    out: Option<PathBuf>,
    until: Option<f64>,
    set: &[String],
) -> Result<()> {
    let (dir, case, drift, simulated, status, particles) = match from {
        Some(dir) => {
            if !set.is_empty() || until.is_some() || out.is_some() {
                bail!(
                    "--from checks an earlier run as it was: --set, --until and --out do not apply"
                );
            }
            let run = surflab::study::FinishedRun::read(&dir)?;
            let number = |key: &str| {
                run.summary[key]
                    .as_f64()
                    .with_context(|| format!("{}/summary.json: no number {key}", dir.display()))
            };
            let status = run.status().to_string();
            let particles = run.summary["particles"].as_u64().map(|n| n as usize);
            (
                dir.clone(),
                run.case.clone(),
                number("volume_drift_max")?,
                number("simulated_s")?,
                status,
                particles,
            )
        }
        None => {
            let case = load(path, set, until)?;
            let dir = out.unwrap_or_else(|| PathBuf::from("runs").join(&case.name));
            eprintln!(
                "surflab: {} to t = {} s, h = {} m, output to {}",
                case.name,
                case.time.end_s,
                case.particles.spacing_m,
                dir.display()
            );
            let opts = RunOptions {
                out_dir: dir.clone(),
                rrd: false,
                progress: true,
                one_core: false,
            };
            let (figures, drift, status) = if case.flume.width_m.is_some() {
                let s = surflab::output::run3d::run3d(&case, &opts)?.summary;
                if surflab::validation::against_2d::applies(&case) && s.status == "ok" {
                    // The 2D twin, for the check against the 2D code.
                    let twin = surflab::validation::against_2d::twin_2d(&case)?;
                    let twin_dir = dir.join(surflab::study::TWIN_2D_DIR);
                    eprintln!("surflab: its 2D twin, output to {}", twin_dir.display());
                    let twin_opts = RunOptions {
                        out_dir: twin_dir,
                        ..opts.clone()
                    };
                    let t = run(&twin, &twin_opts)?.summary;
                    eprintln!("surflab: 2D: {}", t.run.line());
                    if t.status != "ok" {
                        bail!(
                            "the 2D twin did not finish ({}); nothing to compare",
                            t.status
                        );
                    }
                }
                (s.run, s.volume_drift_max, s.status)
            } else {
                let s = run(&case, &opts)?.summary;
                (s.run, s.volume_drift_max, s.status)
            };
            eprintln!("surflab: {}", figures.line());
            let (simulated, particles) = (figures.simulated_s, Some(figures.particles));
            (dir, case, drift, simulated, status, particles)
        }
    };
    if status != "ok" {
        bail!(
            "the run did not finish ({status}); nothing to validate in {}",
            dir.display()
        );
    }
    let report = surflab::study::validate_outputs(&dir, &case, drift, simulated, particles)?;
    println!(
        "{}: {}, averaged over t = {:.2}–{:.2} s",
        case.name, report.kind, report.window_s[0], report.window_s[1]
    );
    // A count without decimals, a unit only where there is one.
    let value = |v: f64, unit: &str| {
        let number = if v.fract() == 0.0 && v.abs() < 1e15 {
            format!("{v:.0}")
        } else {
            format!("{v:.5}")
        };
        format!("{number} {unit}").trim_end().to_string()
    };
    for c in &report.checks {
        println!(
            "  {:4}  {}: {} ({:+.2} % of {:.5}; bar {})",
            if c.passed { "pass" } else { "FAIL" },
            c.what,
            value(c.measured, &c.unit),
            100.0 * c.error(),
            c.target,
            c.bar()
        );
    }
    for f in &report.figures {
        println!("        {}: {}", f.what, value(f.value, &f.unit));
    }
    let file = dir.join("validation.json");
    std::fs::write(&file, serde_json::to_string_pretty(&report)?)
        .with_context(|| format!("writing {}", file.display()))?;
    let failed = report.checks.iter().filter(|c| !c.passed).count();
    if failed > 0 {
        bail!(
            "{failed} of {} checks failed (written to {})",
            report.checks.len(),
            file.display()
        );
    }
    println!(
        "all {} checks pass; written to {}",
        report.checks.len(),
        file.display()
    );
    Ok(())
}

fn cmd_study(dirs: &[PathBuf], out: Option<PathBuf>) -> Result<()> {
    let found = surflab::study::find_runs(dirs)?;
    eprintln!("surflab: {} runs; validating each", found.len());
    let runs = surflab::study::read_study(dirs)?;
    for r in &runs {
        let verdict = match (r.kinds.is_empty(), r.all_passed()) {
            (true, _) => format!("no checks ({})", r.note.as_deref().unwrap_or("none apply")),
            (false, true) => format!("all {} kinds of check pass", r.kinds.len()),
            (false, false) => {
                let failed: Vec<&str> = r
                    .kinds
                    .iter()
                    .filter(|k| !k.passed)
                    .map(|k| k.kind.as_str())
                    .collect();
                format!("FAIL: {}", failed.join("; "))
            }
        };
        println!("α = {}, δ = {}: {verdict}", r.alpha, r.delta);
    }
    let out = out.unwrap_or_else(|| dirs[0].clone());
    for file in surflab::study::write_study(&runs, &out)? {
        println!("wrote {}", file.display());
    }
    Ok(())
}

fn cmd_bench(path: &Path, steps: u64, json: bool, set: &[String]) -> Result<()> {
    if steps == 0 {
        bail!("--steps must be at least 1");
    }
    let case = load(path, set, None)?;
    if case.flume.width_m.is_some() {
        return surflab::output::bench3d::bench_case(&case, steps, json);
    }
    let mut sim = Simulation::new(&case).context("seeding the case")?;
    let n = sim.particles.len();
    // Logging is timed into a throw-away recording, one frame every `every` steps, as `run`
    // records at each output.
    let tmp = std::env::temp_dir().join(format!("surflab-bench-{}.rrd", std::process::id()));
    let mut recorder = FrameRecorder::to_file(&tmp, "surflab-bench", &sim)?;
    let every = 10;
    let mut stages = StageStats::default();
    let mut log_ms = Vec::new();
    let mut iters = Vec::new();
    // Insertion and removal change the count: particle-steps are summed step by step.
    let mut particle_steps = 0usize;
    let started = Instant::now();
    for k in 0..steps {
        let report = sim
            .step_towards(f64::INFINITY)
            .with_context(|| format!("step {k} at t = {:.5} s", sim.time_s))?;
        particle_steps += sim.particles.len();
        stages.push(report.timings);
        iters.push(report.pressure_iterations as f64);
        if k % every == 0 {
            let t0 = Instant::now();
            recorder.log(&sim, &Frame::of(&sim), Some(&report.timings), &[])?;
            log_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        }
    }
    let wall = started.elapsed().as_secs_f64();
    recorder.flush();
    drop(recorder);
    let _ = std::fs::remove_file(&tmp);

    let log_per_step = median(&log_ms) / every as f64;
    let step_ms = stages.median_total_ms();
    let particle_steps_per_s = particle_steps as f64 / wall;
    let mean_particles = particle_steps as f64 / steps as f64;
    // In step order, then the logging.
    let medians = stages.stage_medians();
    let mut stages: Vec<(String, f64)> = surflab::solver::StageTimings::default()
        .named()
        .iter()
        .map(|(name, _)| (name.to_string(), medians[*name]))
        .collect();
    stages.push(("logging".into(), log_per_step));
    if json {
        let obj = serde_json::json!({
            "case": case.name,
            "particles_initial": n,
            "particles_mean": mean_particles,
            "fluid_particles": sim.particles.fluid_count(),
            "steps": steps,
            "simulated_s": sim.time_s,
            "wall_s": wall,
            "median_ms_per_step": step_ms,
            "stage_ms": stages.iter().cloned().collect::<std::collections::BTreeMap<_, _>>(),
            "median_pressure_iterations": median(&iters),
            "pressure_solver": format!("{:?}", case.solver.pressure_solver).to_lowercase(),
            "particle_steps_per_s": particle_steps_per_s,
            "real_time_factor": sim.time_s / wall,
        });
        println!("{obj}");
    } else {
        println!(
            "case {}: {} particles at start, {:.0} on average, {} at the end ({} fluid); {} steps; pressure solver {:?}",
            case.name,
            n,
            mean_particles,
            sim.particles.len(),
            sim.particles.fluid_count(),
            steps,
            case.solver.pressure_solver
        );
        println!("{:<16} {:>10}", "stage", "median ms");
        for (name, ms) in &stages {
            println!("{name:<16} {ms:>10.3}");
        }
        println!("{:<16} {:>10.3}", "step (total)", step_ms);
        println!("median pressure iterations: {:.0}", median(&iters));
        println!(
            "particle-steps/s: {:.0}   simulated {:.4} s in {:.2} s wall: real-time factor {:.3}",
            particle_steps_per_s,
            sim.time_s,
            wall,
            sim.time_s / wall
        );
    }
    Ok(())
}
