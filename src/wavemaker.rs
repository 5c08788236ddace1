//! The paddle as a moving wall of the mesh (thesis eqs. 2.32–2.40; method.md §5).
//!
//! The paddle is a column of wall nodes standing on the bed at `wavemaker.x_m`, from half a
//! spacing above the bed up to the top of the flume. Before each step the simulation gives every
//! paddle node the velocity that takes it from where it is to where the motion puts it at the end
//! of the step, (X(t + Δt) − x)/Δt (eq. 2.40): that velocity is the node's Dirichlet condition in
//! the step, and after the step the node is put exactly on the path, so no error accumulates. The
//! face, extended without limit, also guards the fluid: no particle crosses it, and no triangle
//! behind it is kept.

use crate::case::Case;
use crate::geometry::{Flume, PaddleFace};
use crate::particles::Particles;
use crate::waves::WaveError;
use crate::waves::linear::PaddleKind;
use crate::waves::paddle::PaddleMotion;
use nalgebra::Vector2;

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
}

impl Wavemaker {
    /// The case's paddle, or `None` without one. The case was validated, so the motion exists.
    pub fn from_case(
        case: &Case,
        flume: &Flume,
        first_node: usize,
    ) -> Option<Result<Self, WaveError>> {
        let w = case.wavemaker.as_ref()?;
        let motion = match case.paddle_motion()? {
            Ok(m) => m,
            Err(e) => return Some(Err(e)),
        };
        let h = case.particles.spacing_m;
        let hinge = Vector2::new(w.x_m, flume.bed_y(w.x_m));
        let length_m = flume.height_m - hinge.y;
        let n = (length_m / h).round().max(1.0) as usize;
        let spacing = length_m / (n as f64 + 0.5);
        let offsets_m = (0..=n).map(|k| (k as f64 + 0.5) * spacing).collect();
        Some(Ok(Wavemaker {
            motion,
            hinge,
            depth_m: case.paddle_depth_m().unwrap_or(0.0),
            offsets_m,
            first_node,
            length_m,
            hold_m: 0.0,
            start_s: 0.0,
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
        self.hold_m + self.motion.displacement_m(t_s - self.start_s)
    }

    /// Switches to a new motion at `t_s` (the lab's wave controls): the paddle holds where it is
    /// and the new motion starts from there with its own ramp, so the face never jumps.
    pub fn retune(&mut self, motion: PaddleMotion, t_s: f64) {
        self.hold_m = self.displacement_m(t_s);
        self.start_s = t_s;
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
    }

    /// After the step (which reached `t_s`): put the nodes exactly on the path.
    pub fn snap(&self, particles: &mut Particles, t_s: f64) {
        for (k, &r) in self.offsets_m.iter().enumerate() {
            particles.position[self.first_node + k] = self.point(r, t_s);
        }
    }
}
