//! The wall nodes' velocity in the 3D step: what slip walls take from the water beside them,
//! and what a wall node may move with (its planes', or the bed's, constraints).

use super::Flow3;
use crate::geometry::bed3d::Bed3;
use crate::mesh3d::{AlphaShape, Tetrahedralisation};
use nalgebra::Vector3;

impl Flow3 {
    /// A slip wall node stands still while the water slides past it: its velocity is the
    /// water's at a fixed point, not that of a particle. Left to its own momentum equation it
    /// changes by Δt times the acceleration of the water passing it, which differs from the
    /// change at a fixed point by Δt (u·∇)u, a term whose mean over a standing wave is not zero:
    /// the walls' velocity drifted from the water's and fed the wave (3D sloshing at
    /// h = 2.5 cm, 4 h wide: kinetic-energy peaks ×2.39 in 1.2 s, no-slip ×1.03). So at the
    /// start of each step every wall node of a kept tetrahedron takes the mean velocity of the
    /// fluid nodes of its kept tetrahedra (each counted once per tetrahedron), less the
    /// components across its planes, which are the planes' own: free slip has no normal
    /// gradient of the velocity along the wall, so the water beside the node is what moves at
    /// it (×1.23; 8 h wide ×1.09 against ×2.06). Explicitly subtracting Δt (u·∇)u instead
    /// diverged.
    pub(super) fn slip_walls_take_the_water_velocity(
        &mut self,
        mesh: &Tetrahedralisation,
        shape: &AlphaShape,
    ) {
        let mut sum = vec![(Vector3::zeros(), 0usize); self.x.len()];
        for &t in &shape.kept {
            let v = mesh.tets[t as usize].map(|i| i as usize);
            let (fluid, count) = v
                .iter()
                .filter(|&&j| self.walls[j] == 0)
                .fold((Vector3::zeros(), 0), |(sum, k), &j| {
                    (sum + self.u[j], k + 1)
                });
            for &w in v.iter().filter(|&&w| self.walls[w] != 0) {
                sum[w].0 += fluid;
                sum[w].1 += count;
            }
        }
        for (i, &(total, count)) in sum.iter().enumerate() {
            if count > 0 {
                self.u[i] = self.admissible_velocity(i, total / count as f64);
            } else if self.walls[i] != 0 {
                // Beside no water (dry, or in a wetted corner's all-wall tetrahedra only): the
                // planes' own velocity, not the one the node was left with (as in 2D).
                self.u[i] = self.admissible_velocity(i, Vector3::zeros());
            }
        }
    }

    /// `u` as wall node `i` may move: the components across each of its planes replaced by
    /// the plane's own velocity (0 but on a piston), so an edge keeps the part along it and a
    /// corner none.
    pub(super) fn admissible_velocity(&self, i: usize, mut u: Vector3<f64>) -> Vector3<f64> {
        let mask = self.walls[i];
        if let Some(bed) = &self.bed
            && mask & 1 != 0
        {
            return self.admissible_on_the_bed(bed, i, u);
        }
        for (b, plane) in self.planes.iter().enumerate() {
            if mask & (1 << b) != 0 {
                u[plane.axis] = plane.velocity_m_s;
            }
        }
        u
    }

    /// [`Self::admissible_velocity`] of a node on a bed that is not flat: the components
    /// along the bed's normal and the node's other planes' axes removed (the normal made
    /// orthogonal to those axes first, where the bed meets a wall at an angle), each plane's
    /// own velocity put back along its axis; a node on a crease of the bed is held (the 2D
    /// flume's corner nodes are).
    fn admissible_on_the_bed(&self, bed: &Bed3, i: usize, mut u: Vector3<f64>) -> Vector3<f64> {
        let mask = self.walls[i];
        let others = || {
            self.planes
                .iter()
                .enumerate()
                .skip(1)
                .filter(move |(b, _)| mask & (1 << b) != 0)
                .map(|(_, plane)| plane)
        };
        let x = &self.x[i];
        let Some(normal) = bed.normal(x[0], x[2]) else {
            let mut held = Vector3::zeros();
            for plane in others() {
                held[plane.axis] = plane.velocity_m_s;
            }
            return held;
        };
        let mut across = normal;
        for plane in others() {
            u[plane.axis] = 0.0;
            across[plane.axis] = 0.0;
        }
        if across.norm() > 1e-6 {
            let e = across.normalize();
            u -= u.dot(&e) * e;
        }
        for plane in others() {
            u[plane.axis] = plane.velocity_m_s;
        }
        u
    }
}
