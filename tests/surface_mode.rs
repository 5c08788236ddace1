//! The free-surface ripple that caps Δt, measured on one surface mode, and the one-mode model
//! that chose its cure (issue 22; docs/validation/surface_mode.md).
//!
//! The still tank (1 m, 0.5 m deep, h = 2 cm, weak surface λ = 0.3 h, no filter, no
//! merging, no surface-wave bound) starts with mode 16 on its surface: wavelength 0.125 m =
//! 6.25 h, inside the 3–8 h band where the ripple grows, amplitude 1 mm. Its amplitude, the
//! surface projected on cos(k x), gives the mode's frequency ω and growth rate σ.
//!
//! The model: one surface mode is an oscillator η'' = −ω² η. The explicit geometry evaluates
//! its restoring force on xⁿ; the step's second pass evaluates it on xⁿ + θₓ Δt uⁿ⁺¹, which
//! turns the update into wⁿ⁺¹ (1 + θₓ ω² Δt²) = wⁿ − Δt ω² ηⁿ, ηⁿ⁺¹ = ηⁿ + Δt wⁿ⁺¹, whose
//! amplification has |λ|² = 1/(1 + θₓ ω² Δt²): the pass adds a damping rate
//! ln(1 + θₓ ω² Δt²)/(2Δt) ≈ θₓ ω² Δt/2 to whatever the explicit step does. So the model
//! predicts, from the explicit run's σ₀ and ω,
//!
//! σ(θₓ) = σ₀ − ln(1 + θₓ ω² Δt²)/(2Δt),
//!
//! and the cure is right when the solver's θₓ run agrees. Measured (this machine): at
//! Δt = 5 ms the explicit mode grows at σ₀ ≈ +0.67/s (ω ≈ 16.5 rad/s), the model predicts
//! ≈ 0 with θₓ = 1 and the solver gives +0.005/s.

mod common;

use surflab::diagnostics::surface_elevation;
use surflab::simulation::Simulation;

/// The amplitude of mode 16 on the surface: (2/L) ∫ η cos(k x) dx by the midpoint rule on
/// 200 points (the other modes the start excites drop out).
fn mode_amplitude(sim: &Simulation) -> f64 {
    let (length, k) = (1.0, 16.0 * std::f64::consts::PI);
    let n = 200;
    let dx = length / n as f64;
    (0..n)
        .map(|i| {
            let x = (i as f64 + 0.5) * dx;
            surface_elevation(sim, x).expect("wet surface") * (k * x).cos()
        })
        .sum::<f64>()
        * 2.0
        * dx
        / length
}

/// Runs the seeded tank for `end_s` with Δt `dt_s` fixed; returns (ω, σ) of the mode.
fn measure(dt_s: f64, geometry_theta: f64, end_s: f64) -> (f64, f64) {
    let dt = format!("time.dt_max_s={dt_s}");
    let theta = format!("solver.geometry_theta={geometry_theta}");
    let end = format!("time.end_s={end_s}");
    let case = common::case(
        "still_water.toml",
        &[
            "water.0.surface_amplitude_m=0.001",
            "water.0.surface_mode=16",
            "solver.weak_surface_length_h=0.3",
            "time.dt_policy=fixed",
            "time.surface_wave_courant=0",
            &dt,
            &theta,
            &end,
        ],
    );
    let mut sim = Simulation::new(&case).unwrap();
    let mut record = vec![(0.0, mode_amplitude(&sim))];
    sim.advance_to(case.time.end_s, |s, _| {
        record.push((s.time_s, mode_amplitude(s)));
    })
    .expect("the seeded tank runs");
    // The first half period carries the start's transient (the columns are stretched
    // uniformly, not along the mode's decaying profile).
    let settled: Vec<(f64, f64)> = record.into_iter().filter(|(t, _)| *t > 0.2).collect();
    let fit = common::fit_oscillation(&settled).expect("the mode oscillates");
    println!(
        "  Δt = {} ms, θₓ = {geometry_theta}: mode amplitude per period {:?} mm",
        dt_s * 1e3,
        fit.amplitudes
            .iter()
            .map(|(_, a)| (a * 1e4).round() / 10.0)
            .collect::<Vec<_>>()
    );
    (2.0 * std::f64::consts::PI / fit.period_s, fit.growth_per_s)
}

#[test]
fn implicit_geometry_damps_the_surface_mode_as_the_one_mode_model_says() {
    let dt = 5.0e-3;
    // The explicit run stops at 2 s, before its mode has grown out of the linear range (by
    // 3 s at 1 mm it has turned the surface over into a mix of modes).
    let (omega0, sigma0) = measure(dt, 0.0, 2.0);
    let (omega1, sigma1) = measure(dt, 1.0, 5.0);
    let model_damping = (1.0 + omega0 * omega0 * dt * dt).ln() / (2.0 * dt);
    let predicted = sigma0 - model_damping;
    println!(
        "mode 16 (6.25 h), Δt = {} ms: explicit geometry ω = {omega0:.2} rad/s, σ = {sigma0:+.3}/s; \
         θₓ = 1: ω = {omega1:.2} rad/s, σ = {sigma1:+.3}/s; model σ₀ − ln(1 + ω²Δt²)/(2Δt) = \
         {predicted:+.3}/s (the pass's damping {model_damping:.3}/s)",
        dt * 1e3
    );
    // The ripple is there: the explicit step grows this mode.
    assert!(sigma0 > 0.2, "explicit growth {sigma0}/s");
    // Model and solver agree to a fifth of the damping the pass adds (the fit of a growth
    // rate over ten periods is good to a few 0.01/s; the model leaves out the ω shift).
    let error = sigma1 - predicted;
    assert!(
        error.abs() < 0.2 * model_damping,
        "solver {sigma1:+.3}/s against model {predicted:+.3}/s"
    );
    // And the mode no longer grows.
    assert!(sigma1 < 0.05, "θₓ = 1 growth {sigma1}/s");
}
