//! Cnoidal waves from a piston (Goring/Zhang).

use super::fit::{crossing_stats, last_periods, mean_at_crests};
use super::{Check, CheckError, Report};
use crate::case::{Case, WaveTheory};
use crate::output::timeseries::GaugeRecord;
use crate::waves::cnoidal::CnoidalWave;
use crate::waves::linear::PaddleKind;

/// A cnoidal piston (Goring/Zhang): at the gauge two wavelengths out, the zero-crossing height
/// against H and the period against T; the crest elevation against cnoidal theory's η_c.
pub fn cnoidal(case: &Case, record: &GaugeRecord) -> Result<Report, CheckError> {
    let w = case
        .wavemaker
        .as_ref()
        .filter(|w| w.theory == WaveTheory::Cnoidal && w.paddle == PaddleKind::Piston)
        .ok_or_else(|| CheckError::NotApplicable("this check is for a cnoidal piston".into()))?;
    let depth = case
        .water
        .first()
        .map(|r| r.depth_m)
        .ok_or_else(|| CheckError::NotApplicable("the case has no water".into()))?;
    let wave = CnoidalWave::new(w.height_m, w.period_s, depth, case.fluid.gravity_m_s2)?;
    let window = last_periods(record, w.period_s, 5.0)?;
    let mut report = Report::new("cnoidal piston", window);
    report.figure("cnoidal wavelength L", wave.wavelength_m, "m");
    report.figure("Ursell number", wave.ursell_number(), "");
    let target_x = w.x_m + 2.0 * wave.wavelength_m;
    let (x, eta) = record
        .elevation_gauges()
        .into_iter()
        .min_by(|a, b| (a.0 - target_x).abs().total_cmp(&(b.0 - target_x).abs()))
        .filter(|(x, _)| (x - target_x).abs() <= 0.25 * wave.wavelength_m)
        .ok_or_else(|| {
            CheckError::NotApplicable(format!(
                "no elevation gauge within L/4 of two wavelengths out (x = {target_x:.2} m)"
            ))
        })?;
    // Cnoidal theory is for the constant depth: over a beach the wave shoals (and the beach
    // reflects), so the height there is no check of the paddle.
    let bed = case.flume.bed_y_at(x);
    if bed.abs() > 0.01 * depth {
        return Err(CheckError::NotApplicable(format!(
            "the gauge two wavelengths out (x = {x:.2} m) stands where the bed is {bed:.3} m high, \
             not in the {depth} m depth cnoidal theory is for"
        )));
    }
    let stats = crossing_stats(&record.t_s, eta, window)
        .ok_or_else(|| CheckError::TooShort(format!("no whole wave at x = {x} m")))?;
    report.checks.push(Check::new(
        format!(
            "wave height at x = {x:.3} m ({:.2} L)",
            (x - w.x_m) / wave.wavelength_m
        ),
        stats.mean_height_m,
        w.height_m,
        0.05,
        "m",
    ));
    // The period: the output interval resolves an up-crossing to a fraction of a sample; 1 %
    // of 2 s is one output interval of the case.
    report.checks.push(Check::new(
        format!("wave period at x = {x:.3} m"),
        stats.mean_period_s,
        w.period_s,
        0.01,
        "s",
    ));
    // Crests: mean of the highest wet sample of each wave, measured from the still water.
    let crest = mean_crest(&record.t_s, eta, window);
    if let Some(c) = crest {
        report.figure("mean crest elevation above still water", c, "m");
    }
    report.figure("cnoidal theory's crest elevation η_c", wave.crest_m(), "m");
    if let Some(c) = crest {
        report.figure("crest / η_c", c / wave.crest_m(), "");
        // η_c is measured from the wave's mean level; a flume that lost water has its mean
        // level below the still water it started from.
        report.figure("mean level over the window", stats.mean_level_m, "m");
        report.figure(
            "crest above the mean level / η_c",
            (c - stats.mean_level_m) / wave.crest_m(),
            "",
        );
    }
    Ok(report)
}

/// Mean of the highest wet sample between successive up-crossings of the window's mean level.
fn mean_crest(t_s: &[f64], eta: &[Option<f64>], window_s: [f64; 2]) -> Option<f64> {
    mean_at_crests(t_s, eta, eta, window_s)
}

#[cfg(test)]
mod tests {
    use super::super::test_record as record;
    use super::*;

    /// A cnoidal record from theory at the case's gauges: height, period and crest all agree.
    #[test]
    fn cnoidal_checks_on_a_theoretical_wave() {
        let case = Case::load(std::path::Path::new("cases/piston_cnoidal.toml"), &[]).unwrap();
        let w = case.wavemaker.as_ref().unwrap();
        let wave = CnoidalWave::new(w.height_m, w.period_s, 0.4, 9.81).unwrap();
        let t: Vec<f64> = (0..1200).map(|i| i as f64 * 0.02).collect();
        let cols = case
            .output
            .gauges_x_m
            .iter()
            .map(|&x| {
                let c = t.iter().map(|&t| Some(wave.eta_m(x - w.x_m, t))).collect();
                (format!("eta_{x:.3}"), c)
            })
            .collect();
        let r = cnoidal(&case, &record(&t, cols)).unwrap();
        println!("{r:#?}");
        assert!(r.passed());
        assert!(r.checks[0].error().abs() < 0.005, "{:?}", r.checks[0]);
        let crest = r.figures.iter().find(|f| f.what == "crest / η_c").unwrap();
        assert!((crest.value - 1.0).abs() < 0.01, "{crest:?}");
    }

    /// Ting & Kirby's gauge two wavelengths out (x = 8 m) is over the 1:35 slope (toe at
    /// 4.3 m, bed 0.106 m high): the waves shoal there, so the check does not apply.
    #[test]
    fn a_gauge_over_the_beach_is_no_check_of_the_paddle() {
        let case = Case::load(std::path::Path::new("cases/ting_kirby_spilling.toml"), &[]).unwrap();
        let t: Vec<f64> = (0..1800).map(|i| i as f64 * 0.02).collect();
        let cols = case
            .output
            .gauges_x_m
            .iter()
            .map(|&x| (format!("eta_{x:.3}"), t.iter().map(|_| Some(0.0)).collect()))
            .collect();
        match cnoidal(&case, &record(&t, cols)) {
            Err(CheckError::NotApplicable(why)) => assert!(why.contains("bed is"), "{why}"),
            other => panic!("expected not applicable, got {other:?}"),
        }
    }
}
