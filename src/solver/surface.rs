//! The free surface as chains of fluid nodes, for the two stages that work along it: the
//! surface filter (`filter.rs`) and the short-scale shift of the implicit geometry
//! (`motion.rs`, `geometry_theta`).
//!
//! Boundary edges run with the water on their left, so each surface node has one edge in and
//! one out. A node is usable when it is a fluid node on the free surface with exactly one
//! edge in and one out (where the surface pinches, a node has two, and is left alone).

use crate::mesh::Mesh;
use crate::particles::Particles;

const NONE: u32 = u32::MAX;

pub(super) struct SurfaceChains {
    prev: Vec<u32>,
    next: Vec<u32>,
    usable: Vec<bool>,
}

impl SurfaceChains {
    pub(super) fn new(mesh: &Mesh, particles: &Particles) -> SurfaceChains {
        let n = particles.len();
        let mut next = vec![NONE; n];
        let mut prev = vec![NONE; n];
        let mut branched = vec![false; n];
        for &[a, b] in &mesh.boundary_edges {
            let (ia, ib) = (a as usize, b as usize);
            branched[ia] |= next[ia] != NONE;
            next[ia] = b;
            branched[ib] |= prev[ib] != NONE;
            prev[ib] = a;
        }
        let usable = (0..n)
            .map(|i| particles.is_fluid(i) && mesh.free_surface[i] && !branched[i])
            .collect();
        SurfaceChains { prev, next, usable }
    }

    pub(super) fn usable(&self, i: u32) -> bool {
        i != NONE && self.usable[i as usize]
    }

    /// The usable nodes up to `reach` steps before and after `i` along its chain: the widest
    /// symmetric window of usable, distinct nodes (as many before as after; none where a
    /// neighbour of `i` is not usable). `None` if `i` itself is not usable.
    pub(super) fn window(&self, i: u32, reach: usize) -> Option<(Vec<u32>, Vec<u32>)> {
        if !self.usable(i) {
            return None;
        }
        let (mut before, mut after) = (Vec::with_capacity(reach), Vec::with_capacity(reach));
        let (mut a, mut b) = (i, i);
        for _ in 0..reach {
            let (pa, nb) = (self.prev[a as usize], self.next[b as usize]);
            // A closed chain shorter than the window would come round to a node twice.
            let repeats =
                pa == nb || pa == i || nb == i || after.contains(&pa) || before.contains(&nb);
            if !(self.usable(pa) && self.usable(nb)) || repeats {
                break;
            }
            (a, b) = (pa, nb);
            before.push(a);
            after.push(b);
        }
        Some((before, after))
    }
}
