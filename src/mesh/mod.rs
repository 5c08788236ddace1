//! Remeshing, every step: Delaunay triangulation of all nodes (spade), then the α-shape.
//!
//! α-shape (thesis §2.3): a Delaunay triangle is kept when its circumradius R < α·h, with h the
//! initial particle spacing (a global h, as the open PFEM codes use). Triangles whose three nodes
//! are wall nodes are dropped, since they would glue the solid to itself, unless one of their
//! nodes has a fluid neighbour (PFEM3D's rule): that keeps the wetted corner of the flume, where
//! the Delaunay split of the corner cell makes an all-wall triangle that is water. Without it the
//! fluid node beside the corner faces a void and is pushed into it. The free surface is made of
//! the edges of kept triangles that have no kept neighbour across them and are not wall–wall
//! edges; their nodes get p = 0, wall nodes included (they are contact points: leaving their
//! pressure unknown took the first kick at the water line of `sloshing.toml` from 0.12 to
//! 0.011 m/s, but the bed node ahead of the dam-break front then oscillated until the run
//! diverged). Nodes in no kept triangle are isolated (flying).
//!
//! Boundary triangles: a triangle whose three nodes are all boundary nodes (wall, or free
//! surface at the previous step) must pass a tighter test, R < α_b·h with α_b ≤ α (1.0 by
//! default), as Kratos does with its smaller α multiplier for boundary elements. Such a triangle
//! has no interior node to vouch for it: it bridges a concave stretch of the surface, and with
//! the full α the bridges accumulate as spurious water (the dam break gained 1.1 % by the impact
//! with α_b = α = 1.2, 0.6 % with α_b = 1.0).
//!
//! Contact lines: a triangle made of two wall nodes and one fluid node that was on the free
//! surface at the previous step is kept only if it lies below that node (its centroid is lower)
//! and the node stands over the wall segment (its projection on the segment falls inside it,
//! give or take a tenth of it). Otherwise the triangle is air between the water and the wall: above the water line on a side wall, it would add weight to the contact node
//! that no pressure can carry (its pressure gradient is normal to the wall), so the node would
//! sink along the wall; ahead of a front running along the bed, it fills the air wedge under
//! the sloping front face, and since the front moves on, that wedge would be left behind as
//! water at every step (a steady volume gain that grows with α).

use crate::geometry::PaddleFace;
use crate::particles::{NodeKind, Particles};
use nalgebra::Vector2;
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation};

/// A node as spade sees it: a position and our index.
#[derive(Debug, Clone, Copy)]
pub struct Vertex {
    pos: Point2<f64>,
    id: u32,
}

impl HasPosition for Vertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.pos
    }
}

pub type Delaunay = DelaunayTriangulation<Vertex>;

#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    #[error(
        "Delaunay triangulation failed: {0:?} (a particle position is NaN, infinite or out of range)"
    )]
    Insertion(spade::InsertionError),
}

/// The kept mesh of one step and what it says about each node.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Kept triangles, counter-clockwise, as node indices.
    pub triangles: Vec<[u32; 3]>,
    /// Edges on the boundary of the kept mesh (free surface and wetted walls), as node pairs.
    pub boundary_edges: Vec<[u32; 2]>,
    /// Per boundary edge: the kept triangle it belongs to (index into `triangles`).
    pub boundary_edge_triangle: Vec<u32>,
    /// Per node: on a free-surface edge, fluid or wall (p = 0 there).
    pub free_surface: Vec<bool>,
    /// The free-surface flags of the previous remesh (for the contact-line rule).
    previous_free_surface: Vec<bool>,
    /// Per node: belongs to at least one kept triangle.
    pub in_mesh: Vec<bool>,
    /// Number of Delaunay triangles before the α-shape and wall filters.
    pub delaunay_triangles: usize,
}

/// Stage 1: the Delaunay triangulation of every node, inserted one by one in Morton (Z-curve)
/// order so that each insertion starts its walk from a neighbour (spade's last-used-vertex
/// hint). spade's bulk loader sweeps a circle out from the centroid, which suits round clouds
/// but not a flume 15–25 times longer than deep: on `flap_deep_water` (19 207 nodes) it took
/// 33–36 ms per step against 15–18 ms this way, on the dam break (5 500) the two are alike.
/// The triangles then also come out in space-filling order, which the later stages read.
pub fn triangulate(
    particles: &Particles,
    scratch: &mut Vec<Vertex>,
) -> Result<Delaunay, MeshError> {
    scratch.clear();
    scratch.extend(particles.position.iter().enumerate().map(|(i, p)| Vertex {
        pos: Point2::new(p.x, p.y),
        id: i as u32,
    }));
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for v in scratch.iter() {
        lo = [lo[0].min(v.pos.x), lo[1].min(v.pos.y)];
        hi = [hi[0].max(v.pos.x), hi[1].max(v.pos.y)];
    }
    // One scale for both axes, so that the curve's cells are square.
    let cells_per_m =
        f64::from(u16::MAX) / (hi[0] - lo[0]).max(hi[1] - lo[1]).max(f64::MIN_POSITIVE);
    scratch.sort_by_cached_key(|v| {
        // A NaN or infinite position gives some key; its insertion then fails below.
        let qx = ((v.pos.x - lo[0]) * cells_per_m) as u16;
        let qy = ((v.pos.y - lo[1]) * cells_per_m) as u16;
        morton_key(qx, qy)
    });
    let n = scratch.len();
    let mut tri = Delaunay::with_capacity(n, 3 * n, 2 * n);
    for v in scratch.drain(..) {
        tri.insert(v).map_err(MeshError::Insertion)?;
    }
    Ok(tri)
}

/// The bits of x and y interleaved (x in the even bits).
fn morton_key(x: u16, y: u16) -> u32 {
    let spread = |v: u16| {
        let mut v = u32::from(v);
        v = (v | (v << 8)) & 0x00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333;
        (v | (v << 1)) & 0x5555_5555
    };
    spread(x) | (spread(y) << 1)
}

/// Stage 2: the α-shape, the all-wall filter and the free surface, written into `mesh`.
pub fn alpha_shape(
    tri: &Delaunay,
    particles: &Particles,
    alpha: f64,
    alpha_boundary: f64,
    h: f64,
    paddle: Option<&PaddleFace>,
    mesh: &mut Mesh,
) {
    let n = particles.len();
    let max_r2 = (alpha * h) * (alpha * h);
    let max_r2_boundary = (alpha_boundary.min(alpha) * h).powi(2);
    mesh.triangles.clear();
    mesh.boundary_edges.clear();
    mesh.boundary_edge_triangle.clear();
    std::mem::swap(&mut mesh.free_surface, &mut mesh.previous_free_surface);
    mesh.previous_free_surface.resize(n, false);
    mesh.free_surface.clear();
    mesh.free_surface.resize(n, false);
    mesh.in_mesh.clear();
    mesh.in_mesh.resize(n, false);
    mesh.delaunay_triangles = tri.num_inner_faces();

    let is_wall = |i: u32| particles.kind[i as usize] == NodeKind::Wall;
    // Per Delaunay face: its index in `mesh.triangles`, or u32::MAX when it is not kept.
    let mut kept = vec![u32::MAX; tri.num_all_faces()];
    for face in tri.inner_faces() {
        let [a, b, c] = face.vertices().map(|v| v.data().id);
        if is_wall(a) && is_wall(b) && is_wall(c) {
            let wetted = face
                .vertices()
                .iter()
                .any(|v| v.out_edges().any(|e| !is_wall(e.to().data().id)));
            if !wetted {
                continue;
            }
        }
        if let Some(face_line) = paddle {
            // Nothing behind the paddle is water.
            let centroid = [a, b, c]
                .iter()
                .map(|&i| particles.position[i as usize])
                .sum::<Vector2<f64>>()
                / 3.0;
            if face_line.distance(centroid) < 0.0 {
                continue;
            }
        }
        let (_, r2) = face.circumcircle();
        if !(r2.is_finite() && r2 < max_r2 && face.area() > 0.0) {
            continue;
        }
        if air_at_contact_line([a, b, c], particles, &mesh.previous_free_surface) {
            continue;
        }
        let on_boundary = |i: u32| is_wall(i) || mesh.previous_free_surface[i as usize];
        if on_boundary(a) && on_boundary(b) && on_boundary(c) && r2 >= max_r2_boundary {
            continue;
        }
        {
            kept[face.fix().index()] = mesh.triangles.len() as u32;
            mesh.triangles.push([a, b, c]);
            for v in [a, b, c] {
                mesh.in_mesh[v as usize] = true;
            }
        }
    }
    for face in tri.inner_faces() {
        let owner = kept[face.fix().index()];
        if owner == u32::MAX {
            continue;
        }
        for edge in face.adjacent_edges() {
            let across = edge.rev().face();
            if !across.is_outer() && kept[across.fix().index()] != u32::MAX {
                continue;
            }
            let [from, to] = edge.vertices().map(|v| v.data().id);
            mesh.boundary_edges.push([from, to]);
            mesh.boundary_edge_triangle.push(owner);
            if is_wall(from) && is_wall(to) {
                continue;
            }
            // Both ends touch the atmosphere: a wall node here is a contact point (the water
            // line on a wall, the bed just ahead of a front), at p = 0 like the fluid nodes.
            for v in [from, to] {
                mesh.free_surface[v as usize] = true;
            }
        }
    }
}

/// The contact-line rule (see the module doc): two wall nodes and a free-surface fluid node,
/// with the triangle above the node or the node not standing over the segment.
fn air_at_contact_line(t: [u32; 3], particles: &Particles, was_free: &[bool]) -> bool {
    let is_wall = |i: &u32| particles.kind[*i as usize] == NodeKind::Wall;
    let walls: Vec<usize> = t
        .iter()
        .filter(|i| is_wall(i))
        .map(|&i| i as usize)
        .collect();
    if walls.len() != 2 {
        return false;
    }
    let f = t
        .iter()
        .find(|i| !is_wall(i))
        .map(|&i| i as usize)
        .expect("one fluid node");
    if !was_free[f] {
        return false;
    }
    let (a, b) = (particles.position[walls[0]], particles.position[walls[1]]);
    let d = b - a;
    let s = (particles.position[f] - a).dot(&d) / d.norm_squared();
    // A tenth of the segment either way: a node right at the end of the segment (a flat surface
    // meeting a wall node) stands over it; a node off the end by round-off must not flip.
    let centroid_y = t
        .iter()
        .map(|&i| particles.position[i as usize].y)
        .sum::<f64>()
        / 3.0;
    centroid_y > particles.position[f].y || !(-0.1..=1.1).contains(&s)
}

impl Mesh {
    /// Node removal between steps: keeps the per-node flags of the surviving nodes, in order.
    /// The triangles and edges refer to the old numbering and are cleared; the next remesh
    /// rebuilds them.
    pub fn remove_nodes(&mut self, drop: &[bool]) {
        let keep = |v: &mut Vec<bool>| {
            let mut k = 0;
            for i in 0..v.len() {
                if !drop[i] {
                    v[k] = v[i];
                    k += 1;
                }
            }
            v.truncate(k);
        };
        keep(&mut self.free_surface);
        keep(&mut self.in_mesh);
        self.triangles.clear();
        self.boundary_edges.clear();
        self.boundary_edge_triangle.clear();
    }

    /// Node insertion between steps: `count` new interior nodes at the end.
    pub fn add_interior_nodes(&mut self, count: usize) {
        let n = self.free_surface.len() + count;
        self.free_surface.resize(n, false);
        self.in_mesh.resize(n, true);
    }

    /// Area of the kept mesh, m² per metre of flume width: the water volume.
    pub fn area(&self, position: &[Vector2<f64>]) -> f64 {
        self.triangles
            .iter()
            .map(|t| crate::fem::triangle_area(position, t))
            .sum()
    }

    /// Connected components of the kept mesh through shared nodes: a label per node
    /// (`u32::MAX` for nodes in no triangle) and the number of components.
    pub fn components(&self, n: usize) -> (Vec<u32>, usize) {
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn find(parent: &mut [u32], mut i: u32) -> u32 {
            while parent[i as usize] != i {
                parent[i as usize] = parent[parent[i as usize] as usize];
                i = parent[i as usize];
            }
            i
        }
        for t in &self.triangles {
            let r0 = find(&mut parent, t[0]);
            for &v in &t[1..] {
                let r = find(&mut parent, v);
                if r != r0 {
                    parent[r as usize] = r0;
                }
            }
        }
        let mut label = vec![u32::MAX; n];
        let mut root_label = vec![u32::MAX; n];
        let mut count = 0;
        for i in 0..n {
            if !self.in_mesh[i] {
                continue;
            }
            let r = find(&mut parent, i as u32) as usize;
            if root_label[r] == u32::MAX {
                root_label[r] = count;
                count += 1;
            }
            label[i] = root_label[r];
        }
        (label, count as usize)
    }

    /// The component labels of [`Mesh::components`] and the label of the main body of water,
    /// the component with the most fluid nodes (`None` when no fluid node is in the mesh).
    pub fn main_body(&self, particles: &Particles) -> (Vec<u32>, Option<u32>) {
        let n = particles.len();
        let (label, count) = self.components(n);
        let mut size = vec![0usize; count];
        for i in 0..n {
            if particles.is_fluid(i) && label[i] != u32::MAX {
                size[label[i] as usize] += 1;
            }
        }
        let main = (0..count)
            .filter(|&c| size[c] > 0)
            .max_by_key(|&c| size[c])
            .map(|c| c as u32);
        (label, main)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_block(n: usize, h: f64) -> Particles {
        let mut walls = Vec::new();
        let mut fluid = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let p = Vector2::new(i as f64 * h, j as f64 * h);
                if j == 0 || i == 0 || i == n {
                    walls.push(p);
                } else {
                    fluid.push(p);
                }
            }
        }
        Particles::new(&walls, &fluid)
    }

    #[test]
    fn a_block_of_water_meshes_to_its_area_with_the_top_free() {
        let h = 0.1;
        let p = square_block(10, h);
        let tri = triangulate(&p, &mut Vec::new()).unwrap();
        let mut mesh = Mesh::default();
        alpha_shape(&tri, &p, 1.2, 1.0, h, None, &mut mesh);
        assert!((mesh.area(&p.position) - 1.0).abs() < 1e-12);
        // The top row is free surface, its two wall nodes (contact points) included; nothing
        // else is.
        for i in 0..p.len() {
            let top = (p.position[i].y - 1.0).abs() < 1e-9;
            assert_eq!(mesh.free_surface[i], top, "node {i}");
        }
        let (_, count) = mesh.components(p.len());
        assert_eq!(count, 1);
    }

    #[test]
    fn morton_keys_interleave_the_bits() {
        assert_eq!(morton_key(0, 0), 0);
        assert_eq!(morton_key(1, 0), 1);
        assert_eq!(morton_key(0, 1), 2);
        assert_eq!(morton_key(3, 3), 15);
        assert_eq!(morton_key(u16::MAX, 0), 0x5555_5555);
        assert_eq!(morton_key(u16::MAX, u16::MAX), u32::MAX);
    }

    #[test]
    fn a_far_particle_is_isolated() {
        let h = 0.1;
        let mut p = square_block(5, h);
        p.push_fluid(
            Vector2::new(0.25, 2.0),
            Vector2::zeros(),
            0.0,
            Vector2::zeros(),
        );
        let tri = triangulate(&p, &mut Vec::new()).unwrap();
        let mut mesh = Mesh::default();
        alpha_shape(&tri, &p, 1.3, 1.0, h, None, &mut mesh);
        assert!(!mesh.in_mesh[p.len() - 1]);
    }
}
