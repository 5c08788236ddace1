//! A 2D check of the 3D code (issue 26): a narrow 3D tank with slip side walls and a
//! linear piston against the same case run by the 2D code, wave height by wave height.
//!
//! Each gauge is read over its own window, between the first wave at full height and the
//! first of the end wall's reflection, both at the linear group velocity c_g: from
//! (ramp + 1) T + (x − x_p)/c_g (the ramp's waves have passed, and one period more) to
//! (2 x_w − x_p − x)/c_g (the ramp's first wave there and back from the wall at x_w), or the
//! record's end. Heights are zero-crossing means over the window's whole waves, in both runs
//! alike; the 3D height at every gauge within two wavelengths of the piston must lie within
//! 5 % of the 2D one. Gauges further off are reported, not checked.
//!
//! A single gauge's height also holds what rides on the wave there: the little the end wall
//! sends back, the free second harmonic beating with the bound one, the start-up's transients
//! (the 2D twin of `tank3d_piston` reads from 31.5 to 39.9 mm along 0.8–2.6 m). Where the case
//! has at least four gauges within half a wavelength of 1 L or 2 L, the report also gives the
//! incident wave's height there from all of them ([`incident_wave`]: the first harmonic split
//! into the waves going and coming back), read over the window the array's gauges share, for
//! both runs: figures, beside the checks.

use super::fit::{ARRAY_MIN_GAUGES, crossing_stats, incident_wave};
use super::{Check, CheckError, Report, linear_wave};
use crate::case::{Case, WaveTheory};
use crate::output::timeseries::GaugeRecord;
use crate::waves::linear::PaddleKind;
use std::f64::consts::TAU;

/// The 3D height within this fraction of the 2D one (the bar).
pub const HEIGHT_TOLERANCE: f64 = 0.05;

/// Gauges up to this many wavelengths from the piston are checked (the "at 2 L").
pub const CHECKED_WAVELENGTHS: f64 = 2.0;

/// Whole waves a gauge's window must hold to be measured.
pub const MIN_WAVES: f64 = 3.0;

/// Where gauge arrays are read, in wavelengths from the piston.
pub const ARRAY_STATIONS_L: [f64; 2] = [1.0, 2.0];

/// How far an array's gauges may stand from its station, in wavelengths.
pub const ARRAY_HALF_LENGTH_L: f64 = 0.5;

/// Says whether `case` is a 3D tank that this check applies to: a width, a linear piston, no
/// absorber, no beach or bars (the 2D code has neither across the tank).
pub fn applies(case: &Case) -> bool {
    case.flume.width_m.is_some()
        && case.absorber.is_none()
        && case.flume.beach.is_none()
        && case.flume.bars.is_empty()
        && case
            .wavemaker
            .as_ref()
            .is_some_and(|w| w.paddle == PaddleKind::Piston && w.theory == WaveTheory::Linear)
}

/// The 2D twin of a 3D case: the same file without its width and its planes z = const (the
/// 3D tank starts at the piston's face; the 2D flume keeps its dry strip behind the paddle).
pub fn twin_2d(case: &Case) -> Result<Case, CheckError> {
    if !applies(case) {
        return Err(CheckError::NotApplicable(
            "the 2D check is for a 3D tank with a linear piston, no absorber, beach or bars".into(),
        ));
    }
    let mut twin = case.clone();
    twin.name = format!("{}_2d", case.name);
    twin.flume.width_m = None;
    twin.output.planes_z_m.clear();
    twin.surf.stations_z_m.clear();
    Ok(twin)
}

/// Each gauge's window `[start, end]` in s (see the module doc), or `None` when it would hold
/// fewer than [`MIN_WAVES`] periods of a record ending at `end_s`.
pub fn windows(
    case: &Case,
    gauges_x_m: &[f64],
    end_s: f64,
) -> Result<Vec<Option<[f64; 2]>>, CheckError> {
    let (_, period, depth, _, x_paddle) = linear_wave(case)?;
    let w = case
        .wavemaker
        .as_ref()
        .expect("linear_wave found the wavemaker");
    let group_velocity =
        crate::waves::linear::group_velocity(period, depth, case.fluid.gravity_m_s2)?;
    let x_wall = case.flume.length_m;
    Ok(gauges_x_m
        .iter()
        .map(|&x| {
            let start = (w.ramp_periods + 1.0) * period + (x - x_paddle) / group_velocity;
            let end = ((2.0 * x_wall - x_paddle - x) / group_velocity).min(end_s);
            (end - start >= MIN_WAVES * period).then_some([start, end])
        })
        .collect())
}

/// The 3D run's heights against the 2D twin's, gauge by gauge (module doc). `record_3d` and
/// `record_2d` are the two runs' `gauges.csv`; the 3D run's largest volume drift is reported.
pub fn against_2d(
    case: &Case,
    record_3d: &GaugeRecord,
    record_2d: &GaugeRecord,
    volume_drift_max_3d: f64,
) -> Result<Report, CheckError> {
    let (height, period, _, k, x_paddle) = linear_wave(case)?;
    let wavelength = TAU / k;
    let end = |r: &GaugeRecord| r.t_s.last().copied().unwrap_or(0.0);
    let end_s = end(record_3d).min(end(record_2d));
    let gauges_3d = record_3d.elevation_gauges();
    let gauges_2d = record_2d.elevation_gauges();
    let xs: Vec<f64> = gauges_3d.iter().map(|(x, _)| *x).collect();
    let windows = windows(case, &xs, end_s)?;
    let mut report = Report::new(
        "3D narrow tank against the 2D code (linear piston)",
        [0.0, end_s],
    );
    report.figure("linear wavelength L", wavelength, "m");
    report.figure("paddle's height H", height, "m");
    report.figure(
        "3D run's largest volume drift",
        100.0 * volume_drift_max_3d,
        "%",
    );
    let mut first = f64::INFINITY;
    for ((x, eta_3d), window) in gauges_3d.iter().zip(&windows) {
        let reach = (x - x_paddle) / wavelength;
        // A gauge placed "at 2 L" by hand may stand a little beyond it.
        let checked = reach <= CHECKED_WAVELENGTHS + 0.05;
        let Some(window) = window else {
            if checked {
                return Err(CheckError::TooShort(format!(
                    "the gauge at x = {x} m ({reach:.2} L) sees fewer than {MIN_WAVES} waves \
                     between the ramp and the end wall's reflection in {end_s:.2} s"
                )));
            }
            continue;
        };
        let Some((_, eta_2d)) = gauges_2d.iter().find(|(x2, _)| (x2 - x).abs() < 1e-9) else {
            return Err(CheckError::NotApplicable(format!(
                "the 2D run has no gauge at x = {x} m"
            )));
        };
        let stats = |r: &GaugeRecord, eta: &[Option<f64>], run: &str| {
            crossing_stats(&r.t_s, eta, *window).ok_or_else(|| {
                CheckError::TooShort(format!("no whole wave at x = {x} m in the {run} run"))
            })
        };
        let h3 = stats(record_3d, eta_3d, "3D")?;
        let h2 = stats(record_2d, eta_2d, "2D")?;
        first = first.min(window[0]);
        let what = format!(
            "3D wave height at x = {x:.3} m ({reach:.2} L) against 2D, t = {:.2}–{:.2} s",
            window[0], window[1]
        );
        report.figure(
            format!("2D wave height at x = {x:.3} m"),
            h2.mean_height_m,
            "m",
        );
        report.figure(
            format!("3D waves at x = {x:.3} m (2D: {})", h2.waves),
            h3.waves as f64,
            "",
        );
        if checked {
            report.checks.push(Check::new(
                what,
                h3.mean_height_m,
                h2.mean_height_m,
                HEIGHT_TOLERANCE,
                "m",
            ));
        } else {
            report.figure(what, h3.mean_height_m, "m");
        }
    }
    let arrays = Arrays {
        x_paddle,
        wavelength,
        period,
        xs: &xs,
        windows: &windows,
    };
    for reach in ARRAY_STATIONS_L {
        arrays.report(&mut report, reach, record_3d, record_2d);
    }
    if report.checks.is_empty() {
        return Err(CheckError::NotApplicable(format!(
            "no elevation gauge within {CHECKED_WAVELENGTHS} wavelengths ({:.2} m) of the piston",
            CHECKED_WAVELENGTHS * wavelength
        )));
    }
    report.window_s = [first, end_s];
    Ok(report)
}

/// The gauges and windows of [`against_2d`], read as arrays (module doc).
struct Arrays<'a> {
    x_paddle: f64,
    wavelength: f64,
    period: f64,
    xs: &'a [f64],
    windows: &'a [Option<[f64; 2]>],
}

impl Arrays<'_> {
    /// Figures of the incident wave at `reach` wavelengths from the piston, from the gauges
    /// within [`ARRAY_HALF_LENGTH_L`] of it that have a window, over the part of it they all
    /// share; nothing when fewer than [`ARRAY_MIN_GAUGES`] or that part under [`MIN_WAVES`].
    fn report(
        &self,
        report: &mut Report,
        reach: f64,
        record_3d: &GaugeRecord,
        record_2d: &GaugeRecord,
    ) {
        let centre = self.x_paddle + reach * self.wavelength;
        let members: Vec<(f64, [f64; 2])> = self
            .xs
            .iter()
            .zip(self.windows)
            .filter(|(x, _)| (*x - centre).abs() <= ARRAY_HALF_LENGTH_L * self.wavelength + 1e-9)
            .filter_map(|(x, w)| w.map(|w| (*x, w)))
            .collect();
        let start = members
            .iter()
            .map(|m| m.1[0])
            .fold(f64::NEG_INFINITY, f64::max);
        let end = members.iter().map(|m| m.1[1]).fold(f64::INFINITY, f64::min);
        if members.len() < ARRAY_MIN_GAUGES || end - start < MIN_WAVES * self.period {
            return;
        }
        let fit = |record: &GaugeRecord| {
            let gauges: Vec<(f64, &[Option<f64>])> = record
                .elevation_gauges()
                .into_iter()
                .filter(|(x, _)| members.iter().any(|m| (m.0 - x).abs() < 1e-9))
                .collect();
            incident_wave(
                &record.t_s,
                &gauges,
                TAU / self.period,
                TAU / self.wavelength,
                [start, end],
            )
        };
        let (Some(a3), Some(a2)) = (fit(record_3d), fit(record_2d)) else {
            return;
        };
        let label = format!(
            "incident wave by the {} gauges within L/2 of x = {centre:.3} m ({reach} L), \
             t = {start:.2}–{end:.2} s",
            members.len()
        );
        let (h2, h3) = (2.0 * a2.going.norm(), 2.0 * a3.going.norm());
        report.figure(format!("{label}: height, 2D"), h2, "m");
        report.figure(format!("{label}: height, 3D"), h3, "m");
        report.figure(
            format!("{label}: 3D against 2D"),
            100.0 * (h3 / h2 - 1.0),
            "%",
        );
        for (run, a) in [("2D", a2), ("3D", a3)] {
            let reflection = a.back.norm() / a.going.norm();
            report.figure(format!("{label}: reflection, {run}"), reflection, "");
            report.figure(format!("{label}: wavenumber, {run}"), a.k_rad_m, "rad/m");
            report.figure(format!("{label}: misfit, {run}"), a.misfit, "");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn case(name: &str) -> Case {
        let file = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("cases")
            .join(name);
        Case::load(&file, &[]).expect("the case loads")
    }

    /// A record of sinusoidal waves of height `h` (m) at each gauge, sampled every 0.02 s.
    fn record(case: &Case, heights: &[f64], end_s: f64) -> GaugeRecord {
        let w = case.wavemaker.as_ref().unwrap();
        let omega = TAU / w.period_s;
        let t: Vec<f64> = (0..=(end_s / 0.02).round() as usize)
            .map(|i| i as f64 * 0.02)
            .collect();
        let xs = &case.output.gauges_x_m;
        GaugeRecord {
            names: xs.iter().map(|x| format!("eta_{x}")).collect(),
            columns: xs
                .iter()
                .zip(heights)
                .map(|(x, h)| {
                    t.iter()
                        .map(|t| Some(0.5 * h * (omega * t - 6.7 * x).sin()))
                        .collect()
                })
                .collect(),
            t_s: t,
        }
    }

    #[test]
    fn the_narrow_piston_tank_is_checked_against_its_2d_twin_and_the_bars_tank_is_not() {
        let narrow = case("tank3d_piston.toml");
        assert!(applies(&narrow));
        let twin = twin_2d(&narrow).unwrap();
        assert_eq!(twin.flume.width_m, None);
        assert!(twin.output.planes_z_m.is_empty());
        assert_eq!(twin.output.gauges_x_m, narrow.output.gauges_x_m);
        assert!(!applies(&case("tank3d_bars.toml")));
        assert!(!applies(&case("dam_break3d.toml")));
        assert!(twin_2d(&case("tank3d_bars.toml")).is_err());
    }

    #[test]
    fn each_gauge_is_read_between_the_ramp_and_the_end_walls_reflection() {
        let narrow = case("tank3d_piston.toml");
        let w = windows(&narrow, &[1.23, 2.16, 4.0], 8.5).unwrap();
        // T = 0.8 s, d = 0.25 m: c_g = 0.7184 m/s; the piston at 0.3 m, the wall at 4.5 m.
        let c_g = 0.7184;
        let [a, b] = w[0].unwrap();
        assert!((a - (3.0 * 0.8 + 0.93 / c_g)).abs() < 0.01, "start {a}");
        assert_eq!(b, 8.5, "the record ends before the reflection at 1 L");
        let [a, b] = w[1].unwrap();
        assert!((a - (2.4 + 1.86 / c_g)).abs() < 0.01, "start {a}");
        assert_eq!(b, 8.5, "the reflection reaches 2 L at 9.10 s");
        assert!(
            w[2].is_none(),
            "4 m: the reflection comes before three whole waves"
        );
        println!("windows at 1 L and 2 L: {:?} {:?}", w[0], w[1]);
    }

    #[test]
    fn a_3d_height_within_5_percent_of_2d_passes_and_one_7_percent_off_fails() {
        let mut narrow = case("tank3d_piston.toml");
        narrow.output.gauges_x_m = vec![1.23, 2.16];
        let r2 = record(&narrow, &[0.0345, 0.0327], 8.5);
        let near = record(&narrow, &[0.0335, 0.0317], 8.5);
        let report = against_2d(&narrow, &near, &r2, 0.01).unwrap();
        assert_eq!(report.checks.len(), 2);
        for c in &report.checks {
            println!("{}: {:.5} against {:.5}", c.what, c.measured, c.target);
            assert!(c.passed);
        }
        let off = record(&narrow, &[0.0345, 0.0304], 8.5);
        let report = against_2d(&narrow, &off, &r2, 0.01).unwrap();
        assert!(report.checks[0].passed && !report.checks[1].passed);
        assert!(
            (report.checks[1].error() + 0.0703).abs() < 0.005,
            "{}",
            report.checks[1].error()
        );
        // Too short a record: the 2 L gauge sees no three waves before the end.
        let short = record(&narrow, &[0.0345, 0.0327], 6.0);
        assert!(matches!(
            against_2d(&narrow, &short, &short, 0.0),
            Err(CheckError::TooShort(_))
        ));
    }

    #[test]
    fn the_case_s_gauge_arrays_give_the_incident_wave_at_1_and_2_wavelengths() {
        let narrow = case("tank3d_piston.toml");
        let n = narrow.output.gauges_x_m.len();
        let r2 = record(&narrow, &vec![0.0320; n], 8.5);
        let r3 = record(&narrow, &vec![0.0345; n], 8.5);
        let report = against_2d(&narrow, &r3, &r2, 0.01).unwrap();
        let figures: Vec<_> = report
            .figures
            .iter()
            .filter(|f| f.what.starts_with("incident wave") && f.what.ends_with("3D against 2D"))
            .collect();
        assert_eq!(figures.len(), 2, "an array at 1 L and one at 2 L");
        for f in figures {
            println!("{}: {:+.3} %", f.what, f.value);
            assert!((f.value - 100.0 * (0.0345 / 0.0320 - 1.0)).abs() < 0.05);
        }
    }
}
