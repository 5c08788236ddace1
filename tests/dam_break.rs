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

use common::{interpolate, reference};
use surflab::diagnostics::Integrals;

const A_M: f64 = 0.146;
const G: f64 = 9.81;
/// The front reaches the far wall (x = 4a) at t ≈ 0.28 s; stop just after.
const UNTIL_S: f64 = 0.29;
/// The release time Lethe adds to its simulated T before comparing with this table (see the
/// top of this file).
const PUBLISHED_SHIFT_T: f64 = 0.175;

struct Figures {
    particles: usize,
    front_raw: f64,
    front_shifted: f64,
    shift_t: f64,
    front_published_shift: f64,
    speed_ratio: f64,
    column: f64,
    volume_drift: f64,
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// Least-squares slope of y against x.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let (mx, my) = (mean(x), mean(y));
    let num: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    num / x.iter().map(|a| (a - mx).powi(2)).sum::<f64>()
}

fn figures(series: &[Integrals], particles: usize) -> Figures {
    let t_scale = (2.0 * G / A_M).sqrt();
    let t: Vec<f64> = series.iter().map(|m| m.t_s * t_scale).collect();
    let z: Vec<f64> = series.iter().map(|m| m.front_x_m / A_M).collect();
    let front: Vec<(f64, f64)> = reference("martin_moyce_1952_n2_surge_front.csv")
        .iter()
        .map(|r| (r[0], r[1]))
        .filter(|(tt, _)| *tt <= 3.0)
        .collect();
    let error_with_shift = |s: f64| {
        mean(
            &front
                .iter()
                .map(|(tt, zz)| (interpolate(&t, &z, (tt - s).max(0.0)) - zz).abs())
                .collect::<Vec<_>>(),
        )
    };
    let front_raw = error_with_shift(0.0);
    let front_published_shift = error_with_shift(PUBLISHED_SHIFT_T);
    let (front_shifted, shift_t) = (0..=40)
        .map(|k| (error_with_shift(0.01 * k as f64), 0.01 * k as f64))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap();
    let late: Vec<&(f64, f64)> = front.iter().filter(|(tt, _)| *tt >= 1.4).collect();
    let data_speed = slope(
        &late.iter().map(|r| r.0).collect::<Vec<_>>(),
        &late.iter().map(|r| r.1).collect::<Vec<_>>(),
    );
    let sim_t: Vec<f64> = t
        .iter()
        .copied()
        .filter(|tt| (1.4..=3.0).contains(tt))
        .collect();
    let sim_z: Vec<f64> = sim_t.iter().map(|tt| interpolate(&t, &z, *tt)).collect();
    let speed_ratio = slope(&sim_t, &sim_z) / data_speed;

    let tau_scale = (G / A_M).sqrt();
    let tau: Vec<f64> = series.iter().map(|m| m.t_s * tau_scale).collect();
    let hh: Vec<f64> = series
        .iter()
        .map(|m| m.left_wall_height_m / (2.0 * A_M))
        .collect();
    let column: Vec<f64> = reference("martin_moyce_1952_n2_column_height.csv")
        .iter()
        .filter(|r| r[0] <= tau[tau.len() - 1])
        .map(|r| (interpolate(&tau, &hh, r[0]) - r[1]).abs())
        .collect();
    let v0 = series[0].volume_m2;
    let volume_drift = series
        .iter()
        .filter(|m| m.t_s <= 0.28)
        .map(|m| (m.volume_m2 / v0 - 1.0).abs())
        .fold(0.0, f64::max);
    Figures {
        particles,
        front_raw,
        front_shifted,
        shift_t,
        front_published_shift,
        speed_ratio,
        column: mean(&column),
        volume_drift,
    }
}

fn run_at(spacing_m: f64, name: &str) -> Figures {
    let until = format!("time.end_s={UNTIL_S}");
    let spacing = format!("particles.spacing_m={spacing_m}");
    let case = common::case("dam_break.toml", &[&until, &spacing]);
    let outcome = common::run_case(&case, name, false);
    assert!(outcome.ok(), "{}", outcome.summary.status);
    let f = figures(&outcome.series, outcome.summary.particles);
    println!(
        "dam break h = {:.2} mm: {} particles, {} steps, {:.1} ms/step median | front mean |ΔZ| (T ≤ 3) = {:.3} raw, \
         {:.3} with the time origin shifted by ΔT = {:.2} ({:.1} ms), {:.3} with Lethe's ΔT = {PUBLISHED_SHIFT_T} | front speed dZ/dT on T ∈ [1.4, 3] = {:.3} × data | \
         column mean |ΔH| = {:.4} | volume drift to the impact = {:.3} %",
        spacing_m * 1e3,
        f.particles,
        outcome.summary.steps,
        outcome.summary.median_ms_per_step,
        f.front_raw,
        f.front_shifted,
        f.shift_t,
        f.shift_t / (2.0 * G / A_M).sqrt() * 1e3,
        f.front_published_shift,
        f.speed_ratio,
        f.column,
        100.0 * f.volume_drift
    );
    f
}

#[test]
fn dam_break_against_martin_moyce_and_in_h() {
    let fine = run_at(0.00292, "dam-fine");
    let coarse = run_at(0.00584, "dam-coarse");
    println!(
        "convergence h = 5.84 → 2.92 mm: shifted front error {:.3} → {:.3}; |speed ratio − 1| {:.3} → {:.3}; volume drift {:.3} % → {:.3} %; raw front error {:.3} → {:.3}; with Lethe's shift {:.3} → {:.3}",
        coarse.front_shifted,
        fine.front_shifted,
        (coarse.speed_ratio - 1.0).abs(),
        (fine.speed_ratio - 1.0).abs(),
        100.0 * coarse.volume_drift,
        100.0 * fine.volume_drift,
        coarse.front_raw,
        fine.front_raw,
        coarse.front_published_shift,
        fine.front_published_shift
    );
    // The front: its speed within 5 % of the data, and its position within 0.10 in Z once the
    // time origin is fitted (the raw figure is printed above).
    assert!(
        (fine.speed_ratio - 1.0).abs() < 0.05,
        "front speed ratio {}",
        fine.speed_ratio
    );
    assert!(
        fine.front_shifted <= 0.10,
        "shifted front error {}",
        fine.front_shifted
    );
    assert!(fine.shift_t <= 0.3, "time-origin shift {}", fine.shift_t);
    // The same with the published release time instead of a fitted one.
    assert!(
        fine.front_published_shift <= 0.10,
        "front error with the published shift {}",
        fine.front_published_shift
    );
    // The residual column follows the table to within 0.05 in H = h/(2a).
    assert!(fine.column < 0.05, "mean |ΔH| = {}", fine.column);
    // Volume within 1 % up to the impact.
    assert!(
        fine.volume_drift < 0.01,
        "volume drift {}",
        fine.volume_drift
    );
    // Convergence: halving h brings the (shifted) front and the volume closer.
    assert!(fine.front_shifted < coarse.front_shifted);
    assert!(fine.volume_drift < coarse.volume_drift);
}
