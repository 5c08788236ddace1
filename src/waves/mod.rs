//! Wavemaker theory for the numerical flume.
//!
//! This module turns a requested target wave (height `H`, period `T`, still
//! water depth `h`) into a prescribed paddle motion, and provides the free
//! surface of the target wave for comparison with the simulation.
//!
//! * [`elliptic`] — complete elliptic integrals `K(m)`, `E(m)` and the Jacobi
//!   functions `sn`, `cn`, `dn` (parameter convention `m = k²`), evaluated with
//!   the arithmetic–geometric mean and the descending Landen transformation.
//!   Companion entry points take `1 − m` directly so that the nearly-solitary
//!   regime `1 − m ≪ 1` keeps full accuracy.
//! * [`linear`] — Airy theory: the dispersion relation `ω² = g k tanh(k h)`,
//!   the piston and bed-hinged flap transfer functions `H/S` (thesis eqs.
//!   2.36–2.37) and a ramped sinusoidal paddle (thesis eqs. 2.32–2.35).
//! * [`cnoidal`] — first-order (KdV) cnoidal waves (thesis eqs. 2.41–2.54):
//!   the Ursell/period relation is solved for `m`, and a piston trajectory is
//!   generated from the depth-averaged velocity `u = c η / (h + η)`.
//! * [`solitary`] — a single solitary wave `η = H sech²(κ (c t − X))` generated
//!   with the same depth-averaged velocity rule (Goring 1978), for which the
//!   paddle path has a closed implicit form.
//!
//! Coordinates: `x` is horizontal, positive in the direction of propagation,
//! `z` is vertical with `z = 0` at the still water level and `z = −h` at the
//! bed. Gravity is always passed in explicitly (`gravity_m_s2`).

pub mod absorption;
pub mod breaker;
pub mod cnoidal;
pub mod elliptic;
pub mod linear;
pub mod paddle;
pub mod solitary;

use std::fmt;

/// Failure modes of the wave-generation routines.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WaveError {
    /// A physical quantity that must be finite and strictly positive was not.
    NonPositive {
        /// Name of the offending argument (with its unit suffix).
        name: &'static str,
        /// The value that was supplied.
        value: f64,
    },
    /// A parameter lies outside its admissible range (e.g. a negative ramp).
    OutOfRange {
        /// Name of the offending argument (with its unit suffix).
        name: &'static str,
        /// The value that was supplied.
        value: f64,
    },
    /// The requested wave exceeds the breaking (steepness or depth) limit.
    TooSteep {
        /// Requested wave height.
        height_m: f64,
        /// Largest admissible height for the given period and depth.
        max_height_m: f64,
    },
    /// The cnoidal Ursell/period relation has no admissible root.
    UrsellSolve {
        /// Requested wave period.
        period_s: f64,
        /// Why no solution exists.
        reason: &'static str,
    },
    /// An iterative solver did not reach its tolerance.
    NoConvergence {
        /// Which solver failed.
        what: &'static str,
    },
}

impl fmt::Display for WaveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WaveError::NonPositive { name, value } => {
                write!(f, "{name} must be finite and positive, got {value}")
            }
            WaveError::OutOfRange { name, value } => {
                write!(f, "{name} is out of its admissible range, got {value}")
            }
            WaveError::TooSteep {
                height_m,
                max_height_m,
            } => write!(
                f,
                "wave height {height_m} m exceeds the breaking limit of {max_height_m:.3} m"
            ),
            WaveError::UrsellSolve { period_s, reason } => {
                write!(f, "no cnoidal wave with period {period_s} s: {reason}")
            }
            WaveError::NoConvergence { what } => write!(f, "{what} did not converge"),
        }
    }
}

impl std::error::Error for WaveError {}

/// Result type of the wave-generation routines.
pub type Result<T> = std::result::Result<T, WaveError>;

/// Returns `value` if it is finite and strictly positive, otherwise a
/// [`WaveError::NonPositive`] naming the argument.
/// Largest wave height to depth ratio the long-wave paddles accept (the breaking limit).
pub(crate) const MAX_HEIGHT_TO_DEPTH: f64 = 0.78;

/// Refuses a wave at or above the breaking limit H/h = 0.78.
pub(crate) fn require_unbroken(height_m: f64, depth_m: f64) -> Result<()> {
    if height_m >= MAX_HEIGHT_TO_DEPTH * depth_m {
        return Err(WaveError::TooSteep {
            height_m,
            max_height_m: MAX_HEIGHT_TO_DEPTH * depth_m,
        });
    }
    Ok(())
}

pub(crate) fn require_positive(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(WaveError::NonPositive { name, value })
    }
}

/// Half-cosine start-up ramp `½ (1 − cos(π t / t_ramp))` for `0 ≤ t < t_ramp`,
/// `0` before `t = 0` and `1` afterwards. A zero ramp duration gives a unit
/// step at `t = 0`.
pub fn half_cosine_ramp(t_s: f64, ramp_duration_s: f64) -> f64 {
    if t_s <= 0.0 {
        0.0
    } else if t_s >= ramp_duration_s {
        1.0
    } else {
        0.5 * (1.0 - (std::f64::consts::PI * t_s / ramp_duration_s).cos())
    }
}

/// Time derivative (1/s) of [`half_cosine_ramp`]:
/// `(π / (2 t_ramp)) sin(π t / t_ramp)` inside the ramp, zero outside.
pub fn half_cosine_ramp_rate(t_s: f64, ramp_duration_s: f64) -> f64 {
    if t_s <= 0.0 || t_s >= ramp_duration_s {
        0.0
    } else {
        let pi = std::f64::consts::PI;
        0.5 * pi / ramp_duration_s * (pi * t_s / ramp_duration_s).sin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_is_continuous_and_rate_matches_difference() {
        let ramp_s = 3.0;
        assert_eq!(half_cosine_ramp(-1.0, ramp_s), 0.0);
        assert_eq!(half_cosine_ramp(4.0, ramp_s), 1.0);
        assert!((half_cosine_ramp(1.5, ramp_s) - 0.5).abs() < 1e-15);
        assert_eq!(half_cosine_ramp(0.5, 0.0), 1.0);
        let mut worst = 0.0_f64;
        for i in 1..300 {
            let t = i as f64 * 0.01;
            let d = 1e-6;
            let fd =
                (half_cosine_ramp(t + d, ramp_s) - half_cosine_ramp(t - d, ramp_s)) / (2.0 * d);
            worst = worst.max((fd - half_cosine_ramp_rate(t, ramp_s)).abs());
        }
        println!("ramp rate vs finite difference: worst abs error {worst:.3e} 1/s");
        assert!(worst < 1e-8);
    }

    #[test]
    fn error_messages_are_readable() {
        let e = WaveError::NonPositive {
            name: "depth_m",
            value: -1.0,
        };
        assert!(e.to_string().contains("depth_m"));
        let boxed: Box<dyn std::error::Error> = Box::new(e);
        assert!(!boxed.to_string().is_empty());
    }
}
