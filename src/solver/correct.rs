//! Stage `correct`: the end-of-step velocity (thesis eq. 2.8, method.md §1 step 3) and the
//! pressure-gradient projection of the FIC stabilisation (step 4):
//!
//! uⁿ⁺¹_i = ũ_i − (Δt/m_i) Σ_e (A_e/3) ∇(pⁿ⁺¹ − γ pⁿ)_e   (nodes in the mesh; the gradient form,
//! as in `predict.rs`; a slip wall node
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
            let grad_p: Vector2<f64> = (0..3).map(|a| e.grad[a] * self.p_new[idx[a]]).sum();
            let grad_dp: Vector2<f64> = (0..3)
                .map(|a| e.grad[a] * (self.p_new[idx[a]] - gamma * p_old[idx[a]]))
                .sum();
            let w = self.tau_e[k] * e.area / 3.0;
            for &i in &idx {
                impulse[i] -= (e.area / 3.0) * grad_dp;
                self.pi_new[i] -= w * grad_p;
            }
        }
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
