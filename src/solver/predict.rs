//! Stage `predict`: the momentum equation without the pressure increment (thesis eq. 2.6,
//! method.md §1 step 1), with lumped mass M, viscous matrix K and θ-weighted viscosity:
//!
//! (M/Δt + θK) ũ = (M/Δt) uⁿ − (1 − θ) K uⁿ + γ Dᵀpⁿ + M g.
//!
//! Per cell, K u contributes 2μ_e A S(u) b_i to node i (symmetric-gradient form); Dᵀp
//! contributes A p̄ b_i on a triangle and ∮ N_i p n − ∫ N_i ∇p on a polygon (`element_set.rs`),
//! less the traction on the edges that end at a wall contact point
//! (`Solver::cancel_contact_traction`). With θ = 0 this is explicit per node; with θ > 0 it
//! is solved by matrix-free Jacobi-CG. No-slip wall nodes keep their Dirichlet velocity (0);
//! slip wall nodes keep the component of ũ along the wall (they do not move; their velocity
//! lets the water next to them slide); isolated particles fly ballistically, ũ = uⁿ + Δt g.

use super::{Solver, cg};
use crate::fem;
use crate::particles::Particles;
use nalgebra::Vector2;

impl Solver {
    /// Slip wall nodes take the water's velocity (before `predict`): each slip wall node of a
    /// kept triangle with fluid nodes gets their mean velocity (each counted once per
    /// triangle), the part along its wall kept (`Particles::admissible_velocity`). A wall node
    /// stands still, so its velocity is the water's at a fixed point; left to its own momentum
    /// equation it changed by Δt times the acceleration of the water passing it, which misses
    /// the −Δt (u·∇)u of a fixed point, a term whose mean over a standing wave is not zero, and
    /// mode-1 sloshing with slip walls grew (as in 3D: `solver3d`, docs/three_d.md). Free slip
    /// has no normal gradient of the velocity along the wall, so the water beside the node is
    /// what moves at it. A slip wall node beside no water (dry, or in a wetted corner's
    /// all-wall triangles only) takes its wall's own velocity: left with the one it had, it
    /// carried a velocity from step to step into a corner puddle's pressure. Corner nodes (no
    /// tangent) and no-slip walls are left alone.
    pub(super) fn slip_walls_take_the_water_velocity(&self, particles: &mut Particles) {
        use crate::particles::NodeKind;
        // No-slip flumes (every committed 2D case) have nothing to do: no pass over the mesh.
        if !particles.any_wall_slides() {
            return;
        }
        let n = particles.len();
        let mut sum = vec![(Vector2::zeros(), 0usize); n];
        for t in &self.mesh.triangles {
            let v = t.map(|i| i as usize);
            let (total, count) = v
                .iter()
                .filter(|&&j| particles.kind[j] == NodeKind::Fluid)
                .fold((Vector2::zeros(), 0), |(sum, k), &j| {
                    (sum + particles.velocity[j], k + 1)
                });
            for &w in v.iter().filter(|&&w| particles.slides(w)) {
                sum[w].0 += total;
                sum[w].1 += count;
            }
        }
        for (i, &(total, count)) in sum.iter().enumerate() {
            if count > 0 {
                particles.velocity[i] = particles.admissible_velocity(i, total / count as f64);
            } else if particles.slides(i) {
                particles.velocity[i] = particles.wall_velocity[i];
            }
        }
    }

    pub(super) fn predict(&mut self, particles: &Particles, dt: f64) {
        let p = &self.params;
        let n = particles.len();
        let (x_u, pres) = (&particles.velocity, &self.p_old);
        // Explicit forces: −(1−θ)K uⁿ + γ Dᵀpⁿ.
        let mut force = vec![Vector2::zeros(); n];
        let explicit_visc = 1.0 - p.settings.theta;
        for e in 0..self.cells.len() {
            if let Some(ops) = self.cells.polygon_operators(e) {
                ops.specialised(
                    #[inline(always)]
                    |ops| {
                        for cell in self.cells.cells(e) {
                            let cell = cell.sized(ops.len());
                            let g = cell.velocity_gradient(|i| x_u[i]);
                            let (s, _) = fem::strain_rate(&g);
                            let visc = (-2.0 * explicit_visc * self.mu_e[e] * cell.area) * s;
                            for (a, &b) in cell.grad.iter().enumerate() {
                                force[cell.node(a)] += visc * b;
                            }
                        }
                        let (x, gamma) = (&particles.position, p.settings.gamma);
                        ops.add_pressure_term(x, gamma, |i| pres[i], &mut force);
                    },
                );
                continue;
            }
            for cell in self.cells.cells(e) {
                let g = cell.velocity_gradient(|i| x_u[i]);
                let (s, _) = fem::strain_rate(&g);
                let visc = (-2.0 * explicit_visc * self.mu_e[e] * cell.area) * s;
                let p_mean = cell.mean(|i| pres[i]);
                let press = p.settings.gamma * cell.area * p_mean;
                for (a, &b) in cell.grad.iter().enumerate() {
                    force[cell.node(a)] += visc * b + press * b;
                }
            }
        }
        self.cancel_contact_traction(particles, |i| p.settings.gamma * pres[i], &mut force);
        self.u_tilde.clear();
        self.u_tilde.resize(n, Vector2::zeros());
        for i in 0..n {
            let u = if self.mass[i] > 0.0 {
                x_u[i] + dt * (force[i] / self.mass[i] + p.gravity_m_s2)
            } else if particles.is_fluid(i) {
                x_u[i] + dt * p.gravity_m_s2
            } else {
                Vector2::zeros()
            };
            self.u_tilde[i] = particles.admissible_velocity(i, u);
        }
        if p.settings.theta > 0.0 {
            self.implicit_viscous_correction(particles, dt);
        }
    }

    /// For θ > 0: ũ above is the explicit predictor with K uⁿ weighted by (1 − θ). The implicit
    /// part solves (M/Δt + θK) δ = −θ K ũ on the free velocity DOFs, so that ũ + δ satisfies
    /// (M/Δt + θK)(ũ + δ) = (M/Δt) ũ, i.e. the θ-weighted predictor.
    fn implicit_viscous_correction(&mut self, particles: &Particles, dt: f64) {
        let n = particles.len();
        let theta = self.params.settings.theta;
        let free: Vec<bool> = (0..n)
            .map(|i| particles.is_fluid(i) && self.mass[i] > 0.0)
            .collect();
        let (cells, mu_e, mass) = (&self.cells, &self.mu_e, &self.mass);
        // K v (flattened 2n vector), zero on Dirichlet rows.
        let k_apply = |v: &[f64], out: &mut [f64]| {
            out.iter_mut().for_each(|o| *o = 0.0);
            for e in 0..cells.len() {
                for cell in cells.cells(e) {
                    let vel = |i: usize| Vector2::new(v[2 * i], v[2 * i + 1]);
                    let (s, _) = fem::strain_rate(&cell.velocity_gradient(vel));
                    let f = (2.0 * mu_e[e] * cell.area) * s;
                    for (a, &b) in cell.grad.iter().enumerate() {
                        let fi = f * b;
                        let i = cell.node(a);
                        out[2 * i] += fi.x;
                        out[2 * i + 1] += fi.y;
                    }
                }
            }
        };
        let mut u_flat: Vec<f64> = self.u_tilde.iter().flat_map(|u| [u.x, u.y]).collect();
        let mut ku = vec![0.0; 2 * n];
        k_apply(&u_flat, &mut ku);
        let mut diag_inv = vec![0.0; 2 * n];
        let mut kdiag = vec![0.0; 2 * n];
        for e in 0..cells.len() {
            for cell in cells.cells(e) {
                for (a, &b) in cell.grad.iter().enumerate() {
                    let i = cell.node(a);
                    kdiag[2 * i] += mu_e[e] * cell.area * (b.norm_squared() + b.x * b.x);
                    kdiag[2 * i + 1] += mu_e[e] * cell.area * (b.norm_squared() + b.y * b.y);
                }
            }
        }
        let mut rhs = vec![0.0; 2 * n];
        for i in 0..n {
            if free[i] {
                for d in 0..2 {
                    diag_inv[2 * i + d] = 1.0 / (mass[i] / dt + theta * kdiag[2 * i + d]);
                    rhs[2 * i + d] = -theta * ku[2 * i + d];
                }
            }
        }
        let apply = |v: &[f64], out: &mut [f64]| {
            k_apply(v, out);
            for j in 0..2 * n {
                out[j] = if free[j / 2] {
                    mass[j / 2] / dt * v[j] + theta * out[j]
                } else {
                    0.0
                };
            }
        };
        let mut delta = vec![0.0; 2 * n];
        let tol = self.params.settings.cg_tolerance;
        let max_it = self.params.settings.cg_max_iterations;
        // A non-converged viscous correction is still an improvement on the explicit one; the
        // pressure stage reports real trouble.
        let _ = cg::pcg(
            apply,
            &diag_inv,
            &rhs,
            &mut delta,
            tol,
            max_it,
            &mut self.cg,
        );
        for i in 0..n {
            u_flat[2 * i] += delta[2 * i];
            u_flat[2 * i + 1] += delta[2 * i + 1];
            self.u_tilde[i] = Vector2::new(u_flat[2 * i], u_flat[2 * i + 1]);
        }
    }
}
