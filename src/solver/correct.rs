//! Stage `correct`: the end-of-step velocity (thesis eq. 2.8, method.md §1 step 3) and the
//! pressure-gradient projection of the FIC stabilisation (step 4):
//!
//! uⁿ⁺¹_i = ũ_i + (Δt/m_i) Σ_e A_e (p̄ⁿ⁺¹ − γ p̄ⁿ)_e b_i   (nodes in the mesh, less the traction
//! on the edges that end at a wall contact point as in `predict.rs`; a slip wall node
//! keeps only the part along its wall, a no-slip one none),
//! π_i = −Σ_e τ_e (A_e/3) ∇pⁿ⁺¹_e / Σ_e τ_e (A_e/3).
//!
//! Nothing is written to the particles here: the `move` stage commits, so a step whose Δt must
//! be halved can be redone.

use super::Solver;
use crate::particles::Particles;
use nalgebra::Vector2;

impl Solver {
    pub(super) fn correct(&mut self, particles: &Particles, dt: f64) {
        let n = particles.len();
        let gamma = self.params.gamma;
        let p_old = &self.p_old;
        let mut impulse = vec![Vector2::zeros(); n];
        self.pi_new.clear();
        self.pi_new.resize(n, Vector2::zeros());
        for (k, t) in self.mesh.triangles.iter().enumerate() {
            let e = &self.elems[k];
            let idx = t.map(|i| i as usize);
            let dp_mean: f64 = idx
                .iter()
                .map(|&i| self.p_new[i] - gamma * p_old[i])
                .sum::<f64>()
                / 3.0;
            let grad_p: Vector2<f64> = (0..3).map(|a| e.grad[a] * self.p_new[idx[a]]).sum();
            let w = self.tau_e[k] * e.area / 3.0;
            for (a, &i) in idx.iter().enumerate() {
                impulse[i] += e.area * dp_mean * e.grad[a];
                self.pi_new[i] -= w * grad_p;
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
