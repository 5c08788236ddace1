//! Solitary-wave generation with a piston (Goring 1978).
//!
//! **Wave.** First-order (KdV) solitary wave of height `H` in depth `h`:
//!
//! ```text
//! η(x, t) = H sech²(κ (c (t − t₀) − x)),   κ = sqrt(3H / (4h³)),   c = sqrt(g (h + H)).
//! ```
//!
//! **Paddle.** The piston moves with the depth-averaged velocity under the
//! wave at its own position, `dX/dt = c η(X, t) / (h + η(X, t))`. With
//! `θ = κ (c (t − t₀) − X)` this ODE has the exact implicit solution
//!
//! ```text
//! X(t) = A + (H / (κ h)) tanh θ,
//! ```
//!
//! (differentiate: `Ẋ = (H/h) sech²θ (c − Ẋ)`, which rearranges to the ODE),
//! so the full stroke is `2H/(κh) = sqrt(16 H h / 3)`. The motion is started
//! when the surface at the paddle is `η ≈ 0.002 H`, i.e. `θ(0) = −3.8`
//! (`sech² 3.8 ≈ 0.002`), which puts the crest at the paddle at
//! `t₀ = 3.8 / (κ c)`; `A = (H/(κh)) tanh 3.8` makes `X(0) = 0`. The motion is
//! stopped symmetrically when `θ = +3.8`, after a travel of
//! `2A = sqrt(16Hh/3) · tanh 3.8` (0.1 % short of the full stroke). At both
//! ends the velocity is about `0.002 c H / h`, i.e. 0.2 % of its peak
//! `c H / (h + H)`; outside `[0, t_end]` the paddle is held still.
//!
//! `X(t)` is obtained from the implicit relation by Newton iteration
//! safeguarded with bisection; the residual `X − A − B tanh θ(X)` has slope
//! `1 + (H/h) sech²θ ∈ [1, 1 + H/h]`, so the root is unique and brackets are
//! easy: `X ∈ [0, 2A]` for `t ∈ [0, t_end]`.

use super::{Result, require_positive, require_unbroken};

/// Value of |θ| at start and end of the motion: `sech²(3.8) ≈ 0.002`.
const START_DECAY: f64 = 3.8;

/// Piston trajectory generating a single solitary wave.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolitaryPaddle {
    /// Solitary wave height.
    pub height_m: f64,
    /// Still water depth.
    pub depth_m: f64,
    /// Wave celerity `sqrt(g (h + H))`.
    pub celerity_m_s: f64,
    /// Decay rate `κ = sqrt(3H / (4h³))` of the profile.
    pub kappa_per_m: f64,
    /// Time at which the crest passes the initial paddle position.
    pub crest_time_s: f64,
    /// `A`, the position about which the tanh profile is centred.
    centre_m: f64,
    /// `B = H/(κh)`, half the theoretical stroke.
    half_stroke_m: f64,
    /// Time at which the motion stops (`θ = +3.8`).
    end_time_s: f64,
}

/// The effective period of a solitary wave of height `height_m` in depth `depth_m`, s:
/// T_eff = 2 · 3.8 / (κ c), κ = sqrt(3H / (4d³)), c = sqrt(g (d + H)).
///
/// A solitary wave has no period, but whatever watches it needs a time scale where a periodic
/// wave's T would go. This one is the time the wave takes to pass a point between the two
/// places where its surface stands 0.002 H high (θ = ∓3.8): the same cut-off Goring's piston
/// is designed on ([`SolitaryPaddle`] starts and stops there), so it is the paddle's motion
/// less the time its own stroke adds, and c · T_eff = 2 · 3.8 / κ is the wave's effective
/// length. It grows as the wave gets lower and longer (d = 0.3 m: 2.2 s for H/d = 0.35, 4.6 s
/// for H/d = 0.1), as the time a breaker or a run-up of this wave lasts does.
pub fn effective_period_s(height_m: f64, depth_m: f64, gravity_m_s2: f64) -> f64 {
    let kappa = (3.0 * height_m / (4.0 * depth_m.powi(3))).sqrt();
    let celerity = (gravity_m_s2 * (depth_m + height_m)).sqrt();
    2.0 * START_DECAY / (kappa * celerity)
}

impl SolitaryPaddle {
    /// Designs the paddle motion for a solitary wave of height `height_m` in
    /// depth `depth_m`. Errors on non-positive inputs or `H/h ≥ 0.78`.
    pub fn new(height_m: f64, depth_m: f64, gravity_m_s2: f64) -> Result<Self> {
        let height_m = require_positive("height_m", height_m)?;
        let depth_m = require_positive("depth_m", depth_m)?;
        let gravity_m_s2 = require_positive("gravity_m_s2", gravity_m_s2)?;
        require_unbroken(height_m, depth_m)?;
        let kappa_per_m = (3.0 * height_m / (4.0 * depth_m.powi(3))).sqrt();
        let celerity_m_s = (gravity_m_s2 * (depth_m + height_m)).sqrt();
        let crest_time_s = START_DECAY / (kappa_per_m * celerity_m_s);
        let half_stroke_m = height_m / (kappa_per_m * depth_m);
        let centre_m = half_stroke_m * START_DECAY.tanh();
        // θ(t_end) = +3.8 with X(t_end) = 2A.
        let end_time_s = crest_time_s + (START_DECAY / kappa_per_m + 2.0 * centre_m) / celerity_m_s;
        Ok(Self {
            height_m,
            depth_m,
            celerity_m_s,
            kappa_per_m,
            crest_time_s,
            centre_m,
            half_stroke_m,
            end_time_s,
        })
    }

    /// Paddle travel from start to stop, `sqrt(16Hh/3) · tanh 3.8` (m).
    pub fn stroke_m(&self) -> f64 {
        2.0 * self.centre_m
    }

    /// Full theoretical stroke of the untruncated motion, `sqrt(16Hh/3)` (m).
    pub fn theoretical_stroke_m(&self) -> f64 {
        2.0 * self.half_stroke_m
    }

    /// Time at which the paddle stops (s); it starts at `t = 0`.
    pub fn duration_s(&self) -> f64 {
        self.end_time_s
    }

    /// Target surface elevation `H sech²(κ (c (t − t₀) − x))` (m).
    pub fn eta_m(&self, x_m: f64, t_s: f64) -> f64 {
        let theta = self.kappa_per_m * (self.celerity_m_s * (t_s - self.crest_time_s) - x_m);
        let sech = 1.0 / theta.cosh();
        self.height_m * sech * sech
    }

    /// Paddle position `X(t)` (m): `0` before the start, `stroke_m()` after
    /// the stop, the root of `X = A + (H/(κh)) tanh θ(X, t)` in between.
    /// NaN for NaN input.
    pub fn position_at(&self, t_s: f64) -> f64 {
        if t_s.is_nan() {
            return f64::NAN;
        }
        if t_s <= 0.0 {
            return 0.0;
        }
        if t_s >= self.end_time_s {
            return self.stroke_m();
        }
        let (a, b, kappa) = (self.centre_m, self.half_stroke_m, self.kappa_per_m);
        let shift = self.celerity_m_s * (t_s - self.crest_time_s);
        let (mut lo, mut hi) = (0.0, 2.0 * a);
        // Start from the position the paddle would have if it stood still.
        let mut x = (a + b * (kappa * (shift - a)).tanh()).clamp(lo, hi);
        for _ in 0..100 {
            let tanh_theta = (kappa * (shift - x)).tanh();
            let residual = x - a - b * tanh_theta;
            if residual > 0.0 {
                hi = x;
            } else {
                lo = x;
            }
            let slope = 1.0 + b * kappa * (1.0 - tanh_theta * tanh_theta);
            let mut next = x - residual / slope;
            if !(next >= lo && next <= hi) {
                next = 0.5 * (lo + hi);
            }
            let converged = (next - x).abs() <= 1e-15 * (a + x.abs()) || hi - lo <= 1e-15 * a;
            x = next;
            if converged {
                break;
            }
        }
        x
    }

    /// Paddle velocity `c η(X, t) / (h + η(X, t))` (m/s) during the motion,
    /// zero outside `(0, duration_s())`; NaN for NaN input.
    pub fn velocity_at(&self, t_s: f64) -> f64 {
        if t_s.is_nan() {
            return f64::NAN;
        }
        if t_s <= 0.0 || t_s >= self.end_time_s {
            return 0.0;
        }
        let eta = self.eta_m(self.position_at(t_s), t_s);
        self.celerity_m_s * eta / (self.depth_m + eta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::waves::WaveError;

    const G: f64 = 9.81;

    #[test]
    fn the_effective_period_is_the_paddle_motion_less_its_stroke() {
        let (h, d, g) = (0.105, 0.3, 9.81);
        let paddle = SolitaryPaddle::new(h, d, g).unwrap();
        let t_eff = effective_period_s(h, d, g);
        let stroke_time = paddle.stroke_m() / paddle.celerity_m_s;
        println!(
            "T_eff = {t_eff:.4} s, paddle motion {:.4} s",
            paddle.duration_s()
        );
        assert!((t_eff + stroke_time - paddle.duration_s()).abs() < 1e-12);
        assert!((t_eff - 2.233).abs() < 0.001, "{t_eff}");
    }

    #[test]
    fn stroke_matches_goring_estimate() {
        let (height_m, depth_m) = (0.04, 0.4);
        let paddle = SolitaryPaddle::new(height_m, depth_m, G).unwrap();
        let estimate = (16.0 * height_m * depth_m / 3.0).sqrt();
        let travelled = paddle.position_at(paddle.duration_s()) - paddle.position_at(0.0);
        let rel = travelled / estimate - 1.0;
        println!(
            "H/h = 0.1: travel = {travelled:.5} m, sqrt(16Hh/3) = {estimate:.5} m (rel {rel:.2e}), duration = {:.3} s, crest at {:.3} s",
            paddle.duration_s(),
            paddle.crest_time_s
        );
        assert!(rel.abs() < 0.02);
        assert!((paddle.theoretical_stroke_m() / estimate - 1.0).abs() < 1e-14);
        // Symmetric motion: half the travel when the crest is at the paddle.
        let x_crest =
            paddle.position_at(paddle.crest_time_s + paddle.stroke_m() / 2.0 / paddle.celerity_m_s);
        assert!((x_crest - 0.5 * paddle.stroke_m()).abs() < 1e-12);
    }

    #[test]
    fn velocity_vanishes_at_both_ends() {
        let paddle = SolitaryPaddle::new(0.04, 0.4, G).unwrap();
        let peak = paddle.celerity_m_s * paddle.height_m / (paddle.depth_m + paddle.height_m);
        let eps = 1e-9 * paddle.duration_s();
        let start = paddle.velocity_at(eps) / peak;
        let end = paddle.velocity_at(paddle.duration_s() - eps) / peak;
        let max_sampled = (1..1000)
            .map(|i| paddle.velocity_at(paddle.duration_s() * i as f64 / 1000.0))
            .fold(0.0_f64, f64::max);
        println!(
            "velocity / peak: start {start:.3e}, end {end:.3e}; sampled max / peak = {:.6}",
            max_sampled / peak
        );
        assert!(start < 5e-3 && end < 5e-3);
        assert!((max_sampled / peak - 1.0).abs() < 1e-3);
        assert_eq!(paddle.velocity_at(-1.0), 0.0);
        assert_eq!(paddle.velocity_at(2.0 * paddle.duration_s()), 0.0);
    }

    #[test]
    fn implicit_solution_matches_ode_integration() {
        let paddle = SolitaryPaddle::new(0.2, 0.5, G).unwrap();
        let rhs = |t: f64, x: f64| {
            let eta = paddle.eta_m(x, t);
            paddle.celerity_m_s * eta / (paddle.depth_m + eta)
        };
        let steps = 20_000;
        let h = paddle.duration_s() / steps as f64;
        let mut x = 0.0;
        let mut worst = 0.0_f64;
        for i in 0..steps {
            let t = i as f64 * h;
            let k1 = rhs(t, x);
            let k2 = rhs(t + 0.5 * h, x + 0.5 * h * k1);
            let k3 = rhs(t + 0.5 * h, x + 0.5 * h * k2);
            let k4 = rhs(t + h, x + h * k3);
            x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            let t_next = if i + 1 == steps {
                paddle.duration_s()
            } else {
                t + h
            };
            worst = worst.max((paddle.position_at(t_next) - x).abs());
        }
        println!(
            "implicit X(t) vs RK4 of dX/dt = cη/(h+η) (H/h = 0.4): max |ΔX| = {worst:.3e} m, stroke {:.4} m",
            paddle.stroke_m()
        );
        assert!(worst < 1e-9 * paddle.stroke_m());
    }

    #[test]
    fn invalid_inputs_are_rejected() {
        assert!(matches!(
            SolitaryPaddle::new(0.0, 0.4, G),
            Err(WaveError::NonPositive {
                name: "height_m",
                ..
            })
        ));
        assert!(matches!(
            SolitaryPaddle::new(0.35, 0.4, G),
            Err(WaveError::TooSteep { .. })
        ));
        assert!(SolitaryPaddle::new(0.1, 0.4, -9.81).is_err());
    }
}
