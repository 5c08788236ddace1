//! The Iribarren number and the breaker type it predicts (thesis eq. 1.22 and table 1.1).
//!
//! I_r = tan β / sqrt(H/L₀), L₀ = gT²/(2π). The thesis's table (Sánchez-Arcilla & Lemos) has
//! overlapping bands: spilling below 0.4, plunging 0.4–1.4, plunging or collapsing up to 1.6,
//! collapsing or surging 1.6–3.1, surging above 3.1; Battjes (1974) puts the spilling–plunging
//! limit at 0.5. We use one set of disjoint bands:
//!
//! spilling < 0.45 ≤ plunging < 1.6 ≤ collapsing < 3.1 ≤ surging.
//!
//! The spilling limit sits between the two sources: the thesis's own spilling case has
//! I_r = 0.41 (above its table's 0.4) and Ting & Kirby's plunging case 0.499 (just below
//! Battjes's 0.5), and each paper calls its case what it observed.

use std::f64::consts::TAU;

/// A breaker type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BreakerType {
    Spilling,
    Plunging,
    Collapsing,
    Surging,
}

impl BreakerType {
    pub fn name(self) -> &'static str {
        match self {
            BreakerType::Spilling => "spilling",
            BreakerType::Plunging => "plunging",
            BreakerType::Collapsing => "collapsing",
            BreakerType::Surging => "surging",
        }
    }

    /// The band of I_r this type is predicted for.
    pub fn band(self) -> (f64, f64) {
        match self {
            BreakerType::Spilling => (0.0, SPILLING_MAX),
            BreakerType::Plunging => (SPILLING_MAX, PLUNGING_MAX),
            BreakerType::Collapsing => (PLUNGING_MAX, COLLAPSING_MAX),
            BreakerType::Surging => (COLLAPSING_MAX, f64::INFINITY),
        }
    }
}

const SPILLING_MAX: f64 = 0.45;
const PLUNGING_MAX: f64 = 1.6;
const COLLAPSING_MAX: f64 = 3.1;

/// Deep-water wavelength L₀ = gT²/(2π), m.
pub fn deep_water_wavelength_m(period_s: f64, gravity_m_s2: f64) -> f64 {
    gravity_m_s2 * period_s * period_s / TAU
}

/// I_r = tan β / sqrt(H/L₀) for a beach of slope `slope` (tan β).
pub fn iribarren(slope: f64, height_m: f64, period_s: f64, gravity_m_s2: f64) -> f64 {
    slope / (height_m / deep_water_wavelength_m(period_s, gravity_m_s2)).sqrt()
}

/// The breaker type predicted for `iribarren`.
pub fn predicted_type(iribarren: f64) -> BreakerType {
    if iribarren < SPILLING_MAX {
        BreakerType::Spilling
    } else if iribarren < PLUNGING_MAX {
        BreakerType::Plunging
    } else if iribarren < COLLAPSING_MAX {
        BreakerType::Collapsing
    } else {
        BreakerType::Surging
    }
}

/// Battjes's (1974) bands for the Iribarren number at the breaking point, ξ_b = tan β /
/// sqrt(H_b/L₀): spilling < 0.4 ≤ plunging < 2.0 ≤ collapsing or surging. A second opinion
/// beside [`predicted_type`], which applies the thesis's table to the case's H; ξ_b uses the
/// height the simulated wave broke at.
pub fn battjes_breaker_point_type(iribarren_b: f64) -> &'static str {
    if iribarren_b < 0.4 {
        "spilling"
    } else if iribarren_b < 2.0 {
        "plunging"
    } else {
        "collapsing_or_surging"
    }
}

/// Grilli, Svendsen & Subramanya's (1997) slope parameter of a solitary wave of height
/// `height_m` in depth `depth_m` (off the beach) on a beach of slope `slope` (tan β):
/// S₀ = 1.521 tan β / sqrt(H/d). It is the Iribarren number's counterpart for a single wave:
/// the slope against the wave's steepness, with the wave's length taken from its shape (the
/// factor 1.521 is their normalisation of that length), so that it needs no period.
pub fn solitary_slope_parameter(slope: f64, height_m: f64, depth_m: f64) -> f64 {
    1.521 * slope / (height_m / depth_m).sqrt()
}

/// The type Grilli et al.'s (1997) bands give a solitary wave's slope parameter S₀: spilling
/// below 0.025, plunging below 0.3, collapsing below 0.37, surging (no breaking) above.
pub fn solitary_predicted_type(slope_parameter: f64) -> BreakerType {
    if slope_parameter < 0.025 {
        BreakerType::Spilling
    } else if slope_parameter < 0.3 {
        BreakerType::Plunging
    } else if slope_parameter < 0.37 {
        BreakerType::Collapsing
    } else {
        BreakerType::Surging
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_and_ting_kirby_cases() {
        let g = 9.81;
        // (slope, H, T, expected I_r, expected type)
        let cases = [
            (0.25, 0.30, 2.2, 1.25, BreakerType::Plunging),
            (0.25, 0.125, 2.2, 1.94, BreakerType::Collapsing),
            (0.125, 0.12, 0.91, 0.41, BreakerType::Spilling),
            (1.0 / 35.0, 0.125, 2.0, 0.20, BreakerType::Spilling),
            (1.0 / 35.0, 0.128, 5.0, 0.50, BreakerType::Plunging),
        ];
        for (slope, h, t, ir_expected, kind) in cases {
            let ir = iribarren(slope, h, t, g);
            println!(
                "slope {slope:.4}, H {h} m, T {t} s: Ir = {ir:.3} → {}",
                predicted_type(ir).name()
            );
            assert!((ir - ir_expected).abs() < 0.01, "{ir} vs {ir_expected}");
            assert_eq!(predicted_type(ir), kind);
        }
    }

    #[test]
    fn battjes_breaker_point_bands() {
        // The 1:4 collapsing case's steady breakers (H_b 0.135 m, T 2.2 s) sit in Battjes's
        // plunging band; the same beach with a 0.06 m breaker is past 2.0.
        let xi = |h_b: f64| iribarren(0.25, h_b, 2.2, 9.81);
        assert!((xi(0.135) - 1.87).abs() < 0.01, "{}", xi(0.135));
        assert_eq!(battjes_breaker_point_type(xi(0.135)), "plunging");
        assert_eq!(
            battjes_breaker_point_type(xi(0.06)),
            "collapsing_or_surging"
        );
        assert_eq!(battjes_breaker_point_type(0.39), "spilling");
        assert_eq!(battjes_breaker_point_type(0.4), "plunging");
        assert_eq!(battjes_breaker_point_type(2.0), "collapsing_or_surging");
    }

    #[test]
    fn grilli_solitary_bands() {
        // A 1:15 beach with H/d = 0.35 (cases/solitary_beach.toml) plunges; a 1:100 beach with
        // H/d = 0.4 spills (S₀ = 0.024), and steep beaches collapse and surge.
        let s0 = solitary_slope_parameter(1.0 / 15.0, 0.105, 0.3);
        assert!((s0 - 0.1714).abs() < 1e-4, "{s0}");
        assert_eq!(solitary_predicted_type(s0), BreakerType::Plunging);
        let gentle = solitary_slope_parameter(0.01, 0.4, 1.0);
        assert!((gentle - 0.0240).abs() < 1e-4, "{gentle}");
        assert_eq!(solitary_predicted_type(gentle), BreakerType::Spilling);
        assert_eq!(solitary_predicted_type(0.33), BreakerType::Collapsing);
        assert_eq!(solitary_predicted_type(0.4), BreakerType::Surging);
    }
}
