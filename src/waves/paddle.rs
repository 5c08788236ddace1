//! One type for every paddle motion the flume can run: the horizontal displacement of the
//! paddle face at the still-water level, X(t), from linear, cnoidal or solitary theory.
//!
//! For a piston every point of the face moves by X(t). For a bed-hinged flap the face turns
//! rigidly about the hinge by the angle whose tangent is X(t)/h, so that the still-water point
//! moves by X(t) (method.md §5).
//!
//! This module knows nothing of cases: the motion a case asks for is designed by
//! `PaddleMotion::from_case` in `crate::wavemaker`.

use super::Result;
use super::cnoidal::{CnoidalPaddle, CnoidalWave};
use super::linear::{LinearPaddle, PaddleKind};
use super::solitary::SolitaryPaddle;

/// A designed paddle motion.
#[derive(Debug, Clone, PartialEq)]
pub enum PaddleMotion {
    Linear(LinearPaddle),
    /// Boxed: the tabulated path is large.
    Cnoidal(Box<CnoidalPaddle>),
    Solitary(SolitaryPaddle),
}

impl PaddleMotion {
    /// Linear theory for a piston or a flap.
    pub fn linear(
        kind: PaddleKind,
        height_m: f64,
        period_s: f64,
        depth_m: f64,
        gravity_m_s2: f64,
        ramp_periods: f64,
    ) -> Result<Self> {
        LinearPaddle::new(
            kind,
            height_m,
            period_s,
            depth_m,
            gravity_m_s2,
            ramp_periods,
        )
        .map(PaddleMotion::Linear)
    }

    /// A cnoidal piston.
    pub fn cnoidal(
        height_m: f64,
        period_s: f64,
        depth_m: f64,
        gravity_m_s2: f64,
        ramp_periods: f64,
    ) -> Result<Self> {
        let wave = CnoidalWave::new(height_m, period_s, depth_m, gravity_m_s2)?;
        CnoidalPaddle::new(wave, ramp_periods).map(|p| PaddleMotion::Cnoidal(Box::new(p)))
    }

    /// A solitary-wave piston.
    pub fn solitary(height_m: f64, depth_m: f64, gravity_m_s2: f64) -> Result<Self> {
        SolitaryPaddle::new(height_m, depth_m, gravity_m_s2).map(PaddleMotion::Solitary)
    }

    /// Piston or flap.
    pub fn kind(&self) -> PaddleKind {
        match self {
            PaddleMotion::Linear(p) => p.kind,
            _ => PaddleKind::Piston,
        }
    }

    /// Displacement of the face at the still-water level, m (0 before t = 0).
    pub fn displacement_m(&self, t_s: f64) -> f64 {
        match self {
            PaddleMotion::Linear(p) => p.displacement_m(t_s, 0.0),
            PaddleMotion::Cnoidal(p) => p.position_at(t_s),
            PaddleMotion::Solitary(p) => p.position_at(t_s),
        }
    }

    /// Peak-to-peak excursion at the still-water level once running, m.
    pub fn stroke_m(&self) -> f64 {
        match self {
            PaddleMotion::Linear(p) => p.stroke_m,
            PaddleMotion::Cnoidal(p) => p.stroke_m(),
            PaddleMotion::Solitary(p) => p.stroke_m(),
        }
    }

    /// The wave period, s (the duration of the motion for a solitary wave).
    pub fn period_s(&self) -> f64 {
        match self {
            PaddleMotion::Linear(p) => p.period_s,
            PaddleMotion::Cnoidal(p) => p.wave().period_s,
            PaddleMotion::Solitary(p) => p.duration_s(),
        }
    }

    /// Length of the start-up ramp, s (0 for a solitary wave).
    pub fn ramp_duration_s(&self) -> f64 {
        match self {
            PaddleMotion::Linear(p) => p.ramp_duration_s(),
            PaddleMotion::Cnoidal(p) => p.ramp_duration_s(),
            PaddleMotion::Solitary(_) => 0.0,
        }
    }

    /// The range [min, max] of X(t) at the still-water level, sampled at T/400 over the ramp and
    /// four periods after it, m.
    pub fn excursion_m(&self) -> (f64, f64) {
        let period = self.period_s();
        let ramp = self.ramp_duration_s();
        let n = ((ramp / period + 4.0) * 400.0).ceil() as usize;
        let dt = (ramp + 4.0 * period) / n as f64;
        (0..=n)
            .map(|i| self.displacement_m(i as f64 * dt))
            .fold((0.0_f64, 0.0_f64), |(lo, hi), x| (lo.min(x), hi.max(x)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excursions_match_strokes() {
        let flap = PaddleMotion::linear(PaddleKind::Flap, 0.06, 0.91, 0.7, 9.81, 2.0).unwrap();
        let (lo, hi) = flap.excursion_m();
        println!(
            "flap: stroke {:.4} m, excursion [{lo:.4}, {hi:.4}] m",
            flap.stroke_m()
        );
        assert!((hi - lo - flap.stroke_m()).abs() < 1e-3 * flap.stroke_m());
        let cn = PaddleMotion::cnoidal(0.125, 2.0, 0.4, 9.81, 2.0).unwrap();
        let (lo, hi) = cn.excursion_m();
        println!(
            "cnoidal: stroke {:.4} m, excursion [{lo:.4}, {hi:.4}] m",
            cn.stroke_m()
        );
        assert!(hi - lo >= 0.99 * cn.stroke_m());
        let sol = PaddleMotion::solitary(0.04, 0.4, 9.81).unwrap();
        let (lo, hi) = sol.excursion_m();
        assert!(lo == 0.0 && (hi - sol.stroke_m()).abs() < 1e-9, "{lo} {hi}");
    }
}
