//! Stage `move`: commit uⁿ⁺¹, pⁿ⁺¹ and π (stopping the run if a velocity is not finite or
//! beyond the speed limit), move the fluid particles, x ← x + Δt uⁿ⁺¹ (thesis
//! eq. 2.59), and put back any particle that came closer to the solid than the wall margin
//! (method.md §2 (c)–(d)), removing its velocity into the wall. Also the inversion check that
//! lets the step halve Δt. In a damping layer (`absorber`), fluid velocities are first
//! multiplied by max(0, 1 − Δt·β·f²), f the fraction of the way into the layer.

use super::surface::SurfaceChains;
use super::{Solver, StepError};
use crate::geometry::Flume;
use crate::particles::Particles;
use nalgebra::Vector2;

/// Half width, in surface nodes, of the window whose mean velocity the implicit geometry leaves
/// out (`shift_geometry`): 4, a 9-node (8 h) window, which separates the 3–8 h modes that grow
/// from the waves of 30 h and more that the validation cases carry.
pub(super) const SHIFT_REACH: usize = 4;

impl Solver {
    /// Would moving the nodes by Δt·uⁿ⁺¹ turn a well-shaped kept triangle (area above 1 % of
    /// h²) inside out? Slivers are left out: they flip under any motion and the next remesh
    /// replaces them anyway.
    pub(super) fn would_invert(&self, particles: &Particles, dt: f64) -> bool {
        let x = &particles.position;
        let u = &self.u_new;
        let min_area = 0.01 * self.params.spacing_m * self.params.spacing_m;
        self.mesh.triangles.iter().any(|t| {
            if crate::fem::triangle_area(x, t).abs() < min_area {
                return false;
            }
            let [a, b, c] = t.map(|i| {
                let i = i as usize;
                x[i] + dt * u[i]
            });
            (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) <= 0.0
        })
    }

    /// Keeps xⁿ and moves each free-surface fluid node by `dt_s` (θₓ Δt) times the short-scale
    /// part of its velocity, uⁿ⁺¹ less its mean over the window of 2·[`SHIFT_REACH`] + 1 surface
    /// nodes centred on it; the other nodes stay. This is the geometry of the second pass of
    /// `geometry_theta`; [`Solver::restore_geometry`] puts the nodes back. A mode of wavenumber
    /// k is shifted by (1 − ŝ(k)) of its motion, ŝ(k) = sin((2r + 1)kh/2) / ((2r + 1) sin(kh/2))
    /// the window's response (r the reach): 1.23 for a 6.25 h ripple, 0.03 for a 65 h wave.
    /// Where the chain ends within the reach (a wall, a pinch, a short drop) the window
    /// narrows to what is left on both sides; a node next to the end stays.
    pub(super) fn shift_geometry(&mut self, particles: &mut Particles, dt_s: f64) {
        self.geometry_saved.clear();
        self.geometry_saved.extend_from_slice(&particles.position);
        let chains = SurfaceChains::new(&self.mesh, particles);
        let u = &self.u_new;
        let shift: Vec<(usize, Vector2<f64>)> = (0..particles.len() as u32)
            .filter_map(|i| {
                let (before, after) = chains.window(i, SHIFT_REACH)?;
                let sum: Vector2<f64> = before.iter().chain(&after).map(|&k| u[k as usize]).sum();
                let mean = (sum + u[i as usize]) / (2 * before.len() + 1) as f64;
                Some((i as usize, dt_s * (u[i as usize] - mean)))
            })
            .collect();
        for (i, dx) in shift {
            particles.position[i] += dx;
        }
    }

    /// The positions xⁿ that [`Solver::shift_geometry`] kept, exactly.
    pub(super) fn restore_geometry(&self, particles: &mut Particles) {
        particles.position.copy_from_slice(&self.geometry_saved);
    }

    /// Returns how many particles the wall guard put back.
    pub(super) fn move_particles(
        &mut self,
        particles: &mut Particles,
        flume: &Flume,
        dt: f64,
    ) -> Result<usize, StepError> {
        let margin = self.params.wall_margin_m;
        let mut guarded = 0;
        for i in 0..particles.len() {
            particles.pressure[i] = self.p_new[i];
            particles.pressure_gradient_projection[i] = self.pi_new[i];
            if !particles.is_fluid(i) {
                // Walls move with their solid (a paddle; fixed walls stay put); a slip wall keeps
                // its velocity along the wall.
                particles.position[i] += dt * particles.wall_velocity[i];
                particles.velocity[i] = self.u_new[i];
                continue;
            }
            let mut u = self.u_new[i];
            if !(u.x.is_finite() && u.y.is_finite()) {
                let x = particles.position[i];
                return Err(StepError::NonFinite {
                    quantity: "velocity",
                    node: i,
                    x: x.x,
                    y: x.y,
                });
            }
            let speed = u.norm();
            if speed > self.params.speed_limit_m_s {
                let x = particles.position[i];
                return Err(StepError::Diverged {
                    speed_m_s: speed,
                    limit_m_s: self.params.speed_limit_m_s,
                    x: x.x,
                    y: x.y,
                });
            }
            if let Some((x0, length, beta)) = self.params.absorber {
                let f = ((particles.position[i].x - x0) / length).clamp(0.0, 1.0);
                u *= (1.0 - dt * beta * f * f).max(0.0);
            }
            let mut x = particles.position[i] + dt * u;
            if flume.guard(&mut x, &mut u, margin) {
                guarded += 1;
            }
            particles.position[i] = x;
            particles.velocity[i] = u;
        }
        Ok(guarded)
    }
}
