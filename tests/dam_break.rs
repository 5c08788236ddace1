//! Dam break against Martin & Moyce (1952), n² = 2: the surge front Z = x/a against
//! T = t·sqrt(2g/a) up to T = 3 (before the front reaches the far wall), the residual column
//! height H = h/(2a) against τ = t·sqrt(g/a), the volume up to the impact, and convergence in h.
//!
//! What the runs show (see the README): the simulated front leads the measured one by a nearly
//! constant ΔT ≈ 0.2 (17 ms), gained in the first 0.07 s; after that its speed matches the
//! data. An instantaneous release against a real gate that takes time to clear the column is
//! the usual reading of such a lead. So the test asserts the raw error is reported, the front
//! speed, the error once the experiment's time origin is fitted (a shift of at most ΔT = 0.4),
//! the column height and the volume. The raw mean |ΔZ| (about 0.24) misses the 0.10 and
//! is printed, not hidden.
//!
//! A correction that is not fitted here: Lethe's dam-break example (chaos-polymtl/lethe,
//! `examples/multiphysics/dam-break/dam-break-2d.py`) plots its VOF front against the same
//! Martin & Moyce table with the simulated T advanced by a fixed 0.175 for the release. The
//! error with that published shift is asserted too.

mod common;

use surflab::validation::{DamBreakSeries, Report, dam_break};

/// The front reaches the far wall (x = 4a) at t ≈ 0.28 s; stop just after.
const UNTIL_S: f64 = 0.29;

/// Runs the dam break at `spacing_m` with EDT parameter `delta` and scores it with the library
/// check `surflab validate` uses (`validation::dam_break`), printing every figure.
fn run_at(spacing_m: f64, name: &str, delta: f64) -> Report {
    let until = format!("time.end_s={UNTIL_S}");
    let spacing = format!("particles.spacing_m={spacing_m}");
    let delta_set = format!("solver.delta={delta}");
    let case = common::case("dam_break.toml", &[&until, &spacing, &delta_set]);
    let outcome = common::run_case(&case, name, false);
    assert!(outcome.ok(), "{}", outcome.summary.status);
    let series =
        DamBreakSeries::from_integrals(&outcome.series, Some(outcome.summary.run.particles));
    let report = dam_break(&case, &series).expect("the dam break is scored");
    println!(
        "dam break h = {:.2} mm, δ = {delta}: {} steps, {:.1} ms/step median",
        spacing_m * 1e3,
        outcome.summary.run.steps,
        outcome.summary.run.median_ms_per_step
    );
    for c in &report.checks {
        let verdict = if c.passed { "pass" } else { "FAIL" };
        println!(
            "  {verdict} {}: {:.4} (bar {})",
            c.what,
            c.measured,
            c.bar()
        );
    }
    for f in &report.figures {
        println!("       {}: {:.4} {}", f.what, f.value, f.unit);
    }
    report
}

/// The measured value of the check whose description starts with `what`.
fn measured(report: &Report, what: &str) -> f64 {
    report
        .checks
        .iter()
        .find(|c| c.what.starts_with(what))
        .unwrap_or_else(|| panic!("no check `{what}`"))
        .measured
}

const SHIFTED: &str = "front mean |ΔZ| on T ≤ 3, time origin fitted";
const DRIFT: &str = "volume drift";

/// At h = 2.92 mm every bar holds: front speed within 5 % of the data, the front within 0.10
/// in Z with the fitted time origin (ΔT ≤ 0.3) and with Lethe's, the column within 0.05 in H,
/// the volume within 1 % to the impact; halving h from 5.84 mm brings the front and the volume
/// closer.
#[test]
fn dam_break_against_martin_moyce_and_in_h() {
    let fine = run_at(0.00292, "dam-fine", 0.0);
    let coarse = run_at(0.00584, "dam-coarse", 0.0);
    println!(
        "convergence h = 5.84 → 2.92 mm: shifted front error {:.3} → {:.3}; volume drift {:.3} % → {:.3} %",
        measured(&coarse, SHIFTED),
        measured(&fine, SHIFTED),
        100.0 * measured(&coarse, DRIFT),
        100.0 * measured(&fine, DRIFT),
    );
    assert!(fine.passed(), "a bar failed at h = 2.92 mm");
    assert!(measured(&fine, SHIFTED) < measured(&coarse, SHIFTED));
    assert!(measured(&fine, DRIFT) < measured(&coarse, DRIFT));
}

/// The same bars with the EDT polygons of δ = 0.03 (issue 24).
#[test]
fn dam_break_with_edt_polygons() {
    let report = run_at(0.00292, "dam-fine-delta", 0.03);
    assert!(report.passed(), "a bar failed with δ = 0.03");
}
