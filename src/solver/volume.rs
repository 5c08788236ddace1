//! Stage `recover_volume` (optional, `solver.volume_recovery`): a global correction of the water
//! volume, as Kratos' PFEM-Fluid does (its "recover volume losses" process). The mesh area lost
//! (or gained) since t = 0, ΔV, is spread over the free surface: every fluid node on it moves
//! by ΔV / L along its outward normal, L the length of the free surface.
//!
//! It hides the loss rather than removing its cause (the free-surface layer, where p = 0 and no
//! continuity equation is solved, and contact lines sliding over wall nodes): the figure it
//! changes is reported with and without it.

use super::Solver;
use crate::particles::Particles;
use nalgebra::Vector2;

impl Solver {
    /// Moves the free surface to restore `target_m2`; returns the area change asked for.
    pub(super) fn recover_volume(
        &mut self,
        particles: &mut Particles,
        area_m2: f64,
        target_m2: f64,
    ) -> f64 {
        let n = particles.len();
        let x = &particles.position;
        let mut normal = vec![Vector2::<f64>::zeros(); n];
        let mut length = 0.0;
        for &[a, b] in &self.mesh.boundary_edges {
            let (a, b) = (a as usize, b as usize);
            if !(particles.is_fluid(a) || particles.is_fluid(b)) {
                continue;
            }
            // A boundary edge of a kept triangle runs counter-clockwise around it: the water is
            // on its left, so (dy, −dx) points out of the water.
            let d = x[b] - x[a];
            let out = Vector2::new(d.y, -d.x);
            normal[a] += out;
            normal[b] += out;
            length += d.norm();
        }
        let missing = target_m2 - area_m2;
        if length <= 0.0 || missing == 0.0 {
            return 0.0;
        }
        let offset = missing / length;
        for i in 0..n {
            if particles.is_fluid(i) && self.mesh.free_surface[i] {
                let norm = normal[i].norm();
                if norm > 0.0 {
                    particles.position[i] += offset / norm * normal[i];
                }
            }
        }
        missing
    }
}
