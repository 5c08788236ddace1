use super::super::linear;
use super::*;

const G: f64 = 9.81;

fn mean_over_wavelength(wave: &CnoidalWave, f: impl Fn(f64) -> f64) -> f64 {
    let n = wave.quadrature_nodes();
    (0..n)
        .map(|i| f(wave.wavelength_m * i as f64 / n as f64))
        .sum::<f64>()
        / n as f64
}

#[test]
fn ting_kirby_spilling() {
    let wave = CnoidalWave::new(0.125, 2.0, 0.40, G).unwrap();
    println!(
        "TK spilling: m = {:.5}, 1 - m = {:.4e}, L = {:.4} m, c = {:.4} m/s, trough = {:.4} m, crest = {:.4} m, Ursell = {:.1}",
        wave.m,
        wave.one_minus_m,
        wave.wavelength_m,
        wave.celerity_m_s,
        wave.trough_m,
        wave.crest_m(),
        wave.ursell_number()
    );
    assert!((wave.m / 0.870 - 1.0).abs() < 0.01);
    assert!((wave.wavelength_m / 3.78 - 1.0).abs() < 0.01);
    assert!((wave.wavelength_m / wave.celerity_m_s / 2.0 - 1.0).abs() < 1e-9);
}

#[test]
fn ting_kirby_plunging() {
    let wave = CnoidalWave::new(0.128, 5.0, 0.40, G).unwrap();
    println!(
        "TK plunging: 1 - m = {:.4e}, K = {:.4}, L = {:.4} m, c = {:.4} m/s, trough = {:.5} m",
        wave.one_minus_m, wave.k_m, wave.wavelength_m, wave.celerity_m_s, wave.trough_m
    );
    let ratio = wave.one_minus_m / 3.0e-5;
    assert!((1.0 / 1.5..=1.5).contains(&ratio));
    assert!((wave.wavelength_m / 10.8 - 1.0).abs() < 0.02);
}

#[test]
fn surface_has_zero_mean() {
    let mut worst = 0.0_f64;
    for (h_m, t_s) in [(0.125, 2.0), (0.128, 5.0), (0.05, 8.0), (0.02, 30.0)] {
        let wave = CnoidalWave::new(h_m, t_s, 0.4, G).unwrap();
        let mean = mean_over_wavelength(&wave, |x| wave.eta_m(x, 0.0));
        let relative = mean.abs() / wave.height_m;
        println!(
            "H = {h_m} m, T = {t_s} s: 1 - m = {:.3e}, |mean η|/H = {relative:.3e}",
            wave.one_minus_m
        );
        worst = worst.max(relative);
        // Crest at the origin, trough half a wavelength away.
        assert!((wave.eta_m(0.0, 0.0) - wave.crest_m()).abs() < 1e-12);
        assert!((wave.eta_m(0.5 * wave.wavelength_m, 0.0) - wave.trough_m).abs() < 1e-12);
    }
    println!("worst |mean η| / H = {worst:.3e}");
    assert!(worst < 1e-6);
}

#[test]
fn small_parameter_is_sinusoidal() {
    let (height_m, period_s, depth_m) = (1e-4, 10.0, 1.0);
    let wave = CnoidalWave::new(height_m, period_s, depth_m, G).unwrap();
    let mut worst = 0.0_f64;
    for i in 0..=400 {
        let x = wave.wavelength_m * i as f64 / 400.0;
        let sine = 0.5 * height_m * (std::f64::consts::TAU * x / wave.wavelength_m).cos();
        worst = worst.max((wave.eta_m(x, 0.0) - sine).abs() / height_m);
    }
    let l_linear = linear::wavelength(period_s, depth_m, G).unwrap();
    let l_rel = (wave.wavelength_m / l_linear - 1.0).abs();
    println!(
        "small m: m = {:.4e}, max |η − (H/2)cos(kx)|/H = {worst:.3e}, L = {:.4} m vs linear {l_linear:.4} m (rel {l_rel:.2e})",
        wave.m, wave.wavelength_m
    );
    assert!(wave.m < 0.02);
    assert!(worst < wave.m);
    assert!(l_rel < 0.01);
}

#[test]
fn invalid_inputs_are_rejected() {
    assert!(matches!(
        CnoidalWave::new(-0.1, 2.0, 0.4, G),
        Err(WaveError::NonPositive {
            name: "height_m",
            ..
        })
    ));
    assert!(matches!(
        CnoidalWave::new(0.35, 2.0, 0.4, G),
        Err(WaveError::TooSteep { .. })
    ));
    let short = CnoidalWave::new(0.1, 0.5, 0.4, G);
    let long = CnoidalWave::new(0.1, 1e4, 0.4, G);
    println!("T = 0.5 s: {short:?}\nT = 1e4 s: {long:?}");
    assert!(matches!(short, Err(WaveError::UrsellSolve { .. })));
    assert!(matches!(long, Err(WaveError::UrsellSolve { .. })));
    let wave = CnoidalWave::new(0.125, 2.0, 0.4, G).unwrap();
    assert!(CnoidalPaddle::new(wave.clone(), -1.0).is_err());
    assert!(CnoidalPaddle::new(wave.clone(), f64::NAN).is_err());
    let paddle = CnoidalPaddle::new(wave, 1.0).unwrap();
    assert!(paddle.trajectory(0.0, 1.0).is_empty());
    assert!(paddle.trajectory(0.1, -1.0).is_empty());
    assert!(paddle.position_at(f64::NAN).is_nan());
    assert_eq!(paddle.position_at(-1.0), 0.0);
}

/// Net displacement over `periods` post-ramp periods and the stroke seen
/// over them, from a trajectory sampled at T/200.
fn drift_and_stroke(
    samples: &[(f64, f64, f64)],
    ramp_periods: usize,
    periods: usize,
) -> (f64, f64) {
    let per = RK4_STEPS_PER_PERIOD as usize;
    let start = ramp_periods * per;
    let end = start + periods * per;
    let window = &samples[start..=end];
    let (lo, hi) = window
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(s.1), hi.max(s.1))
        });
    ((samples[end].1 - samples[start].1).abs(), hi - lo)
}

#[test]
fn paddle_does_not_drift() {
    for (height_m, period_s) in [(0.125, 2.0), (0.128, 5.0)] {
        let wave = CnoidalWave::new(height_m, period_s, 0.4, G).unwrap();
        let paddle = CnoidalPaddle::new(wave, 2.0).unwrap();
        let dt = period_s / RK4_STEPS_PER_PERIOD;
        let samples = paddle.trajectory(dt, 7.0 * period_s);
        let (drift, stroke) = drift_and_stroke(&samples, 2, 5);
        // Same integration with the plain fixed-point average at X = 0.
        let fixed_mean = mean_over_wavelength(&paddle.wave, |x| {
            paddle.wave.depth_averaged_velocity_m_s(x, 0.0)
        });
        let naive = paddle.integrate(dt, 7.0 * period_s, fixed_mean);
        let (naive_drift, _) = drift_and_stroke(&naive, 2, 5);
        println!(
            "H = {height_m} m, T = {period_s} s: stroke = {stroke:.4} m (table {:.4} m), U0 = {:.2e} m/s vs fixed-point mean {fixed_mean:.5} m/s; \
             drift over 5 periods = {drift:.3e} m ({:.3e} of stroke); with fixed-point mean: {naive_drift:.3e} m ({:.2} % of stroke)",
            paddle.stroke_m(),
            paddle.mean_velocity_m_s(),
            drift / stroke,
            100.0 * naive_drift / stroke
        );
        assert!(drift < 0.01 * stroke);
        assert!(paddle.mean_velocity_m_s().abs() < 1e-12 * paddle.wave.celerity_m_s);
        assert!((paddle.stroke_m() / stroke - 1.0).abs() < 1e-3);
    }
}

#[test]
fn position_lookup_matches_integration() {
    let wave = CnoidalWave::new(0.125, 2.0, 0.4, G).unwrap();
    let paddle = CnoidalPaddle::new(wave, 1.5).unwrap();
    let dt = 0.0037;
    let samples = paddle.trajectory(dt, 12.0 * 2.0);
    let mut worst_x = 0.0_f64;
    let mut worst_u = 0.0_f64;
    let peak_u = samples.iter().fold(0.0_f64, |a, s| a.max(s.2.abs()));
    for &(t, x, u) in &samples {
        worst_x = worst_x.max((paddle.position_at(t) - x).abs());
        worst_u = worst_u.max((paddle.velocity_at(t) - u).abs());
    }
    println!(
        "position_at vs RK4 over 12 periods: max |ΔX| = {worst_x:.3e} m ({:.3e} of stroke), max |ΔU| / peak U = {:.3e}",
        worst_x / paddle.stroke_m(),
        worst_u / peak_u
    );
    assert!(worst_x < 1e-6 * paddle.stroke_m());
    assert!(worst_u < 1e-5 * peak_u);
    assert_eq!(paddle.velocity_at(0.0), 0.0);
}

#[test]
fn long_wave_limit_matches_linear_piston() {
    // At small m the Goring stroke tends to the shallow-water piston
    // stroke H / (kh); the full linear transfer function differs by O(kh²).
    let (height_m, period_s, depth_m) = (1e-4, 10.0, 1.0);
    let wave = CnoidalWave::new(height_m, period_s, depth_m, G).unwrap();
    let paddle = CnoidalPaddle::new(wave, 2.0).unwrap();
    let k = linear::wavenumber(period_s, depth_m, G).unwrap();
    let linear_stroke = height_m / linear::piston_height_to_stroke(k * depth_m);
    let rel = paddle.stroke_m() / linear_stroke - 1.0;
    println!(
        "small-m cnoidal stroke {:.5e} m vs linear piston {linear_stroke:.5e} m (rel {rel:.2e}, kh = {:.3})",
        paddle.stroke_m(),
        k * depth_m
    );
    assert!(rel.abs() < 0.03);
}
