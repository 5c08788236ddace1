//! Stage `nodes` of the 3D step (issue 26; the 2D stage is `solver::nodes`): keep the particle
//! spacing near h after the move.
//!
//! The flow stretches the cloud in places and crowds it in others. Where it stretches, a kept
//! tetrahedron grows until the α-shape drops it and opens a hole in the water whose faces are
//! a spurious free surface. Without this stage the 3D dam break had lost 26.7 % of its water
//! by the impact and its front ran 17.5 % slow; with it, +5.9 % and −6.9 % (before the slip
//! walls took the water's velocity).
//! - insertion: a kept tetrahedron whose circumradius at the moved positions exceeds the insert
//!   radius gets a fluid node at its centroid with the mean velocity and pressure of its four
//!   nodes, unless another new node already stands within h/2 (a grid of h/2 cells), one of its
//!   nodes is on the free surface (as in 2D: such a tetrahedron may bridge air, and a node in it
//!   would turn air into water; skipping only those whose four nodes are all on the boundary,
//!   the 3D dam break gained 19 % of its water by the impact, against 5.9 %), it is a sliver
//!   (quality below `SLIVER_QUALITY`: four nearly coplanar nodes, as on a face of the seeding's
//!   lattice, whose circumradius says nothing of the spacing; with them, 3D sloshing at
//!   h = 2.5 cm got 700–770 nodes in its first 0.1 s, a third of its 2 340), or its centroid
//!   lies within h/2 of one of its nodes;
//! - removal: an interior fluid node (in the mesh, not on the free surface, so the volume does
//!   not change) closer than the remove distance to a neighbour along an edge of a kept
//!   tetrahedron is removed (one of each pair);
//! - merging (`solver.merge_surface_distance_h`, off by default, as in 2D): two free-surface
//!   fluid nodes joined by an edge of a kept tetrahedron and closer than that times h become
//!   one at their midpoint with their mean velocity (a merged node is not merged again in the
//!   same step): colliding surface particles make slivers with their neighbours that removal,
//!   which spares the surface, does not reach.
//!
//! The insert radius is the case's `solver.insert_radius_h` times √3/√2: the tetrahedra of a
//! cubic lattice of spacing h have a circumradius of √3/2 h where the triangles of a square
//! lattice have √2/2 h, so the same setting splits the same stretch in 2D and 3D (0.9 → 1.10 h).

use super::Flow3;
use crate::mesh3d::{AlphaShape, SLIVER_QUALITY, Tetrahedralisation, circumsphere};
use nalgebra::Vector3;

/// The ratio of the 3D insert radius to the 2D one at the same `solver.insert_radius_h`.
pub const INSERT_RADIUS_3D_OVER_2D: f64 = 1.224_744_871_391_589; // √3 / √2

/// The 3D insert radius, m, for the case's `solver.insert_radius_h` and the spacing `h_m`.
pub fn insert_radius_3d(insert_radius_h: f64, h_m: f64) -> f64 {
    insert_radius_h * INSERT_RADIUS_3D_OVER_2D * h_m
}

/// What the stage did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NodeChanges3 {
    pub inserted: usize,
    pub removed: usize,
}

impl Flow3 {
    /// Inserts and removes fluid nodes on the step's kept tetrahedra (`mesh`, `shape.kept`, at
    /// the moved positions) and renumbers every per-node array; wall nodes keep their indices
    /// when they come before the fluid (as `setup::from_case` seeds them), and the piston's
    /// band follows them otherwise. `in_mesh`, `was_free` and `surface` must already be the
    /// step's (the α-shape's, moved out of `shape`).
    pub(super) fn manage_nodes(
        &mut self,
        mesh: &Tetrahedralisation,
        shape: &AlphaShape,
    ) -> NodeChanges3 {
        let h = self.h_m;
        let mut changes = NodeChanges3::default();
        if let Some(radius_m) = self.insert_radius_m {
            let cell = 0.5 * h;
            let key = |p: &[f64; 3]| p.map(|c| (c / cell).floor() as i64);
            let mut taken = std::collections::HashSet::new();
            let mut added = Vec::new();
            for (&t, &q) in shape.kept.iter().zip(&shape.kept_quality) {
                let v = mesh.tets[t as usize];
                if q < SLIVER_QUALITY || v.iter().any(|&i| self.was_free[i as usize]) {
                    continue;
                }
                let p = v.map(|i| self.x[i as usize]);
                let (_, r) = circumsphere(&p[0], &p[1], &p[2], &p[3]);
                if r.is_nan() || r <= radius_m {
                    continue;
                }
                let c: [f64; 3] =
                    std::array::from_fn(|k| 0.25 * (p[0][k] + p[1][k] + p[2][k] + p[3][k]));
                let near_a_node = p.iter().any(|q| {
                    (0..3).map(|k| (q[k] - c[k]).powi(2)).sum::<f64>() < (0.5 * h).powi(2)
                });
                let k = key(&c);
                let crowded = (-1..=1).any(|a| {
                    (-1..=1)
                        .any(|b| (-1..=1).any(|d| taken.contains(&[k[0] + a, k[1] + b, k[2] + d])))
                });
                if near_a_node || crowded {
                    continue;
                }
                taken.insert(k);
                let u = v.iter().map(|&i| self.u[i as usize]).sum::<Vector3<f64>>() / 4.0;
                let pressure = v.iter().map(|&i| self.p[i as usize]).sum::<f64>() / 4.0;
                let pi = v.iter().map(|&i| self.pi[i as usize]).sum::<Vector3<f64>>() / 4.0;
                added.push((c, u, pressure, pi));
            }
            changes.inserted = added.len();
            for (c, u, pressure, pi) in added {
                self.x.push(c);
                self.u.push(u);
                self.p.push(pressure);
                self.pi.push(pi);
                self.walls.push(0);
                self.in_mesh.push(true);
                self.was_free.push(false);
            }
        }
        let removable = |i: usize| self.walls[i] == 0 && self.in_mesh[i] && !self.was_free[i];
        let surface = |i: usize| self.walls[i] == 0 && self.in_mesh[i] && self.was_free[i];
        let close = |i: usize, j: usize, d: f64| {
            (0..3)
                .map(|k| (self.x[i][k] - self.x[j][k]).powi(2))
                .sum::<f64>()
                < d * d
        };
        let mut drop = vec![false; self.x.len()];
        let mut merged: Vec<(usize, usize, [f64; 3], Vector3<f64>)> = Vec::new();
        for &t in &shape.kept {
            let v = mesh.tets[t as usize].map(|i| i as usize);
            for a in 0..4 {
                for b in a + 1..4 {
                    let (i, j) = (v[a], v[b]);
                    if drop[i] || drop[j] {
                        continue;
                    }
                    if let Some(d) = self.remove_distance_m
                        && close(i, j, d)
                    {
                        if removable(j) {
                            drop[j] = true;
                            continue;
                        } else if removable(i) {
                            drop[i] = true;
                            continue;
                        }
                    }
                    if let Some(d) = self.merge_distance_m
                        && surface(i)
                        && surface(j)
                        && close(i, j, d)
                        && !merged.iter().any(|m| m.0 == i || m.0 == j)
                    {
                        drop[j] = true;
                        let x = std::array::from_fn(|k| 0.5 * (self.x[i][k] + self.x[j][k]));
                        merged.push((i, j, x, 0.5 * (self.u[i] + self.u[j])));
                    }
                }
            }
        }
        for &(i, _, x, u) in &merged {
            self.x[i] = x;
            self.u[i] = u;
        }
        changes.removed = drop.iter().filter(|&&d| d).count();
        if changes.removed > 0 {
            let into: Vec<(usize, usize)> = merged.iter().map(|m| (m.1, m.0)).collect();
            self.remove_nodes(&drop, &into);
        }
        changes
    }

    /// Drops the nodes marked in `drop` (all of them fluid nodes) and renumbers the rest in
    /// order. A dropped node `j` of a pair (`j`, `i`) in `into` was merged into `i`: the last
    /// free surface and tetrahedra name `i` where they named `j` (those left with a repeated
    /// node are dropped), so that the surface stays closed until the next remesh.
    fn remove_nodes(&mut self, drop: &[bool], into: &[(usize, usize)]) {
        let mut new_index = vec![u32::MAX; drop.len()];
        let mut next = 0u32;
        for (i, &d) in drop.iter().enumerate() {
            if !d {
                new_index[i] = next;
                next += 1;
            }
        }
        for &(j, i) in into {
            new_index[j] = new_index[i];
        }
        fn keep<T: Copy>(v: &mut Vec<T>, drop: &[bool]) {
            let mut i = 0;
            v.retain(|_| {
                i += 1;
                !drop[i - 1]
            });
        }
        keep(&mut self.x, drop);
        keep(&mut self.u, drop);
        keep(&mut self.p, drop);
        keep(&mut self.pi, drop);
        keep(&mut self.walls, drop);
        keep(&mut self.in_mesh, drop);
        keep(&mut self.was_free, drop);
        let distinct = |v: &[u32]| (1..v.len()).all(|a| !v[..a].contains(&v[a]));
        for f in &mut self.surface {
            *f = f.map(|i| new_index[i as usize]);
        }
        self.surface
            .retain(|f| distinct(f) && f.iter().all(|&i| i != u32::MAX));
        for t in &mut self.tetrahedra {
            *t = t.map(|i| new_index[i as usize]);
        }
        self.tetrahedra
            .retain(|t| distinct(t) && t.iter().all(|&i| i != u32::MAX));
        if let Some(piston) = &mut self.piston {
            piston.renumber(&new_index);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::tank_with_nodes;
    use super::{Flow3, NodeChanges3};

    /// Two free-surface particles 0.15 h apart: removal spares the surface, merging at 0.2 h makes
    /// them one particle at their midpoint.
    #[test]
    fn colliding_surface_particles_merge_into_one() {
        let h = 0.1;
        let collide = |merge: Option<f64>| {
            let mut flow = tank_with_nodes(h);
            flow.merge_distance_m = merge.map(|d| d * h);
            let top = (0..flow.x.len())
                .filter(|&i| flow.walls[i] == 0)
                .map(|i| flow.x[i][1])
                .fold(f64::MIN, f64::max);
            let at = |f: &Flow3, x: f64| {
                (0..f.x.len())
                    .find(|&i| {
                        f.walls[i] == 0
                            && (f.x[i][1] - top).abs() < 1e-9
                            && (f.x[i][0] - x).abs() < 1e-9
                            && (f.x[i][2] - 3.0 * h).abs() < 1e-9
                    })
                    .unwrap()
            };
            let (a, b) = (at(&flow, 4.0 * h), at(&flow, 5.0 * h));
            flow.x[a][0] += 0.85 * h;
            let target = [0.5 * (flow.x[a][0] + flow.x[b][0]), top, 3.0 * h];
            let n = flow.x.len();
            let s = flow.step(1e-6).unwrap();
            (s.nodes, n, flow, target)
        };
        let (spared, n, flow, _) = collide(None);
        assert_eq!(spared, NodeChanges3::default());
        assert_eq!(flow.x.len(), n);
        let (merged, n, flow, target) = collide(Some(0.2));
        println!("merged: {merged:?}");
        assert_eq!((merged.inserted, merged.removed), (0, 1));
        assert_eq!(flow.x.len(), n - 1);
        assert!(
            (0..flow.x.len()).any(|i| (0..3).all(|k| (flow.x[i][k] - target[k]).abs() < 1e-9)),
            "no particle at the midpoint {target:?}"
        );
    }
}
