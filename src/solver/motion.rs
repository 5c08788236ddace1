//! Stage `move`: commit uⁿ⁺¹, pⁿ⁺¹ and π (stopping the run if a velocity is not finite or
//! beyond the speed limit), move the fluid particles, x ← x + Δt uⁿ⁺¹ (thesis eq. 2.59; with
//! `solver.midpoint_move` by the implicit midpoint rule in the end-of-step flow,
//! [`midpoint_factors`]), and put back any particle that came closer to the solid than the
//! wall margin (method.md §2 (c)–(d)), removing its velocity into the wall. Also the inversion check that
//! lets the step halve Δt. In a damping layer (`absorber`), fluid velocities are first
//! multiplied by max(0, 1 − Δt·β·f²), f the fraction of the way into the layer.

use super::element_set::ElementSet;
use super::surface::SurfaceChains;
use super::{Solver, StepError};
use crate::geometry::Flume;
use crate::particles::Particles;
use nalgebra::{Matrix2, Vector2};

/// Half width, in surface nodes, of the window whose mean velocity the implicit geometry leaves
/// out (`shift_geometry`): 4, a 9-node (8 h) window, which separates the 3–8 h modes that grow
/// from the waves of 30 h and more that the validation cases carry.
pub(super) const SHIFT_REACH: usize = 4;

/// The largest Δt G/2 (Frobenius norm) the midpoint move uses; a larger one is scaled down to
/// it. A smooth wave has Δt |∇u|/2 of order 1e-3; values near 1 come from a node among
/// slivers or a splash, where the flow is not linear over the node's cells.
const MIDPOINT_CAP: f64 = 0.1;

impl Solver {
    /// Would moving the nodes by Δt·uⁿ⁺¹ turn a well-shaped kept triangle (area above 1 % of
    /// h²) inside out? Slivers are left out: they flip under any motion and the next remesh
    /// replaces them anyway.
    pub(super) fn would_invert(&self, particles: &Particles, dt: f64) -> bool {
        let x = &particles.position;
        let u = &self.u_new;
        let h_min = self.params.spacing.finest_m();
        let min_area = 0.01 * h_min * h_min;
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
        let midpoint = self
            .params
            .settings
            .midpoint_move
            .then(|| midpoint_factors(&self.cells, &self.u_new, particles.len(), dt));
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
            let step = match &midpoint {
                Some(m) => m[i] * u,
                None => u,
            };
            let mut x = particles.position[i] + dt * step;
            let margin = self.params.wall_margin_m(x.x);
            if flume.guard(&mut x, &mut u, margin) {
                guarded += 1;
            }
            particles.position[i] = x;
            particles.velocity[i] = u;
        }
        Ok(guarded)
    }
}

/// For `midpoint_move`: per node, (I − Δt G/2)⁻¹ with G the area-weighted mean of
/// ∇uⁿ⁺¹ over the node's cells, so that the move is Δt (I − Δt G/2)⁻¹ uⁿ⁺¹. In the flow
/// u = u₀ + G x this is the implicit midpoint rule x' = x + Δt u((x + x')/2), whose map
/// (I − Δt G/2)⁻¹ (I + Δt G/2) has determinant 1 when tr G = 0 (in 2D det(I ± A) =
/// 1 ± tr A + det A): a divergence-free flow moves no area, where x + Δt u changes an
/// element's area by Δt² A det G. A node with no cell keeps the straight-line move; a Δt G/2
/// larger than [`MIDPOINT_CAP`] is scaled down to it.
fn midpoint_factors(
    cells: &ElementSet,
    u: &[Vector2<f64>],
    n: usize,
    dt: f64,
) -> Vec<Matrix2<f64>> {
    let mut g = vec![Matrix2::zeros(); n];
    let mut w = vec![0.0; n];
    for e in 0..cells.len() {
        for cell in cells.cells(e) {
            let grad = cell.velocity_gradient(|j| u[j]);
            for a in 0..cell.nodes.len() {
                let i = cell.node(a);
                g[i] += cell.area * grad;
                w[i] += cell.area;
            }
        }
    }
    g.iter()
        .zip(&w)
        .map(|(g, &w)| {
            if w <= 0.0 {
                return Matrix2::identity();
            }
            let half = (0.5 * dt / w) * g;
            let size = half.norm();
            let half = if size > MIDPOINT_CAP {
                half * (MIDPOINT_CAP / size)
            } else {
                half
            };
            (Matrix2::identity() - half)
                .try_inverse()
                .unwrap_or_else(Matrix2::identity)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::element_set::{ElementSet, tests::mixed_mesh};
    use super::midpoint_factors;
    use nalgebra::{Matrix2, Vector2};

    /// In a linear, divergence-free flow (strain and rotation), the straight-line move changes
    /// every element's area by Δt² A det G; the midpoint move keeps each to round-off, on
    /// triangles and on EDT polygons (whose cell gradients are exact for a linear field).
    #[test]
    fn the_midpoint_move_keeps_the_area_of_a_divergence_free_linear_flow() {
        for delta in [0.0, 0.05] {
            let (p, mesh) = mixed_mesh(delta);
            let set = ElementSet::from_mesh(&mesh, &p.position);
            let g = Matrix2::new(0.8, 0.5, -0.3, -0.8);
            let u: Vec<Vector2<f64>> = p
                .position
                .iter()
                .map(|x| Vector2::new(0.2, -0.1) + g * x)
                .collect();
            let dt = 0.05;
            let factors = midpoint_factors(&set, &u, p.len(), dt);
            let area = |x: &[Vector2<f64>]| mesh.area(x);
            let a0 = area(&p.position);
            let straight: Vec<_> = (0..p.len()).map(|i| p.position[i] + dt * u[i]).collect();
            let midpoint: Vec<_> = (0..p.len())
                .map(|i| p.position[i] + dt * factors[i] * u[i])
                .collect();
            let (ds, dm) = (area(&straight) / a0 - 1.0, area(&midpoint) / a0 - 1.0);
            println!(
                "δ = {delta}: area change straight {ds:+.3e} (Δt² det G = {:+.3e}), midpoint {dm:+.3e}",
                dt * dt * g.determinant()
            );
            assert!((ds - dt * dt * g.determinant()).abs() < 1e-12, "{ds:e}");
            assert!(dm.abs() < 1e-13, "{dm:e}");
        }
    }
}
