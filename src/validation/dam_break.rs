//! The collapse of a water column against Martin & Moyce (1952), n² = 2: a column a wide and
//! 2a high at the left wall of a dry, flat flume at least 4a long.
//!
//! Compared up to the moment the measured front would meet a far wall at x = 4a (t = 0.28 s
//! for a = 0.146 m, T ≈ 3.25): the surge front Z = x/a against T = t·sqrt(2g/a) for T ≤ 3,
//! raw and with the experiment's time origin fitted or taken from Lethe's dam-break example
//! (which advances its simulated T by 0.175 for the release of the gate); the front speed on
//! T ∈ [1.4, 3] by least squares; the residual column H = h/(2a) at the left wall against
//! τ = t·sqrt(g/a); the volume drift. Everything after that moment is ignored, so the figures
//! of a run do not depend on how long it went on.

use super::{Check, CheckError, Report};
use crate::case::Case;
use crate::diagnostics::Integrals;

/// Front position Z = x/a against T = t·sqrt(2g/a), Martin & Moyce's Table 2 (first two
/// columns; the last two are Lethe's transcription, for cross-checking).
const FRONT_TABLE: &str =
    include_str!("../../assets/validation/martin_moyce_1952_n2_surge_front.csv");
/// Residual column H = h/(2a) against τ = t·sqrt(g/a), their Table 6.
const COLUMN_TABLE: &str =
    include_str!("../../assets/validation/martin_moyce_1952_n2_column_height.csv");

/// The front is compared up to this T.
const FRONT_END_T: f64 = 3.0;
/// The front speed is fitted from this T to [`FRONT_END_T`].
const SPEED_FROM_T: f64 = 1.4;
/// The time-origin shift is searched on 0, 0.01, …, this.
const SHIFT_SEARCH_STEPS: usize = 40;
const SHIFT_SEARCH_STEP_T: f64 = 0.01;
/// Lethe's release time, added to its simulated T before comparing with this table.
const PUBLISHED_SHIFT_T: f64 = 0.175;
/// The end of the comparison for the reference set-up (a = 0.146 m, g = 9.81 m/s²), where the
/// front reaches the far wall; scaled with sqrt(a/g) for another column.
const IMPACT_REF_S: f64 = 0.28;
const A_REF_M: f64 = 0.146;
const G_REF_M_S2: f64 = 9.81;

/// The bars.
const SPEED_TOLERANCE: f64 = 0.05;
const FRONT_ERROR_MAX: f64 = 0.10;
const SHIFT_MAX_T: f64 = 0.3;
const COLUMN_ERROR_LIMIT: f64 = 0.05;
const VOLUME_DRIFT_LIMIT: f64 = 0.01;

/// What the dam-break check reads of a run: four columns of its `timeseries.csv`, one entry
/// per output time, in time order.
#[derive(Debug, Clone, Default)]
pub struct DamBreakSeries {
    pub t_s: Vec<f64>,
    /// Largest x of the main body of water, m.
    pub front_x_m: Vec<f64>,
    /// Top of the water at the left wall, m.
    pub left_wall_height_m: Vec<f64>,
    pub volume_m2: Vec<f64>,
    /// Particles in the run (the summary's count), reported when known.
    pub particles: Option<usize>,
}

impl DamBreakSeries {
    /// The series of the integrals a run returns in memory.
    pub fn from_integrals(series: &[Integrals], particles: Option<usize>) -> Self {
        Self {
            t_s: series.iter().map(|m| m.t_s).collect(),
            front_x_m: series.iter().map(|m| m.front_x_m).collect(),
            left_wall_height_m: series.iter().map(|m| m.left_wall_height_m).collect(),
            volume_m2: series.iter().map(|m| m.volume_m2).collect(),
            particles,
        }
    }
}

/// Width a of the case's dam-break column, or why the case is not Martin & Moyce's n² = 2
/// set-up: no wavemaker, one water region with a flat surface, starting at the left wall,
/// 2a deep, on a flat floor, in a flume at least 4a long (so that the front runs to T = 3
/// before it meets the far wall).
pub fn column_width(case: &Case) -> Result<f64, CheckError> {
    let refuse = |why: String| Err(CheckError::NotApplicable(why));
    if case.wavemaker.is_some() {
        return refuse("a case with a wavemaker is not a dam break".into());
    }
    let Some(column) = case.water.first() else {
        return refuse("the case has no water".into());
    };
    let length = case.flume.length_m;
    if column.x_start_m.abs() > 1e-9 {
        return refuse(format!(
            "not a dam-break column: the first water region starts at x = {} m, not at the left wall x = 0",
            column.x_start_m
        ));
    }
    let a = column.x_end_m - column.x_start_m;
    if column.x_end_m >= length - 1e-9 {
        return refuse(format!(
            "not a dam-break column: the first water region spans the flume (x = 0–{} m in a {length} m flume)",
            column.x_end_m
        ));
    }
    if case.water.len() > 1 {
        return refuse(format!(
            "not Martin & Moyce's set-up: {} water regions, where their column stands alone on a dry floor",
            case.water.len()
        ));
    }
    if (column.depth_m / (2.0 * a) - 1.0).abs() > 1e-3 {
        return refuse(format!(
            "not Martin & Moyce's n² = 2 column: {} m deep and {a} m wide, where the table needs a depth 2a = {} m",
            column.depth_m,
            2.0 * a
        ));
    }
    if column.surface_amplitude_m != 0.0 {
        return refuse("not a dam-break column: its surface is not flat".into());
    }
    if case.flume.bed_points().iter().any(|p| p[1].abs() > 1e-9) {
        return refuse("not Martin & Moyce's set-up: the flume's floor is not flat".into());
    }
    if length < 4.0 * a * (1.0 - 1e-6) {
        return refuse(format!(
            "the flume ({length} m) is shorter than 4a = {} m: the front would meet the far wall before T = 3",
            4.0 * a
        ));
    }
    Ok(a)
}

/// Checks a dam-break run against Martin & Moyce (1952), n² = 2 (see the module's comment):
/// the front speed within 5 % of the data's, the mean |ΔZ| of the front at most 0.10 with the
/// fitted time origin (shift at most ΔT = 0.3) and with Lethe's published one, the column's
/// mean |ΔH| under 0.05, the volume drift under 1 %. The raw front error, the fitted shift in
/// seconds, the column width and the particles are reported. The series must reach the end
/// of the comparison.
pub fn dam_break(case: &Case, series: &DamBreakSeries) -> Result<Report, CheckError> {
    let a = column_width(case)?;
    let g = case.fluid.gravity_m_s2;
    let t_scale = (2.0 * g / a).sqrt();
    let tau_scale = (g / a).sqrt();
    let end_s = IMPACT_REF_S * ((a / A_REF_M) * (G_REF_M_S2 / g)).sqrt();
    let n = series.t_s.len();
    if [
        series.front_x_m.len(),
        series.left_wall_height_m.len(),
        series.volume_m2.len(),
    ]
    .iter()
    .any(|&len| len != n)
    {
        return Err(CheckError::NotApplicable(
            "the series' columns differ in length".into(),
        ));
    }
    let last = series.t_s.last().copied().unwrap_or(f64::NEG_INFINITY);
    if n < 2 || last < end_s - 1e-6 {
        return Err(CheckError::TooShort(format!(
            "the comparison runs to t = {end_s:.3} s (T = {:.2}, the front at x = 4a), the record to {}",
            end_s * t_scale,
            if n == 0 {
                "no time at all".to_string()
            } else {
                format!("t = {last:.3} s")
            }
        )));
    }
    let within: Vec<usize> = (0..n).filter(|&i| series.t_s[i] <= end_s).collect();
    let points = |values: &[f64], scale: f64, y_scale: f64| -> (Vec<f64>, Vec<f64>) {
        within
            .iter()
            .filter(|&&i| values[i].is_finite())
            .map(|&i| (series.t_s[i] * scale, values[i] / y_scale))
            .unzip()
    };
    let (t, z) = points(&series.front_x_m, t_scale, a);
    let (tau, h) = points(&series.left_wall_height_m, tau_scale, 2.0 * a);
    if t.len() < 2 || tau.len() < 2 {
        return Err(CheckError::TooShort(
            "fewer than two outputs with a front and a column before the impact".into(),
        ));
    }

    let front: Vec<(f64, f64)> = table(FRONT_TABLE)
        .into_iter()
        .filter(|(tt, _)| *tt <= FRONT_END_T)
        .collect();
    let (front_shifted, shift) = (0..=SHIFT_SEARCH_STEPS)
        .map(|k| k as f64 * SHIFT_SEARCH_STEP_T)
        .map(|s| (front_error(&t, &z, &front, s), s))
        .min_by(|p, q| p.0.total_cmp(&q.0))
        .expect("the search has points");
    let late: Vec<(f64, f64)> = front
        .iter()
        .copied()
        .filter(|(tt, _)| *tt >= SPEED_FROM_T)
        .collect();
    let data_speed = slope(&late);
    let sim_late: Vec<(f64, f64)> = t
        .iter()
        .zip(&z)
        .map(|(tt, zz)| (*tt, *zz))
        .filter(|(tt, _)| (SPEED_FROM_T..=FRONT_END_T).contains(tt))
        .collect();
    let sim_speed = slope(&sim_late);
    let column: Vec<f64> = table(COLUMN_TABLE)
        .into_iter()
        .filter(|(tt, _)| *tt <= tau[tau.len() - 1])
        .map(|(tt, hh)| (interpolate(&tau, &h, tt) - hh).abs())
        .collect();
    let v0 = series.volume_m2[0];
    let volume_drift = within
        .iter()
        .map(|&i| (series.volume_m2[i] / v0 - 1.0).abs())
        .fold(0.0, f64::max);

    let mut report = Report::new(
        "dam break, Martin & Moyce (1952) n² = 2, up to the front at x = 4a",
        [series.t_s[0], end_s],
    );
    report.checks.push(Check::new(
        format!("front speed dZ/dT on T ∈ [{SPEED_FROM_T}, {FRONT_END_T}] (least squares)"),
        sim_speed,
        data_speed,
        SPEED_TOLERANCE,
        "",
    ));
    report.checks.push(Check::at_most(
        format!("front mean |ΔZ| on T ≤ {FRONT_END_T}, time origin fitted"),
        front_shifted,
        FRONT_ERROR_MAX,
        "",
    ));
    report.checks.push(Check::at_most(
        "fitted time-origin shift ΔT",
        shift,
        SHIFT_MAX_T,
        "",
    ));
    report.checks.push(Check::at_most(
        format!("front mean |ΔZ| on T ≤ {FRONT_END_T}, Lethe's shift ΔT = {PUBLISHED_SHIFT_T}"),
        front_error(&t, &z, &front, PUBLISHED_SHIFT_T),
        FRONT_ERROR_MAX,
        "",
    ));
    report.checks.push(Check::below(
        "residual column mean |ΔH|",
        mean(&column),
        COLUMN_ERROR_LIMIT,
        "",
    ));
    report.checks.push(Check::below(
        "volume drift max |V/V0 - 1| up to the impact",
        volume_drift,
        VOLUME_DRIFT_LIMIT,
        "",
    ));
    report.figure(
        format!("front mean |ΔZ| on T ≤ {FRONT_END_T}, raw (no shift)"),
        front_error(&t, &z, &front, 0.0),
        "",
    );
    report.figure("fitted time-origin shift", shift / t_scale, "s");
    report.figure("column width a", a, "m");
    if let Some(p) = series.particles {
        report.figure("particles", p as f64, "");
    }
    Ok(report)
}

/// Mean |Z_sim(T − shift) − Z| over the table's points: the simulation's clock started
/// `shift` (in T) before the experiment's.
fn front_error(t: &[f64], z: &[f64], front: &[(f64, f64)], shift: f64) -> f64 {
    let errors: Vec<f64> = front
        .iter()
        .map(|(tt, zz)| (interpolate(t, z, (tt - shift).max(0.0)) - zz).abs())
        .collect();
    mean(&errors)
}

/// The first two columns of an embedded table: `#` lines are comments, then one header line.
fn table(text: &str) -> Vec<(f64, f64)> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .skip(1)
        .map(|l| {
            let mut cells = l.split(',').map(|c| {
                c.trim()
                    .parse::<f64>()
                    .unwrap_or_else(|_| panic!("embedded table: bad row {l:?}"))
            });
            let x = cells.next().expect("a first column");
            (x, cells.next().expect("a second column"))
        })
        .collect()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// Least-squares slope of the points (x, y).
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let num: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    num / points.iter().map(|(x, _)| (x - mx).powi(2)).sum::<f64>()
}

/// Linear interpolation of (xs, ys) at x, xs increasing; the end segments extend outside.
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let k = xs.partition_point(|&v| v < x).clamp(1, xs.len() - 1);
    let (x0, x1, y0, y1) = (xs[k - 1], xs[k], ys[k - 1], ys[k]);
    y0 + (y1 - y0) * (x - x0) / (x1 - x0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case() -> Case {
        Case::load(std::path::Path::new("cases/dam_break.toml"), &[]).unwrap()
    }

    /// The table with Lethe's trivial first point (T = 0, Z = 1) in front.
    fn with_origin(text: &str) -> (Vec<f64>, Vec<f64>) {
        std::iter::once((0.0, 1.0)).chain(table(text)).unzip()
    }

    /// A run of the reference column to t = 0.29 s every 5 ms whose front follows the table
    /// with the simulated clock `lead` (in T) ahead, and whose column follows its table.
    fn synthetic(case: &Case, lead: f64) -> DamBreakSeries {
        let a = column_width(case).unwrap();
        let g = case.fluid.gravity_m_s2;
        let (front_t, front_z) = with_origin(FRONT_TABLE);
        let (column_tau, column_h) = with_origin(COLUMN_TABLE);
        let t_s: Vec<f64> = (0..=58).map(|k| k as f64 * 0.005).collect();
        DamBreakSeries {
            front_x_m: t_s
                .iter()
                .map(|t| a * interpolate(&front_t, &front_z, t * (2.0 * g / a).sqrt() + lead))
                .collect(),
            left_wall_height_m: t_s
                .iter()
                .map(|t| 2.0 * a * interpolate(&column_tau, &column_h, t * (g / a).sqrt()))
                .collect(),
            volume_m2: vec![2.0 * a * a; t_s.len()],
            t_s,
            particles: Some(5000),
        }
    }

    fn check<'r>(report: &'r Report, what: &str) -> &'r Check {
        report
            .checks
            .iter()
            .find(|c| c.what.contains(what))
            .unwrap_or_else(|| panic!("no check {what}"))
    }

    #[test]
    fn the_embedded_tables_parse() {
        let front = table(FRONT_TABLE);
        assert_eq!(front.len(), 15);
        assert_eq!(front[0], (0.41, 1.11));
        assert_eq!(front[14], (3.33, 4.11));
        let column = table(COLUMN_TABLE);
        assert_eq!(column.len(), 17);
        assert_eq!(column[16], (7.4, 0.06));
    }

    #[test]
    fn a_front_on_the_table_scores_no_error_and_the_data_speed() {
        let case = case();
        let report = dam_break(&case, &synthetic(&case, 0.0)).unwrap();
        let speed = check(&report, "front speed");
        assert!(
            (speed.measured / speed.target - 1.0).abs() < 0.01,
            "{speed:?}"
        );
        assert!(check(&report, "time origin fitted").measured < 0.01);
        assert!(check(&report, "shift ΔT").measured < 0.015);
        assert!(report.figures[0].value < 0.01, "{:?}", report.figures[0]);
        assert!(check(&report, "column").measured < 0.01);
        assert_eq!(check(&report, "volume").measured, 0.0);
        assert!(report.figures.iter().any(|f| f.what == "particles"));
        // Lethe's shift moves a front that needs none by ΔT = 0.175, about 0.2 in Z.
        assert!(!check(&report, "Lethe").passed);
    }

    #[test]
    fn a_front_ahead_by_a_constant_shift_fits_that_shift() {
        let case = case();
        let report = dam_break(&case, &synthetic(&case, 0.2)).unwrap();
        let shift = check(&report, "shift ΔT").measured;
        assert!((shift - 0.2).abs() <= 0.01 + 1e-12, "fitted ΔT = {shift}");
        assert!(check(&report, "time origin fitted").measured < 0.01);
        assert!(report.figures[0].value > 0.1, "raw {:?}", report.figures[0]);
        let speed = check(&report, "front speed");
        assert!(
            (speed.measured / speed.target - 1.0).abs() < 0.05,
            "{speed:?}"
        );
        assert!(report.passed(), "{report:#?}");
    }

    #[test]
    fn a_run_that_stops_before_the_impact_is_too_short() {
        let case = case();
        let mut series = synthetic(&case, 0.2);
        for column in [
            &mut series.t_s,
            &mut series.front_x_m,
            &mut series.left_wall_height_m,
            &mut series.volume_m2,
        ] {
            column.truncate(50);
        }
        match dam_break(&case, &series) {
            Err(CheckError::TooShort(m)) => assert!(m.contains("t = 0.245 s"), "{m}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_column_wider_than_the_flume_or_off_the_wall_is_not_applicable() {
        let refusal = |edit: &dyn Fn(&mut Case)| {
            let mut case = case();
            edit(&mut case);
            let series = synthetic(&self::case(), 0.0);
            match dam_break(&case, &series) {
                Err(CheckError::NotApplicable(m)) => m,
                other => panic!("{other:?}"),
            }
        };
        let wide = refusal(&|c| c.water[0].x_end_m = 0.7);
        assert!(wide.contains("spans the flume"), "{wide}");
        let off = refusal(&|c| {
            c.water[0].x_start_m = 0.05;
            c.water[0].x_end_m = 0.196;
        });
        assert!(off.contains("starts at x = 0.05 m"), "{off}");
        let shallow = refusal(&|c| c.water[0].depth_m = 0.2);
        assert!(shallow.contains("n² = 2"), "{shallow}");
        let short = refusal(&|c| c.flume.length_m = 0.5);
        assert!(short.contains("shorter than 4a"), "{short}");
    }
}
