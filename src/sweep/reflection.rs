//! The reflection coefficient of a run from two elevation gauges (Goda & Suzuki 1976).
//!
//! Over every whole wave period of `gauges.csv` after the reflection has come back (at least
//! three) the first harmonic of each gauge, η ≈ Re{Z e^{−iωt}}, is split as
//! Z(x) = P e^{ikx} + Q e^{−ikx} with the linear wavenumber k of the period and the depth at the
//! gauges; K_r = |Q|/|P|. Two gauges give the two
//! unknowns exactly; the separation is ill-posed where sin(kΔx) → 0, so only pairs with
//! 0.05 < Δx/L < 0.45 are used (Goda & Suzuki's range), the one with the largest |sin kΔx|.
//!
//! The gauges must stand in water of the paddle's depth (the flat part of the flume, before the
//! beach's toe), at least one depth from the paddle and from the toe (the evanescent modes
//! there), and the record must
//! be long enough for the reflection to have come back: the ramp, then the way to the end of
//! the flume and back to the gauges at the group velocity, then the three periods analysed.
//! Otherwise there is no coefficient (an empty cell).

use crate::case::{Case, WaveTheory};
use crate::output::timeseries::GaugeRecord;
use crate::validation::harmonic_fit;
use nalgebra::Complex;
use std::f64::consts::TAU;

/// The fewest periods of the record the harmonics are fitted over. All the whole periods
/// after the reflection's return are used: at the plunging points of the 1:4 sweep, windows of
/// three periods gave K_r from 0.005 to 0.126 (ξ₀ = 1.23) and 0.039 to 0.095 (1.48) depending on
/// where they ended, the last one at the low end; at ξ₀ ≥ 1.98 they agreed within 0.04.
const MIN_PERIODS_FITTED: f64 = 3.0;

/// The coefficient and the gauge pair it came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reflection {
    pub coefficient: f64,
    pub gauges_x_m: [f64; 2],
    /// The stretch of the record fitted, s.
    pub window_s: [f64; 2],
}

/// K_r of a run of `case` from its gauge `record`, or why there is none.
pub fn reflection(case: &Case, record: &GaugeRecord) -> Result<Reflection, String> {
    let w = case.wavemaker.as_ref().ok_or("the case has no wavemaker")?;
    if w.theory == WaveTheory::Solitary || w.period_s <= 0.0 {
        return Err("the waves have no period".into());
    }
    let depth = case
        .paddle_depth_m()
        .filter(|d| *d > 0.0)
        .ok_or("no water at the paddle")?;
    let g = case.fluid.gravity_m_s2;
    let k = crate::waves::linear::wavenumber(w.period_s, depth, g).map_err(|e| e.to_string())?;
    let wavelength = TAU / k;
    let omega = TAU / w.period_s;
    let group_velocity =
        crate::waves::linear::group_velocity(w.period_s, depth, g).map_err(|e| e.to_string())?;
    // Gauges in the paddle's depth, clear of the paddle and of the beach's toe by a depth
    // (the evanescent modes of either).
    let paddle_depth = |x: f64| {
        let d = case.still_level_at(x).unwrap_or(0.0) - case.bed_y_at(x);
        (d - depth).abs() <= 0.01 * depth
    };
    let flat: Vec<(f64, &[Option<f64>])> = record
        .elevation_gauges()
        .into_iter()
        .filter(|(x, _)| *x >= w.x_m + depth && paddle_depth(*x) && paddle_depth(*x + depth))
        .collect();
    if flat.len() < 2 {
        return Err("fewer than two gauges in the flat part of the flume".into());
    }
    let mut best: Option<(f64, usize, usize)> = None;
    for i in 0..flat.len() {
        for j in i + 1..flat.len() {
            let spacing = (flat[j].0 - flat[i].0).abs() / wavelength;
            let conditioning = (TAU * spacing).sin().abs();
            if spacing > 0.05 && spacing < 0.45 && best.is_none_or(|b| conditioning > b.0) {
                best = Some((conditioning, i, j));
            }
        }
    }
    let (_, i, j) = best.ok_or_else(|| {
        format!("no two flat-part gauges are 0.05–0.45 wavelengths (L = {wavelength:.2} m) apart")
    })?;
    let (x1, x2) = (flat[i].0, flat[j].0);
    let end = record.t_s.last().copied().unwrap_or(0.0);
    let back_s = 2.0 * (case.flume.length_m - x1.min(x2)) / group_velocity;
    let back_at = w.ramp_periods * w.period_s + back_s;
    let needed = back_at + MIN_PERIODS_FITTED * w.period_s;
    if end < needed {
        return Err(format!(
            "the record ends at {end:.1} s; the reflection needs {needed:.1} s"
        ));
    }
    let periods = ((end - back_at) / w.period_s).floor();
    let window = [end - periods * w.period_s, end];
    let harmonic = |eta: &[Option<f64>]| -> Result<Complex<f64>, String> {
        let (_, amplitude, phase) = harmonic_fit(&record.t_s, eta, omega, window)
            .ok_or("too few wet samples at a gauge")?;
        Ok(Complex::from_polar(amplitude, phase))
    };
    let (z1, z2) = (harmonic(flat[i].1)?, harmonic(flat[j].1)?);
    let (incident, reflected) = separate(k, x1, z1, x2, z2);
    if incident.norm() <= 0.0 {
        return Err("no incident wave at the gauges".into());
    }
    Ok(Reflection {
        coefficient: reflected.norm() / incident.norm(),
        gauges_x_m: [x1, x2],
        window_s: window,
    })
}

/// Solves Z₁ = P e^{ikx₁} + Q e^{−ikx₁}, Z₂ = P e^{ikx₂} + Q e^{−ikx₂} for (P, Q).
fn separate(
    k: f64,
    x1: f64,
    z1: Complex<f64>,
    x2: f64,
    z2: Complex<f64>,
) -> (Complex<f64>, Complex<f64>) {
    let e = |x: f64| Complex::from_polar(1.0, k * x);
    // det = e^{ik(x₁−x₂)} − e^{−ik(x₁−x₂)} = 2i sin k(x₁ − x₂).
    let det = e(x1) / e(x2) - e(x2) / e(x1);
    let p = (z1 / e(x2) - z2 / e(x1)) / det;
    let q = (e(x1) * z2 - e(x2) * z1) / det;
    (p, q)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A partial standing wave with K_r = 0.3 sampled at two of the 1:4 case's gauges.
    #[test]
    fn recovers_a_known_reflection() {
        let case = Case::load(std::path::Path::new("cases/collapsing_slope025.toml"), &[]).unwrap();
        let w = case.wavemaker.as_ref().unwrap();
        let depth = case.paddle_depth_m().unwrap();
        let k =
            crate::waves::linear::wavenumber(w.period_s, depth, case.fluid.gravity_m_s2).unwrap();
        let omega = TAU / w.period_s;
        let (a, kr, phase) = (0.06, 0.3, 0.8);
        let t: Vec<f64> = (0..2000).map(|i| i as f64 * 0.04).collect();
        // The reflection `kr_at(t)` of the wave at time t.
        let column = |x: f64, kr_at: &dyn Fn(f64) -> f64| -> Vec<Option<f64>> {
            t.iter()
                .map(|&t| {
                    let incident = a * (k * x - omega * t).cos();
                    let reflected = kr_at(t) * a * (-k * x - omega * t + phase).cos();
                    Some(0.01 + incident + reflected)
                })
                .collect()
        };
        let xs = [2.1, 4.1, 5.9, 7.4];
        let record_of = |kr_at: &dyn Fn(f64) -> f64| GaugeRecord {
            t_s: t.clone(),
            names: xs.iter().map(|x| format!("eta_{x:.3}")).collect(),
            columns: xs.iter().map(|&x| column(x, kr_at)).collect(),
        };
        let record = record_of(&|_| kr);
        let r = reflection(&case, &record).unwrap();
        assert!((r.coefficient - kr).abs() < 1e-3, "{r:?}");
        // Every whole period after the reflection's return is fitted, not the last three: a
        // reflection of 0.2 over the first half of that stretch and 0.4 over the second reads
        // as their mean (the last three periods alone would read 0.4).
        let [from, to] = r.window_s;
        let periods = (to - from) / w.period_s;
        assert!(
            periods > 20.0 && (periods - periods.round()).abs() < 1e-9,
            "{periods}"
        );
        let middle = to - (0.5 * periods).floor() * w.period_s;
        let stepped = reflection(&case, &record_of(&|t| if t < middle { 0.2 } else { 0.4 }));
        let stepped = stepped.unwrap().coefficient;
        assert!((stepped - 0.3).abs() < 0.02, "{stepped}");
        // 7.4 m is on the beach and 5.9 m at its toe; only 2.1 and 4.1 are clear of both.
        assert_eq!(r.gauges_x_m, [2.1, 4.1]);
        // Too short a record: no coefficient.
        let short = GaugeRecord {
            t_s: t[..200].to_vec(),
            names: record.names.clone(),
            columns: record.columns.iter().map(|c| c[..200].to_vec()).collect(),
        };
        assert!(reflection(&case, &short).unwrap_err().contains("needs"));
    }

    #[test]
    fn separation_inverts_the_two_wave_sum() {
        let (k, p, q) = (2.0, Complex::new(0.3, -0.1), Complex::new(-0.05, 0.02));
        let z = |x: f64| p * Complex::from_polar(1.0, k * x) + q * Complex::from_polar(1.0, -k * x);
        let (pp, qq) = separate(k, 0.4, z(0.4), 1.1, z(1.1));
        assert!((pp - p).norm() < 1e-12 && (qq - q).norm() < 1e-12);
    }
}
