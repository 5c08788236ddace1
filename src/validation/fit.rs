//! The fits and wave statistics the checks share: the first harmonic of a record, zero-crossing
//! statistics over a window, values under the crests, a line through points, phases unwrapped
//! along the flume, and the window of the last whole periods.

use super::CheckError;
use crate::diagnostics::{WaveStats, wave_stats};
use crate::output::timeseries::GaugeRecord;
use nalgebra::Complex;
use std::f64::consts::TAU;

/// Least-squares fit of `c + a cos ωt + b sin ωt` to the wet samples with t in `window`.
/// Returns `(mean, amplitude, phase)` with the signal ≈ mean + amplitude·cos(ωt − phase),
/// or `None` with fewer than 8 samples.
pub fn harmonic_fit(
    t_s: &[f64],
    y: &[Option<f64>],
    omega_rad_s: f64,
    window_s: [f64; 2],
) -> Option<(f64, f64, f64)> {
    let mut m = nalgebra::Matrix3::<f64>::zeros();
    let mut r = nalgebra::Vector3::<f64>::zeros();
    let mut n = 0usize;
    for (t, v) in t_s.iter().zip(y) {
        let Some(v) = v else { continue };
        if *t < window_s[0] || *t > window_s[1] {
            continue;
        }
        let basis = nalgebra::Vector3::new(1.0, (omega_rad_s * t).cos(), (omega_rad_s * t).sin());
        m += basis * basis.transpose();
        r += basis * *v;
        n += 1;
    }
    if n < 8 {
        return None;
    }
    let c = m.lu().solve(&r)?;
    Some((c[0], c[1].hypot(c[2]), c[2].atan2(c[1])))
}

/// The first harmonic along a line of gauges as two waves, one travelling towards +x and one
/// coming back, by the least-squares separation of Mansard & Funke (1980) with the
/// wavenumber free: Z(x) = P e^{ik(x − x₀)} + Q e^{−ik(x − x₀)}, Z the complex first harmonic
/// of a gauge with its signal ≈ Re{Z e^{−iωt}}.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaveSplit {
    /// P, the wave travelling towards +x, m.
    pub going: Complex<f64>,
    /// Q, the wave travelling towards −x, m.
    pub back: Complex<f64>,
    /// The wavenumber that fits best, rad/m.
    pub k_rad_m: f64,
    /// What the two waves leave of the gauges' Z, relative (rms over rms).
    pub misfit: f64,
}

/// Gauges a [`WaveSplit`] needs at least.
pub const ARRAY_MIN_GAUGES: usize = 4;

/// Fits [`WaveSplit`] to `points` (x in m, Z) about `x0_m`: k scanned over `k_range_rad_m` in
/// 400 steps, then refined by golden section around the best (a k at which the two waves look
/// alike on the gauges, as where all stand whole half-wavelengths apart, is skipped). `None`
/// with fewer than [`ARRAY_MIN_GAUGES`] points, or when no k tells the two waves apart (the
/// gauges all at one place).
pub fn split_waves(
    points: &[(f64, Complex<f64>)],
    x0_m: f64,
    k_range_rad_m: [f64; 2],
) -> Option<WaveSplit> {
    if points.len() < ARRAY_MIN_GAUGES {
        return None;
    }
    // For a given k: P, Q and the squared residual. Normal equations of the two unknowns:
    // [[n, s̄], [s, n]] (P, Q) = (Σ e^{−ikξ} Z, Σ e^{ikξ} Z), ξ = x − x₀, s = Σ e^{2ikξ}.
    let fit = |k: f64| -> Option<(Complex<f64>, Complex<f64>, f64)> {
        let n = points.len() as f64;
        let [mut s, mut b0, mut b1] = [Complex::default(); 3];
        for (x, z) in points {
            let e = Complex::from_polar(1.0, k * (x - x0_m));
            s += e * e;
            b0 += e.conj() * z;
            b1 += e * z;
        }
        let det = n * n - s.norm_sqr();
        if det <= 1e-9 * n * n {
            return None;
        }
        let going = (b0 * n - s.conj() * b1) / det;
        let back = (b1 * n - s * b0) / det;
        let residual = points
            .iter()
            .map(|(x, z)| {
                let e = Complex::from_polar(1.0, k * (x - x0_m));
                (going * e + back * e.conj() - z).norm_sqr()
            })
            .sum();
        Some((going, back, residual))
    };
    let residual = |k: f64| fit(k).map_or(f64::INFINITY, |f| f.2);
    let [lo, hi] = k_range_rad_m;
    let steps = 400;
    let step = (hi - lo) / steps as f64;
    let (best, _) = (0..=steps)
        .map(|i| lo + step * i as f64)
        .filter_map(|k| fit(k).map(|f| (k, f.2)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let (mut lo, mut hi) = (best - step, best + step);
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let a = hi - ratio * (hi - lo);
        let b = lo + ratio * (hi - lo);
        if residual(a) < residual(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let k = 0.5 * (lo + hi);
    let (going, back, residual) = fit(k)?;
    let norm: f64 = points.iter().map(|(_, z)| z.norm_sqr()).sum();
    Some(WaveSplit {
        going,
        back,
        k_rad_m: k,
        misfit: (residual / norm).sqrt(),
    })
}

/// The complex first harmonic Z of `eta` over `window_s` (signal ≈ Re{Z e^{−iωt}}), from
/// [`harmonic_fit`].
pub fn first_harmonic(
    t_s: &[f64],
    eta: &[Option<f64>],
    omega_rad_s: f64,
    window_s: [f64; 2],
) -> Option<Complex<f64>> {
    let (_, amplitude, phase) = harmonic_fit(t_s, eta, omega_rad_s, window_s)?;
    Some(Complex::from_polar(amplitude, phase))
}

/// [`split_waves`] of `gauges` (`(x, record)`, each read by [`first_harmonic`] over
/// `window_s`), k over ±20 % of `k_guess_rad_m`; the gauges without a fit are left out.
pub fn incident_wave(
    t_s: &[f64],
    gauges: &[(f64, &[Option<f64>])],
    omega_rad_s: f64,
    k_guess_rad_m: f64,
    window_s: [f64; 2],
) -> Option<WaveSplit> {
    let points: Vec<(f64, Complex<f64>)> = gauges
        .iter()
        .filter_map(|(x, eta)| Some((*x, first_harmonic(t_s, eta, omega_rad_s, window_s)?)))
        .collect();
    split_waves(&points, 0.0, [0.8 * k_guess_rad_m, 1.2 * k_guess_rad_m])
}

/// Zero-crossing heights and the mean period over `window` (at most `last_waves` waves).
pub(super) fn crossing_stats(
    t_s: &[f64],
    eta: &[Option<f64>],
    window_s: [f64; 2],
) -> Option<WaveStats> {
    let (t, e): (Vec<f64>, Vec<Option<f64>>) = t_s
        .iter()
        .zip(eta)
        .filter(|(t, _)| **t <= window_s[1])
        .map(|(t, e)| (*t, *e))
        .unzip();
    wave_stats(&t, &e, window_s[0], 10_000)
}

/// Mean of the column at the times of the crests of `eta` within `window` (each crest the
/// highest wet sample between two up-crossings of the mean level).
pub(super) fn mean_at_crests(
    t_s: &[f64],
    eta: &[Option<f64>],
    column: &[Option<f64>],
    window_s: [f64; 2],
) -> Option<f64> {
    let idx: Vec<usize> = (0..t_s.len())
        .filter(|&i| t_s[i] >= window_s[0] && t_s[i] <= window_s[1] && eta[i].is_some())
        .collect();
    if idx.len() < 3 {
        return None;
    }
    let mean = idx.iter().map(|&i| eta[i].unwrap_or(0.0)).sum::<f64>() / idx.len() as f64;
    let ups: Vec<usize> = idx
        .windows(2)
        .filter(|w| eta[w[0]].unwrap_or(0.0) < mean && eta[w[1]].unwrap_or(0.0) >= mean)
        .map(|w| w[1])
        .collect();
    let mut values = Vec::new();
    for w in ups.windows(2) {
        let crest = idx
            .iter()
            .copied()
            .filter(|&i| i >= w[0] && i < w[1])
            .max_by(|&a, &b| eta[a].unwrap_or(0.0).total_cmp(&eta[b].unwrap_or(0.0)))?;
        if let Some(v) = column[crest] {
            values.push(v);
        }
    }
    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
}

/// Least-squares line through `(x, y)`: `(slope, intercept)`.
pub(super) fn line_fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let slope = sxy / sxx;
    (slope, my - slope * mx)
}

/// Unwraps phases measured at increasing x so that each step is the one nearest `k Δx`
/// (the choice of the multiple of 2π only; the fit then measures k).
pub(super) fn unwrap_phases(points: &[(f64, f64)], k_guess: f64) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(points.len());
    for &(x, p) in points {
        let q = match out.last() {
            None => p,
            Some(&(x0, p0)) => {
                let expected = p0 + k_guess * (x - x0);
                p + TAU * ((expected - p) / TAU).round()
            }
        };
        out.push((x, q));
    }
    out
}

/// The last `periods` whole periods of the record.
pub(super) fn last_periods(
    record: &GaugeRecord,
    period_s: f64,
    periods: f64,
) -> Result<[f64; 2], CheckError> {
    let end = record.t_s.last().copied().unwrap_or(0.0);
    let start = end - periods * period_s;
    if start <= 0.0 {
        return Err(CheckError::TooShort(format!(
            "{periods} periods of {period_s} s need more than the {end:.2} s recorded"
        )));
    }
    Ok([start, end])
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn harmonic_fit_recovers_amplitude_and_phase() {
        let t: Vec<f64> = (0..4000).map(|i| i as f64 * 0.01).collect();
        let y: Vec<Option<f64>> = t
            .iter()
            .map(|t| Some(0.2 + 0.03 * (2.0 * t - 0.7).cos() + 0.005 * (4.0 * t).sin()))
            .collect();
        let (m, a, p) = harmonic_fit(&t, &y, 2.0, [0.0, 10.0 * PI]).unwrap();
        assert!((m - 0.2).abs() < 1e-4 && (a - 0.03).abs() < 1e-4 && (p - 0.7).abs() < 1e-3);
    }

    #[test]
    fn an_array_of_gauges_splits_the_incident_wave_from_the_reflected_one() {
        // 30 mm travelling towards +x and 3 mm back (k = 6.8 rad/m, T = 0.8 s), over a mean
        // level sinking 5 mm and a bound second harmonic of 3 mm: gauges 0.1 m apart over
        // one wavelength, sampled every 0.02 s for 4 periods.
        let (omega, k) = (TAU / 0.8, 6.8);
        let t: Vec<f64> = (0..=160).map(|i| 5.0 + i as f64 * 0.02).collect();
        let xs: Vec<f64> = (0..10).map(|i| 1.7 + 0.1 * i as f64).collect();
        let records: Vec<Vec<Option<f64>>> = xs
            .iter()
            .map(|x| {
                t.iter()
                    .map(|t| {
                        let incident = 0.015 * (omega * t - k * x).cos();
                        let reflected = 0.0015 * (omega * t + k * x + 0.4).cos();
                        let bound = 0.0015 * (2.0 * (omega * t - k * x)).cos();
                        Some(incident + reflected + bound - 0.005 * (t - 5.0) / 3.2)
                    })
                    .collect()
            })
            .collect();
        let gauges: Vec<(f64, &[Option<f64>])> = xs
            .iter()
            .zip(&records)
            .map(|(x, r)| (*x, r.as_slice()))
            .collect();
        let f = incident_wave(&t, &gauges, omega, 6.76, [5.0, 8.2]).unwrap();
        println!("{f:?}");
        assert!((2.0 * f.going.norm() - 0.030).abs() < 0.0003, "{f:?}");
        assert!((f.back.norm() / f.going.norm() - 0.1).abs() < 0.01, "{f:?}");
        assert!((f.k_rad_m - k).abs() < 0.02 * k, "{f:?}");
        // Too few gauges, or all in one place: no fit.
        assert!(incident_wave(&t, &gauges[..3], omega, 6.76, [5.0, 8.2]).is_none());
        let same = vec![gauges[0]; 5];
        assert!(incident_wave(&t, &same, omega, 6.76, [5.0, 8.2]).is_none());
    }
}
