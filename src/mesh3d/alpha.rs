//! The 3D α-shape on a tetrahedralisation: which tetrahedra are water, where the free surface
//! is, and what happens to slivers.
//!
//! Rules, as the 2D mesher's (`mesh`): a tetrahedron is a candidate when its circumradius is
//! below α h. A candidate whose four nodes are wall nodes is kept only if one of them is wetted
//! (shares a candidate with a fluid node, PFEM3D's rule): that keeps the water in the flume's
//! corners, where the Delaunay split of a corner cube makes all-wall tetrahedra, and drops the
//! walls' own tetrahedra elsewhere.
//!
//! Slivers: four nearly co-circular nodes make a tetrahedron of small circumradius and almost
//! no volume, which the α test keeps. Its gradients are O(1/thickness): inside the water it
//! is harmless to the assembled operators' consistency (its volume weights it) and dropping it
//! would open a hole, so it is kept; on the surface it is a skin across the free surface that
//! holds no water, so it is dropped, repeatedly, until no sliver has a face on the surface. A
//! sliver is a tetrahedron of quality q = 6√2 V / l_rms³ < [`SLIVER_QUALITY`] (q = 1 for the
//! regular tetrahedron, 0.66 for the six of a cube's Kuhn split, 0.77 for the corners of its five).

use super::delaunay::{cross, dot, sub};
use super::{NONE, Tetrahedralisation, circumsphere};

/// Below this quality a tetrahedron is a sliver.
pub const SLIVER_QUALITY: f64 = 0.05;

/// The kept tetrahedra and the free surface.
#[derive(Debug, Clone, Default)]
pub struct AlphaShape {
    /// Indices into the tetrahedralisation's `tets`.
    pub kept: Vec<u32>,
    /// Free-surface triangles: faces of kept tetrahedra with no kept tetrahedron across them
    /// and not on a wall (three nodes of one wall); nodes ordered so that (b − a) × (c − a)
    /// points out of the water.
    pub surface: Vec<[u32; 3]>,
    /// Per node: on a free-surface triangle.
    pub free_surface: Vec<bool>,
    /// Per node: in a kept tetrahedron (the rest are flying or dry).
    pub in_mesh: Vec<bool>,
    /// Slivers kept inside the water.
    pub slivers_kept: usize,
    /// Slivers dropped from the surface.
    pub slivers_dropped: usize,
}

/// The tetrahedron's quality 6√2 V / l_rms³: 1 when regular, 0 when flat.
pub fn quality(x: [&[f64; 3]; 4]) -> f64 {
    let volume = dot(sub(x[1], x[0]), cross(sub(x[2], x[0]), sub(x[3], x[0]))).abs() / 6.0;
    let mut sum = 0.0;
    for i in 0..4 {
        for j in i + 1..4 {
            let e = sub(x[j], x[i]);
            sum += dot(e, e);
        }
    }
    let l_rms = (sum / 6.0).sqrt();
    6.0 * 2f64.sqrt() * volume / (l_rms * l_rms * l_rms)
}

/// The α-shape of `mesh` over `points`, with `alpha_h_m` = α h in metres. `walls` says which
/// walls each node lies on, one bit per wall (a node on an edge between two walls has both
/// bits, a fluid node none): a face whose three nodes share a wall lies on that wall, and a
/// face of wall nodes that share none (across a corner of the water) can be free surface.
pub fn alpha_shape(
    points: &[[f64; 3]],
    walls: &[u16],
    mesh: &Tetrahedralisation,
    alpha_h_m: f64,
) -> AlphaShape {
    let n = points.len();
    assert_eq!(walls.len(), n, "one wall mask per node");
    let is_wall = |i: u32| walls[i as usize] != 0;
    let nodes = |t: usize| mesh.tets[t].map(|i| &points[i as usize]);
    let candidate: Vec<bool> = (0..mesh.tets.len())
        .map(|t| {
            let x = nodes(t);
            circumsphere(x[0], x[1], x[2], x[3]).1 < alpha_h_m
        })
        .collect();
    let mut wetted = vec![false; n];
    for (t, v) in mesh.tets.iter().enumerate() {
        if candidate[t] && v.iter().any(|&i| !is_wall(i)) {
            for &i in v {
                wetted[i as usize] = true;
            }
        }
    }
    let mut keep: Vec<bool> = (0..mesh.tets.len())
        .map(|t| {
            let v = &mesh.tets[t];
            let all_wall = v.iter().all(|&i| is_wall(i));
            let wetted_wall = v.iter().any(|&i| wetted[i as usize]);
            candidate[t] && (!all_wall || wetted_wall)
        })
        .collect();
    let sliver: Vec<bool> = (0..mesh.tets.len())
        .map(|t| keep[t] && quality(nodes(t)) < SLIVER_QUALITY)
        .collect();
    // A face of a kept tetrahedron is on the surface when nothing kept is across it and its
    // nodes do not share a wall.
    let on_surface = |keep: &[bool], t: usize, i: usize| {
        let across = mesh.neighbours[t][i];
        let open = across == NONE || !keep[across as usize];
        let v = mesh.tets[t];
        let shared = (0..4)
            .filter(|&k| k != i)
            .fold(u16::MAX, |m, k| m & walls[v[k] as usize]);
        open && shared == 0
    };
    let mut dropped = 0;
    loop {
        let peel: Vec<usize> = (0..mesh.tets.len())
            .filter(|&t| keep[t] && sliver[t] && (0..4).any(|i| on_surface(&keep, t, i)))
            .collect();
        if peel.is_empty() {
            break;
        }
        dropped += peel.len();
        for t in peel {
            keep[t] = false;
        }
    }
    let mut shape = AlphaShape {
        free_surface: vec![false; n],
        in_mesh: vec![false; n],
        slivers_dropped: dropped,
        ..Default::default()
    };
    for t in 0..mesh.tets.len() {
        if !keep[t] {
            continue;
        }
        shape.kept.push(t as u32);
        shape.slivers_kept += sliver[t] as usize;
        let v = mesh.tets[t];
        for &i in &v {
            shape.in_mesh[i as usize] = true;
        }
        for i in 0..4 {
            if !on_surface(&keep, t, i) {
                continue;
            }
            let mut f: Vec<u32> = (0..4).filter(|&k| k != i).map(|k| v[k]).collect();
            let [a, b, c] = [0, 1, 2].map(|k| &points[f[k] as usize]);
            // Outward: the normal points away from the node opposite the face.
            if dot(cross(sub(b, a), sub(c, a)), sub(&points[v[i] as usize], a)) > 0.0 {
                f.swap(1, 2);
            }
            for &k in &f {
                shape.free_surface[k as usize] = true;
            }
            shape.surface.push([f[0], f[1], f[2]]);
        }
    }
    shape
}
