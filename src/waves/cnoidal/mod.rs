//! First-order cnoidal (KdV) waves and their piston wavemaker
//! (thesis eqs. 2.41–2.54, after Goring 1978 and Zhang).
//!
//! **Wave.** For height `H`, period `T` and depth `h`, the elliptic parameter
//! `m` (with `K = K(m)`, `E = E(m)`, see [`super::elliptic`]) fixes
//!
//! ```text
//! wavelength (Ursell relation):  L = 4 K h sqrt(m h / (3 H))
//! celerity:                      c = sqrt(g h) [1 + (H / (m h)) (1 − m/2 − 3E/(2K))]
//! period:                        T = L / c
//! trough:                        η_t = (H / m) (1 − m − E/K)
//! surface:                       η(x, t) = η_t + H cn²(2K (x/L − t/T) | m)
//! ```
//!
//! and `m` is found by matching `L(m)/c(m)` to the requested `T`. Long waves
//! have `m` extremely close to one, so the unknown is the logit
//! `s = log10((1 − m)/m)`, from which both `m` and `1 − m` are formed to full
//! relative accuracy and passed to the elliptic routines together. The
//! implied period grows without bound as `m → 1` (`K → ∞`); coming down from
//! `m → 1` it decreases until the celerity correction drives it back up
//! (KdV loses validity at small Ursell numbers). The physical root is the
//! first crossing met when scanning `s` upward from `−200` (i.e. from
//! `1 − m = 10⁻²⁰⁰`), refined by bisection. The trough level makes the
//! surface mean zero, since the period average of `cn²` is
//! `(E − (1 − m) K) / (m K)`.
//!
//! **Paddle.** Goring's rule moves a piston with the depth-averaged fluid
//! velocity under the target wave, evaluated at the paddle position `X`:
//!
//! ```text
//! dX/dt = r(t) [ c η(X, t) / (h + η(X, t)) − U₀ ]
//! ```
//!
//! with `r(t)` the half-cosine start-up ramp of [`super::half_cosine_ramp`]
//! and `U₀` a constant that removes the mean drift. `U₀` is not the plain
//! average of `cη/(h+η)` at a fixed point: because the paddle itself moves,
//! it samples the wave at the Doppler-shifted rate `(c − Ẋ)/L`, and a fixed
//! point average leaves a drift of order `L ⟨(Ẋ/c)²⟩` per period. Writing
//! `f(ξ) = c η/(h+η)` as a function of the phase `ξ = X/L − t/T`, the motion
//! after the ramp is autonomous in `ξ`, and one wave cycle displaces the paddle
//! by `L ∫₀¹ (f − U₀)/(c − f + U₀) dξ` while lasting
//! `T [1 + ∫₀¹ (f − U₀)/(c − f + U₀) dξ]`. Choosing `U₀` as the root of
//! that integral (evaluated once by trapezoidal quadrature over one period,
//! spectrally accurate for this smooth periodic integrand; the integrand is
//! monotone in `U₀`) therefore makes the post-ramp path exactly `T`-periodic
//! with zero drift. `U₀` equals the time mean of `f` along the paddle path.
//! Since `f/(c − f) = η/h`, the integral at `U₀ = 0` is the mean surface
//! elevation divided by `h`, which vanishes for this wave: Goring's rule is
//! drift-free as it stands and the root is `U₀ = 0` up to round-off. The root
//! is nevertheless solved numerically, so that any residual mean level is
//! compensated. (Subtracting instead the fixed-point mean of `f`, about
//! −0.02 m/s in the Ting & Kirby cases, would make the paddle creep by
//! roughly its whole stroke every five periods.)
//!
//! The trajectory is integrated with classical RK4 at a step of at most
//! `T/200`. For random access, [`CnoidalPaddle`] tabulates position and
//! velocity over the ramp plus one period (step `T/400`) and interpolates with
//! cubic Hermite polynomials; later times are folded back into the last
//! tabulated period, which is exact because the post-ramp path is periodic.

use super::elliptic::JacobiElliptic;
use super::{Result, WaveError, half_cosine_ramp, require_positive, require_unbroken};

/// Scan range and resolution of the logit `s = log10((1 − m)/m)`.
const LOGIT_MIN: f64 = -200.0;
const LOGIT_MAX: f64 = 12.0;
const LOGIT_STEP: f64 = 0.05;
/// RK4 steps per wave period in [`CnoidalPaddle::trajectory`] (brief: ≤ T/200).
const RK4_STEPS_PER_PERIOD: f64 = 200.0;
/// Table nodes per wave period for [`CnoidalPaddle::position_at`].
const TABLE_STEPS_PER_PERIOD: f64 = 400.0;
/// Longest accepted start-up ramp (keeps the lookup table bounded).
const MAX_RAMP_PERIODS: f64 = 1000.0;

/// A first-order cnoidal wave solved from height, period and depth.
#[derive(Debug, Clone, PartialEq)]
pub struct CnoidalWave {
    /// Crest-to-trough height.
    pub height_m: f64,
    /// Wave period.
    pub period_s: f64,
    /// Still water depth.
    pub depth_m: f64,
    /// Elliptic parameter `m = k²`.
    pub m: f64,
    /// `1 − m`, to full relative accuracy.
    pub one_minus_m: f64,
    /// Complete elliptic integral `K(m)`.
    pub k_m: f64,
    /// Complete elliptic integral `E(m)`.
    pub e_m: f64,
    /// Wavelength from the Ursell relation.
    pub wavelength_m: f64,
    /// Phase celerity `L / T`.
    pub celerity_m_s: f64,
    /// Trough elevation relative to the still water level (negative).
    pub trough_m: f64,
    jacobi: JacobiElliptic,
}

/// One trial value of the parameter in the period solve.
struct Trial {
    period_s: f64,
    wavelength_m: f64,
    celerity_m_s: f64,
    k_m: f64,
    e_m: f64,
    jacobi: JacobiElliptic,
}

/// `(m, 1 − m)` from the logit `s = log10((1 − m)/m)`, both accurate.
fn parameter_from_logit(logit: f64) -> (f64, f64) {
    if logit <= 0.0 {
        let r = 10f64.powf(logit);
        (1.0 / (1.0 + r), r / (1.0 + r))
    } else {
        let r = 10f64.powf(-logit);
        (r / (1.0 + r), 1.0 / (1.0 + r))
    }
}

/// Wavelength, celerity and implied period for the parameter at `logit`;
/// `None` where the celerity is not positive (outside the KdV branch).
fn trial(height_m: f64, depth_m: f64, gravity_m_s2: f64, logit: f64) -> Option<Trial> {
    let (m, one_minus_m) = parameter_from_logit(logit);
    let jacobi = JacobiElliptic::from_pair(m, one_minus_m)?;
    let (k_m, e_m) = jacobi.complete_integrals();
    if !k_m.is_finite() || m <= 0.0 {
        return None;
    }
    let wavelength_m = 4.0 * k_m * depth_m * (m * depth_m / (3.0 * height_m)).sqrt();
    // 1 − m/2 written as (1 + (1 − m))/2 to keep 1 − m exact.
    let correction = height_m / (m * depth_m) * (0.5 * (1.0 + one_minus_m) - 1.5 * e_m / k_m);
    let celerity_m_s = (gravity_m_s2 * depth_m).sqrt() * (1.0 + correction);
    if celerity_m_s.is_nan() || celerity_m_s <= 0.0 {
        return None;
    }
    Some(Trial {
        period_s: wavelength_m / celerity_m_s,
        wavelength_m,
        celerity_m_s,
        k_m,
        e_m,
        jacobi,
    })
}

impl CnoidalWave {
    /// Solves the cnoidal wave of height `height_m` and period `period_s` in
    /// depth `depth_m`.
    ///
    /// Errors on non-positive inputs, `H/h ≥ 0.78`, a period too short for the
    /// KdV branch (small Ursell number; use linear theory) or too long (beyond
    /// `1 − m = 10⁻²⁰⁰`, effectively a solitary wave).
    pub fn new(height_m: f64, period_s: f64, depth_m: f64, gravity_m_s2: f64) -> Result<Self> {
        let height_m = require_positive("height_m", height_m)?;
        let period_s = require_positive("period_s", period_s)?;
        let depth_m = require_positive("depth_m", depth_m)?;
        let gravity_m_s2 = require_positive("gravity_m_s2", gravity_m_s2)?;
        require_unbroken(height_m, depth_m)?;
        let implied = |logit: f64| trial(height_m, depth_m, gravity_m_s2, logit);

        // Scan upward from m → 1 for the first logit whose implied period
        // drops to the target.
        let steps = ((LOGIT_MAX - LOGIT_MIN) / LOGIT_STEP).round() as usize;
        let mut bracket = None;
        let mut previous: Option<f64> = None;
        for i in 0..=steps {
            let logit = LOGIT_MIN + i as f64 * LOGIT_STEP;
            let Some(t) = implied(logit) else { break };
            if t.period_s <= period_s {
                match previous {
                    Some(lo) => bracket = Some((lo, logit)),
                    None => {
                        return Err(WaveError::UrsellSolve {
                            period_s,
                            reason: "period too long (1 - m below 1e-200); use a solitary wave",
                        });
                    }
                }
                break;
            }
            previous = Some(logit);
        }
        let Some((mut lo, mut hi)) = bracket else {
            return Err(WaveError::UrsellSolve {
                period_s,
                reason: "period too short for KdV cnoidal theory at this height and depth \
                         (Ursell number too small); use linear theory",
            });
        };
        // Bisection: implied period > target at `lo`, ≤ target at `hi`.
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            match implied(mid) {
                Some(t) if t.period_s > period_s => lo = mid,
                Some(_) => hi = mid,
                None => {
                    return Err(WaveError::NoConvergence {
                        what: "cnoidal period bisection",
                    });
                }
            }
        }
        let solution = implied(0.5 * (lo + hi)).ok_or(WaveError::NoConvergence {
            what: "cnoidal period bisection",
        })?;
        if (solution.period_s / period_s - 1.0).abs() > 1e-9 {
            return Err(WaveError::NoConvergence {
                what: "cnoidal period bisection",
            });
        }
        let m = solution.jacobi.parameter();
        let one_minus_m = solution.jacobi.complement();
        let trough_m = height_m / m * (one_minus_m - solution.e_m / solution.k_m);
        Ok(Self {
            height_m,
            period_s,
            depth_m,
            m,
            one_minus_m,
            k_m: solution.k_m,
            e_m: solution.e_m,
            wavelength_m: solution.wavelength_m,
            celerity_m_s: solution.celerity_m_s,
            trough_m,
            jacobi: solution.jacobi,
        })
    }

    /// Crest elevation above the still water level, `η_t + H`.
    pub fn crest_m(&self) -> f64 {
        self.trough_m + self.height_m
    }

    /// Ursell number `H L² / h³`.
    pub fn ursell_number(&self) -> f64 {
        self.height_m * self.wavelength_m * self.wavelength_m / self.depth_m.powi(3)
    }

    /// Free-surface elevation `η(x, t) = η_t + H cn²(2K (x/L − t/T) | m)`,
    /// with the crest at `x = 0` when `t = 0`.
    pub fn eta_m(&self, x_m: f64, t_s: f64) -> f64 {
        let phase = x_m / self.wavelength_m - t_s / self.period_s;
        // cn² has period 2K in its argument, i.e. period 1 in the phase;
        // reduce to [−½, ½] so the Landen recursion sees |u| ≤ K.
        let reduced = phase - phase.round();
        let (_, cn, _) = self.jacobi.sn_cn_dn(2.0 * self.k_m * reduced);
        self.trough_m + self.height_m * cn * cn
    }

    /// Depth-averaged horizontal velocity `c η / (h + η)` under the wave.
    pub fn depth_averaged_velocity_m_s(&self, x_m: f64, t_s: f64) -> f64 {
        let eta = self.eta_m(x_m, t_s);
        self.celerity_m_s * eta / (self.depth_m + eta)
    }

    /// Number of trapezoidal nodes used for period averages: enough to
    /// resolve the crest, whose width in phase scales like `1/K`.
    fn quadrature_nodes(&self) -> usize {
        (256.0 * self.k_m).clamp(4096.0, 1_048_576.0) as usize
    }
}

/// Goring-type piston trajectory for a [`CnoidalWave`].
#[derive(Debug, Clone, PartialEq)]
pub struct CnoidalPaddle {
    wave: CnoidalWave,
    ramp_periods: f64,
    mean_velocity_m_s: f64,
    table_step_s: f64,
    table_x_m: Vec<f64>,
    table_u_m_s: Vec<f64>,
    stroke_m: f64,
}

impl CnoidalPaddle {
    /// Builds the paddle for `wave` with a half-cosine start-up ramp of
    /// `ramp_periods` wave periods (0 ≤ ramp_periods ≤ 1000): solves for the
    /// drift-cancelling mean velocity `U₀` and tabulates the path over the
    /// ramp plus one period.
    pub fn new(wave: CnoidalWave, ramp_periods: f64) -> Result<Self> {
        if !(ramp_periods.is_finite() && (0.0..=MAX_RAMP_PERIODS).contains(&ramp_periods)) {
            return Err(WaveError::OutOfRange {
                name: "ramp_periods",
                value: ramp_periods,
            });
        }
        let mean_velocity_m_s = closed_orbit_mean_velocity(&wave)?;
        let mut paddle = Self {
            table_step_s: wave.period_s / TABLE_STEPS_PER_PERIOD,
            wave,
            ramp_periods,
            mean_velocity_m_s,
            table_x_m: Vec::new(),
            table_u_m_s: Vec::new(),
            stroke_m: 0.0,
        };
        let steps = ((ramp_periods + 1.0) * TABLE_STEPS_PER_PERIOD).ceil() as usize;
        let h = paddle.table_step_s;
        let mut x = 0.0;
        paddle.table_x_m.reserve(steps + 1);
        paddle.table_u_m_s.reserve(steps + 1);
        for i in 0..=steps {
            let t = i as f64 * h;
            paddle.table_x_m.push(x);
            paddle.table_u_m_s.push(paddle.rhs(t, x, mean_velocity_m_s));
            x = paddle.rk4_step(t, x, h, mean_velocity_m_s);
        }
        // Stroke: excursion over the tabulated post-ramp period.
        let first = (paddle.ramp_duration_s() / h).floor() as usize;
        let (lo, hi) = paddle.table_x_m[first.min(steps)..]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            });
        paddle.stroke_m = hi - lo;
        Ok(paddle)
    }

    /// The target wave.
    pub fn wave(&self) -> &CnoidalWave {
        &self.wave
    }

    /// Start-up ramp length in wave periods.
    pub fn ramp_periods(&self) -> f64 {
        self.ramp_periods
    }

    /// Start-up ramp duration (s).
    pub fn ramp_duration_s(&self) -> f64 {
        self.ramp_periods * self.wave.period_s
    }

    /// The constant `U₀` subtracted from the Goring velocity (m/s).
    pub fn mean_velocity_m_s(&self) -> f64 {
        self.mean_velocity_m_s
    }

    /// Peak-to-peak paddle excursion once the ramp is over (m).
    pub fn stroke_m(&self) -> f64 {
        self.stroke_m
    }

    /// Right-hand side `r(t) [c η(X,t)/(h + η(X,t)) − U₀]` of the paddle ODE.
    fn rhs(&self, t_s: f64, x_m: f64, mean_velocity_m_s: f64) -> f64 {
        let ramp = half_cosine_ramp(t_s, self.ramp_duration_s());
        if ramp == 0.0 {
            return 0.0;
        }
        ramp * (self.wave.depth_averaged_velocity_m_s(x_m, t_s) - mean_velocity_m_s)
    }

    /// One classical Runge–Kutta step of length `h_s` from `(t_s, x_m)`.
    fn rk4_step(&self, t_s: f64, x_m: f64, h_s: f64, mean_velocity_m_s: f64) -> f64 {
        let k1 = self.rhs(t_s, x_m, mean_velocity_m_s);
        let k2 = self.rhs(t_s + 0.5 * h_s, x_m + 0.5 * h_s * k1, mean_velocity_m_s);
        let k3 = self.rhs(t_s + 0.5 * h_s, x_m + 0.5 * h_s * k2, mean_velocity_m_s);
        let k4 = self.rhs(t_s + h_s, x_m + h_s * k3, mean_velocity_m_s);
        x_m + h_s / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    }

    /// Integrates the paddle path from `X(0) = 0` with RK4 (internal step at
    /// most `T/200`, an integer fraction of `dt_s`) and returns samples
    /// `(t_s, x_m, u_m_s)` at `t = 0, dt, 2 dt, …` up to `duration_s`.
    /// Returns an empty vector for a non-positive or non-finite `dt_s` or a
    /// negative or non-finite `duration_s`.
    pub fn trajectory(&self, dt_s: f64, duration_s: f64) -> Vec<(f64, f64, f64)> {
        self.integrate(dt_s, duration_s, self.mean_velocity_m_s)
    }

    fn integrate(
        &self,
        dt_s: f64,
        duration_s: f64,
        mean_velocity_m_s: f64,
    ) -> Vec<(f64, f64, f64)> {
        let valid = dt_s.is_finite() && dt_s > 0.0 && duration_s.is_finite() && duration_s >= 0.0;
        if !valid {
            return Vec::new();
        }
        let outputs = (duration_s / dt_s * (1.0 + 1e-12)).floor() as usize;
        let max_step_s = self.wave.period_s / RK4_STEPS_PER_PERIOD;
        let substeps = ((dt_s / max_step_s) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
        let h = dt_s / substeps as f64;
        let mut samples = Vec::with_capacity(outputs + 1);
        let mut x = 0.0;
        for i in 0..=outputs {
            let t = i as f64 * dt_s;
            samples.push((t, x, self.rhs(t, x, mean_velocity_m_s)));
            if i == outputs {
                break;
            }
            for j in 0..substeps {
                x = self.rk4_step(t + j as f64 * h, x, h, mean_velocity_m_s);
            }
        }
        samples
    }

    /// Maps `t_s` into the tabulated interval `[0, ramp + T]` using the
    /// periodicity of the post-ramp motion.
    fn folded_time_s(&self, t_s: f64) -> f64 {
        let ramp_s = self.ramp_duration_s();
        let period_s = self.wave.period_s;
        if t_s <= ramp_s + period_s {
            t_s
        } else {
            ramp_s + (t_s - ramp_s).rem_euclid(period_s)
        }
    }

    /// Cubic Hermite interpolation of the table at a folded time.
    fn interpolate(&self, t_s: f64) -> f64 {
        let h = self.table_step_s;
        let last = self.table_x_m.len() - 1;
        let scaled = t_s / h;
        let index = (scaled.floor().max(0.0) as usize).min(last - 1);
        let tau = scaled - index as f64;
        let (x0, x1) = (self.table_x_m[index], self.table_x_m[index + 1]);
        let (u0, u1) = (self.table_u_m_s[index], self.table_u_m_s[index + 1]);
        let tau2 = tau * tau;
        let tau3 = tau2 * tau;
        (2.0 * tau3 - 3.0 * tau2 + 1.0) * x0
            + (tau3 - 2.0 * tau2 + tau) * h * u0
            + (3.0 * tau2 - 2.0 * tau3) * x1
            + (tau3 - tau2) * h * u1
    }

    /// Paddle position `X(t)` (m), zero for `t ≤ 0`; NaN for non-finite `t`.
    /// Deterministic and O(1): cubic Hermite interpolation of the tabulated
    /// RK4 path (agrees with [`Self::trajectory`] to about 1e-9 of the stroke).
    pub fn position_at(&self, t_s: f64) -> f64 {
        if !t_s.is_finite() {
            return f64::NAN;
        }
        if t_s <= 0.0 {
            return 0.0;
        }
        self.interpolate(self.folded_time_s(t_s))
    }

    /// Paddle velocity `dX/dt` (m/s) from the ODE right-hand side at the
    /// interpolated position; zero for `t ≤ 0`, NaN for non-finite `t`.
    pub fn velocity_at(&self, t_s: f64) -> f64 {
        if !t_s.is_finite() {
            return f64::NAN;
        }
        if t_s <= 0.0 {
            return 0.0;
        }
        let folded = self.folded_time_s(t_s);
        self.rhs(folded, self.interpolate(folded), self.mean_velocity_m_s)
    }
}

/// Solves `∫₀¹ (f − U₀)/(c − f + U₀) dξ = 0` for `U₀`, with `f = c η/(h + η)`
/// sampled over one wavelength (trapezoidal rule, periodic integrand), by
/// Newton iteration safeguarded with bisection on `[min f, max f]`.
fn closed_orbit_mean_velocity(wave: &CnoidalWave) -> Result<f64> {
    let nodes = wave.quadrature_nodes();
    let c = wave.celerity_m_s;
    let samples: Vec<f64> = (0..nodes)
        .map(|i| wave.depth_averaged_velocity_m_s(wave.wavelength_m * i as f64 / nodes as f64, 0.0))
        .collect();
    let (mut lo, mut hi) = samples
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &f| {
            (lo.min(f), hi.max(f))
        });
    let mut u0 = samples.iter().sum::<f64>() / nodes as f64;
    let tolerance = 1e-14 * c;
    for _ in 0..200 {
        let (mut value, mut slope) = (0.0, 0.0);
        for &f in &samples {
            let denom = c - f + u0;
            value += (f - u0) / denom;
            slope -= c / (denom * denom);
        }
        if value > 0.0 {
            lo = u0;
        } else {
            hi = u0;
        }
        let mut next = u0 - value / slope;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - u0).abs() <= tolerance || hi - lo <= tolerance {
            return Ok(next);
        }
        u0 = next;
    }
    Err(WaveError::NoConvergence {
        what: "cnoidal paddle mean velocity",
    })
}

#[cfg(test)]
mod tests;
