//! Stage `correct`: the end-of-step velocity (thesis eq. 2.8, method.md §1 step 3) and the
//! pressure-gradient projection of the FIC stabilisation (step 4):
//!
//! uⁿ⁺¹_i = ũ_i + (Δt/m_i) Σ_e A_e (p̄ⁿ⁺¹ − γ p̄ⁿ)_e b_i   (nodes in the mesh, less the traction
//! on the edges that end at a wall contact point as in `predict.rs`; a slip wall node
//! keeps only the part along its wall, a no-slip one none),
//! π_i = −Σ_e τ_e (A_e/3) ∇pⁿ⁺¹_e / Σ_e τ_e (A_e/3);
//! on a polygon element the impulse is ∮ N_i Δp n − ∫ N_i ∇Δp and π's sums use ∫ N_i ∇p and
//! ∫ N_i (`element_set.rs`).
//!
//! Nothing is written to the particles here: the `move` stage commits, so a step whose Δt must
//! be halved can be redone.

use super::Solver;
use crate::particles::Particles;
use nalgebra::Vector2;

impl Solver {
    pub(super) fn correct(&mut self, particles: &Particles, dt: f64) {
        let n = particles.len();
        let gamma = self.params.settings.gamma;
        let p_old = &self.p_old;
        let mut impulse = vec![Vector2::zeros(); n];
        self.pi_new.clear();
        self.pi_new.resize(n, Vector2::zeros());
        let p_new = &self.p_new;
        let dp = |i: usize| p_new[i] - gamma * p_old[i];
        for e in 0..self.cells.len() {
            let tau = self.tau_e[e];
            if let Some(ops) = self.cells.polygon_operators(e) {
                ops.specialised(
                    #[inline(always)]
                    |ops| {
                        // ∮ N_a Δp n − ∫ N_a ∇(Δp), and π from −τ ∫ N_a ∇p (see `element_set.rs`).
                        ops.add_pressure_term(&particles.position, 1.0, dp, &mut impulse);
                        for a in 0..ops.len() {
                            self.pi_new[ops.node(a)] -= tau * ops.gradient_row(a, |j| p_new[j]);
                        }
                    },
                );
                continue;
            }
            for cell in self.cells.cells(e) {
                let grad_p = cell.gradient(|i| p_new[i]);
                let dp_mean = cell.mean(dp);
                for (a, &b) in cell.grad.iter().enumerate() {
                    let i = cell.node(a);
                    impulse[i] += cell.area * dp_mean * b;
                    self.pi_new[i] -= cell.integral(a, tau) * grad_p;
                }
            }
        }
        let (p_new, p_old) = (&self.p_new, &self.p_old);
        let dp = |i: usize| p_new[i] - gamma * p_old[i];
        self.cancel_contact_traction(particles, dp, &mut impulse);
        self.u_new.clear();
        self.u_new.extend_from_slice(&self.u_tilde);
        for i in 0..n {
            if self.mass[i] > 0.0 {
                let u = self.u_new[i] + dt / self.mass[i] * impulse[i];
                self.u_new[i] = particles.admissible_velocity(i, u);
            }
            if self.tau_mass[i] > 0.0 {
                self.pi_new[i] /= self.tau_mass[i];
            }
        }
    }
}
