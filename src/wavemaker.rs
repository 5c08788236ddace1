//! The paddle as a moving wall of the mesh (thesis eqs. 2.32–2.40; method.md §5), and the
//! design of its motion from a case ([`PaddleMotion::from_case`]: the schema in `case` names
//! the wave, the theory in `waves` knows nothing of cases, and this layer joins the two).
//!
//! The paddle is a column of wall nodes standing on the bed at `wavemaker.x_m`, from half a
//! spacing above the bed up to the top of the flume. Before each step the simulation gives every
//! paddle node the velocity that takes it from where it is to where the motion puts it at the end
//! of the step, (X(t + Δt) − x)/Δt (eq. 2.40): that velocity is the node's Dirichlet condition in
//! the step, and after the step the node is put exactly on the path, so no error accumulates. The
//! face, extended without limit, also guards the fluid: no particle crosses it, and no triangle
//! behind it is kept.
//!
//! A piston may also absorb the long waves that reach it (`wavemaker.absorb_long_waves`): the
//! seiche and the set-down a beach sends back, which a rigid paddle would reflect into the
//! flume for ever. Shallow-water active absorption (Schäffer & Klopman 2000, in its long-wave
//! limit): at the face (read one depth in front of it) η = 2 η_R + (h/c) U_a, with η_R the
//! long wave arriving, U_a the paddle's absorbing velocity and c = √(g h); the paddle cancels
//! the re-reflection by moving with U_a = −(c/h) η_R. Only the mean over the last wave period
//! is used, so the waves the paddle makes are left to their theory and only the long motion
//! is absorbed. The paddle's own absorbing motion is taken out of what is read, so with a face
//! that answers as the model says there is no feedback at all; one that answers g times the
//! model closes a loop of gain (g − 1)/2 times the one-period mean, stable for 0 < g < 3.
//!
//! A paddle may also absorb the wave the beach reflects, at its own period
//! (`wavemaker.absorb_reflected_waves`, piston or flap): two gauges in front of it split the
//! last period into the waves going out and coming back, and the paddle adds the motion that
//! radiates the opposite of the second (`waves::absorption`). Its displacement is capped at the
//! paddle's own amplitude, for which the case's check leaves room.

use std::collections::VecDeque;

use crate::case::{Case, WaveTheory};
use crate::geometry::{Flume, PaddleFace};
use crate::particles::Particles;
use crate::waves::WaveError;
use crate::waves::absorption::{self, ReflectionAbsorber};
use crate::waves::linear::PaddleKind;
use crate::waves::paddle::PaddleMotion;
use nalgebra::Vector2;

impl PaddleMotion {
    /// The paddle motion a case asks for, designed from its theory for the still-water depth in
    /// front of the paddle (`None` without a wavemaker). Errors say why the wave cannot be made.
    /// The case's validation calls it too, to refuse a wave that cannot be made or a stroke the
    /// flume has no room for.
    pub fn from_case(case: &Case) -> Option<Result<PaddleMotion, WaveError>> {
        let w = case.wavemaker.as_ref()?;
        let depth = case.paddle_depth_m().unwrap_or(0.0);
        let g = case.fluid.gravity_m_s2;
        let height = w.paddle_height();
        Some(match w.theory {
            WaveTheory::Linear => {
                PaddleMotion::linear(w.paddle, height, w.period_s, depth, g, w.ramp_periods)
            }
            WaveTheory::Cnoidal => {
                PaddleMotion::cnoidal(height, w.period_s, depth, g, w.ramp_periods)
            }
            WaveTheory::Solitary => PaddleMotion::solitary(height, depth, g),
        })
    }
}

#[derive(Debug, Clone)]
pub struct Wavemaker {
    pub motion: PaddleMotion,
    /// The face's foot at rest: the hinge of a flap, the bottom of a piston (on the bed), m.
    pub hinge: Vector2<f64>,
    /// Still-water depth in front of the paddle, m.
    pub depth_m: f64,
    /// Distance of each paddle node from the hinge along the face, m.
    offsets_m: Vec<f64>,
    /// Index of the first paddle node among the particles (they are consecutive wall nodes).
    pub first_node: usize,
    /// Length of the face, hinge to top, m.
    length_m: f64,
    /// Displacement held from an earlier motion, and when the current motion started (see
    /// [`Wavemaker::retune`]).
    hold_m: f64,
    start_s: f64,
    /// The long-wave absorber, when the case asks for it.
    absorber: Option<LongWaveAbsorber>,
    /// The absorber of the reflected wave, when the case asks for it, and what a retune needs
    /// to build it again for another period.
    reflection: Option<ReflectionAbsorber>,
    reflection_design: Option<ReflectionDesign>,
    /// The slip wall nodes of the flume, with their tangents (empty with no-slip walls): those
    /// the face stands over or behind are held at rest ([`Wavemaker::prescribe`]).
    slip_walls: Vec<(usize, Vector2<f64>)>,
    /// Particle spacing h, m.
    spacing_m: f64,
}

/// What the reflected-wave absorber is built from (see [`Wavemaker::retune`]).
#[derive(Debug, Clone, Copy)]
struct ReflectionDesign {
    gravity_m_s2: f64,
    /// Flat bed in front of the paddle, m.
    flat_m: f64,
}

impl ReflectionDesign {
    /// The absorber for `motion` started at `start_s` (it begins one period after the ramp,
    /// or after the first period: the split assumes a steady wave); `None` when the flat bed
    /// has no room for its gauges at that period.
    fn build(
        &self,
        motion: &PaddleMotion,
        depth_m: f64,
        start_s: f64,
    ) -> Option<ReflectionAbsorber> {
        let period = motion.period_s();
        let gauges =
            absorption::gauge_offsets_m(period, depth_m, self.gravity_m_s2, self.flat_m).ok()?;
        let begin = start_s + motion.ramp_duration_s().max(period);
        ReflectionAbsorber::new(
            motion.kind(),
            period,
            depth_m,
            self.gravity_m_s2,
            gauges,
            begin,
            0.5 * motion.stroke_m(),
        )
        .ok()
    }
}

/// The long-wave absorber's state (see the module comment).
#[derive(Debug, Clone)]
pub struct LongWaveAbsorber {
    /// Averaging window: one wave period, s.
    window_s: f64,
    /// √(g h), m/s, and the still depth h at the paddle, m.
    celerity_m_s: f64,
    depth_m: f64,
    /// (time, η − (h/c) U_a) at the face, m, over the last window.
    samples: VecDeque<(f64, f64)>,
    /// Displacement made by absorbing, at `at_s`, m; the velocity it moves with until the
    /// next step ends, m/s.
    offset_m: f64,
    at_s: f64,
    velocity_m_s: f64,
    /// The absorbing displacement stays within [−back, forward], m: forward at most one
    /// depth, back no closer than two spacings to the left wall at the end of the stroke.
    /// A flume that loses water steadily would otherwise push the paddle on for ever.
    limits_m: (f64, f64),
}

impl LongWaveAbsorber {
    pub fn new(window_s: f64, depth_m: f64, gravity_m_s2: f64) -> Self {
        Self {
            window_s,
            celerity_m_s: (gravity_m_s2 * depth_m).sqrt(),
            depth_m,
            samples: VecDeque::new(),
            offset_m: 0.0,
            at_s: 0.0,
            velocity_m_s: 0.0,
            limits_m: (-f64::INFINITY, f64::INFINITY),
        }
    }

    /// Bounds the absorbing displacement to [−`back_m`, `forward_m`].
    pub fn with_limits(mut self, back_m: f64, forward_m: f64) -> Self {
        self.limits_m = (-back_m.max(0.0), forward_m.max(0.0));
        self
    }

    /// Displacement from absorbing at `t_s` (≥ the last commit), m.
    pub fn offset_at(&self, t_s: f64) -> f64 {
        self.offset_m + self.velocity_m_s * (t_s - self.at_s)
    }

    /// The absorbing velocity for the step starting at `t_s`, m/s, given η at the face then
    /// (m above still water; `None` when no surface was found: the last velocity is kept).
    pub fn update(&mut self, t_s: f64, eta_m: Option<f64>) -> f64 {
        self.offset_m = self.offset_at(t_s);
        self.at_s = t_s;
        let Some(eta) = eta_m else {
            return self.velocity_m_s;
        };
        let ratio = self.depth_m / self.celerity_m_s;
        self.samples
            .push_back((t_s, eta - ratio * self.velocity_m_s));
        while self
            .samples
            .get(1)
            .is_some_and(|(t, _)| *t <= t_s - self.window_s)
        {
            self.samples.pop_front();
        }
        // Trapezoidal mean over the window; nothing is done before it is full (a part of a
        // wave period has a mean of its own).
        let span = t_s - self.samples[0].0;
        if span < self.window_s - 1e-9 {
            return self.velocity_m_s;
        }
        // The first interval is cut at t − window, the value interpolated there.
        let from = t_s - self.window_s;
        let integral: f64 = self
            .samples
            .iter()
            .zip(self.samples.iter().skip(1))
            .map(|(a, b)| {
                let (t0, v0) = if a.0 < from {
                    (from, a.1 + (b.1 - a.1) * (from - a.0) / (b.0 - a.0))
                } else {
                    *a
                };
                0.5 * (v0 + b.1) * (b.0 - t0)
            })
            .sum();
        let mean = integral / self.window_s;
        let arriving = 0.5 * mean;
        self.velocity_m_s = -arriving / ratio;
        let (lo, hi) = self.limits_m;
        if (self.offset_m >= hi && self.velocity_m_s > 0.0)
            || (self.offset_m <= lo && self.velocity_m_s < 0.0)
        {
            self.velocity_m_s = 0.0;
        }
        self.velocity_m_s
    }

    /// Forgets the displacement made so far (a retune has put it in the paddle's hold).
    fn clear_offset(&mut self, t_s: f64) {
        self.offset_m = 0.0;
        self.at_s = t_s;
    }
}

impl Wavemaker {
    /// The case's paddle, or `None` without one. The case was validated, so the motion exists.
    pub fn from_case(
        case: &Case,
        flume: &Flume,
        first_node: usize,
    ) -> Option<Result<Self, WaveError>> {
        let w = case.wavemaker.as_ref()?;
        let motion = match PaddleMotion::from_case(case)? {
            Ok(m) => m,
            Err(e) => return Some(Err(e)),
        };
        // The spacing where the paddle stands.
        let h = case.particles.spacing().at(w.x_m);
        let hinge = Vector2::new(w.x_m, flume.bed_y(w.x_m));
        let length_m = flume.height_m - hinge.y;
        let n = (length_m / h).round().max(1.0) as usize;
        let spacing = length_m / (n as f64 + 0.5);
        let offsets_m = (0..=n).map(|k| (k as f64 + 0.5) * spacing).collect();
        let depth = case.paddle_depth_m().unwrap_or(0.0);
        let absorber = w.absorb_long_waves.then(|| {
            // The reflected-wave absorber may swing back as far again as the motion.
            let (back, _) = motion.excursion_m();
            let back = if w.absorb_reflected_waves {
                2.0 * back
            } else {
                back
            };
            LongWaveAbsorber::new(w.period_s, depth, case.fluid.gravity_m_s2)
                .with_limits(w.x_m + back - 2.0 * h, depth)
        });
        let reflection_design = w.absorb_reflected_waves.then(|| ReflectionDesign {
            gravity_m_s2: case.fluid.gravity_m_s2,
            flat_m: absorption::flat_length_m(w.x_m, flume.length_m, |x| flume.bed_y(x)),
        });
        let reflection = reflection_design.and_then(|d| d.build(&motion, depth, 0.0));
        Some(Ok(Wavemaker {
            motion,
            hinge,
            depth_m: case.paddle_depth_m().unwrap_or(0.0),
            offsets_m,
            first_node,
            length_m,
            hold_m: 0.0,
            start_s: 0.0,
            absorber,
            reflection,
            reflection_design,
            slip_walls: if case.flume.walls == crate::case::WallCondition::Slip {
                let walls = flume.wall_nodes_with_tangents(&case.particles.spacing());
                (walls.into_iter().enumerate())
                    .filter(|(_, (_, t))| *t != Vector2::zeros())
                    .map(|(i, (_, t))| (i, t))
                    .collect()
            } else {
                Vec::new()
            },
            spacing_m: h,
        }))
    }

    /// Number of paddle nodes.
    pub fn node_count(&self) -> usize {
        self.offsets_m.len()
    }

    /// The point at distance `r_m` from the hinge along the face at time `t_s`.
    pub fn point(&self, r_m: f64, t_s: f64) -> Vector2<f64> {
        let x = self.displacement_m(t_s);
        match self.motion.kind() {
            PaddleKind::Piston => self.hinge + Vector2::new(x, r_m),
            PaddleKind::Flap => {
                let angle = (x / self.depth_m).atan();
                self.hinge + r_m * Vector2::new(angle.sin(), angle.cos())
            }
        }
    }

    /// Displacement of the face at the still-water level at `t_s`, m.
    pub fn displacement_m(&self, t_s: f64) -> f64 {
        let absorbed = self.absorber.as_ref().map_or(0.0, |a| a.offset_at(t_s))
            + self.reflection.as_ref().map_or(0.0, |a| a.offset_at(t_s));
        self.hold_m + self.motion.displacement_m(t_s - self.start_s) + absorbed
    }

    /// Whether the paddle absorbs long waves (it then needs [`Wavemaker::absorb`] before
    /// every step).
    pub fn absorbs(&self) -> bool {
        self.absorber.is_some()
    }

    /// Where η is read for the absorber at `t_s`: one still depth (at least two spacings) in
    /// front of the face, past the local disturbance of the face itself (its evanescent modes,
    /// and the contact line, whose mean stands above the water's), m. A long wave takes h/c,
    /// under a tenth of a period, from there to the face.
    pub fn probe_x_m(&self, t_s: f64, spacing_m: f64) -> f64 {
        self.hinge.x + self.displacement_m(t_s) + self.depth_m.max(2.0 * spacing_m)
    }

    /// Still-water level at the paddle, m.
    pub fn still_level_m(&self) -> f64 {
        self.hinge.y + self.depth_m
    }

    /// Before a step from `t_s`: feeds η at the probe (m above still water) to the absorber,
    /// which sets the paddle's absorbing velocity for the step. Returns that velocity, m/s
    /// (0 without an absorber).
    pub fn absorb(&mut self, t_s: f64, eta_m: Option<f64>) -> f64 {
        self.absorber.as_mut().map_or(0.0, |a| a.update(t_s, eta_m))
    }

    /// The flume x of the reflected-wave absorber's two gauges, m, when the paddle has one.
    pub fn reflection_gauges_x_m(&self) -> Option<[f64; 2]> {
        let [a, b] = self.reflection.as_ref()?.gauges_m();
        Some([self.hinge.x + a, self.hinge.x + b])
    }

    /// Before a step from `t_s`: feeds η at the two reflection gauges (m above still water;
    /// `None` when either is dry) to the reflected-wave absorber.
    pub fn absorb_reflection(&mut self, t_s: f64, eta_m: Option<[f64; 2]>) {
        if let Some(a) = &mut self.reflection {
            a.update(t_s, eta_m);
        }
    }

    /// The amplitude of the reflected wave arriving at the paddle, from its absorber's last
    /// full period, m (`None` without one).
    pub fn arriving_amplitude_m(&self) -> Option<f64> {
        self.reflection.as_ref().map(|a| a.arriving_amplitude_m())
    }

    /// The amplitude of the wave going out from the paddle, read as
    /// [`Wavemaker::arriving_amplitude_m`], m.
    pub fn outgoing_amplitude_m(&self) -> Option<f64> {
        self.reflection.as_ref().map(|a| a.outgoing_amplitude_m())
    }

    /// The displacement absorbing has added so far, m.
    pub fn absorbed_offset_m(&self, t_s: f64) -> f64 {
        self.absorber.as_ref().map_or(0.0, |a| a.offset_at(t_s))
    }

    /// Switches to a new motion at `t_s` (the lab's wave controls): the paddle holds where it is
    /// and the new motion starts from there with its own ramp, so the face never jumps.
    pub fn retune(&mut self, motion: PaddleMotion, t_s: f64) {
        self.hold_m = self.displacement_m(t_s);
        if let Some(a) = &mut self.absorber {
            a.clear_offset(t_s);
        }
        self.start_s = t_s;
        self.reflection = self
            .reflection_design
            .and_then(|d| d.build(&motion, self.depth_m, t_s));
        self.motion = motion;
    }

    /// Node positions at rest (t = 0).
    pub fn rest_nodes(&self) -> Vec<Vector2<f64>> {
        self.offsets_m.iter().map(|&r| self.point(r, 0.0)).collect()
    }

    /// The face at `t_s`, with the mean velocities of its ends over [t_s − dt_s, t_s].
    pub fn face(&self, t_s: f64, dt_s: f64) -> PaddleFace {
        let (foot, top) = (self.point(0.0, t_s), self.point(self.length_m, t_s));
        let (foot0, top0) = (
            self.point(0.0, t_s - dt_s),
            self.point(self.length_m, t_s - dt_s),
        );
        PaddleFace {
            foot,
            top,
            foot_velocity: (foot - foot0) / dt_s,
            top_velocity: (top - top0) / dt_s,
        }
    }

    /// Before a step from `t_s` to `t_s + dt_s`: give the paddle nodes the velocity that lands
    /// them on the path (eq. 2.40), and set the faces the mesh and the guard use.
    pub fn prescribe(&self, particles: &mut Particles, flume: &mut Flume, t_s: f64, dt_s: f64) {
        for (k, &r) in self.offsets_m.iter().enumerate() {
            let i = self.first_node + k;
            let target = self.point(r, t_s + dt_s);
            particles.wall_velocity[i] = (target - particles.position[i]) / dt_s;
        }
        flume.paddle_now = Some(self.face(t_s, dt_s));
        flume.paddle = Some(self.face(t_s + dt_s, dt_s));
        // A slip wall node under the face's foot or behind it is held at rest, as on a no-slip
        // wall. Its velocity along the bed would be free, and in the thin triangles between
        // the foot, the bed and the water the continuity equation sets it alone: at a piston's
        // foot it reached 5 m/s and the run diverged at 1.83 s (2D, d = 0.25 m, H = 3 cm). In
        // front of the face, it slips again.
        let reach_x =
            self.point(0.0, t_s).x.max(self.point(0.0, t_s + dt_s).x) + 0.5 * self.spacing_m;
        for &(i, tangent) in &self.slip_walls {
            particles.wall_tangent[i] = if particles.position[i].x <= reach_x {
                Vector2::zeros()
            } else {
                tangent
            };
        }
    }

    /// After the step (which reached `t_s`): put the nodes exactly on the path.
    pub fn snap(&self, particles: &mut Particles, t_s: f64) {
        for (k, &r) in self.offsets_m.iter().enumerate() {
            particles.position[self.first_node + k] = self.point(r, t_s);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::LongWaveAbsorber;

    /// The face as the absorber's model sees it, with a gain error: η = 2 η_R + g (h/c) U_a
    /// plus the paddle's own short waves, which average out over a period.
    fn run(gain: f64, arriving_m: impl Fn(f64) -> f64, until_s: f64) -> (LongWaveAbsorber, f64) {
        let (depth, g, period, dt) = (0.4, 9.81, 2.0, 0.01);
        let mut a = LongWaveAbsorber::new(period, depth, g);
        let ratio = depth / (g * depth).sqrt();
        let mut u = 0.0;
        let steps = (until_s / dt).round() as usize;
        for k in 0..steps {
            let t = k as f64 * dt;
            let short = 0.06 * (2.0 * std::f64::consts::PI * t / period).sin();
            let eta = 2.0 * arriving_m(t) + gain * ratio * u + short;
            u = a.update(t, Some(eta));
        }
        (a, u)
    }

    #[test]
    fn a_steady_long_wave_is_absorbed_and_short_waves_are_left_alone() {
        let (depth, g) = (0.4_f64, 9.81_f64);
        let c_over_h = (g * depth).sqrt() / depth;
        // A set-down of 5 mm arriving: the paddle must move with U = −(c/h) η_R = +0.0248 m/s.
        // With a face that answers g times the model, the loop settles at 2/(1 + g) of that,
        // and the long wave leaving is η_R + g (h/c) U = η_R (1 − g)/(1 + g): still absorbed
        // but for that fraction.
        for gain in [1.0, 0.6, 1.5] {
            let (_, u) = run(gain, |_| -0.005, 40.0);
            let want = c_over_h * 0.005 * 2.0 / (1.0 + gain);
            let leaving = -0.005 + gain * u / c_over_h;
            println!(
                "gain {gain}: U_a = {u:.5} m/s (loop theory {want:.5}), long wave leaving {:.2} mm",
                leaving * 1e3
            );
            assert!((u - want).abs() < 0.02 * want, "gain {gain}: {u} vs {want}");
            assert!(leaving.abs() <= 0.005 * ((1.0 - gain) / (1.0 + gain)).abs() + 1e-4);
        }
        // Short waves alone: the paddle barely moves (the mean over a period is zero).
        let (a, u) = run(1.0, |_| 0.0, 40.0);
        let drift = a.offset_at(40.0);
        println!("short waves only: U_a = {u:.2e} m/s, offset {drift:.2e} m");
        assert!(u.abs() < 1e-3 && drift.abs() < 2e-3, "{u} {drift}");
    }

    #[test]
    fn the_absorbing_displacement_is_bounded() {
        // A flume losing water reads a level that keeps falling: the paddle stops one depth in.
        let mut a = LongWaveAbsorber::new(2.0, 0.4, 9.81).with_limits(0.1, 0.4);
        let dt = 0.01;
        for k in 0..20_000 {
            a.update(k as f64 * dt, Some(-0.02));
        }
        let x = a.offset_at(200.0);
        println!("offset after 200 s of a 2 cm deficit: {x:.4} m (limit 0.4)");
        assert!((0.39..=0.41).contains(&x), "{x}");
        let mut a = LongWaveAbsorber::new(2.0, 0.4, 9.81).with_limits(0.1, 0.4);
        for k in 0..20_000 {
            a.update(k as f64 * dt, Some(0.02));
        }
        let x = a.offset_at(200.0);
        assert!((-0.11..=-0.09).contains(&x), "{x}");
    }

    #[test]
    fn a_seiche_is_followed_without_growing() {
        // A 30 s seiche of 3 mm: the absorbing velocity follows −(c/h) η_R, delayed by about
        // half the averaging window, and stays bounded even with a 50 % gain error.
        let (depth, g) = (0.4_f64, 9.81_f64);
        let c_over_h = (g * depth).sqrt() / depth;
        let seiche = |t: f64| 0.003 * (2.0 * std::f64::consts::PI * t / 30.0).sin();
        for gain in [1.0, 1.5] {
            let (_, u) = run(gain, seiche, 120.0);
            let want = -c_over_h * seiche(120.0 - 1.0) * 2.0 / (1.0 + gain);
            println!("gain {gain}: U_a = {u:.5} m/s, −(c/h) η_R one second earlier {want:.5}");
            assert!((u - want).abs() < 0.25 * c_over_h * 0.003, "{u} vs {want}");
        }
    }

    #[test]
    fn a_calibrated_paddle_is_driven_for_its_own_height() {
        use crate::case::Case;
        use crate::waves::paddle::PaddleMotion;
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/ting_kirby_spilling.toml");
        let c = Case::load(&path, &[]).unwrap();
        let w = c.wavemaker.as_ref().unwrap();
        assert_eq!((w.height_m, w.paddle_height()), (0.125, 0.120));
        let depth = c.paddle_depth_m().unwrap();
        let expected = PaddleMotion::cnoidal(0.120, 2.0, depth, 9.81, w.ramp_periods).unwrap();
        let motion = PaddleMotion::from_case(&c).unwrap().unwrap();
        assert_eq!(motion.excursion_m(), expected.excursion_m());
        let e = Case::load(&path, &["wavemaker.paddle_height_m=-0.1".into()]).unwrap_err();
        assert!(e.to_string().contains("wavemaker.paddle_height_m"), "{e}");
    }
}
