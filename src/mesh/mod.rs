//! Remeshing, every step: Delaunay triangulation of all nodes (spade), then the α-shape.
//!
//! α-shape (thesis §2.3): a Delaunay triangle is kept when its circumradius R < α·h, with h the
//! initial particle spacing (a global h, as the open PFEM codes use). Triangles whose three nodes
//! are wall nodes are dropped, since they would glue the solid to itself, unless one of their
//! nodes shares a Delaunay triangle of circumradius < α·h with a fluid node (PFEM3D's rule,
//! which looks at every Delaunay neighbour): that keeps the wetted corner of the flume, where
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

pub mod edt;

use crate::case::Spacing;
use crate::geometry::PaddleFace;
use crate::particles::{NodeKind, Particles};
use crate::second_core::SecondCore;
use nalgebra::Vector2;
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation};

/// A node as spade sees it: a position and our index.
#[derive(Debug, Clone, Copy)]
struct Vertex {
    pos: Point2<f64>,
    id: u32,
}

impl HasPosition for Vertex {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.pos
    }
}

type Delaunay = DelaunayTriangulation<Vertex>;

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
    /// The EDT polygons of the kept mesh (`solver.delta` > 0; see `edt.rs`).
    pub polygons: Vec<MeshPolygon>,
    /// Per kept triangle: the polygon it belongs to, or `u32::MAX` (empty when δ = 0).
    pub polygon_of_triangle: Vec<u32>,
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
    /// The kept triangles around each node i: `around[first[i]..first[i + 1]]` (indices into
    /// `triangles`), for the boundary edges here and the pressure pattern.
    first: Vec<u32>,
    around: Vec<u32>,
    /// The EDT merge's working arrays and its last polygons, reused from step to step.
    merger: edt::Merger,
    merged: Vec<edt::Polygon>,
    candidate_nodes: Vec<[u32; 3]>,
    /// Per candidate of the last α-shape: its polygon, its index among the kept triangles;
    /// per node: wetted wall (scratch, kept to spare the allocations).
    polygon_of: Vec<u32>,
    kept_as: Vec<u32>,
    wetted: Vec<bool>,
}

/// A polygon element of the kept mesh: its boundary loop, counter-clockwise, and the kept
/// triangles it is made of (indices into [`Mesh::triangles`], ascending).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshPolygon {
    pub nodes: Vec<u32>,
    pub triangles: Vec<u32>,
}

const NO_POLYGON: u32 = u32::MAX;
const NOT_KEPT: u32 = u32::MAX;

/// A Delaunay triangle small enough for the α-shape: its nodes counter-clockwise and the
/// square of its circumradius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    pub nodes: [u32; 3],
    pub r2: f64,
}

/// Below this many nodes the cloud is triangulated in one piece.
pub(crate) const SPLIT_MIN_NODES: usize = 2_000;

/// Stage 1: the Delaunay triangles of all nodes with circumradius below `max_r_m` and positive
/// area, the only ones the α-shape can keep.
///
/// The cloud is cut at the median x into two pieces that overlap by `max_r_m` on each side of
/// the cut, each piece is triangulated (on two threads with `two_threads`), and each keeps the
/// triangles whose circumcentre lies on its side. That gives exactly the small triangles of
/// the whole cloud: the circle of such a triangle has radius < `max_r_m`, so every node inside
/// it belongs to the piece, which therefore has it empty (is Delaunay there) exactly when the
/// whole cloud does. Where several nodes lie on one circle (the seeding lattice) the
/// triangles that split it share the circumcentre, so they all come from the same piece. The
/// cut is offset from the median node by 0.3 `max_r_m` (0.36 h at α = 1.2) so that it does
/// not pass through a lattice row or the centre of a lattice cell.
///
/// Each piece is inserted point by point in Morton (Z-curve) order, so each insertion starts
/// its walk from a neighbour (spade's last-used-vertex hint). spade's bulk loader sweeps a
/// circle out from the centroid, which suits round clouds but not a flume 15–25 times longer
/// than deep: on `flap_deep_water` (19 207 nodes) it took 33–36 ms per step against 15–18 ms
/// in Morton order in one piece. The triangles then also come out in space-filling order,
/// which the later stages read.
pub fn triangulate(
    particles: &Particles,
    max_r_m: f64,
    two_threads: bool,
) -> Result<Vec<Candidate>, MeshError> {
    let second = two_threads.then(SecondCore::start).flatten();
    let mut triangulator = Triangulator::default();
    triangulator.run(particles, max_r_m, second.as_ref())?;
    Ok(triangulator.triangles)
}

/// [`triangulate`] with its memory kept from step to step: spade's two triangulations (one per
/// piece) and the candidate lists are cleared and filled again rather than allocated.
///
/// With a second core the caller fills the right (shoreward) piece and the second core the left
/// one: on a beach the shoreward piece, with the swash, is the dearer. On the teaching beach
/// (2 600 nodes a piece; `surflab bench`, eight alternated runs of each) the stage's median
/// went from 2.89 ms (fresh triangulations, a new thread on the shoreward piece) to 2.61 ms
/// with the memory kept and to 2.15 ms with the pieces swapped as well (2.72 and 2.56 ms in a
/// second sitting); the second core's kept thread (`crate::second_core`) took it from
/// 1.84–1.89 to 1.57–1.74 ms over the first 14 s of the run.
#[derive(Default)]
pub struct Triangulator {
    /// The left piece is `Box`ed so that it can travel to the second core and back.
    pieces: (Box<Piece>, Piece),
    /// The result of the last [`Triangulator::run`].
    pub triangles: Vec<Candidate>,
    /// Scratch: the nodes' x, partly sorted to find the median.
    xs: Vec<f64>,
}

/// One piece of the cloud: its nodes and its triangulation, both reused.
#[derive(Default)]
struct Piece {
    vertices: Vec<Vertex>,
    delaunay: Delaunay,
    triangles: Vec<Candidate>,
}

impl Triangulator {
    /// Fills `self.triangles` with the small Delaunay triangles of `particles`, as
    /// [`triangulate`] returns them.
    pub fn run(
        &mut self,
        particles: &Particles,
        max_r_m: f64,
        second: Option<&SecondCore>,
    ) -> Result<(), MeshError> {
        let n = particles.len();
        let x = &particles.position;
        self.triangles.clear();
        if n < SPLIT_MIN_NODES {
            return self.in_one_piece(x, max_r_m);
        }
        let xs = &mut self.xs;
        xs.clear();
        xs.extend(x.iter().map(|p| p.x));
        let mid = n / 2;
        xs.select_nth_unstable_by(mid, f64::total_cmp);
        let x_cut = xs[mid] + 0.3 * max_r_m;
        let band = 1.001 * max_r_m;
        let on_left_piece = move |x: f64| x < x_cut + band;
        let on_right_piece = move |x: f64| x >= x_cut - band;
        // The two pieces' sizes together, counted on the scratch (the same values, reordered).
        let both: usize = xs
            .iter()
            .map(|&v| usize::from(on_left_piece(v)) + usize::from(on_right_piece(v)))
            .sum();
        if !x_cut.is_finite() || both > n + n / 2 {
            // A short cloud (or a bad position, which the insertion reports).
            return self.in_one_piece(x, max_r_m);
        }
        let left = (0..n as u32).filter(|&i| on_left_piece(x[i as usize].x));
        let right = (0..n as u32).filter(|&i| on_right_piece(x[i as usize].x));
        let on_left = move |cx: f64| cx < x_cut;
        let on_right = move |cx: f64| cx >= x_cut;
        self.pieces.0.load(x, left);
        self.pieces.1.load(x, right);
        let (a, b) = if let Some(core) = second {
            let mut first = std::mem::take(&mut self.pieces.0);
            let left_job = core.run(move || {
                let a = first.triangulate(max_r_m, on_left);
                (first, a)
            });
            let b = self.pieces.1.triangulate(max_r_m, on_right);
            let (first, a) = left_job
                .wait()
                .expect("the triangulation of the left piece panicked");
            self.pieces.0 = first;
            (a, b)
        } else {
            (
                self.pieces.0.triangulate(max_r_m, on_left),
                self.pieces.1.triangulate(max_r_m, on_right),
            )
        };
        a?;
        b?;
        self.triangles.extend_from_slice(&self.pieces.0.triangles);
        self.triangles.extend_from_slice(&self.pieces.1.triangles);
        Ok(())
    }

    fn in_one_piece(&mut self, x: &[Vector2<f64>], max_r_m: f64) -> Result<(), MeshError> {
        let piece = &mut self.pieces.1;
        piece.load(x, 0..x.len() as u32);
        piece.triangulate(max_r_m, |_| true)?;
        std::mem::swap(&mut self.triangles, &mut piece.triangles);
        Ok(())
    }
}

impl Piece {
    /// Takes `nodes` as the piece's vertices.
    fn load(&mut self, position: &[Vector2<f64>], nodes: impl Iterator<Item = u32>) {
        self.vertices.clear();
        self.vertices.extend(nodes.map(|i| {
            let p = position[i as usize];
            Vertex {
                pos: Point2::new(p.x, p.y),
                id: i,
            }
        }));
    }

    /// Fills `self.triangles` with the triangles of the Delaunay triangulation of the loaded
    /// nodes with circumradius below `max_r_m`, positive area and a circumcentre x that `owned`
    /// accepts.
    fn triangulate(&mut self, max_r_m: f64, owned: impl Fn(f64) -> bool) -> Result<(), MeshError> {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for v in &self.vertices {
            lo = [lo[0].min(v.pos.x), lo[1].min(v.pos.y)];
            hi = [hi[0].max(v.pos.x), hi[1].max(v.pos.y)];
        }
        // One scale for both axes, so that the curve's cells are square.
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let cells_per_m = f64::from(u16::MAX) / extent.max(f64::MIN_POSITIVE);
        self.vertices.sort_by_cached_key(|v| {
            // A NaN or infinite position gives some key; its insertion then fails below.
            let qx = ((v.pos.x - lo[0]) * cells_per_m) as u16;
            let qy = ((v.pos.y - lo[1]) * cells_per_m) as u16;
            morton_key(qx, qy)
        });
        let tri = &mut self.delaunay;
        tri.clear();
        for &v in &self.vertices {
            tri.insert(v).map_err(MeshError::Insertion)?;
        }
        let max_r2 = max_r_m * max_r_m;
        self.triangles.clear();
        self.triangles.extend(tri.inner_faces().filter_map(|face| {
            let (centre, r2) = face.circumcircle();
            let keep = r2.is_finite() && r2 < max_r2 && face.area() > 0.0 && owned(centre.x);
            keep.then(|| Candidate {
                nodes: face.vertices().map(|v| v.data().id),
                r2,
            })
        }));
        Ok(())
    }
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

/// Connected components of `cells` (triangles, tetrahedra: node indices below `n`) through
/// shared nodes: a label per node (`u32::MAX` where `in_mesh` is false; such a node must be in
/// no cell) and the number of components, numbered in the order of their lowest node.
pub fn components_of<const K: usize>(
    n: usize,
    cells: impl IntoIterator<Item = [u32; K]>,
    in_mesh: impl Fn(usize) -> bool,
) -> (Vec<u32>, usize) {
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    for t in cells {
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
        if !in_mesh(i) {
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

/// The parameters of the α-shape and the EDT merge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeParams {
    /// α: a triangle (or polygon) is kept when its circumradius is below α h.
    pub alpha: f64,
    /// α_b ≤ α for triangles whose nodes are all on the boundary.
    pub alpha_boundary: f64,
    /// δ of the EDT merge (0: plain Delaunay triangles).
    pub delta: f64,
    /// The particle spacing h(x), m: each triangle is judged against α h at its centroid.
    pub spacing: Spacing,
}

/// Stage 2: the α-shape, the all-wall filter and the free surface, written into `mesh`.
///
/// With δ > 0 the candidates are first merged into EDT polygons (`edt.rs`); every triangle of a
/// polygon is then judged by the polygon's radius, the mean circumradius of its triangles (the
/// thesis's fig. 2.5), against the same global α h as a triangle, so that the test is
/// continuous as δ → 0. The other rules (all-wall, paddle, contact line) still judge each
/// triangle; a polygon stays one element only when all its triangles are kept, otherwise its
/// kept triangles stay P1 triangles.
pub fn alpha_shape(
    candidates: &[Candidate],
    particles: &Particles,
    shape: &ShapeParams,
    paddle: Option<&PaddleFace>,
    mesh: &mut Mesh,
) {
    let alpha = shape.alpha;
    let n = particles.len();
    let alpha_b = shape.alpha_boundary.min(alpha);
    mesh.triangles.clear();
    // The polygons' vectors are reused: `used` entries are rewritten, the rest dropped below.
    let mut used = 0;
    mesh.polygon_of_triangle.clear();
    mesh.boundary_edges.clear();
    mesh.boundary_edge_triangle.clear();
    std::mem::swap(&mut mesh.free_surface, &mut mesh.previous_free_surface);
    mesh.previous_free_surface.resize(n, false);
    mesh.free_surface.clear();
    mesh.free_surface.resize(n, false);
    mesh.in_mesh.clear();
    mesh.in_mesh.resize(n, false);

    // EDT: the polygons of the candidates, and each candidate's radius for the α test.
    // Not cleared: `merge_into` rewrites the entries it needs and keeps their vectors (a
    // cleared list made two allocations per polygon every step).
    let mut polygons = std::mem::take(&mut mesh.merged);
    if shape.delta > 0.0 {
        mesh.candidate_nodes.clear();
        mesh.candidate_nodes
            .extend(candidates.iter().map(|c| c.nodes));
        mesh.merger.merge_into(
            &particles.position,
            &mesh.candidate_nodes,
            shape.delta,
            &mut polygons,
        );
    } else {
        polygons.clear();
    }
    // Per candidate (only when there are polygons): its polygon, and its index among the kept
    // triangles if kept.
    let per_candidate = if polygons.is_empty() {
        0
    } else {
        candidates.len()
    };
    let mut polygon_of = std::mem::take(&mut mesh.polygon_of);
    polygon_of.clear();
    polygon_of.resize(per_candidate, NO_POLYGON);
    for (p, poly) in polygons.iter().enumerate() {
        for &k in &poly.triangles {
            polygon_of[k as usize] = p as u32;
        }
    }
    let r2_of = |k: usize| match polygon_of.get(k) {
        Some(&p) if p != NO_POLYGON => polygons[p as usize].radius_m.powi(2),
        _ => candidates[k].r2,
    };
    let mut kept_as = std::mem::take(&mut mesh.kept_as);
    kept_as.clear();
    kept_as.resize(per_candidate, NOT_KEPT);

    let is_wall = |i: u32| particles.kind[i as usize] == NodeKind::Wall;
    // A wall node with a fluid node in one of its candidate triangles is wetted.
    let mut wetted = std::mem::take(&mut mesh.wetted);
    wetted.clear();
    wetted.resize(n, false);
    for c in candidates {
        if c.nodes.iter().any(|&i| !is_wall(i)) {
            for &i in &c.nodes {
                wetted[i as usize] = true;
            }
        }
    }
    for (k, c) in candidates.iter().enumerate() {
        let r2 = r2_of(k);
        let [a, b, cc] = c.nodes;
        if is_wall(a) && is_wall(b) && is_wall(cc) && !c.nodes.iter().any(|&i| wetted[i as usize]) {
            continue;
        }
        let centroid = c
            .nodes
            .iter()
            .map(|&i| particles.position[i as usize])
            .sum::<Vector2<f64>>()
            / 3.0;
        // Nothing behind the paddle is water.
        if paddle.is_some_and(|face_line| face_line.distance(centroid) < 0.0) {
            continue;
        }
        let h = shape.spacing.at(centroid.x);
        let (max_r2, max_r2_boundary) = ((alpha * h).powi(2), (alpha_b * h).powi(2));
        if r2 >= max_r2 {
            continue;
        }
        if air_at_contact_line(c.nodes, particles, &mesh.previous_free_surface) {
            continue;
        }
        let on_boundary = |i: u32| is_wall(i) || mesh.previous_free_surface[i as usize];
        if c.nodes.iter().all(|&i| on_boundary(i)) && r2 >= max_r2_boundary {
            continue;
        }
        if let Some(slot) = kept_as.get_mut(k) {
            *slot = mesh.triangles.len() as u32;
        }
        mesh.triangles.push(c.nodes);
        for v in c.nodes {
            mesh.in_mesh[v as usize] = true;
        }
    }

    // The polygons whose triangles were all kept.
    if !polygons.is_empty() {
        mesh.polygon_of_triangle
            .resize(mesh.triangles.len(), NO_POLYGON);
        for poly in &polygons {
            if poly
                .triangles
                .iter()
                .any(|&k| kept_as[k as usize] == NOT_KEPT)
            {
                continue;
            }
            if used == mesh.polygons.len() {
                mesh.polygons.push(MeshPolygon::default());
            }
            let kept = &mut mesh.polygons[used];
            kept.nodes.clear();
            kept.nodes.extend_from_slice(&poly.nodes);
            kept.triangles.clear();
            kept.triangles
                .extend(poly.triangles.iter().map(|&k| kept_as[k as usize]));
            for &t in &kept.triangles {
                mesh.polygon_of_triangle[t as usize] = used as u32;
            }
            used += 1;
        }
    }
    mesh.polygons.truncate(used);
    mesh.merged = polygons;
    mesh.polygon_of = polygon_of;
    mesh.kept_as = kept_as;
    mesh.wetted = wetted;

    // Boundary edges: an edge a → b of a kept triangle with no kept triangle holding b → a.
    // The kept triangles are Delaunay triangles, all counter-clockwise and none overlapping, so
    // another triangle with both ends holds the edge as b → a.
    mesh.index_triangles(n);
    for (k, t) in mesh.triangles.iter().enumerate() {
        for e in 0..3 {
            let (from, to) = (t[e], t[(e + 1) % 3]);
            let shared = mesh.triangles_around(to as usize).iter().any(|&o| {
                let u = &mesh.triangles[o as usize];
                o as usize != k && (u[0] == from) | (u[1] == from) | (u[2] == from)
            });
            if shared {
                continue;
            }
            mesh.boundary_edges.push([from, to]);
            mesh.boundary_edge_triangle.push(k as u32);
            if is_wall(from) && is_wall(to) {
                continue;
            }
            // Both ends touch the atmosphere: a wall node here is a contact point (the water
            // line on a wall, the bed just ahead of a front), at p = 0 like the fluid nodes.
            mesh.free_surface[from as usize] = true;
            mesh.free_surface[to as usize] = true;
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
    /// The kept triangles that have node `i` as a vertex (indices into `triangles`).
    pub fn triangles_around(&self, i: usize) -> &[u32] {
        match (self.first.get(i), self.first.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.around[a as usize..b as usize],
            _ => &[],
        }
    }

    /// Builds the node → kept-triangle index for `n` nodes.
    fn index_triangles(&mut self, n: usize) {
        self.first.clear();
        self.first.resize(n + 1, 0);
        for t in &self.triangles {
            for &v in t {
                self.first[v as usize + 1] += 1;
            }
        }
        for i in 0..n {
            self.first[i + 1] += self.first[i];
        }
        let mut cursor = self.first[..n].to_vec();
        self.around.clear();
        self.around.resize(3 * self.triangles.len(), 0);
        for (k, t) in self.triangles.iter().enumerate() {
            for &v in t {
                self.around[cursor[v as usize] as usize] = k as u32;
                cursor[v as usize] += 1;
            }
        }
    }

    /// A mesh of the given triangles over `n` nodes, with no free surface (for tests).
    #[cfg(test)]
    pub(crate) fn from_triangles(n: usize, triangles: Vec<[u32; 3]>) -> Mesh {
        let mut mesh = Mesh {
            triangles,
            ..Default::default()
        };
        mesh.index_triangles(n);
        mesh
    }

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
        self.polygons.clear();
        self.polygon_of_triangle.clear();
        self.boundary_edges.clear();
        self.boundary_edge_triangle.clear();
        self.first.clear();
        self.around.clear();
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
        components_of(n, self.triangles.iter().copied(), |i| self.in_mesh[i])
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
mod tests;
