//! What `surflab validate` checks (issue 3): what a flume's gauge and probe records say about
//! the waves its paddle made, against linear or cnoidal theory. [`check_case`] picks the check
//! that fits the case; each check is a pure function of the case and the records. Reading
//! `gauges.csv` and printing the verdicts is the binary's job.
//!
//! - `progressive`: a linear paddle into an absorbing end;
//! - `standing`: a linear paddle against a vertical end wall;
//! - `cnoidal`: a cnoidal piston;
//! - `fit`: the fits and wave statistics they share.

mod cnoidal;
mod fit;
mod progressive;
mod standing;

pub use cnoidal::cnoidal;
pub use fit::harmonic_fit;
pub use progressive::progressive;
pub use standing::standing;

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
    /// Allowed |measured/target − 1|; `None` when the bar is an upper bound, measured < target.
    pub relative_tolerance: Option<f64>,
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
            unit: unit.into(),
            passed: measured < limit,
        }
    }

    /// The bar in words: `±5 %` or `< 0.005`.
    pub fn bar(&self) -> String {
        match self.relative_tolerance {
            Some(tol) => format!("{:.4} {} ± {} %", self.target, self.unit, 100.0 * tol),
            None => format!("< {} {}", self.target, self.unit),
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

/// Validates the waves of a run of `case` from its gauge and probe `record`, with the check
/// its wavemaker calls for: a cnoidal piston against cnoidal theory ([`cnoidal`]); a linear
/// paddle into an absorbing end ([`progressive`], which also bars the run's
/// `volume_drift_max` over its `simulated_s`) or, without one, against the end wall
/// ([`standing`]). A case without a wavemaker, or with a solitary wave (`tests/solitary.rs`
/// validates that one), is not applicable.
pub fn check_case(
    case: &Case,
    record: &GaugeRecord,
    volume_drift_max: f64,
    simulated_s: f64,
) -> Result<Report, CheckError> {
    let wavemaker = case
        .wavemaker
        .as_ref()
        .ok_or_else(|| CheckError::NotApplicable("the case has no wavemaker to validate".into()))?;
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

    /// Each wavemaker gets its own check; a case without one, or a solitary wave, none.
    #[test]
    fn each_case_gets_the_check_its_wavemaker_calls_for() {
        // Too short a record for any window: the error says which check refused it.
        let record = test_record(&[0.0, 0.1], Vec::new());
        let kind = |name: &str| match check_case(&case(name), &record, 0.0, 1.0) {
            Err(CheckError::TooShort(m)) => format!("too short: {m}"),
            Err(CheckError::NotApplicable(m)) => m,
            other => panic!("{name}: {other:?}"),
        };
        assert!(kind("flap_deep_water").contains("20 periods"));
        assert!(kind("wall_reflection").contains("3 periods"));
        assert!(kind("piston_cnoidal").contains("5 periods"));
        assert!(kind("solitary").contains("tests/solitary.rs"));
        assert!(kind("dam_break").contains("no wavemaker"));
    }
}
