//! Complete elliptic integrals and Jacobi elliptic functions.
//!
//! Parameter convention: `m = k²` (never the modulus `k` or the modular angle),
//!
//! ```text
//! K(m) = ∫₀^{π/2} dθ / sqrt(1 − m sin²θ),    E(m) = ∫₀^{π/2} sqrt(1 − m sin²θ) dθ.
//! ```
//!
//! Both integrals come from the arithmetic–geometric mean (A&S 17.6):
//! start from `a₀ = 1`, `b₀ = sqrt(1 − m)`, `c₀ = sqrt(m)` and iterate
//!
//! ```text
//! a_{n+1} = (a_n + b_n)/2,   b_{n+1} = sqrt(a_n b_n),   c_{n+1} = (a_n − b_n)/2
//! ```
//!
//! until `c_N` is negligible; then `K = π / (2 a_N)` and
//! `E = K [1 − ½ Σ_{n=0}^{N} 2ⁿ c_n²]`. The difference `c_{n+1}` is evaluated
//! as `c_n² / (4 a_{n+1})` (equal to `(a_n − b_n)/2` because
//! `c_n² = a_n² − b_n²`), which avoids cancellation once `a_n ≈ b_n`.
//!
//! The Jacobi functions use the descending Landen transformation (A&S 16.4):
//! with the same sequence, `φ_N = 2ᴺ a_N u` and
//! `φ_{n−1} = ½ [φ_n + asin((c_n / a_n) sin φ_n)]`, giving `am(u) = φ₀`,
//! `sn = sin φ₀`, `cn = cos φ₀`. The delta amplitude is formed as
//! `dn = sqrt(cn² + (1 − m) sn²)`, an exact rewrite of `sqrt(1 − m sn²)` that
//! has no cancellation and no 0/0 at `u = K` (where the textbook ratio
//! `cos φ₀ / cos(φ₁ − φ₀)` degenerates when `m → 1`).
//!
//! Near `m = 1` the arguments of the arcsines approach one, where `asin` is
//! ill-conditioned. Because `1 − c_n/a_n = b_{n−1}/a_n` exactly, the distance
//! to one is known accurately and the arcsine is taken through
//! `asin(1 − w) = π/2 − 2 asin(sqrt(w/2))`. Together with entry points that
//! take `1 − m` directly (so that `b₀ = sqrt(1 − m)` is not polluted by the
//! rounding of `m`), this keeps the functions accurate for `1 − m` down to
//! `1e-12` and far below, as needed for long cnoidal waves.
//!
//! Inputs outside `0 ≤ m ≤ 1` are not supported and yield NaN.

use std::f64::consts::{FRAC_PI_2, PI};

/// Maximum number of AGM steps kept; convergence is quadratic so even
/// `1 − m ≈ 1e-300` needs fewer than 20.
const MAX_AGM_STEPS: usize = 40;

/// Stop once `c_N / a_N` falls below this (the brief's 1e-16, made relative).
const AGM_TOLERANCE: f64 = 1e-17;

/// The AGM sequence for one parameter `m`, reusable for many evaluations of
/// `sn`, `cn`, `dn` at the same `m` (e.g. a cnoidal free surface).
#[derive(Debug, Clone, PartialEq)]
pub struct JacobiElliptic {
    m: f64,
    one_minus_m: f64,
    /// Index of the last AGM level computed.
    levels: usize,
    a: [f64; MAX_AGM_STEPS + 1],
    c: [f64; MAX_AGM_STEPS + 1],
    /// `1 − c_n / a_n = b_{n−1} / a_n` for `n ≥ 1` (entry 0 unused).
    gap: [f64; MAX_AGM_STEPS + 1],
}

impl JacobiElliptic {
    /// Prepares the AGM sequence for parameter `m ∈ [0, 1]`; `None` otherwise.
    pub fn from_parameter(m: f64) -> Option<Self> {
        Self::from_pair(m, 1.0 - m)
    }

    /// Prepares the AGM sequence from the complementary parameter
    /// `one_minus_m = 1 − m ∈ [0, 1]`; `None` otherwise. Use this when `m` is
    /// so close to one that `m` itself cannot carry `1 − m` accurately.
    pub fn from_complement(one_minus_m: f64) -> Option<Self> {
        Self::from_pair(1.0 - one_minus_m, one_minus_m)
    }

    /// Builds the sequence from both `m` and `1 − m`, each supplied to full
    /// relative accuracy by the caller (they must sum to one up to rounding).
    pub(crate) fn from_pair(m: f64, one_minus_m: f64) -> Option<Self> {
        let valid = (0.0..=1.0).contains(&m)
            && (0.0..=1.0).contains(&one_minus_m)
            && (m + one_minus_m - 1.0).abs() <= 4.0 * f64::EPSILON;
        if !valid {
            return None;
        }
        let mut a = [0.0; MAX_AGM_STEPS + 1];
        let mut c = [0.0; MAX_AGM_STEPS + 1];
        let mut gap = [0.0; MAX_AGM_STEPS + 1];
        a[0] = 1.0;
        c[0] = m.sqrt();
        let mut b = one_minus_m.sqrt();
        let mut levels = 0;
        // For m = 1 (b₀ = 0) the sequence never converges; that case is
        // handled in closed form by the evaluators, so no steps are taken.
        if one_minus_m > 0.0 {
            while levels < MAX_AGM_STEPS && c[levels] > AGM_TOLERANCE * a[levels] {
                let a_prev = a[levels];
                let a_next = 0.5 * (a_prev + b);
                c[levels + 1] = c[levels] * c[levels] / (4.0 * a_next);
                gap[levels + 1] = b / a_next;
                b = (a_prev * b).sqrt();
                a[levels + 1] = a_next;
                levels += 1;
            }
        }
        Some(Self {
            m,
            one_minus_m,
            levels,
            a,
            c,
            gap,
        })
    }

    /// The parameter `m`.
    pub fn parameter(&self) -> f64 {
        self.m
    }

    /// The complementary parameter `1 − m`.
    pub fn complement(&self) -> f64 {
        self.one_minus_m
    }

    /// Complete integrals `(K(m), E(m))`; `K = ∞`, `E = 1` when `m = 1`.
    pub fn complete_integrals(&self) -> (f64, f64) {
        if self.one_minus_m == 0.0 {
            return (f64::INFINITY, 1.0);
        }
        let k = PI / (2.0 * self.a[self.levels]);
        let mut weighted_sum = 0.0;
        let mut weight = 1.0;
        for n in 0..=self.levels {
            weighted_sum += weight * self.c[n] * self.c[n];
            weight *= 2.0;
        }
        (k, k * (1.0 - 0.5 * weighted_sum))
    }

    /// Jacobi elliptic functions `(sn, cn, dn)` of argument `u` at this `m`.
    pub fn sn_cn_dn(&self, u: f64) -> (f64, f64, f64) {
        if self.one_minus_m == 0.0 {
            let sech = 1.0 / u.cosh();
            return (u.tanh(), sech, sech);
        }
        if self.m == 0.0 {
            return (u.sin(), u.cos(), 1.0);
        }
        let top = self.levels;
        let mut phi = 2f64.powi(top as i32) * self.a[top] * u;
        for n in (1..=top).rev() {
            let ratio = self.c[n] / self.a[n];
            phi = 0.5 * (phi + landen_asin(ratio, self.gap[n], phi));
        }
        let (sn, cn) = phi.sin_cos();
        let dn = (cn * cn + self.one_minus_m * sn * sn).sqrt();
        (sn, cn, dn)
    }
}

/// `asin(ratio · sin φ)` for `0 ≤ ratio < 1`, where `gap = 1 − ratio` is
/// supplied to full relative accuracy. When the argument is close to ±1 the
/// distance `w = 1 − |ratio sin φ|` is assembled from `gap` and
/// `1 − |sin φ| = 2 sin²(ψ/2)` (ψ the offset of φ from the nearest odd multiple
/// of π/2), both free of cancellation, and `asin(1 − w) = π/2 − 2 asin(√(w/2))`.
fn landen_asin(ratio: f64, gap: f64, phi: f64) -> f64 {
    let s = phi.sin();
    let x = ratio * s;
    if x.abs() <= 0.5 {
        return x.asin();
    }
    let turns = ((phi - FRAC_PI_2) / PI).round();
    let psi = phi - (FRAC_PI_2 + turns * PI);
    let half = (0.5 * psi).sin();
    let w = gap + ratio * 2.0 * half * half;
    let magnitude = FRAC_PI_2 - 2.0 * (0.5 * w).sqrt().min(1.0).asin();
    magnitude.copysign(x)
}

/// Complete elliptic integrals `(K(m), E(m))` for `0 ≤ m ≤ 1` by the AGM.
/// Returns `(∞, 1)` at `m = 1` and NaNs outside `[0, 1]`.
pub fn ellip_ke(m: f64) -> (f64, f64) {
    match JacobiElliptic::from_parameter(m) {
        Some(j) => j.complete_integrals(),
        None => (f64::NAN, f64::NAN),
    }
}

/// Complete elliptic integrals `(K(m), E(m))` given `one_minus_m = 1 − m`,
/// which keeps full accuracy when `m` is extremely close to one.
/// Returns `(∞, 1)` for `one_minus_m = 0` and NaNs outside `[0, 1]`.
pub fn ellip_ke_complement(one_minus_m: f64) -> (f64, f64) {
    match JacobiElliptic::from_complement(one_minus_m) {
        Some(j) => j.complete_integrals(),
        None => (f64::NAN, f64::NAN),
    }
}

/// Jacobi elliptic functions `(sn, cn, dn)` of argument `u` and parameter
/// `0 ≤ m ≤ 1` (`sin, cos, 1` at `m = 0`; `tanh, sech, sech` at `m = 1`).
/// Returns NaNs outside `[0, 1]`. For many evaluations at one `m`, build a
/// [`JacobiElliptic`] once instead.
pub fn ellipj(u: f64, m: f64) -> (f64, f64, f64) {
    match JacobiElliptic::from_parameter(m) {
        Some(j) => j.sn_cn_dn(u),
        None => (f64::NAN, f64::NAN, f64::NAN),
    }
}

/// Jacobi elliptic functions `(sn, cn, dn)` of argument `u`, with the
/// parameter given through `one_minus_m = 1 − m` for accuracy near `m = 1`.
pub fn ellipj_complement(u: f64, one_minus_m: f64) -> (f64, f64, f64) {
    match JacobiElliptic::from_complement(one_minus_m) {
        Some(j) => j.sn_cn_dn(u),
        None => (f64::NAN, f64::NAN, f64::NAN),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Leading terms of the expansion about m = 1 (A&S 17.3.26, 17.3.36),
    /// with ε = 1 − m; the neglected terms are O(ε² ln ε).
    fn near_one_reference(eps: f64) -> (f64, f64) {
        let half_log = 0.5 * (16.0 / eps).ln();
        let k = half_log + 0.25 * eps * (half_log - 1.0);
        let e = 1.0 + 0.25 * eps * (2.0 * half_log - 1.0);
        (k, e)
    }

    #[test]
    fn complete_integrals_match_reference_values() {
        let half_pi = FRAC_PI_2;
        let table = [
            (0.0, half_pi, half_pi),
            (0.5, 1.854_074_677_301_372, 1.350_643_881_047_675_5),
            (0.9, 2.578_092_113_348_173, 1.104_774_732_704_073_3),
            (0.99, 3.695_637_362_989_875, 1.015_993_545_025_224),
        ];
        let mut worst = 0.0_f64;
        for &(m, k_ref, e_ref) in &table {
            let (k, e) = ellip_ke(m);
            let err = (k - k_ref).abs().max((e - e_ref).abs());
            println!("m = {m}: K = {k:.16}, E = {e:.16}, error {err:.2e}");
            worst = worst.max(err);
        }
        println!("K/E worst error against tabulated values: {worst:.3e}");
        assert!(worst < 1e-12);

        let mut worst_near_one = 0.0_f64;
        for eps in [1e-6, 1e-9, 1e-12, 1e-30, 1e-100] {
            let (k_ref, e_ref) = near_one_reference(eps);
            let (k, e) = ellip_ke_complement(eps);
            let err = (k - k_ref).abs().max((e - e_ref).abs());
            println!("1 - m = {eps:e}: K = {k:.15}, E = {e:.15}, error {err:.2e}");
            if eps <= 1e-9 {
                worst_near_one = worst_near_one.max(err);
            }
        }
        // Through the plain-m entry point, using the exactly representable
        // difference 1 − m of the rounded parameter.
        let m = 1.0 - 1e-12;
        let (k_ref, e_ref) = near_one_reference(1.0 - m);
        let (k, e) = ellip_ke(m);
        let err = (k - k_ref).abs().max((e - e_ref).abs());
        println!("ellip_ke(1 - 1e-12): K = {k:.15}, error {err:.2e}");
        worst_near_one = worst_near_one.max(err);
        println!("K/E worst error near m = 1 (asymptotic reference): {worst_near_one:.3e}");
        assert!(worst_near_one < 1e-10);

        assert_eq!(ellip_ke(1.0), (f64::INFINITY, 1.0));
        assert_eq!(ellip_ke_complement(0.0), (f64::INFINITY, 1.0));
        assert!(ellip_ke(1.5).0.is_nan());
        assert!(ellip_ke(-0.1).0.is_nan());
    }

    #[test]
    fn jacobi_identities_hold_across_parameter_range() {
        // (m, 1 − m) pairs, each given to full accuracy.
        let params: Vec<(f64, f64)> = [0.0, 1e-6, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 0.999]
            .iter()
            .map(|&m| (m, 1.0 - m))
            .chain([1e-6, 1e-9, 1e-12].iter().map(|&q| (1.0 - q, q)))
            .collect();
        let mut worst_circle = 0.0_f64;
        let mut worst_delta = 0.0_f64;
        for &(m, q) in &params {
            let jac = JacobiElliptic::from_pair(m, q).unwrap();
            let (k, _) = jac.complete_integrals();
            let samples = 1201;
            for i in 0..samples {
                let u = -3.0 * k + 6.0 * k * i as f64 / (samples - 1) as f64;
                let (sn, cn, dn) = if q < 1e-3 {
                    ellipj_complement(u, q)
                } else {
                    ellipj(u, m)
                };
                worst_circle = worst_circle.max((sn * sn + cn * cn - 1.0).abs());
                worst_delta = worst_delta.max((dn * dn + m * sn * sn - 1.0).abs());
            }
        }
        println!("max |sn² + cn² − 1| = {worst_circle:.3e}");
        println!("max |dn² + m sn² − 1| = {worst_delta:.3e}");
        assert!(worst_circle < 1e-13);
        assert!(worst_delta < 1e-13);
    }

    #[test]
    fn jacobi_functions_match_reference_values() {
        // (1 − m, u, sn, cn, dn), references from 40-digit arithmetic (mpmath).
        let table: [(f64, f64, f64, f64, f64); 16] = [
            (
                0.5,
                0.3,
                0.293_412_733_168_455_4,
                0.955_985_861_827_787_1,
                0.978_240_504_174_361_2,
            ),
            (
                0.5,
                1.7,
                0.994_047_700_740_860_5,
                0.108_945_714_242_500_53,
                0.711_290_787_460_307_5,
            ),
            (
                0.5,
                -4.1,
                0.377_416_342_758_240_2,
                -0.926_043_683_753_090_9,
                0.963_731_524_912_149_6,
            ),
            (
                0.5,
                12.5,
                -0.941_173_539_336_655_2,
                -0.337_923_613_931_482_3,
                0.746_388_762_258_822_3,
            ),
            (
                0.1,
                0.3,
                0.291_732_047_818_618_5,
                0.956_500_084_827_782_6,
                0.960_938_692_658_381_7,
            ),
            (
                0.1,
                1.7,
                0.952_230_542_108_018_7,
                0.305_380_082_318_197_2,
                0.428_872_119_878_410_86,
            ),
            (
                0.1,
                -4.1,
                -0.793_565_362_464_448_6,
                -0.608_485_016_657_492,
                0.658_201_043_714_609_6,
            ),
            (
                0.1,
                12.5,
                0.992_033_652_597_575_4,
                0.125_973_140_446_339_4,
                0.338_056_665_224_222_2,
            ),
            (
                1e-9,
                0.3,
                0.291_312_612_455_783_8,
                0.956_627_911_898_971_5,
                0.956_627_911_943_326_8,
            ),
            (
                1e-9,
                1.7,
                0.935_409_070_783_822_1,
                0.353_567_349_023_275_3,
                0.353_567_350_260_649_4,
            ),
            (
                1e-9,
                -4.1,
                -0.999_450_843_936_534_6,
                0.033_136_242_311_838_067,
                0.033_136_257_384_485,
            ),
            (
                1e-9,
                12.5,
                0.999_999_999_659_685_8,
                -2.608_885_435_517_300_7e-5,
                4.099_546_707_728_552e-5,
            ),
            (
                1e-30,
                0.3,
                0.291_312_612_451_590_9,
                0.956_627_911_900_248_3,
                0.956_627_911_900_248_3,
            ),
            (
                1e-30,
                1.7,
                0.935_409_070_603_099,
                0.353_567_349_501_402,
                0.353_567_349_501_402,
            ),
            (
                1e-30,
                -4.1,
                -0.999_450_843_687_797_3,
                0.033_136_249_814_215_53,
                0.033_136_249_814_215_53,
            ),
            (
                1e-30,
                12.5,
                0.999_999_999_972_224_1,
                7.453_306_344_053_831e-6,
                7.453_306_344_053_831e-6,
            ),
        ];
        let mut worst_abs = 0.0_f64;
        let mut worst_dn_rel = 0.0_f64;
        for &(q, u, sn_ref, cn_ref, dn_ref) in &table {
            let (sn, cn, dn) = ellipj_complement(u, q);
            worst_abs = worst_abs
                .max((sn - sn_ref).abs())
                .max((cn - cn_ref).abs())
                .max((dn - dn_ref).abs());
            worst_dn_rel = worst_dn_rel.max((dn / dn_ref - 1.0).abs());
        }
        println!(
            "sn/cn/dn vs 40-digit references: worst abs error {worst_abs:.3e}, worst dn rel. error {worst_dn_rel:.3e}"
        );
        assert!(worst_abs < 1e-13);
        assert!(worst_dn_rel < 1e-10);
    }

    #[test]
    fn quarter_period_values() {
        let mut worst = 0.0_f64;
        for q in [1.0, 0.9, 0.5, 0.1, 1e-2, 1e-4, 1e-6, 1e-9, 1e-12] {
            let (k, _) = ellip_ke_complement(q);
            let (sn, cn, dn) = ellipj_complement(k, q);
            let err = (sn - 1.0).abs().max(cn.abs()).max((dn - q.sqrt()).abs());
            println!(
                "1 - m = {q:e}: sn(K) - 1 = {:.2e}, cn(K) = {cn:.2e}, dn(K) - sqrt(1-m) = {:.2e}",
                sn - 1.0,
                dn - q.sqrt()
            );
            worst = worst.max(err);
        }
        println!("quarter-period worst error: {worst:.3e}");
        assert!(worst < 1e-12);
    }

    #[test]
    fn limiting_cases_are_exact() {
        for u in [-2.0, -0.3, 0.0, 0.7, 5.0] {
            let (sn, cn, dn) = ellipj(u, 0.0);
            assert_eq!((sn, cn, dn), (f64::sin(u), f64::cos(u), 1.0));
            let (sn, cn, dn) = ellipj(u, 1.0);
            assert_eq!(sn, f64::tanh(u));
            assert_eq!(cn, 1.0 / f64::cosh(u));
            assert_eq!(dn, cn);
        }
        assert!(ellipj(0.3, 1.2).0.is_nan());
    }

    #[test]
    fn small_parameter_expansion() {
        // sn(u|m) = sin u − (m/4)(u − sin u cos u) cos u + O(m²) (A&S 16.13.1).
        let first_order = |u: f64, m: f64| u.sin() - 0.25 * m * (u - u.sin() * u.cos()) * u.cos();
        let mut worst_scaled = 0.0_f64;
        let mut errors = Vec::new();
        for m in [1e-2, 1e-3, 1e-4] {
            let (k, _) = ellip_ke(m);
            let mut worst = 0.0_f64;
            for i in 0..=600 {
                let u = -3.0 * k + 6.0 * k * i as f64 / 600.0;
                worst = worst.max((ellipj(u, m).0 - first_order(u, m)).abs());
            }
            println!(
                "m = {m:e}: max |sn − first-order expansion| = {worst:.3e} (m² = {:.1e})",
                m * m
            );
            worst_scaled = worst_scaled.max(worst / (m * m));
            errors.push(worst);
        }
        println!("largest error / m² = {worst_scaled:.3}");
        // The remainder must scale like m² (ratio ≈ 100 per decade).
        let decade_ratio = errors[1] / errors[2];
        println!("error ratio between m = 1e-3 and 1e-4: {decade_ratio:.1}");
        assert!(worst_scaled < 5.0);
        assert!(decade_ratio > 50.0 && decade_ratio < 200.0);
    }

    #[test]
    fn near_one_matches_hyperbolic_expansion() {
        // sn(u|m) ≈ tanh u + ((1−m)/4)(sinh u cosh u − u) sech² u (A&S 16.15.1),
        // with a remainder O((1−m)² cosh⁴ u), negligible for |u| ≤ 3 here.
        let mut worst = 0.0_f64;
        for q in [1e-12, 1e-20, 1e-40] {
            let jac = JacobiElliptic::from_complement(q).unwrap();
            for i in 0..=300 {
                let u = -3.0 + 6.0 * i as f64 / 300.0;
                let sech2 = 1.0 / (u.cosh() * u.cosh());
                let reference = u.tanh() + 0.25 * q * (u.sinh() * u.cosh() - u) * sech2;
                worst = worst.max((jac.sn_cn_dn(u).0 - reference).abs());
            }
        }
        println!("near m = 1, max |sn − hyperbolic expansion| = {worst:.3e}");
        assert!(worst < 1e-14);
    }
}
