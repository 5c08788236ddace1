//! A surf case against Ting & Kirby (1994–96): the bars of docs/validation/ting_kirby.md, read
//! from the run's `summary.json` (`breaking`, `surf`, `volume_drift_max`). The measured
//! breaking points are the committed reference file's
//! (`assets/validation/ting_kirby_1994_setup_and_breakpoint.csv`); a case is matched to a row
//! by its wave height, period, offshore depth and beach slope.

use super::{Check, CheckError, Report};
use crate::case::Case;

const REFERENCE: &str =
    include_str!("../../assets/validation/ting_kirby_1994_setup_and_breakpoint.csv");

/// One measured case of the reference file.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfReference {
    /// The measured breaker type: `spilling` or `plunging`.
    pub breaker: String,
    pub height_m: f64,
    pub period_s: f64,
    pub depth_m: f64,
    pub slope: f64,
    /// The breaking point in the data's frame, m.
    pub x_b_m: f64,
    pub h_b_m: f64,
}

/// The reference file's rows.
pub fn surf_references() -> Vec<SurfReference> {
    let number = |t: &str| -> Option<f64> {
        match t.split_once('/') {
            Some((a, b)) => Some(a.trim().parse::<f64>().ok()? / b.trim().parse::<f64>().ok()?),
            None => t.trim().parse().ok(),
        }
    };
    REFERENCE
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("case,"))
        .filter_map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            Some(SurfReference {
                breaker: c.first()?.trim().to_owned(),
                height_m: number(c.get(1)?)?,
                period_s: number(c.get(2)?)?,
                depth_m: number(c.get(3)?)?,
                slope: number(c.get(4)?)?,
                x_b_m: number(c.get(5)?)?,
                h_b_m: number(c.get(6)?)?,
            })
        })
        .collect()
}

/// The reference row a case reproduces: height, period, offshore depth and slope within 1 %.
pub fn surf_reference(case: &Case) -> Option<SurfReference> {
    let w = case.wavemaker.as_ref()?;
    let beach = case.flume.beach.as_ref()?;
    let depth = case.water.first()?.depth_m;
    let near = |a: f64, b: f64| (a / b - 1.0).abs() <= 0.01;
    surf_references().into_iter().find(|r| {
        near(w.height_m, r.height_m)
            && near(w.period_s, r.period_s)
            && near(depth, r.depth_m)
            && near(beach.slope, r.slope)
    })
}

/// The surf-zone bars: the breaking point (first fold, the data's frame) within 0.5 m of the
/// measured one; the steady breaker type the measured one; at every undertow station the net
/// flux within 0.05 of the onshore flux above the trough, and that flux onshore; the volume
/// drift below 1 %. The set-down and set-up are reported.
pub fn ting_kirby(case: &Case, summary: &serde_json::Value) -> Result<Report, CheckError> {
    let r = surf_reference(case).ok_or_else(|| {
        CheckError::NotApplicable(
            "no Ting & Kirby case has this wave height, period, depth and beach slope".into(),
        )
    })?;
    let missing = |what: &str| {
        CheckError::TooShort(format!(
            "summary.json has no {what} (did the run reach its surf averaging window?)"
        ))
    };
    let breaking = &summary["breaking"];
    let surf = &summary["surf"];
    let window = [
        surf["averaged_from_s"]
            .as_f64()
            .ok_or_else(|| missing("surf.averaged_from_s"))?,
        surf["averaged_to_s"]
            .as_f64()
            .ok_or_else(|| missing("surf.averaged_to_s"))?,
    ];
    let mut report = Report::new(&format!("Ting & Kirby, {}", r.breaker), window);
    // No breaker seen: the bar fails (an infinite distance), it is not a short record.
    let x_b = breaking["x_b_data_frame_m"].as_f64();
    if let Some(x_b) = x_b {
        report.figure("breaking point x_b, the data's frame", x_b, "m");
    }
    report.figure("measured breaking point", r.x_b_m, "m");
    report.checks.push(Check::at_most(
        format!("|x_b − {:.3} m|, x_b the first fold", r.x_b_m),
        x_b.map_or(f64::INFINITY, |x| (x - r.x_b_m).abs()),
        0.5,
        "m",
    ));
    let observed = breaking["observed"].as_str().unwrap_or("none");
    // A yes/no check: 1 against 1 with no tolerance.
    report.checks.push(Check::new(
        format!(
            "steady breaker type is the measured {} (1 = yes): observed {observed}",
            r.breaker
        ),
        if observed == r.breaker { 1.0 } else { 0.0 },
        1.0,
        0.0,
        "",
    ));
    let stations = surf["undertow"]["stations"]
        .as_array()
        .filter(|s| !s.is_empty())
        .ok_or_else(|| missing("undertow stations (surf.undertow.stations)"))?;
    for s in stations {
        let x = s["x_data_frame_m"].as_f64().unwrap_or(f64::NAN);
        let (net, onshore) = (
            s["net_flux_m2_s"].as_f64().unwrap_or(f64::NAN),
            s["flux_above_trough_m2_s"].as_f64().unwrap_or(f64::NAN),
        );
        let mut c = Check::at_most(
            format!("|net flux| / onshore flux at x = {x:.3} m"),
            (net / onshore).abs(),
            0.05,
            "",
        );
        c.passed &= onshore > 0.0;
        report.checks.push(c);
    }
    let drift = summary["volume_drift_max"]
        .as_f64()
        .ok_or_else(|| missing("volume_drift_max"))?;
    report.checks.push(Check::below(
        "volume drift max |V/V0 - 1| over the run",
        drift,
        0.01,
        "",
    ));
    for (key, what) in [("setdown_m", "set-down"), ("setup_m", "set-up")] {
        if let Some(v) = surf[key].as_f64() {
            report.figure(what, v, "m");
        }
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_file_and_the_cases_match() {
        let rows = surf_references();
        assert_eq!(rows.len(), 2, "{rows:?}");
        assert!((rows[0].slope - 1.0 / 35.0).abs() < 1e-15);
        for (file, breaker, x_b) in [
            ("cases/ting_kirby_spilling.toml", "spilling", 6.4),
            ("cases/ting_kirby_plunging.toml", "plunging", 7.795),
        ] {
            let case = Case::load(std::path::Path::new(file), &[]).unwrap();
            let r = surf_reference(&case).unwrap();
            assert_eq!((r.breaker.as_str(), r.x_b_m), (breaker, x_b));
        }
        let other = Case::load(std::path::Path::new("cases/teaching_beach.toml"), &[]).unwrap();
        assert_eq!(surf_reference(&other), None);
    }

    fn summary(x_b: f64, observed: &str, net: f64) -> serde_json::Value {
        serde_json::json!({
            "volume_drift_max": 0.003,
            "breaking": {"x_b_data_frame_m": x_b, "observed": observed},
            "surf": {
                "averaged_from_s": 14.0, "averaged_to_s": 34.0,
                "setdown_m": -0.004, "setup_m": 0.016,
                "undertow": {"stations": [
                    {"x_data_frame_m": 6.665, "net_flux_m2_s": net, "flux_above_trough_m2_s": 0.01}
                ]}
            }
        })
    }

    #[test]
    fn the_bars_of_the_surf_zone() {
        let case = Case::load(std::path::Path::new("cases/ting_kirby_spilling.toml"), &[]).unwrap();
        let r = ting_kirby(&case, &summary(5.985, "spilling", 0.0001)).unwrap();
        println!("{r:#?}");
        assert!(r.passed());
        assert!((r.checks[0].measured - 0.415).abs() < 1e-12);
        // 0.6 m off, the wrong type, a net flux of 10 % of the onshore one: three failures.
        let r = ting_kirby(&case, &summary(5.8, "plunging", 0.001)).unwrap();
        let failed: Vec<&str> = r
            .checks
            .iter()
            .filter(|c| !c.passed)
            .map(|c| c.what.as_str())
            .collect();
        assert_eq!(failed.len(), 3, "{failed:?}");
        // No breaker: the breaking point's bar fails.
        let mut none = summary(5.985, "none", 0.0001);
        none["breaking"]["x_b_data_frame_m"] = serde_json::Value::Null;
        let r = ting_kirby(&case, &none).unwrap();
        assert!(!r.checks[0].passed && !r.checks[1].passed && r.checks[2].passed);
        // A summary without the surf averages is too short, not a failure.
        let bare = serde_json::json!({"volume_drift_max": 0.0});
        assert!(matches!(
            ting_kirby(&case, &bare),
            Err(CheckError::TooShort(_))
        ));
    }
}
