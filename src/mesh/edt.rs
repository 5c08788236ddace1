//! Extended Delaunay Tessellation (EDT, thesis §2.2, eq. 2.2): Delaunay triangles whose
//! circumcircles (nearly) coincide are merged into one polygon.
//!
//! Where four or more nodes lie on one empty circle (the seeding lattice, or nodes that drift
//! onto a common circle), the Delaunay triangulation is not unique: the split of that cyclic
//! polygon into triangles depends on round-off and on the order in which the nodes were
//! inserted. The EDT removes the arbitrariness by merging two triangles that share an edge when
//! their circumcentres c₁, c₂ are close compared with their circumradii r₁, r₂:
//!
//! |c₂ − c₁| ≤ δ · ½(r₁ + r₂)      (eq. 2.2, δ a small fraction such as 0.01),
//!
//! transitively (union–find over the edge-neighbour graph). The merged polygon does not depend
//! on the split, so the mesh built from it is the same whatever the insertion order.
//!
//! Only groups that make a usable element are returned: at least two triangles, one simply
//! connected region without interior nodes (n boundary nodes and n − 2 triangles), convex up to
//! round-off, and at most [`MAX_POLYGON_NODES`] nodes. Anything else (a chain that drifted into a
//! non-convex shape, a ring with a hole, a degenerate triangle) stays as its triangles, which
//! are a valid mesh on their own, so the caller only has to replace the returned groups.
//!
//! The merge is pairwise (each link compares two neighbours, not the group's common circle), so
//! a chain of links could drift away from one circle; the cap of [`MAX_POLYGON_NODES`] nodes
//! (at most six triangles, five links) bounds that drift to 5δ·r̄ of the centre, and a drift that
//! bends the outline is refused by the convexity test.
//!
//! Cost: O(T + N) for T triangles and N nodes (edge adjacency by a counting sort of the directed
//! edges on their lower node, no comparison sort). [`Merger`] keeps the working arrays between
//! calls, so that a step allocates nothing once the mesh has stopped growing.

use nalgebra::Vector2;

/// A polygon of the Extended Delaunay Tessellation: neighbouring Delaunay triangles merged by
/// eq. 2.2.
#[derive(Debug, Clone, PartialEq)]
pub struct Polygon {
    /// Boundary loop, counter-clockwise, starting at the smallest node index (canonical form).
    pub nodes: Vec<u32>,
    /// The merged triangles (indices into the input slice), ascending.
    pub triangles: Vec<u32>,
    /// Mean circumradius of the merged triangles, m (the thesis's fig. 2.5 radius).
    pub radius_m: f64,
}

/// Largest polygon the merge builds (a bigger group stays as its triangles).
pub const MAX_POLYGON_NODES: usize = 8;

/// A polygon of n nodes without interior nodes is made of n − 2 triangles, so a larger group
/// can be rejected before its boundary is traced.
const MAX_GROUP_TRIANGLES: usize = MAX_POLYGON_NODES - 2;

/// No triangle (no neighbour across an edge, or an unused slot).
const NONE: u32 = u32::MAX;

/// Flag of an edge slot: the edge runs from its lower node to its higher one.
const FORWARD: u32 = 1 << 31;

/// Relative round-off allowed for a node that turns right: a turn counts as convex when the
/// cross product of its two edges is ≥ −CONVEX_TOLERANCE · (longest edge)².
const CONVEX_TOLERANCE: f64 = 1e-12;

/// Relative mismatch allowed between the polygon's shoelace area and the sum of its triangles'
/// areas (they differ only if the triangles overlap, which a triangulation never does).
const AREA_TOLERANCE: f64 = 1e-9;

/// Groups the triangles (counter-clockwise node triples into `position`) into EDT polygons:
/// two triangles sharing an edge merge when |c₂ − c₁| ≤ δ·½(r₁ + r₂) (c circumcentre, r
/// circumradius), transitively (union–find). Returns only groups of ≥ 2 triangles whose union
/// is one simply connected, convex polygon (each boundary node turning left or straight within
/// a round-off tolerance) with at most [`MAX_POLYGON_NODES`] nodes; other groups are left as
/// triangles (not returned). δ ≤ 0 (or NaN) returns nothing. Output sorted by first triangle
/// index (deterministic).
///
/// A triangle with a node index out of range, a repeated node, zero or negative area or a
/// non-finite circumcircle never merges.
///
/// Allocates its working arrays on every call; a caller that merges every step should keep a
/// [`Merger`], which reuses them and the polygons' own vectors.
pub fn merge(position: &[Vector2<f64>], triangles: &[[u32; 3]], delta: f64) -> Vec<Polygon> {
    let mut polygons = Vec::new();
    Merger::default().merge_into(position, triangles, delta, &mut polygons);
    polygons
}

/// [`merge`] with working arrays kept between calls (one per simulation), so that a step
/// allocates nothing once the mesh has stopped growing.
#[derive(Debug, Clone, Default)]
pub struct Merger {
    circles: Vec<Circle>,
    /// Directed edges bucketed by their lower node: bucket a is `edges[first[a]..first[a + 1]]`.
    first: Vec<u32>,
    fill: Vec<u32>,
    /// (higher node, slot) of each directed edge: slot 3t + e for edge e of triangle t, with
    /// [`FORWARD`] set when the edge runs from the lower node to the higher.
    edges: Vec<(u32, u32)>,
    /// Per triangle and local edge e (node e to node e + 1): the triangle across, or NONE.
    neighbour: Vec<[u32; 3]>,
    /// Union–find forest, then (after the unions) each triangle's root.
    parent: Vec<u32>,
    size: Vec<u32>,
    /// Members of each group as a list through `next`, ascending, headed at `head[root]`.
    head: Vec<u32>,
    next: Vec<u32>,
}

impl Merger {
    /// The polygons of [`merge`], written into `polygons` (its previous contents are replaced;
    /// their vectors are reused).
    pub fn merge_into(
        &mut self,
        position: &[Vector2<f64>],
        triangles: &[[u32; 3]],
        delta: f64,
        polygons: &mut Vec<Polygon>,
    ) {
        let mut found = 0;
        // NOTE: written so that a NaN δ also returns nothing.
        if delta > 0.0 && triangles.len() >= 2 && 3 * triangles.len() < FORWARD as usize {
            self.circles.clear();
            self.circles
                .extend(triangles.iter().map(|t| circumcircle(position, t)));
            self.find_neighbours(position.len(), triangles);
            self.group(delta);
            found = self.polygons(position, triangles, polygons);
        }
        polygons.truncate(found);
    }

    /// Fills `neighbour`. Each directed edge a → b is put in the bucket of its lower node
    /// min(a, b) (a counting sort); edge a → b of one triangle pairs with edge b → a of another
    /// in the same bucket. The buckets are read in order, which keeps the memory access local.
    fn find_neighbours(&mut self, node_count: usize, triangles: &[[u32; 3]]) {
        let circles = &self.circles;
        let valid = |t: usize| circles[t].valid();
        self.first.clear();
        self.first.resize(node_count + 1, 0);
        for (t, tri) in triangles.iter().enumerate() {
            if valid(t) {
                for e in 0..3 {
                    let low = tri[e].min(tri[(e + 1) % 3]);
                    self.first[low as usize + 1] += 1;
                }
            }
        }
        for i in 0..node_count {
            self.first[i + 1] += self.first[i];
        }
        self.edges.clear();
        self.edges
            .resize(self.first[node_count] as usize, (NONE, NONE));
        self.fill.clear();
        self.fill.extend_from_slice(&self.first[..node_count]);
        for (t, tri) in triangles.iter().enumerate() {
            if valid(t) {
                for e in 0..3 {
                    let (a, b) = (tri[e], tri[(e + 1) % 3]);
                    let (low, high) = if a < b { (a, b) } else { (b, a) };
                    // The edge's slot 3t + e, with the top bit set when it runs low → high.
                    let slot = (3 * t + e) as u32 | if a < b { FORWARD } else { 0 };
                    self.edges[self.fill[low as usize] as usize] = (high, slot);
                    self.fill[low as usize] += 1;
                }
            }
        }
        self.neighbour.clear();
        self.neighbour.resize(triangles.len(), [NONE; 3]);
        for w in self.first.windows(2) {
            let bucket = &self.edges[w[0] as usize..w[1] as usize];
            for (k, &(high, slot)) in bucket.iter().enumerate() {
                if slot & FORWARD == 0 {
                    continue;
                }
                let twin = bucket[k + 1..]
                    .iter()
                    .chain(&bucket[..k])
                    .find(|&&(other, s)| other == high && s & FORWARD == 0);
                if let Some(&(_, back)) = twin {
                    let (t, e) = ((slot & !FORWARD) / 3, (slot & !FORWARD) % 3);
                    let (u, f) = (back / 3, back % 3);
                    self.neighbour[t as usize][e as usize] = u;
                    self.neighbour[u as usize][f as usize] = t;
                }
            }
        }
    }

    /// Union–find over the neighbour pairs that satisfy eq. 2.2 (union by size, path halving),
    /// then each group's members as an ascending list.
    fn group(&mut self, delta: f64) {
        let count = self.circles.len();
        self.parent.clear();
        self.parent.extend(0..count as u32);
        self.size.clear();
        self.size.resize(count, 1);
        let limit = delta * delta * 0.25;
        for (t, across) in self.neighbour.iter().enumerate() {
            for &u in across {
                // Each pair once (from its lower index); NONE is larger than any index.
                if u == NONE || (u as usize) <= t {
                    continue;
                }
                let (a, b) = (&self.circles[t], &self.circles[u as usize]);
                let r_sum = a.radius_m + b.radius_m;
                if (b.centre - a.centre).norm_squared() <= limit * r_sum * r_sum {
                    union(&mut self.parent, &mut self.size, t as u32, u);
                }
            }
        }
        for t in 0..count {
            let r = find(&mut self.parent, t as u32);
            self.parent[t] = r;
        }
        self.head.clear();
        self.head.resize(count, NONE);
        self.next.clear();
        self.next.resize(count, NONE);
        for t in (0..count).rev() {
            let r = self.parent[t] as usize;
            self.next[t] = self.head[r];
            self.head[r] = t as u32;
        }
    }

    /// Writes the accepted groups into `polygons` from the start, reusing its entries, and
    /// returns how many there are.
    fn polygons(
        &self,
        position: &[Vector2<f64>],
        triangles: &[[u32; 3]],
        polygons: &mut Vec<Polygon>,
    ) -> usize {
        let mut found = 0;
        for t in 0..triangles.len() {
            let r = self.parent[t] as usize;
            let members = self.size[r] as usize;
            if self.head[r] != t as u32 || !(2..=MAX_GROUP_TRIANGLES).contains(&members) {
                continue;
            }
            let mut group = [0u32; MAX_GROUP_TRIANGLES];
            let mut m = t as u32;
            for slot in group.iter_mut().take(members) {
                *slot = m;
                m = self.next[m as usize];
            }
            let group = &group[..members];
            let mut nodes = [0u32; MAX_POLYGON_NODES];
            let Some(n) = self.boundary_loop(position, triangles, group, &mut nodes) else {
                continue;
            };
            let radius_m = group
                .iter()
                .map(|&g| self.circles[g as usize].radius_m)
                .sum::<f64>()
                / members as f64;
            if found == polygons.len() {
                polygons.push(Polygon {
                    nodes: Vec::with_capacity(n),
                    triangles: Vec::with_capacity(members),
                    radius_m,
                });
            }
            let p = &mut polygons[found];
            p.nodes.clear();
            p.nodes.extend_from_slice(&nodes[..n]);
            p.triangles.clear();
            p.triangles.extend_from_slice(group);
            p.radius_m = radius_m;
            found += 1;
        }
        found
    }

    /// The counter-clockwise boundary loop of a group (canonical: from its smallest node) into
    /// `nodes`, returning its length, or None if the group is not one convex polygon without
    /// interior nodes of at most [`MAX_POLYGON_NODES`] nodes.
    fn boundary_loop(
        &self,
        position: &[Vector2<f64>],
        triangles: &[[u32; 3]],
        group: &[u32],
        nodes: &mut [u32; MAX_POLYGON_NODES],
    ) -> Option<usize> {
        if let &[first, second] = group {
            return self.quad_loop(position, triangles, [first, second], nodes);
        }
        let group_root = self.parent[group[0] as usize];
        // Directed boundary edges: those whose neighbour is missing or in another group.
        let mut edges = [(0u32, 0u32); 3 * MAX_GROUP_TRIANGLES];
        let mut edge_count = 0;
        for &t in group {
            let tri = &triangles[t as usize];
            for e in 0..3 {
                let u = self.neighbour[t as usize][e];
                if u == NONE || self.parent[u as usize] != group_root {
                    edges[edge_count] = (tri[e], tri[(e + 1) % 3]);
                    edge_count += 1;
                }
            }
        }
        // A disk of n boundary nodes and no interior node has n − 2 triangles and n boundary
        // edges.
        let n = group.len() + 2;
        if edge_count != n || n > MAX_POLYGON_NODES {
            return None;
        }
        let edges = &edges[..n];
        let start = edges.iter().map(|e| e.0).min()?;
        let mut current = start;
        for k in 0..n {
            let mut outgoing = edges.iter().filter(|e| e.0 == current);
            let edge = outgoing.next()?;
            if outgoing.next().is_some() || nodes[..k].contains(&current) {
                // Two boundary edges leave one node (the group touches itself there).
                return None;
            }
            nodes[k] = current;
            current = edge.1;
        }
        if current != start {
            return None;
        }
        let area_m2: f64 = group
            .iter()
            .map(|&t| self.circles[t as usize].area_m2)
            .sum();
        convex_with_area(position, &nodes[..n], area_m2).then_some(n)
    }

    /// [`Merger::boundary_loop`] of a group of two triangles (most groups: the quads of a
    /// lattice), read off their shared edge instead of traced: with t₁ = (a, b, c) sharing
    /// a → b with t₂ = (b, a, q), the loop is b, c, a, q (the same canonical loop the tracing
    /// gives).
    fn quad_loop(
        &self,
        position: &[Vector2<f64>],
        triangles: &[[u32; 3]],
        [first, second]: [u32; 2],
        nodes: &mut [u32; MAX_POLYGON_NODES],
    ) -> Option<usize> {
        let e = (0..3).find(|&e| self.neighbour[first as usize][e] == second)?;
        let t = triangles[first as usize];
        let (a, b, c) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
        let q = *triangles[second as usize]
            .iter()
            .find(|&&v| v != a && v != b)?;
        if q == c {
            return None;
        }
        let quad = [b, c, a, q];
        let start = (0..4).min_by_key(|&k| quad[k])?;
        for (k, node) in nodes.iter_mut().take(4).enumerate() {
            *node = quad[(start + k) % 4];
        }
        let area_m2 = self.circles[first as usize].area_m2 + self.circles[second as usize].area_m2;
        convex_with_area(position, &nodes[..4], area_m2).then_some(4)
    }
}

/// Circumcircle and area of one triangle; a degenerate triangle has a NaN radius.
#[derive(Debug, Clone, Copy)]
struct Circle {
    centre: Vector2<f64>,
    radius_m: f64,
    area_m2: f64,
}

impl Circle {
    fn valid(&self) -> bool {
        self.radius_m.is_finite()
    }
}

/// Circumcentre from the first node: with b, c the other nodes relative to it and
/// D = 2 (b × c), the centre is a + (c_y|b|² − b_y|c|², b_x|c|² − c_x|b|²)/D.
fn circumcircle(position: &[Vector2<f64>], t: &[u32; 3]) -> Circle {
    let bad = Circle {
        centre: Vector2::zeros(),
        radius_m: f64::NAN,
        area_m2: 0.0,
    };
    let [i, j, k] = *t;
    if i == j || j == k || k == i {
        return bad;
    }
    let (Some(&a), Some(&b), Some(&c)) = (
        position.get(i as usize),
        position.get(j as usize),
        position.get(k as usize),
    ) else {
        return bad;
    };
    let (b, c) = (b - a, c - a);
    let twice_area = b.x * c.y - b.y * c.x;
    if !(twice_area.is_finite() && twice_area > 0.0) {
        return bad;
    }
    let (b2, c2) = (b.norm_squared(), c.norm_squared());
    let offset = Vector2::new(c.y * b2 - b.y * c2, b.x * c2 - c.x * b2) / (2.0 * twice_area);
    let radius_m = offset.norm();
    if !radius_m.is_finite() || !a.x.is_finite() || !a.y.is_finite() {
        return bad;
    }
    Circle {
        centre: a + offset,
        radius_m,
        area_m2: 0.5 * twice_area,
    }
}

fn find(parent: &mut [u32], mut t: u32) -> u32 {
    while parent[t as usize] != t {
        let grand = parent[parent[t as usize] as usize];
        parent[t as usize] = grand;
        t = grand;
    }
    t
}

fn union(parent: &mut [u32], size: &mut [u32], a: u32, b: u32) {
    let (mut a, mut b) = (find(parent, a), find(parent, b));
    if a == b {
        return;
    }
    if size[a as usize] < size[b as usize] {
        std::mem::swap(&mut a, &mut b);
    }
    parent[b as usize] = a;
    size[a as usize] += size[b as usize];
}

/// Whether the loop turns left or straight (within round-off) at every node and encloses the
/// area of its triangles.
fn convex_with_area(position: &[Vector2<f64>], nodes: &[u32], area_m2: f64) -> bool {
    let n = nodes.len();
    let mut corner = [Vector2::zeros(); MAX_POLYGON_NODES];
    let Some(corner) = corner.get_mut(..n) else {
        return false;
    };
    for (c, &i) in corner.iter_mut().zip(nodes) {
        *c = position[i as usize];
    }
    // The next node around the loop, without a division.
    let after = |k: usize| if k + 1 == n { 0 } else { k + 1 };
    let longest2 = (0..n)
        .map(|k| (corner[after(k)] - corner[k]).norm_squared())
        .fold(0.0, f64::max);
    let origin = corner[0];
    let mut twice_area = 0.0;
    for k in 0..n {
        let (a, b, c) = (corner[k], corner[after(k)], corner[after(after(k))]);
        // Written so that a NaN turn is refused too.
        let left_or_straight = (b - a).perp(&(c - b)) >= -CONVEX_TOLERANCE * longest2;
        if !left_or_straight {
            return false;
        }
        twice_area += (a - origin).perp(&(b - origin));
    }
    (0.5 * twice_area - area_m2).abs() <= AREA_TOLERANCE * area_m2
}

#[cfg(test)]
mod tests;
