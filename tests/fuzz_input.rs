//! Fuzzing the input: random, hostile values for every field of a case (zeros, negatives, NaN,
//! infinities, huge and tiny numbers, wrong types) given with `--set`, and case files with
//! whole tables missing. `surflab check` must answer every one without a panic or a hang,
//! either accepting the case or refusing it with a message that names a field; a sample of the
//! accepted ones is also run for a few steps, which must end (well or with a clear status)
//! without a panic.
//!
//! What used to fail: a spacing of 1e-300 m made `surflab run` allocate until the kernel killed
//! it, a flume 700 km high aborted on its wall nodes, and an output interval below 1e-12 s
//! looped on frames forever. The seed is fixed (printed; `SURFLAB_FUZZ_SEED` changes it).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use surflab::case::Case;

/// A small tank and a small beach with a wavemaker, gauges and undertow stations: between
/// them every table of the schema is present.
const TANK: &str = "[flume]\nlength_m = 1.0\nheight_m = 0.7\n[[water]]\nx_end_m = 1.0\n\
depth_m = 0.5\n[particles]\nspacing_m = 0.05\n[time]\nend_s = 0.02\n";
const BEACH: &str = "[flume]\nlength_m = 4.0\nheight_m = 0.6\n[flume.beach]\ntoe_x_m = 2.5\n\
slope = 0.2\n[[water]]\nx_start_m = 0.3\nx_end_m = 4.0\ndepth_m = 0.3\n[wavemaker]\n\
paddle = \"piston\"\ntheory = \"linear\"\nheight_m = 0.02\nperiod_s = 1.2\nx_m = 0.3\n\
[absorber]\nlength_m = 0.5\n[particles]\nspacing_m = 0.04\n[solver]\nweak_surface_length_h = 0.3\n\
[time]\nend_s = 0.02\n[output]\ngauges_x_m = [1.0, 2.0]\nprobes_m = [[1.0, 0.1]]\n\
[surf]\nstations_x_m = [2.0]\n";

/// xorshift64*: a few lines, deterministic, no dependency.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Every leaf of a case as a dotted `--set` path (`water.0.depth_m`, `output.gauges_x_m`,
/// `output.gauges_x_m.0`).
fn leaf_paths(value: &serde_json::Value, prefix: &str, out: &mut Vec<String>) {
    let join = |k: &str| {
        if prefix.is_empty() {
            k.to_owned()
        } else {
            format!("{prefix}.{k}")
        }
    };
    match value {
        serde_json::Value::Object(map) => {
            for (k, v) in map {
                leaf_paths(v, &join(k), out);
            }
        }
        serde_json::Value::Array(items) => {
            out.push(prefix.to_owned());
            for (i, v) in items.iter().enumerate() {
                leaf_paths(v, &join(&i.to_string()), out);
            }
        }
        _ => out.push(prefix.to_owned()),
    }
}

fn hostile_value(rng: &mut Rng) -> String {
    const FIXED: [&str; 20] = [
        "0",
        "-1",
        "-0.0",
        "1e-300",
        "-1e-300",
        "1e300",
        "-1e300",
        "nan",
        "inf",
        "-inf",
        "1e-12",
        "1e12",
        "\"text\"",
        "true",
        "[]",
        "[1.0, 2.0]",
        "{}",
        "9223372036854775807",
        "-9223372036854775808",
        "0.5",
    ];
    match rng.below(3) {
        0 => FIXED[rng.below(FIXED.len())].to_owned(),
        // A float of random sign and magnitude, 1e-15 to 1e15.
        1 => {
            let sign = if rng.below(2) == 0 { 1.0 } else { -1.0 };
            format!("{:e}", sign * 10f64.powf(30.0 * rng.unit() - 15.0))
        }
        // A small integer, as many counts and indices are.
        _ => format!("{}", rng.below(2001) as i64 - 1000),
    }
}

struct Outcome {
    code: Option<i32>,
    stderr: String,
    timed_out: bool,
}

/// Runs surflab with a wall-clock limit; a run past it is killed and reported as a hang.
fn surflab(args: &[&str], limit: Duration) -> Outcome {
    let mut child = Command::new(env!("CARGO_BIN_EXE_surflab"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("surflab starts");
    let started = Instant::now();
    let timed_out = loop {
        if child.try_wait().expect("wait").is_some() {
            break false;
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            break true;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let out = child.wait_with_output().expect("collect output");
    Outcome {
        code: out.status.code(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        timed_out,
    }
}

/// Exit 0, or exit 1 with a message that names a field (`field `…``) or the `--set` given.
fn assert_answered(what: &str, o: &Outcome) {
    assert!(!o.timed_out, "{what}: no answer within the limit (a hang)");
    assert!(
        !o.stderr.contains("panicked"),
        "{what}: panicked:\n{}",
        o.stderr
    );
    match o.code {
        Some(0) => {}
        Some(1) => assert!(
            o.stderr.contains("field `") || o.stderr.contains("--set "),
            "{what}: refused without naming a field:\n{}",
            o.stderr
        ),
        code => panic!("{what}: exit {code:?} (a panic or a signal):\n{}", o.stderr),
    }
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn random_and_hostile_fields_are_answered_without_panic_or_hang() {
    let seed: u64 = std::env::var("SURFLAB_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x5eed_2026);
    println!("seed {seed}");
    let mut rng = Rng(seed.max(1));
    let dir = std::env::temp_dir().join(format!("surflab-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bases: Vec<(PathBuf, Vec<String>)> = [("tank.toml", TANK), ("beach.toml", BEACH)]
        .iter()
        .map(|(name, text)| {
            let path = write(&dir, name, text);
            let case = Case::from_toml_str(text, &path, "fuzz", &[]).expect("the bases are valid");
            let mut paths = Vec::new();
            leaf_paths(&serde_json::to_value(&case).unwrap(), "", &mut paths);
            (path, paths)
        })
        .collect();
    // Fields whose hostile values make a legitimate but long run (tiny steps, many frames):
    // `check` bounds them; the sample of runs leaves them at the base's values.
    let long_run = ["time.", "output.interval_s", "particles.spacing_m"];
    let (mut accepted, mut refused, mut ran) = (0, 0, 0);
    let mut run_codes = [0usize; 2];
    let started = Instant::now();
    for k in 0..400 {
        let (base, paths) = &bases[rng.below(bases.len())];
        let path = &paths[rng.below(paths.len())];
        let assignment = format!("{path}={}", hostile_value(&mut rng));
        let what = format!("#{k} {} --set {assignment}", base.display());
        let o = surflab(
            &["check", base.to_str().unwrap(), "--set", &assignment],
            Duration::from_secs(20),
        );
        assert_answered(&what, &o);
        if o.code == Some(0) {
            accepted += 1;
            if !long_run.iter().any(|p| path.starts_with(p)) && ran < 40 {
                ran += 1;
                let out = dir.join(format!("run{k}"));
                let r = surflab(
                    &[
                        "run",
                        base.to_str().unwrap(),
                        "--set",
                        &assignment,
                        "--until",
                        "0.02",
                        "--no-rrd",
                        "--quiet",
                        "--max-particles",
                        "5000",
                        "--out",
                        out.to_str().unwrap(),
                    ],
                    Duration::from_secs(120),
                );
                let what = format!("{what} (run)");
                assert!(!r.timed_out, "{what}: did not end within 120 s");
                assert!(!r.stderr.contains("panicked"), "{what}:\n{}", r.stderr);
                match r.code {
                    Some(0) => run_codes[0] += 1,
                    Some(1) => run_codes[1] += 1,
                    code => panic!("{what}: exit {code:?}:\n{}", r.stderr),
                }
            }
        } else {
            refused += 1;
        }
    }
    // Whole tables missing, from the beach (which has them all).
    let tables = [
        "[flume]",
        "[flume.beach]",
        "[[water]]",
        "[wavemaker]",
        "[absorber]",
        "[particles]",
        "[solver]",
        "[time]",
        "[output]",
        "[surf]",
    ];
    for t in tables {
        let mut text = String::new();
        let mut skipping = false;
        for line in BEACH.lines() {
            if line.starts_with('[') {
                skipping = line == t;
            }
            if !skipping {
                text.push_str(line);
                text.push('\n');
            }
        }
        let path = write(&dir, "missing.toml", &text);
        let o = surflab(&["check", path.to_str().unwrap()], Duration::from_secs(20));
        assert_answered(&format!("without {t}"), &o);
        println!(
            "without {t}: exit {:?} {}",
            o.code,
            o.stderr.lines().last().unwrap_or("")
        );
    }
    // The repository's cases are all accepted as they are.
    let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    for entry in std::fs::read_dir(&cases).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let o = surflab(&["check", path.to_str().unwrap()], Duration::from_secs(20));
            assert_eq!(o.code, Some(0), "{}: {}", path.display(), o.stderr);
        }
    }
    println!(
        "400 random assignments in {:.1} s: {accepted} accepted, {refused} refused with a field \
         named; {ran} accepted ones run for 0.02 s: {} finished, {} stopped with a status",
        started.elapsed().as_secs_f64(),
        run_codes[0],
        run_codes[1]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn absurd_sizes_are_refused_before_seeding() {
    let dir = std::env::temp_dir().join(format!("surflab-sizes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = write(&dir, "tank.toml", TANK);
    for (set, field) in [
        ("particles.spacing_m=1e-300", "particles.spacing_m"),
        ("flume.height_m=7e5", "flume.height_m"),
        ("flume.width_m=7e5", "flume.width_m"),
        ("output.interval_s=1e-200", "output.interval_s"),
    ] {
        let started = Instant::now();
        let o = surflab(
            &[
                "run",
                base.to_str().unwrap(),
                "--set",
                set,
                "--no-rrd",
                "--quiet",
            ],
            Duration::from_secs(20),
        );
        println!(
            "{set}: exit {:?} in {:.2} s: {}",
            o.code,
            started.elapsed().as_secs_f64(),
            o.stderr.trim()
        );
        assert_eq!(o.code, Some(1), "{set}: {}", o.stderr);
        assert!(
            o.stderr.contains(&format!("field `{field}`")),
            "{}",
            o.stderr
        );
        assert!(o.stderr.contains("limit"), "{}", o.stderr);
    }
    // The limit is the machine's: --max-particles moves it.
    let o = surflab(
        &["check", base.to_str().unwrap(), "--max-particles", "100"],
        Duration::from_secs(20),
    );
    assert_eq!(o.code, Some(1), "{}", o.stderr);
    assert!(o.stderr.contains("the limit is 100"), "{}", o.stderr);
    let _ = std::fs::remove_dir_all(&dir);
}
