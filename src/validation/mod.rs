//! What `surflab validate` checks (issue 3): what a flume's gauge and probe records say about
//! the waves its paddle made, against linear or cnoidal theory, and what the time series of a
//! dam break says about its front and column, against Martin & Moyce (1952). [`check_case`]
//! picks the check that fits the case; each check is a pure function of the case and the
//! records. Reading `gauges.csv` or `timeseries.csv` and printing the verdicts is the binary's
//! job.
//!
//! - `progressive`: a linear paddle into an absorbing end;
//! - `standing`: a linear paddle against a vertical end wall;
//! - `cnoidal`: a cnoidal piston;
//! - `dam_break`: the collapse of a water column (no wavemaker);
//! - `surf`: a surf case against Ting & Kirby's breaking point, read from its summary;
//! - `against_2d`: a narrow 3D tank with a linear piston against its 2D twin;
//! - `fit`: the fits and wave statistics they share.

pub mod against_2d;
mod cnoidal;
mod dam_break;
mod fit;
mod progressive;
mod standing;
mod surf;

pub use cnoidal::cnoidal;
pub use dam_break::{DamBreakSeries, column_width, dam_break};
pub use fit::harmonic_fit;
pub use progressive::progressive;
pub use standing::standing;
pub use surf::{SurfReference, surf_reference, surf_references, ting_kirby};

use crate::case::{Case, WaveTheory};
use crate::output::timeseries::GaugeRecord;
use crate::waves::linear;
use serde::Serialize;

/// One verdict: a measured figure against its target and tolerance.
#[derive(Debug, Clone, Serialize)]
pub struct Check {
    pub what: String,
    pub measured: f64,
    pub target: f64,
    /// Allowed |measured/target − 1|; `None` when the bar is an upper bound, measured < target
    /// (or ≤ when `inclusive`).
    pub relative_tolerance: Option<f64>,
    /// An upper bound the measured figure may reach.
    pub inclusive: bool,
    pub unit: String,
    pub passed: bool,
}

impl Check {
    fn new(what: impl Into<String>, measured: f64, target: f64, tol: f64, unit: &str) -> Self {
        let error = (measured / target - 1.0).abs();
        Self {
            what: what.into(),
            measured,
            target,
            relative_tolerance: Some(tol),
            inclusive: false,
            unit: unit.into(),
            passed: error.is_finite() && error <= tol,
        }
    }

    fn below(what: impl Into<String>, measured: f64, limit: f64, unit: &str) -> Self {
        Self {
            what: what.into(),
            measured,
            target: limit,
            relative_tolerance: None,
            inclusive: false,
            unit: unit.into(),
            passed: measured < limit,
        }
    }

    fn at_most(what: impl Into<String>, measured: f64, limit: f64, unit: &str) -> Self {
        Self {
            inclusive: true,
            passed: measured <= limit,
            ..Self::below(what, measured, limit, unit)
        }
    }

    /// The bar in words: `0.1000 m ± 5 %`, `< 0.005` or `≤ 0.1`.
    pub fn bar(&self) -> String {
        let unit = if self.unit.is_empty() {
            String::new()
        } else {
            format!(" {}", self.unit)
        };
        match self.relative_tolerance {
            Some(0.0) => format!("= {}{unit}", self.target),
            Some(tol) => format!("{:.4}{unit} ± {} %", self.target, 100.0 * tol),
            None if self.inclusive => format!("≤ {}{unit}", self.target),
            None => format!("< {}{unit}", self.target),
        }
    }

    /// Signed relative error, measured/target − 1.
    pub fn error(&self) -> f64 {
        self.measured / self.target - 1.0
    }
}

/// A figure reported without a bar.
#[derive(Debug, Clone, Serialize)]
pub struct Figure {
    pub what: String,
    pub value: f64,
    pub unit: String,
}

/// What a validation found: verdicts, reported figures, and the averaging window.
#[derive(Debug, Clone, Serialize)]
pub struct Report {
    pub kind: String,
    pub window_s: [f64; 2],
    pub checks: Vec<Check>,
    pub figures: Vec<Figure>,
}

impl Report {
    fn new(kind: &str, window_s: [f64; 2]) -> Report {
        Report {
            kind: kind.into(),
            window_s,
            checks: Vec::new(),
            figures: Vec::new(),
        }
    }

    pub fn passed(&self) -> bool {
        !self.checks.is_empty() && self.checks.iter().all(|c| c.passed)
    }

    fn figure(&mut self, what: impl Into<String>, value: f64, unit: &str) {
        self.figures.push(Figure {
            what: what.into(),
            value,
            unit: unit.into(),
        });
    }
}

#[derive(Debug, thiserror::Error)]
pub enum CheckError {
    #[error("{0}")]
    NotApplicable(String),
    #[error("the record is too short: {0}")]
    TooShort(String),
    #[error(transparent)]
    Theory(#[from] crate::waves::WaveError),
}

/// Validates a run of `case` with the check its wavemaker calls for: a cnoidal piston
/// against cnoidal theory ([`cnoidal`]); a linear paddle into an absorbing end
/// ([`progressive`], which also bars the run's `volume_drift_max` over its `simulated_s`) or,
/// without one, against the end wall ([`standing`]); these read the gauge and probe `record`.
/// Without a wavemaker, the collapse of a water column at the left wall against Martin &
/// Moyce ([`dam_break`]), from the run's time `series` (no series: an empty one, too short).
/// Any other case without a wavemaker, or a solitary wave (`tests/solitary.rs` validates
/// that one), is not applicable.
pub fn check_case(
    case: &Case,
    record: &GaugeRecord,
    series: Option<&DamBreakSeries>,
    volume_drift_max: f64,
    simulated_s: f64,
) -> Result<Report, CheckError> {
    let Some(wavemaker) = case.wavemaker.as_ref() else {
        return dam_break(case, series.unwrap_or(&DamBreakSeries::default())).map_err(
            |e| match e {
                CheckError::NotApplicable(why) => CheckError::NotApplicable(format!(
                    "the case has no wavemaker, and the dam-break check does not apply: {why}"
                )),
                other => other,
            },
        );
    };
    match wavemaker.theory {
        WaveTheory::Cnoidal => cnoidal(case, record),
        WaveTheory::Linear if case.absorber.is_some() => {
            progressive(case, record, volume_drift_max, simulated_s)
        }
        WaveTheory::Linear => standing(case, record),
        WaveTheory::Solitary => Err(CheckError::NotApplicable(
            "the solitary wave is validated by tests/solitary.rs".into(),
        )),
    }
}

/// The linear wave a linear-theory paddle makes: (H, T, still depth of the first water
/// region, k, paddle x).
fn linear_wave(case: &Case) -> Result<(f64, f64, f64, f64, f64), CheckError> {
    let w = case
        .wavemaker
        .as_ref()
        .ok_or_else(|| CheckError::NotApplicable("the case has no wavemaker".into()))?;
    if w.theory != WaveTheory::Linear {
        return Err(CheckError::NotApplicable(
            "this check is for a linear-theory paddle".into(),
        ));
    }
    let depth = case
        .water
        .first()
        .map(|r| r.depth_m)
        .ok_or_else(|| CheckError::NotApplicable("the case has no water".into()))?;
    let g = case.fluid.gravity_m_s2;
    let k = linear::wavenumber(w.period_s, depth, g)?;
    Ok((w.height_m, w.period_s, depth, k, w.x_m))
}

/// A record of the given columns at times `t`.
#[cfg(test)]
fn test_record(t: &[f64], cols: Vec<(String, Vec<Option<f64>>)>) -> GaugeRecord {
    GaugeRecord {
        t_s: t.to_vec(),
        names: cols.iter().map(|c| c.0.clone()).collect(),
        columns: cols.into_iter().map(|c| c.1).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn case(name: &str) -> Case {
        Case::load(std::path::Path::new(&format!("cases/{name}.toml")), &[]).unwrap()
    }

    /// Each wavemaker gets its own check; a case without one the dam-break check if its water
    /// is a column at the left wall, none otherwise; a solitary wave none.
    #[test]
    fn each_case_gets_the_check_its_wavemaker_calls_for() {
        // Too short a record for any window: the error says which check refused it.
        let record = test_record(&[0.0, 0.1], Vec::new());
        let series = DamBreakSeries {
            t_s: vec![0.0, 0.1],
            front_x_m: vec![0.146, 0.2],
            left_wall_height_m: vec![0.292, 0.28],
            volume_m2: vec![0.0426; 2],
            particles: None,
        };
        let kind = |name: &str| match check_case(&case(name), &record, Some(&series), 0.0, 1.0) {
            Err(CheckError::TooShort(m)) => format!("too short: {m}"),
            Err(CheckError::NotApplicable(m)) => m,
            other => panic!("{name}: {other:?}"),
        };
        assert!(kind("flap_deep_water").contains("20 periods"));
        assert!(kind("wall_reflection").contains("3 periods"));
        assert!(kind("piston_cnoidal").contains("5 periods"));
        assert!(kind("solitary").contains("tests/solitary.rs"));
        assert!(kind("dam_break").contains("too short: the comparison runs to t = 0.280 s"));
        assert!(kind("still_water").contains("no wavemaker"));
        assert!(kind("still_water").contains("spans the flume"));
    }
}
