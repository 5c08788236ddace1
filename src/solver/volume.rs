//! Stage `recover_volume` (optional, `solver.volume_recovery`): a global correction of the water
//! volume, as Kratos' PFEM-Fluid does (its "recover volume losses" process). The mesh area lost
//! (or gained) since t = 0, ΔV, is spread over the free surface of the main body of water:
//! every fluid node on it moves by ΔV / L along its outward normal, L the length of that
//! surface.
//!
//! Only the main body's fluid–fluid surface edges count, so spray and drops are never inflated
//! and a contact point takes its normal from the water, not the wall; the move per step is
//! capped at `MAX_OFFSET_H` · h, so a sudden remeshing jump is made good over several steps
//! rather than in one jolt; and every moved node passes the wall guard again.
//!
//! It hides the loss rather than removing its cause (the free-surface layer, where p = 0 and no
//! continuity equation is solved, shrinks while the interior grows: see the README), so the
//! volume budget in `timeseries.csv` reports the recovered area on its own.

use super::Solver;
use crate::geometry::Flume;
use crate::particles::Particles;
use nalgebra::Vector2;

/// Largest normal move of the surface per step, in units of h.
const MAX_OFFSET_H: f64 = 0.002;

impl Solver {
    /// Moves the free surface towards `target_m2`; returns the area change it made (measured on
    /// the mesh, so that the volume budget closes).
    pub(super) fn recover_volume(
        &mut self,
        particles: &mut Particles,
        flume: &Flume,
        area_m2: f64,
        target_m2: f64,
    ) -> f64 {
        let n = particles.len();
        let (label, main) = self.mesh.main_body(particles);
        let Some(main) = main else {
            return 0.0;
        };
        let x = &particles.position;
        let mut normal = vec![Vector2::<f64>::zeros(); n];
        let mut length = 0.0;
        for &[a, b] in &self.mesh.boundary_edges {
            let (a, b) = (a as usize, b as usize);
            if !(particles.is_fluid(a) && particles.is_fluid(b)) || label[a] != main {
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
        let cap = MAX_OFFSET_H * self.params.spacing_m;
        let offset = (missing / length).clamp(-cap, cap);
        for i in 0..n {
            let norm = normal[i].norm();
            if norm > 0.0 {
                let mut p = particles.position[i] + offset / norm * normal[i];
                let mut u = particles.velocity[i];
                let margin = self.params.wall_margin_m(p.x);
                flume.guard(&mut p, &mut u, margin);
                particles.position[i] = p;
                particles.velocity[i] = u;
            }
        }
        self.mesh.area(&particles.position) - area_m2
    }
}
