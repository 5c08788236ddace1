//! The 3D α-shape on a tetrahedralisation: which tetrahedra are water, where the free surface
//! is, and what happens to slivers.
//!
//! Rules, as the 2D mesher's (`mesh`): a tetrahedron is a candidate when its circumradius is
//! below α h ([`WATER_ALPHA_FACTOR`] α h when it holds a fluid node of the last step's
//! water). A candidate whose four nodes are wall nodes is kept only if one of them is wetted
//! (PFEM3D's rule, here within two candidates of a fluid node rather than one: a lattice's cube
//! split into five can leave a corner of three walls with no node in a candidate with a fluid
//! node): that keeps the water in the flume's corners, where the Delaunay split of a corner
//! cube makes all-wall tetrahedra, and drops the walls' own tetrahedra elsewhere.
//!
//! Slivers: four nearly co-circular nodes make a tetrahedron of small circumradius and almost
//! no volume, which the α test keeps. When the four lie on one plane to round-off, as on a face
//! of a seeding lattice's cube, the circumsphere is ill-defined and its radius anything, so a
//! sliver is judged by its largest face's circle instead (otherwise such a tetrahedron inside
//! the water was dropped, leaving a hole with p = 0 on its nodes). Inside the water a sliver is
//! kept: dropping it would open a hole (the solver leaves the flattest out of its operators,
//! `solver3d::FLAT_QUALITY`, whose entries grow like 1/thickness). On the surface it is a skin
//! across the free surface that holds no water, so it is dropped, repeatedly, until no sliver
//! has a face on the surface — but with the last step's free surface known, only a sliver
//! whose fluid nodes were all on it: one of three surface nodes and a node of the water (in
//! the 3D sloshing, 0.7 of a spacing under them) stays, since dropping it made that node a
//! free-surface node, p = 0 where the water's pressure is ρ g times its depth, and the
//! surface around fell into the pit (the 3D sloshing's first spike, `docs/three_d.md`). A
//! sliver is a tetrahedron of quality q = 6√2 V / l_rms³ <
//! [`SLIVER_QUALITY`] (q = 1 for the regular tetrahedron, 0.66 for the six of a cube's Kuhn
//! split, 0.77 for the corners of its five).

use super::delaunay::{cross, dot, sub};
use super::{NONE, Tetrahedralisation, circumsphere};

/// Below this quality a tetrahedron is a sliver.
pub const SLIVER_QUALITY: f64 = 0.05;

/// With the last step's free surface known, a tetrahedron holding a fluid node that was not
/// on it (a node of the water) is a candidate up to this many times α h: the α test dropping
/// a barely stretched one (1.002 α h in the 3D sloshing) made that node a free-surface node
/// under the surface, as the sliver peel did (module doc). Measured at 1.5 only
/// (`docs/three_d.md`, *The piston*). "Not on it" includes a node that was in no kept
/// tetrahedron (a flying particle), which so joins the water at this bound too; no case with
/// spray has been measured with it.
pub const WATER_ALPHA_FACTOR: f64 = 1.5;

/// The kept tetrahedra and the free surface.
#[derive(Debug, Clone, Default)]
pub struct AlphaShape {
    /// Indices into the tetrahedralisation's `tets`.
    pub kept: Vec<u32>,
    /// The quality ([`quality`]) of each kept tetrahedron, in the order of `kept`.
    pub kept_quality: Vec<f64>,
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

/// Says whether a point lies inside the solid (under the bed), for [`alpha_shape_with`].
pub type InSolid<'a> = &'a dyn Fn(&[f64; 3]) -> bool;

/// The previous step's free surface, for the contact-line rule of [`alpha_shape_with`].
#[derive(Debug, Clone, Copy)]
pub struct ContactLine<'a> {
    /// Per node: on the free surface at the previous step.
    pub was_free: &'a [bool],
    /// The vertical axis (1 for y up).
    pub up_axis: usize,
}

/// The α-shape of `mesh` over `points`, with `alpha_h_m` = α h in metres. `walls` says which
/// walls each node lies on, one bit per wall (a node on an edge between two walls has both
/// bits, a fluid node none): a face whose three nodes share a wall lies on that wall, and a
/// face of wall nodes that share none (across a corner of the water) can be free surface.
/// No contact-line rule (see [`alpha_shape_with`]).
pub fn alpha_shape(
    points: &[[f64; 3]],
    walls: &[u16],
    mesh: &Tetrahedralisation,
    alpha_h_m: f64,
) -> AlphaShape {
    alpha_shape_with(points, walls, mesh, alpha_h_m, None, None)
}

/// [`alpha_shape`] with the contact-line rule, the 2D mesher's one dimension up: a candidate
/// with wall and fluid nodes, whose fluid nodes were all on the free surface at the previous
/// step, is air between the water and a wall — dropped — when its centroid lies above its
/// highest fluid node (a wedge above the water line on a side wall: it would set p = 0 on wall
/// nodes above the water and add weight to the contact nodes that no pressure carries); a
/// wetted candidate of wall nodes alone is air when its centroid lies above the highest fluid
/// node within two candidates of its nodes (the corner between two walls above the water
/// line). The 2D rule's second half, a fluid node that does not stand over its wall face (the
/// air wedge ahead of a front on the bed), is left out: in a corner of the water the lattice's
/// diagonals give water tetrahedra whose fluid node projects outside their face on one wall,
/// and dropping them set p = 0 on wall nodes under the water line. With `solid`, a tetrahedron
/// of wall nodes alone whose centroid it says is inside the solid is dropped too (under a bed
/// that bends down, the tetrahedra of its nodes across the bend lie in the bed, not the water).
pub fn alpha_shape_with(
    points: &[[f64; 3]],
    walls: &[u16],
    mesh: &Tetrahedralisation,
    alpha_h_m: f64,
    contact: Option<ContactLine>,
    solid: Option<InSolid>,
) -> AlphaShape {
    let n = points.len();
    assert_eq!(walls.len(), n, "one wall mask per node");
    let is_wall = |i: u32| walls[i as usize] != 0;
    let nodes = |t: usize| mesh.tets[t].map(|i| &points[i as usize]);
    let quality_of: Vec<f64> = (0..mesh.tets.len()).map(|t| quality(nodes(t))).collect();
    let is_sliver: Vec<bool> = quality_of.iter().map(|&q| q < SLIVER_QUALITY).collect();
    // A tetrahedron holding a fluid node of the last step's water (not on its free surface):
    // a candidate to WATER_ALPHA_FACTOR α h, and never peeled as a sliver (module doc).
    let holds_water: Vec<bool> = (0..mesh.tets.len())
        .map(|t| {
            contact.is_some_and(|c| {
                mesh.tets[t]
                    .iter()
                    .any(|&i| !c.was_free[i as usize] && !is_wall(i))
            })
        })
        .collect();
    let candidate: Vec<bool> = (0..mesh.tets.len())
        .map(|t| {
            let x = nodes(t);
            // A sliver's circumsphere is ill-defined (four nodes of one lattice face, moved by
            // round-off, give any radius at all): it is judged by its largest face circle.
            let radius = if is_sliver[t] {
                largest_face_circumradius(x)
            } else {
                circumsphere(x[0], x[1], x[2], x[3]).1
            };
            let bound = if holds_water[t] {
                WATER_ALPHA_FACTOR * alpha_h_m
            } else {
                alpha_h_m
            };
            radius < bound
                && !contact.is_some_and(|c| air_at_contact_line(points, walls, mesh.tets[t], c))
        })
        .collect();
    // A node is wetted when it shares a candidate with a fluid node; its water level is the
    // highest fluid node of those candidates (for the contact-line rule's all-wall half).
    let up = contact.map_or(1, |c| c.up_axis);
    let mut wet_level = vec![f64::NEG_INFINITY; n];
    for (t, v) in mesh.tets.iter().enumerate() {
        if candidate[t] && v.iter().any(|&i| !is_wall(i)) {
            let level = v
                .iter()
                .filter(|&&i| !is_wall(i))
                .map(|&i| points[i as usize][up])
                .fold(f64::NEG_INFINITY, f64::max);
            for &i in v {
                wet_level[i as usize] = wet_level[i as usize].max(level);
            }
        }
    }
    // The same over two rings: the highest fluid node within two candidates of a node, −∞
    // when there is none. A tetrahedron of wall nodes alone is wetted, and lies below the water
    // line, by this level, not by its nodes' own: where a lattice's cube is split into five,
    // the corner tetrahedron of three walls' nodes can have no node in a candidate with a fluid
    // node (at a corner of three walls), or only with fluid nodes below its centroid (in
    // mid-depth on an edge of two walls), and was dropped from the water.
    let mut line_level = wet_level.clone();
    for (t, v) in mesh.tets.iter().enumerate() {
        if candidate[t] {
            let level = v
                .iter()
                .map(|&i| wet_level[i as usize])
                .fold(f64::NEG_INFINITY, f64::max);
            for &i in v {
                line_level[i as usize] = line_level[i as usize].max(level);
            }
        }
    }
    let mut keep: Vec<bool> = (0..mesh.tets.len())
        .map(|t| {
            let v = &mesh.tets[t];
            if !candidate[t] {
                return false;
            }
            if !v.iter().all(|&i| is_wall(i)) {
                return true;
            }
            // All wall nodes: kept when wetted (a fluid node within two candidates of a node),
            // and with the contact-line rule only when its centroid is not above the water
            // line near its nodes (a corner of the walls above the water line is air).
            let line = v
                .iter()
                .map(|&i| line_level[i as usize])
                .fold(f64::NEG_INFINITY, f64::max);
            let centroid = v.iter().map(|&i| points[i as usize][up]).sum::<f64>() / 4.0;
            let inside_the_solid = solid.is_some_and(|in_solid| {
                in_solid(&std::array::from_fn(|k| {
                    v.iter().map(|&i| points[i as usize][k]).sum::<f64>() / 4.0
                }))
            });
            line > f64::NEG_INFINITY && (contact.is_none() || centroid <= line) && !inside_the_solid
        })
        .collect();
    let sliver: Vec<bool> = (0..mesh.tets.len())
        .map(|t| keep[t] && is_sliver[t])
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
            .filter(|&t| !holds_water[t])
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
        shape.kept_quality.push(quality_of[t]);
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

/// The largest circumradius of the tetrahedron's four faces, m (abc / 4A per triangle).
fn largest_face_circumradius(x: [&[f64; 3]; 4]) -> f64 {
    let len = |a: &[f64; 3], b: &[f64; 3]| dot(sub(a, b), sub(a, b)).sqrt();
    (0..4)
        .map(|skip| {
            let f: Vec<&[f64; 3]> = (0..4).filter(|&k| k != skip).map(|k| x[k]).collect();
            let n = cross(sub(f[1], f[0]), sub(f[2], f[0]));
            let area = 0.5 * dot(n, n).sqrt();
            let product = len(f[0], f[1]) * len(f[1], f[2]) * len(f[2], f[0]);
            if area > 0.0 {
                product / (4.0 * area)
            } else {
                f64::INFINITY
            }
        })
        .fold(0.0, f64::max)
}

/// The contact-line rule of [`alpha_shape_with`] for the tetrahedron `v`.
fn air_at_contact_line(
    points: &[[f64; 3]],
    walls: &[u16],
    v: [u32; 4],
    contact: ContactLine,
) -> bool {
    let fluid: Vec<u32> = v
        .iter()
        .copied()
        .filter(|&i| walls[i as usize] == 0)
        .collect();
    if fluid.is_empty()
        || fluid.len() == 4
        || !fluid
            .iter()
            .all(|&i| contact.was_free.get(i as usize).copied().unwrap_or(false))
    {
        return false;
    }
    let up = contact.up_axis;
    let centroid = v.iter().map(|&i| points[i as usize][up]).sum::<f64>() / 4.0;
    let top = fluid
        .iter()
        .map(|&i| points[i as usize][up])
        .fold(f64::NEG_INFINITY, f64::max);
    centroid > top
}
