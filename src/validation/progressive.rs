//! Progressive waves from a linear paddle into an absorbing end (thesis §3.2).

use super::fit::{
    crossing_stats, harmonic_fit, last_periods, line_fit, mean_at_crests, unwrap_phases,
};
use super::{Check, CheckError, Report, linear_wave};
use crate::case::Case;
use crate::output::timeseries::GaugeRecord;
use std::f64::consts::TAU;

/// Progressive waves from a linear paddle into an absorbing end (thesis §3.2): height at every
/// gauge within `reach_wavelengths` of the paddle, wavelength from the phase of the fundamental
/// along those gauges, the first-harmonic u(z) of the probes against linear theory, the height
/// decay per wavelength, and the volume drift over the run.
pub fn progressive(
    case: &Case,
    record: &GaugeRecord,
    volume_drift_max: f64,
    simulated_s: f64,
) -> Result<Report, CheckError> {
    let (height, period, depth, k, x_paddle) = linear_wave(case)?;
    if simulated_s / period < 20.0 - 1e-6 {
        return Err(CheckError::TooShort(format!(
            "the volume bar is over 20 periods; the run covers {:.1}",
            simulated_s / period
        )));
    }
    let omega = TAU / period;
    let wavelength = TAU / k;
    let reach = 4.0;
    let window = last_periods(record, period, 5.0)?;
    let mut report = Report::new("progressive waves (flap or piston, linear theory)", window);
    report.figure("linear wavelength L", wavelength, "m");
    report.figure("kh", k * depth, "");
    let gauges: Vec<(f64, &[Option<f64>])> = record
        .elevation_gauges()
        .into_iter()
        .filter(|(x, _)| *x - x_paddle <= reach * wavelength + 1e-9)
        .collect();
    if gauges.len() < 3 {
        return Err(CheckError::NotApplicable(format!(
            "need three elevation gauges within {reach} wavelengths ({:.2} m) of the paddle",
            reach * wavelength
        )));
    }
    // Heights (zero-crossing, the whole waves of the window) and phases.
    let mut phases = Vec::new();
    let mut log_heights = Vec::new();
    for (x, eta) in &gauges {
        let stats = crossing_stats(&record.t_s, eta, window)
            .ok_or_else(|| CheckError::TooShort(format!("no whole wave at x = {x} m")))?;
        report.checks.push(Check::new(
            format!(
                "wave height at x = {x:.3} m ({:.2} L)",
                (x - x_paddle) / wavelength
            ),
            stats.mean_height_m,
            height,
            0.05,
            "m",
        ));
        log_heights.push(((x - x_paddle) / wavelength, stats.mean_height_m.ln()));
        let (_, _, phase) = harmonic_fit(&record.t_s, eta, omega, window)
            .ok_or_else(|| CheckError::TooShort(format!("gauge at x = {x} m")))?;
        phases.push((*x, phase));
    }
    let (k_measured, _) = line_fit(&unwrap_phases(&phases, k));
    report.checks.push(Check::new(
        "wavelength from the phase along the gauges",
        TAU / k_measured,
        wavelength,
        0.03,
        "m",
    ));
    let (decay, _) = line_fit(&log_heights);
    report.figure(
        "height change per wavelength (fit of ln H over the gauges)",
        100.0 * (decay.exp() - 1.0),
        "%",
    );
    // Probes: first harmonic of u against a σ cosh(k y)/sinh(k d), y above the bed; and the
    // value under the crests of the gauge at the probes' x.
    let probes = record.u_probes();
    if !probes.is_empty() {
        let x_probe = probes[0].0;
        let eta = record
            .elevation_gauges()
            .into_iter()
            .find(|(x, _)| (x - x_probe).abs() < 1e-6)
            .map(|(_, e)| e);
        let a_local = eta
            .and_then(|e| harmonic_fit(&record.t_s, e, omega, window))
            .map(|f| f.1);
        let mut worst: Option<Check> = None;
        for (x, y, u) in &probes {
            let Some((mean, amplitude, _)) = harmonic_fit(&record.t_s, u, omega, window) else {
                continue;
            };
            let theory = 0.5 * height * omega * (k * y).cosh() / (k * depth).sinh();
            let c = Check::new(
                format!("u1 amplitude at x = {x:.3} m, {y:.2} m above the bed"),
                amplitude,
                theory,
                0.10,
                "m/s",
            );
            report.figure(
                format!("u1 amplitude/theory at y = {y:.2} m"),
                c.measured / c.target,
                "",
            );
            report.figure(format!("mean u1 at y = {y:.2} m"), mean, "m/s");
            if let Some(crest) = eta.and_then(|e| mean_at_crests(&record.t_s, e, u, window)) {
                report.figure(format!("u1 under the crests at y = {y:.2} m"), crest, "m/s");
                report.figure(
                    format!("(u1 under the crests − mean u1)/theory at y = {y:.2} m"),
                    (crest - mean) / theory,
                    "",
                );
            }
            if worst
                .as_ref()
                .is_none_or(|w| c.error().abs() > w.error().abs())
            {
                worst = Some(c);
            }
        }
        // Linear waves carry g H²/(8c) m²/s onshore (Stokes drift); in a closed flume a
        // uniform current returns it, which the mean u1 of the probes should show.
        let celerity = omega / k;
        report.figure(
            "return current −g H²/(8 c d) of linear theory",
            -case.fluid.gravity_m_s2 * height * height / (8.0 * celerity * depth),
            "m/s",
        );
        if let Some(mut w) = worst {
            w.what = format!("u1(z) under a crest, worst probe: {}", w.what);
            report.checks.push(w);
        }
        if let Some(a) = a_local {
            report.figure(
                "first-harmonic height 2a at the probes' gauge",
                2.0 * a,
                "m",
            );
        }
    }
    report.figure("simulated", simulated_s, "s");
    report.figure("periods simulated", simulated_s / period, "");
    report.checks.push(Check::below(
        "volume drift max |V/V0 - 1| over the run",
        volume_drift_max,
        0.005,
        "",
    ));
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::super::test_record as record;
    use super::*;

    /// A linear progressive wave, sampled like the flap case's gauges and probes, passes;
    /// the same with a wavelength 5 % long fails the wavelength check only.
    #[test]
    fn progressive_checks_on_a_synthetic_wave() {
        let case = Case::load(std::path::Path::new("cases/flap_deep_water.toml"), &[]).unwrap();
        let (h, period, d, k, xp) = linear_wave(&case).unwrap();
        let omega = TAU / period;
        let t: Vec<f64> = (0..4000).map(|i| i as f64 * 0.0455).collect();
        let make = |kk: f64| {
            let mut cols = Vec::new();
            for &x in &case.output.gauges_x_m {
                let c = t
                    .iter()
                    .map(|t| Some(0.5 * h * (kk * (x - xp) - omega * t).cos()))
                    .collect();
                cols.push((format!("eta_{x:.3}"), c));
            }
            for p in &case.output.probes_m {
                let c = t
                    .iter()
                    .map(|t| {
                        let amp = 0.5 * h * omega * (k * p[1]).cosh() / (k * d).sinh();
                        Some(amp * (kk * (p[0] - xp) - omega * t).cos())
                    })
                    .collect();
                cols.push((format!("u_{:.3}_{:.3}", p[0], p[1]), c));
            }
            record(&t, cols)
        };
        let good = progressive(&case, &make(k), 0.001, 182.0).unwrap();
        for c in &good.checks {
            assert!(c.passed, "{c:?}");
        }
        let long = progressive(&case, &make(k / 1.05), 0.001, 182.0).unwrap();
        let failed: Vec<&Check> = long.checks.iter().filter(|c| !c.passed).collect();
        assert_eq!(failed.len(), 1, "{failed:?}");
        assert!(failed[0].what.starts_with("wavelength"));
        assert!(
            (failed[0].error() - 0.05).abs() < 1e-3,
            "{}",
            failed[0].error()
        );
    }
}
