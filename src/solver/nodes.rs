//! Stage `nodes`: keep the particle spacing near h (method.md §3, after PFEM3D and Kratos).
//!
//! The water stretches and compresses the cloud. Where it stretches, a kept triangle grows until
//! the α-shape drops it, opening a crack inside the water whose nodes become a spurious free
//! surface (p = 0 inside the fluid) and whose area is lost. Where it compresses, nodes crowd and
//! make slivers. So, after the move:
//! - insertion: a kept triangle whose circumradius (at the current positions) exceeds
//!   `insert_radius_h`·h gets a new fluid node at its centroid, with the mean velocity, pressure and
//!   π of its nodes, unless another new node already stands within h/2, or one of its nodes is
//!   on the free surface: such a triangle may bridge air, and a node put in it would turn air
//!   into water (Kratos and PFEM3D avoid it likewise);
//! - removal: an interior fluid node (not on the free surface, so the volume does not change)
//!   closer than `remove_distance_h`·h to a neighbour in the kept mesh is removed (one of each pair).
//! - merging (`merge_surface_distance_h`, off by default): two free-surface fluid nodes joined by
//!   an edge of the kept mesh and closer than that·h become one node at their midpoint with
//!   their mean velocity. Where a plunging jet lands or a bore runs over the crest ahead, surface
//!   particles collide; the slivers they make with their neighbours are beyond removal's reach
//!   (it spares the surface so as not to change the volume) and were where the breaking runs
//!   diverged.

use super::Solver;
use crate::particles::{NodeKind, Particles};
use nalgebra::Vector2;

/// A particle to insert, with the mean state of the triangle it splits.
struct NewNode {
    position: Vector2<f64>,
    velocity: Vector2<f64>,
    pressure: f64,
    projection: Vector2<f64>,
}

/// What the stage did.
#[derive(Debug, Clone, Copy, Default)]
pub struct NodeChanges {
    pub inserted: usize,
    pub removed: usize,
}

impl Solver {
    pub(super) fn manage_nodes(&mut self, particles: &mut Particles) -> NodeChanges {
        // h(x): the local spacing, at a triangle's centroid or an edge's midpoint.
        let spacing = self.params.spacing;
        let insert_r_h = self.params.settings.insert_radius_h;
        let x = &particles.position;
        let mut added: Vec<NewNode> = Vec::new();
        let mut taken = std::collections::HashSet::new();
        let cell = 0.5 * spacing.finest_m();
        for t in &self.mesh.triangles {
            let [a, b, c] = t.map(|i| i as usize);
            let fs = &self.mesh.free_surface;
            if fs[a] || fs[b] || fs[c] {
                continue;
            }
            let (pa, pb, pc) = (x[a], x[b], x[c]);
            let area = 0.5 * ((pb - pa).perp(&(pc - pa)));
            if area <= 0.0 {
                continue;
            }
            let r = (pb - pa).norm() * (pc - pb).norm() * (pa - pc).norm() / (4.0 * area);
            let centroid = (pa + pb + pc) / 3.0;
            if insert_r_h.is_none_or(|r_h| r <= r_h * spacing.at(centroid.x)) {
                continue;
            }
            let key = (
                (centroid.x / cell).floor() as i64,
                (centroid.y / cell).floor() as i64,
            );
            let crowded =
                (-1..=1).any(|dx| (-1..=1).any(|dy| taken.contains(&(key.0 + dx, key.1 + dy))));
            if crowded {
                continue;
            }
            taken.insert(key);
            let u = (particles.velocity[a] + particles.velocity[b] + particles.velocity[c]) / 3.0;
            let p = (particles.pressure[a] + particles.pressure[b] + particles.pressure[c]) / 3.0;
            let pi = (particles.pressure_gradient_projection[a]
                + particles.pressure_gradient_projection[b]
                + particles.pressure_gradient_projection[c])
                / 3.0;
            added.push(NewNode {
                position: centroid,
                velocity: u,
                pressure: p,
                projection: pi,
            });
        }

        let n = particles.len();
        let mut drop = vec![false; n];
        let remove_h = self.params.settings.remove_distance_h;
        // The square of d h(x) at the middle of the edge i–j.
        let within = |d_h: Option<f64>, i: usize, j: usize| {
            d_h.is_some_and(|d| {
                let h = spacing.at(0.5 * (x[i].x + x[j].x));
                (x[i] - x[j]).norm_squared() < (d * h).powi(2)
            })
        };
        let removable = |i: usize, mesh: &crate::mesh::Mesh| {
            particles.kind[i] == NodeKind::Fluid && mesh.in_mesh[i] && !mesh.free_surface[i]
        };
        for t in &self.mesh.triangles {
            for k in 0..3 {
                let (i, j) = (t[k] as usize, t[(k + 1) % 3] as usize);
                if drop[i] || drop[j] || !within(remove_h, i, j) {
                    continue;
                }
                if removable(j, &self.mesh) {
                    drop[j] = true;
                } else if removable(i, &self.mesh) {
                    drop[i] = true;
                }
            }
        }
        // Colliding surface particles: merge each close pair into its midpoint.
        let merge_h = self.params.settings.merge_surface_distance_h;
        let mut moved: Vec<(usize, Vector2<f64>, Vector2<f64>)> = Vec::new();
        if merge_h.is_some() {
            let surface = |i: usize| {
                particles.kind[i] == NodeKind::Fluid
                    && self.mesh.in_mesh[i]
                    && self.mesh.free_surface[i]
            };
            for t in &self.mesh.triangles {
                for k in 0..3 {
                    let (i, j) = (t[k] as usize, t[(k + 1) % 3] as usize);
                    if drop[i] || drop[j] || !surface(i) || !surface(j) {
                        continue;
                    }
                    if !within(merge_h, i, j) || moved.iter().any(|m| m.0 == i || m.0 == j) {
                        continue;
                    }
                    drop[j] = true;
                    moved.push((
                        i,
                        0.5 * (x[i] + x[j]),
                        0.5 * (particles.velocity[i] + particles.velocity[j]),
                    ));
                }
            }
        }
        for &(i, xi, ui) in &moved {
            particles.position[i] = xi;
            particles.velocity[i] = ui;
        }
        let removed = drop.iter().filter(|d| **d).count();
        if removed > 0 {
            particles.remove_where(&drop);
            self.mesh.remove_nodes(&drop);
        }
        for node in &added {
            particles.push_fluid(node.position, node.velocity, node.pressure, node.projection);
        }
        self.mesh.add_interior_nodes(added.len());
        NodeChanges {
            inserted: added.len(),
            removed,
        }
    }
}
