//! Stage `elements`: per element (`element_set.rs`) its cells' geometry (P1 on a triangle, MFEM
//! on a polygon), the effective viscosity
//! μ_e = μ + ρ(C_s h_e)²|S(uⁿ)| (Smagorinsky, thesis eqs. 1.20–1.21, lagged so the step stays
//! linear) and the stabilisation τ_e; per node the lumped mass m_i = ρ Σ_e ∫_e N_i (A_e/3 on a
//! triangle, thesis eq. 2.22) and the τ-weighted mass Σ_e τ_e ∫_e N_i used by the
//! pressure-gradient projection.
//!
//! It also sets the previous pressure the step splits against, pⁿ with this step's Dirichlet
//! values (p = 0 on the current free surface and isolated nodes, the hydrostatic value at wall
//! contact points, see `pressure.rs`): a node that has just reached the surface would
//! otherwise carry its old interior pressure into the increment pⁿ⁺¹ − γpⁿ, and the splitting
//! error, which grows with that increment, would compress the water around it.

use super::Solver;
use crate::fem;
use crate::mesh::edt::MAX_POLYGON_NODES;
use crate::particles::Particles;

impl Solver {
    pub(super) fn element_properties(&mut self, particles: &Particles, dt: f64) {
        let p = &self.params;
        let rho = p.density_kg_m3;
        let n = particles.len();
        let x = &particles.position;
        let u = &particles.velocity;
        self.mu_e.clear();
        self.tau_e.clear();
        self.mass.clear();
        self.mass.resize(n, 0.0);
        self.tau_mass.clear();
        self.tau_mass.resize(n, 0.0);
        let mut p_old = std::mem::take(&mut self.p_old);
        p_old.clear();
        p_old.extend((0..n).map(|i| {
            if self.dirichlet[i] {
                self.p_fixed[i]
            } else {
                particles.pressure[i]
            }
        }));
        self.p_old = p_old;
        // The element's eddy viscosity (Smagorinsky) and stabilisation τ from its size, strain
        // rate and mean speed.
        let viscosity_and_tau = |h_e: f64, s_mag: f64, speed: f64| {
            let cs = p.settings.smagorinsky_cs;
            let mu_e = fem::smagorinsky_viscosity(p.viscosity_pa_s, rho, cs, h_e, s_mag);
            (
                mu_e,
                fem::tau(p.settings.tau_formula(false), rho, mu_e, h_e, dt, speed),
            )
        };
        let mut cells = std::mem::take(&mut self.cells);
        cells.clear_geometry();
        for e in 0..cells.len() {
            let nodes = cells.nodes(e);
            let (mu_e, tau) = if let &[a, b, c] = nodes {
                let [a, b, c] = [a, b, c].map(|i| i as usize);
                let mut e = fem::p1(x[a], x[b], x[c]);
                // Kept triangles are counter-clockwise; on the moved geometry of the second
                // pass (`geometry_theta`) a sliver may have turned over, and a negative area
                // would make the pressure matrix indefinite. Its gradients are right either way.
                e.area = e.area.abs();
                let h_e = fem::element_size(e.area);
                let g = fem::velocity_gradient(&e, [u[a], u[b], u[c]]);
                let (_, s_mag) = fem::strain_rate(&g);
                let speed = ((u[a] + u[b] + u[c]) / 3.0).norm();
                let (mu_e, tau) = viscosity_and_tau(h_e, s_mag, speed);
                let third = e.area / 3.0;
                for i in [a, b, c] {
                    self.mass[i] += rho * third;
                    self.tau_mass[i] += tau * third;
                }
                cells.push_triangle(&e);
                (mu_e, tau)
            } else {
                // A polygon: its size is that of its Delaunay triangles (n − 2 of them), its
                // strain rate the area mean over its cells: Σ_c A_c ∇N_k,c = ∮ N_k n, which
                // with N_k linear on the two edges at node k is half the sum of their outward
                // normals times their lengths.
                let n = nodes.len();
                let mut ids = [0u32; MAX_POLYGON_NODES];
                ids[..n].copy_from_slice(nodes);
                let nodes = &ids[..n];
                let mut pts = [nalgebra::Vector2::zeros(); MAX_POLYGON_NODES];
                for (p, &i) in pts.iter_mut().zip(nodes) {
                    *p = x[i as usize];
                }
                let mut node_weight = [0.0; MAX_POLYGON_NODES];
                let area = cells.push_polygon(&pts[..n], &mut node_weight[..n]);
                let h_e = fem::element_size(area / (n - 2) as f64);
                let mut g = nalgebra::Matrix2::zeros();
                let mut mean_u = nalgebra::Vector2::zeros();
                for (k, &i) in nodes.iter().enumerate() {
                    let u_i = u[i as usize];
                    mean_u += u_i;
                    let d = pts[(k + 1) % n] - pts[(k + n - 1) % n];
                    g += u_i * nalgebra::Vector2::new(d.y, -d.x).transpose() * 0.5;
                }
                let (_, s_mag) = fem::strain_rate(&(g / area));
                let speed = (mean_u / n as f64).norm();
                let (mu_e, tau) = viscosity_and_tau(h_e, s_mag, speed);
                for (k, &i) in nodes.iter().enumerate() {
                    self.mass[i as usize] += rho * node_weight[k];
                    self.tau_mass[i as usize] += tau * node_weight[k];
                }
                (mu_e, tau)
            };
            self.mu_e.push(mu_e);
            self.tau_e.push(tau);
        }
        self.cells = cells;
    }
}
