//! Linear (Airy) wave theory and first-order wavemaker transfer functions.
//!
//! **Dispersion.** A wave of period `T` (`ω = 2π/T`) in depth `h` has wave
//! number `k` satisfying `ω² = g k tanh(k h)`. It is solved in the
//! dimensionless form `y tanh y = α` with `y = k h`, `α = ω² h / g`, by Newton
//! iteration started from Guo's (2002) explicit approximation
//! `y₀ = x² (1 − e^{−x^{5/2}})^{−2/5}`, `x = ω sqrt(h/g)`, which is already
//! within about 1 % everywhere; two or three Newton steps reach round-off.
//! Then `L = 2π/k`, `c = ω/k`, and in deep water `L₀ = g T² / (2π)`.
//!
//! **Transfer functions** (ratio of wave height `H` to paddle stroke `S`,
//! with `S` the full excursion of the paddle at the still water level):
//!
//! ```text
//! piston (thesis eq. 2.37):  H/S = 2 (cosh 2kh − 1) / (sinh 2kh + 2kh)
//! flap hinged at the bed (thesis eq. 2.36):
//!                            H/S = 4 (sinh kh / kh) (kh sinh kh − cosh kh + 1) / (sinh 2kh + 2kh)
//! ```
//!
//! In shallow water these tend to `kh` and `kh/2`; in deep water both tend
//! to 2 (the flap only slowly, as `2 (1 − 1/kh)`). They are evaluated with
//! `cosh x − 1 = 2 sinh²(x/2)` to avoid cancellation at small `kh`, and in
//! terms of `e^{−kh}` for `kh > 20` to avoid overflow.
//!
//! **Paddle motion** (thesis eqs. 2.32–2.35): the horizontal displacement of
//! the paddle face at elevation `z` is `X(z, t) = r(t) · S(z)/2 · sin(ω t)`,
//! with `S(z) = S` for a piston and `S(z) = S (1 + z/h)` for a flap hinged at
//! the bed (`z = 0` at the still water level, `z = −h` at the bed). The
//! start-up ramp `r(t)` is the half-cosine of [`super::half_cosine_ramp`]
//! over `ramp_periods · T`. The velocity is the exact time derivative,
//! including the ramp term `r'(t) · S(z)/2 · sin(ω t)`.
//!
//! **Breaking limit.** Miche's criterion `H/L < 0.142 tanh(kh)`.

use std::f64::consts::TAU;

use super::{Result, WaveError, half_cosine_ramp, half_cosine_ramp_rate, require_positive};

/// Miche's limiting steepness coefficient: `H/L < MICHE · tanh(kh)`.
const MICHE_COEFFICIENT: f64 = 0.142;

/// Above this `kh` the transfer functions switch to their `e^{−kh}` forms.
const LARGE_KH: f64 = 20.0;

/// Wave number `k` (rad/m) of a linear wave with the given period and depth,
/// the root of `ω² = g k tanh(k h)` to a relative accuracy of about 1e-15.
pub fn wavenumber(period_s: f64, depth_m: f64, gravity_m_s2: f64) -> Result<f64> {
    let period_s = require_positive("period_s", period_s)?;
    let depth_m = require_positive("depth_m", depth_m)?;
    let gravity_m_s2 = require_positive("gravity_m_s2", gravity_m_s2)?;
    let omega = TAU / period_s;
    let alpha = omega * omega * depth_m / gravity_m_s2;
    let x = omega * (depth_m / gravity_m_s2).sqrt();
    // Guo's explicit start; below x ≈ 1e-6 it is indistinguishable from the
    // shallow-water value y = x (and its formula would underflow).
    let mut y = if x < 1e-6 {
        x
    } else {
        x * x * (-(-x.powf(2.5)).exp_m1()).powf(-0.4)
    };
    for _ in 0..60 {
        let tanh_y = y.tanh();
        let cosh_y = y.cosh();
        let residual = y * tanh_y - alpha;
        let slope = tanh_y + y / (cosh_y * cosh_y);
        let step = residual / slope;
        y -= step;
        if step.abs() <= 1e-15 * y {
            break;
        }
    }
    let relative_residual = (y * y.tanh() - alpha).abs() / alpha;
    if y.is_finite() && y > 0.0 && relative_residual <= 1e-13 {
        Ok(y / depth_m)
    } else {
        Err(WaveError::NoConvergence {
            what: "linear dispersion relation",
        })
    }
}

/// Linear wavelength `L = 2π / k` (m).
pub fn wavelength(period_s: f64, depth_m: f64, gravity_m_s2: f64) -> Result<f64> {
    Ok(TAU / wavenumber(period_s, depth_m, gravity_m_s2)?)
}

/// Linear phase celerity `c = ω / k = L / T` (m/s).
pub fn celerity(period_s: f64, depth_m: f64, gravity_m_s2: f64) -> Result<f64> {
    Ok(wavelength(period_s, depth_m, gravity_m_s2)? / period_s)
}

/// Linear group velocity `c_g = ½ (ω/k) (1 + 2kd / sinh 2kd)` (m/s): the speed at which a
/// wave train's front and its energy travel.
pub fn group_velocity(period_s: f64, depth_m: f64, gravity_m_s2: f64) -> Result<f64> {
    let k = wavenumber(period_s, depth_m, gravity_m_s2)?;
    let kd2 = 2.0 * k * depth_m;
    Ok(0.5 * (TAU / period_s / k) * (1.0 + kd2 / kd2.sinh()))
}

/// Deep-water wavelength `L₀ = g T² / (2π)` (m).
pub fn deep_water_wavelength_m(period_s: f64, gravity_m_s2: f64) -> f64 {
    gravity_m_s2 * period_s * period_s / TAU
}

/// Piston transfer function `H/S = 2 (cosh 2kh − 1) / (sinh 2kh + 2kh)`
/// (thesis eq. 2.37) for `kh ≥ 0`; `0` at `kh = 0`, NaN for negative `kh`.
pub fn piston_height_to_stroke(kh: f64) -> f64 {
    if kh.is_nan() || kh < 0.0 {
        f64::NAN
    } else if kh == 0.0 {
        0.0
    } else if kh > LARGE_KH {
        // Numerator and denominator divided by e^{2kh}; q = e^{−2kh}.
        let q = (-2.0 * kh).exp();
        2.0 * (1.0 - q) * (1.0 - q) / (1.0 - q * q + 4.0 * kh * q)
    } else {
        // cosh 2kh − 1 = 2 sinh² kh.
        let s = kh.sinh();
        4.0 * s * s / ((2.0 * kh).sinh() + 2.0 * kh)
    }
}

/// Transfer function of a flap hinged at the bed,
/// `H/S = 4 (sinh kh / kh)(kh sinh kh − cosh kh + 1) / (sinh 2kh + 2kh)`
/// (thesis eq. 2.36) for `kh ≥ 0`; `0` at `kh = 0`, NaN for negative `kh`.
pub fn flap_height_to_stroke(kh: f64) -> f64 {
    if kh.is_nan() || kh < 0.0 {
        f64::NAN
    } else if kh == 0.0 {
        0.0
    } else if kh > LARGE_KH {
        // Divided through by e^{2kh}; s = e^{−kh}.
        let s = (-kh).exp();
        let s2 = s * s;
        let numerator = (1.0 - s2) * (1.0 - s2) - (1.0 - s2) * (1.0 - s) * (1.0 - s) / kh;
        2.0 * numerator / (1.0 - s2 * s2 + 4.0 * kh * s2)
    } else {
        let sinh_kh = kh.sinh();
        let half = (0.5 * kh).sinh();
        // kh sinh kh − (cosh kh − 1), with cosh kh − 1 = 2 sinh²(kh/2).
        let bracket = kh * sinh_kh - 2.0 * half * half;
        4.0 * (sinh_kh / kh) * bracket / ((2.0 * kh).sinh() + 2.0 * kh)
    }
}

/// Miche breaking criterion: `true` when `H/L < 0.142 tanh(2π h / L)`.
/// Returns `false` for non-finite or non-positive wavelength or depth, or a
/// negative or non-finite height.
pub fn steepness_limit_ok(height_m: f64, wavelength_m: f64, depth_m: f64) -> bool {
    let valid = height_m.is_finite()
        && height_m >= 0.0
        && wavelength_m.is_finite()
        && wavelength_m > 0.0
        && depth_m.is_finite()
        && depth_m > 0.0;
    valid && height_m < miche_height_limit_m(wavelength_m, depth_m)
}

/// Largest height allowed by Miche's criterion, `0.142 L tanh(kh)` (m).
fn miche_height_limit_m(wavelength_m: f64, depth_m: f64) -> f64 {
    MICHE_COEFFICIENT * wavelength_m * (TAU * depth_m / wavelength_m).tanh()
}

/// Type of wavemaker: how the paddle moves. The case schema uses it too (`wavemaker.paddle`,
/// written `piston` or `flap`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PaddleKind {
    /// A rigid vertical plate translating along x (uniform stroke).
    Piston,
    /// A rigid plate hinged on the bed, rotating about the hinge (stroke ∝ z + h).
    Flap,
}

/// A sinusoidal first-order wavemaker with a half-cosine start-up ramp.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearPaddle {
    /// Piston or bed-hinged flap.
    pub kind: PaddleKind,
    /// Target wave height.
    pub height_m: f64,
    /// Wave (and paddle) period.
    pub period_s: f64,
    /// Still water depth at the paddle.
    pub depth_m: f64,
    /// Full paddle excursion at the still water level, from the transfer function.
    pub stroke_m: f64,
    /// Length of the start-up ramp in wave periods (0 = no ramp).
    pub ramp_periods: f64,
    /// Linear wavelength of the generated wave.
    pub wavelength_m: f64,
}

impl LinearPaddle {
    /// Designs a paddle producing a linear wave of height `height_m` and
    /// period `period_s` in depth `depth_m`: solves the dispersion relation and
    /// sets the stroke from the piston or flap transfer function.
    ///
    /// Errors on non-positive inputs, a negative or non-finite ramp length,
    /// or a wave exceeding Miche's steepness limit.
    pub fn new(
        kind: PaddleKind,
        height_m: f64,
        period_s: f64,
        depth_m: f64,
        gravity_m_s2: f64,
        ramp_periods: f64,
    ) -> Result<Self> {
        let height_m = require_positive("height_m", height_m)?;
        if !(ramp_periods.is_finite() && ramp_periods >= 0.0) {
            return Err(WaveError::OutOfRange {
                name: "ramp_periods",
                value: ramp_periods,
            });
        }
        let k = wavenumber(period_s, depth_m, gravity_m_s2)?;
        let wavelength_m = TAU / k;
        if !steepness_limit_ok(height_m, wavelength_m, depth_m) {
            return Err(WaveError::TooSteep {
                height_m,
                max_height_m: miche_height_limit_m(wavelength_m, depth_m),
            });
        }
        let kh = k * depth_m;
        let height_to_stroke = match kind {
            PaddleKind::Piston => piston_height_to_stroke(kh),
            PaddleKind::Flap => flap_height_to_stroke(kh),
        };
        Ok(Self {
            kind,
            height_m,
            period_s,
            depth_m,
            stroke_m: height_m / height_to_stroke,
            ramp_periods,
            wavelength_m,
        })
    }

    /// Paddle angular frequency `ω = 2π/T` (rad/s).
    pub fn angular_frequency_rad_s(&self) -> f64 {
        TAU / self.period_s
    }

    /// Duration of the start-up ramp (s).
    pub fn ramp_duration_s(&self) -> f64 {
        self.ramp_periods * self.period_s
    }

    /// Local stroke `S(z)` at elevation `z_m`: uniform for a piston, linear
    /// from zero at the hinge (`z = −h`) for a flap. Below the bed the flap
    /// stroke is clamped to zero; above the still water level the rigid plate
    /// continues linearly.
    pub fn stroke_at_m(&self, z_m: f64) -> f64 {
        match self.kind {
            PaddleKind::Piston => self.stroke_m,
            PaddleKind::Flap => self.stroke_m * (1.0 + z_m / self.depth_m).max(0.0),
        }
    }

    /// Horizontal displacement of the paddle face at time `t_s` and elevation
    /// `z_m`: `r(t) · S(z)/2 · sin(ω t)`; zero for `t ≤ 0`.
    pub fn displacement_m(&self, t_s: f64, z_m: f64) -> f64 {
        if t_s <= 0.0 {
            return 0.0;
        }
        let ramp = half_cosine_ramp(t_s, self.ramp_duration_s());
        let omega = self.angular_frequency_rad_s();
        ramp * 0.5 * self.stroke_at_m(z_m) * (omega * t_s).sin()
    }

    /// Horizontal velocity of the paddle face, the exact time derivative of
    /// [`Self::displacement_m`] (including the ramp term); zero for `t ≤ 0`.
    pub fn velocity_m_s(&self, t_s: f64, z_m: f64) -> f64 {
        if t_s <= 0.0 {
            return 0.0;
        }
        let ramp_s = self.ramp_duration_s();
        let ramp = half_cosine_ramp(t_s, ramp_s);
        let ramp_rate = half_cosine_ramp_rate(t_s, ramp_s);
        let omega = self.angular_frequency_rad_s();
        let (sin_wt, cos_wt) = (omega * t_s).sin_cos();
        0.5 * self.stroke_at_m(z_m) * (ramp_rate * sin_wt + ramp * omega * cos_wt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 9.81;

    #[test]
    fn transfer_functions_shallow_and_deep_limits() {
        let kh = 1e-3;
        let piston_rel = (piston_height_to_stroke(kh) / kh - 1.0).abs();
        let flap_rel = (flap_height_to_stroke(kh) / (0.5 * kh) - 1.0).abs();
        println!(
            "kh = 1e-3: piston H/S / kh − 1 = {piston_rel:.3e}, flap H/S / (kh/2) − 1 = {flap_rel:.3e}"
        );
        assert!(piston_rel < 1e-3 && flap_rel < 1e-3);

        let piston_deep = piston_height_to_stroke(50.0);
        let flap_deep = flap_height_to_stroke(1e6);
        println!("piston H/S(kh = 50) = {piston_deep:.15}, flap H/S(kh = 1e6) = {flap_deep:.15}");
        assert!((piston_deep - 2.0).abs() < 1e-12);
        assert!((flap_deep - 2.0).abs() < 1e-5);
        // Flap deep-water asymptote 2 (1 − 1/kh).
        let flap_50 = flap_height_to_stroke(50.0);
        println!(
            "flap H/S(kh = 50) = {flap_50:.15} vs 2(1 − 1/kh) = {:.15}",
            2.0 * (1.0 - 1.0 / 50.0)
        );
        assert!((flap_50 - 2.0 * (1.0 - 1.0 / 50.0)).abs() < 1e-12);
        for kh in [400.0, 1000.0, 1e300] {
            assert!(piston_height_to_stroke(kh).is_finite());
            assert!(flap_height_to_stroke(kh).is_finite());
        }
        assert_eq!(piston_height_to_stroke(0.0), 0.0);
        assert!(piston_height_to_stroke(-1.0).is_nan());
        assert!(flap_height_to_stroke(f64::NAN).is_nan());
    }

    #[test]
    fn transfer_functions_match_textbook_forms() {
        // Direct transcription of eqs. 2.36/2.37 at moderate kh, plus
        // continuity where the large-kh forms take over.
        let mut worst = 0.0_f64;
        for kh in [0.05_f64, 0.3, 1.0, 2.5, 6.0, 12.0] {
            let denom = (2.0 * kh).sinh() + 2.0 * kh;
            let piston = 2.0 * ((2.0 * kh).cosh() - 1.0) / denom;
            let flap = 4.0 * (kh.sinh() / kh) * (kh * kh.sinh() - kh.cosh() + 1.0) / denom;
            worst = worst
                .max((piston_height_to_stroke(kh) / piston - 1.0).abs())
                .max((flap_height_to_stroke(kh) / flap - 1.0).abs());
        }
        let below = LARGE_KH * (1.0 - 1e-15);
        let above = LARGE_KH * (1.0 + 1e-15);
        let jump = (piston_height_to_stroke(below) - piston_height_to_stroke(above))
            .abs()
            .max((flap_height_to_stroke(below) - flap_height_to_stroke(above)).abs());
        println!(
            "transfer functions vs textbook form: worst rel. diff {worst:.3e}; jump at kh = 20: {jump:.3e}"
        );
        assert!(worst < 1e-10);
        assert!(jump < 1e-13);
    }

    #[test]
    fn dispersion_residual_is_tiny() {
        let mut worst = 0.0_f64;
        for &period_s in &[0.2, 0.5, 0.91, 1.5, 3.0, 8.0, 20.0, 100.0] {
            for &depth_m in &[0.01, 0.1, 0.4, 0.7, 2.0, 10.0, 100.0, 4000.0] {
                let k = wavenumber(period_s, depth_m, G).unwrap();
                let omega = TAU / period_s;
                let residual =
                    (G * k * (k * depth_m).tanh() - omega * omega).abs() / (omega * omega);
                worst = worst.max(residual);
            }
        }
        println!("dispersion relative residual, worst over grid: {worst:.3e}");
        assert!(worst < 1e-12);
    }

    #[test]
    fn deep_water_wavelength() {
        let mut worst = 0.0_f64;
        for period_s in [0.5, 1.0, 2.0, 5.0] {
            let l = wavelength(period_s, 1000.0, G).unwrap();
            let l0 = deep_water_wavelength_m(period_s, G);
            assert!((l / l0 - 1.0).abs() < 1e-12);
            worst = worst.max((l / (period_s * period_s) / 1.56 - 1.0).abs());
        }
        println!(
            "deep water: L/T² = {:.5} m/s² (g/2π), worst rel. diff from 1.56: {worst:.3e}",
            G / TAU
        );
        assert!(worst < 1.5e-3);
    }

    #[test]
    fn thesis_flume_wavelengths() {
        let l_091 = wavelength(0.91, 0.7, G).unwrap();
        let l_095 = wavelength(0.95, 0.7, G).unwrap();
        let kh_091 = TAU / l_091 * 0.7;
        println!(
            "d = 0.7 m, T = 0.91 s: L = {l_091:.4} m (kh = {kh_091:.3}, L0 = {:.4} m)",
            deep_water_wavelength_m(0.91, G)
        );
        println!(
            "d = 0.7 m, T = 0.95 s: L = {l_095:.4} m (L0 = {:.4} m)",
            deep_water_wavelength_m(0.95, G)
        );
        assert!((1.27..=1.295).contains(&l_091));
        assert!((l_095 / 1.408 - 1.0).abs() < 5e-3);
        assert!((celerity(0.91, 0.7, G).unwrap() - l_091 / 0.91).abs() < 1e-14);
    }

    #[test]
    fn group_velocity_tends_to_its_shallow_and_deep_limits() {
        // Shallow water: c_g → √(g d); deep water: c_g → c / 2 = g T / (4π).
        let shallow = group_velocity(100.0, 0.1, G).unwrap() / (G * 0.1).sqrt();
        let deep = group_velocity(1.0, 50.0, G).unwrap() / (G / (2.0 * TAU));
        // The narrow piston tank's wave (d = 0.25 m, T = 0.8 s; kd = 1.69).
        let tank = group_velocity(0.8, 0.25, G).unwrap();
        println!("c_g/√(gd) = {shallow:.6}, c_g/(gT/4π) = {deep:.9}, tank c_g = {tank:.4} m/s");
        assert!((shallow - 1.0).abs() < 1e-4);
        assert!((deep - 1.0).abs() < 1e-9);
        assert!((tank - 0.7184).abs() < 5e-5);
    }

    #[test]
    fn paddle_velocity_matches_finite_difference() {
        let mut worst = 0.0_f64;
        for kind in [PaddleKind::Piston, PaddleKind::Flap] {
            let paddle = LinearPaddle::new(kind, 0.05, 1.2, 0.7, G, 2.5).unwrap();
            let peak = 0.5 * paddle.stroke_m * paddle.angular_frequency_rad_s();
            for z_m in [0.0, -0.35, -0.7] {
                for i in 1..2000 {
                    let t = i as f64 * 0.0031;
                    let d = 1e-6;
                    let fd = (paddle.displacement_m(t + d, z_m)
                        - paddle.displacement_m(t - d, z_m))
                        / (2.0 * d);
                    worst = worst.max((fd - paddle.velocity_m_s(t, z_m)).abs() / peak);
                }
            }
            println!(
                "{kind:?}: stroke S = {:.5} m, L = {:.4} m",
                paddle.stroke_m, paddle.wavelength_m
            );
        }
        println!(
            "paddle velocity vs central difference: worst error / peak velocity = {worst:.3e}"
        );
        assert!(worst < 1e-6);
    }

    #[test]
    fn paddle_profile_and_validation() {
        let flap = LinearPaddle::new(PaddleKind::Flap, 0.05, 1.2, 0.7, G, 2.0).unwrap();
        assert_eq!(flap.stroke_at_m(-0.7), 0.0);
        assert_eq!(flap.stroke_at_m(-1.0), 0.0);
        assert!((flap.stroke_at_m(-0.35) - 0.5 * flap.stroke_m).abs() < 1e-15);
        assert_eq!(flap.displacement_m(-1.0, 0.0), 0.0);
        // After the ramp the amplitude is S/2.
        let quarter = flap.period_s * 3.25;
        assert!((flap.displacement_m(quarter, 0.0) - 0.5 * flap.stroke_m).abs() < 1e-12);

        assert!(matches!(
            LinearPaddle::new(PaddleKind::Piston, 0.05, 1.2, -0.7, G, 2.0),
            Err(WaveError::NonPositive {
                name: "depth_m",
                ..
            })
        ));
        assert!(matches!(
            LinearPaddle::new(PaddleKind::Piston, 0.05, 1.2, 0.7, G, -1.0),
            Err(WaveError::OutOfRange { .. })
        ));
        let steep = LinearPaddle::new(PaddleKind::Piston, 0.3, 0.91, 0.7, G, 2.0);
        println!("H = 0.3 m, T = 0.91 s, d = 0.7 m -> {steep:?}");
        assert!(matches!(steep, Err(WaveError::TooSteep { .. })));
        assert!(wavenumber(0.0, 1.0, G).is_err());
        assert!(wavenumber(1.0, f64::NAN, G).is_err());
    }

    #[test]
    fn miche_limit() {
        // Deep water: limit H/L ≈ 0.142.
        assert!(steepness_limit_ok(0.14, 1.0, 10.0));
        assert!(!steepness_limit_ok(0.143, 1.0, 10.0));
        // Shallow water: kh = 2π·0.1 → limit ≈ 0.142·tanh(0.628) ≈ 0.079.
        let limit = MICHE_COEFFICIENT * (TAU * 0.1).tanh();
        println!("Miche limit H/L at h/L = 0.1: {limit:.4}");
        assert!(steepness_limit_ok(0.95 * limit, 1.0, 0.1));
        assert!(!steepness_limit_ok(1.05 * limit, 1.0, 0.1));
        assert!(!steepness_limit_ok(0.01, -1.0, 0.1));
    }
}
