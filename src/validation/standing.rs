//! A standing wave in front of a vertical end wall (thesis §3.2.1).

use super::fit::{ARRAY_MIN_GAUGES, first_harmonic, last_periods, split_waves};
use super::{Check, CheckError, Report, linear_wave};
use crate::case::Case;
use crate::output::timeseries::GaugeRecord;
use std::f64::consts::{PI, TAU};

/// A standing wave in front of a vertical wall (thesis §3.2.1), by the least-squares
/// separation of incident and reflected waves (Mansard & Funke 1980) with the wavenumber free:
/// the first harmonic Z(x) of every gauge over the last three periods is fitted by
/// P e^{ik'(x − x_w)} + Q e^{−ik'(x − x_w)}. Antinode height 2(|P| + |Q|) against 2H,
/// node–antinode spacing π/(2k') against L/4; the node height, the reflection coefficient
/// |Q|/|P| and where the antinode nearest the wall lies are reported. Three periods: the
/// reflected wave at full height reaches the farthest gauge only a few periods before the
/// case's end.
pub fn standing(case: &Case, record: &GaugeRecord) -> Result<Report, CheckError> {
    let (height, period, _depth, k, _) = linear_wave(case)?;
    if case.absorber.is_some() || case.flume.beach.is_some() {
        return Err(CheckError::NotApplicable(
            "this check is for a flume that ends in a vertical wall".into(),
        ));
    }
    let omega = TAU / period;
    let wavelength = TAU / k;
    let x_wall = case.flume.length_m;
    let window = last_periods(record, period, 3.0)?;
    let mut report = Report::new("standing wave at a vertical wall (linear theory)", window);
    report.figure("linear wavelength L", wavelength, "m");
    // (x, Z) with the signal ≈ Re{Z e^{−iωt}}.
    let mut points = Vec::new();
    for (x, eta) in record.elevation_gauges() {
        let z = first_harmonic(&record.t_s, eta, omega, window)
            .ok_or_else(|| CheckError::TooShort(format!("gauge at x = {x} m")))?;
        report.figure(
            format!("first-harmonic height at x = {x:.3} m"),
            2.0 * z.norm(),
            "m",
        );
        points.push((x, z));
    }
    if points.len() < ARRAY_MIN_GAUGES {
        return Err(CheckError::NotApplicable(format!(
            "need at least {ARRAY_MIN_GAUGES} elevation gauges"
        )));
    }
    // k' over ±40 % of the linear k.
    let split = split_waves(&points, x_wall, [0.6 * k, 1.4 * k])
        .ok_or_else(|| CheckError::TooShort("the fit failed".into()))?;
    let k_fit = split.k_rad_m;
    let incident = split.going.norm();
    let reflected = split.back.norm();
    // |Z|² = |P|² + |Q|² + 2 Re(P Q̄ e^{2ik'(x − x_w)}): antinodes where 2k'(x_w − x) = arg(P Q̄).
    let arg = (split.going * split.back.conj()).arg();
    let mut distance = arg.rem_euclid(TAU) / (2.0 * k_fit);
    if distance > PI / (2.0 * k_fit) {
        distance -= PI / k_fit;
    }
    report.checks.push(Check::new(
        "antinode height 2(|P| + |Q|)",
        2.0 * (incident + reflected),
        2.0 * height,
        0.10,
        "m",
    ));
    if let Some(&(x, z)) = points.iter().max_by(|a, b| a.0.total_cmp(&b.0)) {
        report.checks.push(Check::new(
            format!("first-harmonic height at the gauge nearest the wall, x = {x:.3} m"),
            2.0 * z.norm(),
            2.0 * height,
            0.10,
            "m",
        ));
    }
    report.checks.push(Check::new(
        "node-to-antinode spacing π/(2k')",
        PI / (2.0 * k_fit),
        wavelength / 4.0,
        0.05,
        "m",
    ));
    report.figure("incident height 2|P|", 2.0 * incident, "m");
    report.figure("reflected height 2|Q|", 2.0 * reflected, "m");
    report.figure("reflection coefficient |Q|/|P|", reflected / incident, "");
    report.figure(
        "node height 2||P| − |Q||",
        2.0 * (incident - reflected).abs(),
        "m",
    );
    report.figure(
        "antinode nearest the wall: distance from the wall",
        distance,
        "m",
    );
    report.figure("fit residual / signal (rms)", split.misfit, "");
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::super::test_record as record;
    use super::*;

    /// A standing wave with reflection coefficient 0.9 and the linear k: antinode 1.9 H,
    /// spacing L/4, first antinode at the wall.
    #[test]
    fn standing_checks_on_a_synthetic_wave() {
        let case = Case::load(std::path::Path::new("cases/wall_reflection.toml"), &[]).unwrap();
        let (h, period, _d, k, _) = linear_wave(&case).unwrap();
        let omega = TAU / period;
        let xw = case.flume.length_m;
        let t: Vec<f64> = (0..400).map(|i| i as f64 * 0.0475).collect();
        let cols = case
            .output
            .gauges_x_m
            .iter()
            .map(|&x| {
                let c = t
                    .iter()
                    .map(|t| {
                        let s = k * (xw - x);
                        Some(0.5 * h * ((-s - omega * t).cos() + 0.9 * (s - omega * t).cos()))
                    })
                    .collect();
                (format!("eta_{x:.3}"), c)
            })
            .collect();
        let r = standing(&case, &record(&t, cols)).unwrap();
        println!("{r:#?}");
        let antinode = &r.checks[0];
        assert!((antinode.measured - 1.9 * h).abs() < 1e-6, "{antinode:?}");
        let spacing = &r.checks[2];
        assert!(spacing.error().abs() < 1e-6, "{spacing:?}");
        let ratio = r
            .figures
            .iter()
            .find(|f| f.what.starts_with("reflection"))
            .unwrap();
        assert!((ratio.value - 0.9).abs() < 1e-6, "{ratio:?}");
        let at = r
            .figures
            .iter()
            .find(|f| f.what.starts_with("antinode nearest"))
            .unwrap();
        assert!(at.value.abs() < 1e-6, "{at:?}");
    }
}
