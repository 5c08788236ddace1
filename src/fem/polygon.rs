//! MFEM shape functions on a convex polygon of the Extended Delaunay Tessellation (thesis
//! §2.4, "meshless finite element method"), and the integration of a polygon element.
//!
//! Shape functions: the Laplace (non-Sibsonian) coordinates
//!
//! N_i(x) = (s_i/h_i) / Σ_j (s_j/h_j),
//!
//! where s_i is the length of the face shared by x and node x_i in the Voronoi diagram of the
//! polygon's nodes plus x, and h_i = |x − x_i|. The face between x and x_i lies on their
//! bisector, whose normal is (x_i − x)/h_i, so s_i (x_i − x)/h_i is the face's outward normal
//! times its length; these vectors close around the cell (Σ_i s_i (x_i − x)/h_i = 0), which is
//! exactly Σ_i N_i x_i = x. With Σ_i N_i = 1 by construction, the coordinates reproduce every
//! linear field. On an edge of a convex polygon only the edge's two nodes keep a face of
//! growing length as x approaches it, so N_i is the linear 2-node interpolant there, which
//! makes the polygon conforming with its neighbours; on a triangle the coordinates are the
//! barycentric ones (P1).
//!
//! The Voronoi cell of x is found by clipping a square around x with the half-planes
//! (y − x)·(x_i − x) ≤ |x_i − x|²/2 (Sutherland–Hodgman), each new edge tagged with the node
//! whose bisector made it. For x at distance ρ from the boundary and R = max_i |x_i − x|, the
//! point x + ρu (any unit u) lies in the polygon, so some node has u·(x_i − x) ≥ ρ, and the
//! cell ends within R²/(2ρ) of x in every direction: a square of half-size 2(R + R²/(2ρ)) holds
//! it with room to spare. The tags, in order around the cell, are x's natural neighbours;
//! s_i/h_i is then taken from the triangles they make with x (½(cot α + cot β), see
//! `star_weights`), which equals the tagged length over h_i but keeps full precision near the
//! polygon's edges, where the cell is long and thin. The tagged lengths are the fallback.
//!
//! Integration (cell-based smoothed FEM, as in the n-sided polygonal smoothed FEM): the
//! polygon is cut into the fan of sub-triangles (c, x_k, x_{k+1}), c the mean of the nodes. In
//! each cell the gradient is the smoothed one, ∇̃N_i = (1/A_cell) ∮ N_i n ds. On the polygon's
//! edge x_k → x_{k+1}, N_i is linear, so the endpoint values integrate it exactly; on the spokes
//! c → x_k the midpoint rule is used, at the same point for the two cells that share a spoke,
//! so the spokes cancel when the cells are summed. The rule is exact for linear functions,
//! which is all the consistency below needs; one evaluation per spoke instead of two Gauss
//! points took the teaching beach's `elements` stage from 5.2 to 3.0 ms at δ = 0.03 (about
//! 4 000 polygons), and the spoke midpoints also serve the weights. Because the coordinates reproduce
//! constants and linear fields at every point, Σ_i ∇̃N_i = 0 and Σ_i x_i ⊗ ∇̃N_i = I in every
//! cell to round-off, and a mesh of polygons and triangles passes the patch test: the edges
//! shared between elements carry the same linear traces on both sides.

use crate::fem::p1;
use nalgebra::Vector2;

/// Tag of a cell edge that is still a side of the bounding square.
const SQUARE: u32 = u32::MAX;

/// Polygons up to this many nodes are clipped in stack buffers.
const STACK_NODES: usize = 12;

/// Vertices a clipping buffer holds beyond the node count: the square's four, one per clip
/// (a convex cell gains at most one vertex per half-plane), and some to spare.
const EXTRA_VERTICES: usize = 8;

/// A point counts as on the boundary when its distance to it is below this fraction of its
/// distance to the farthest node (then the coordinates are the edge's linear interpolant).
const BOUNDARY_TOLERANCE: f64 = 1e-13;

/// A vertex of the clipped Voronoi cell, relative to x, and the tag of the edge that starts at
/// it (the node whose bisector carries the edge, or SQUARE).
#[derive(Debug, Clone, Copy)]
struct CellVertex {
    y: Vector2<f64>,
    tag: u32,
}

const NO_VERTEX: CellVertex = CellVertex {
    y: Vector2::new(0.0, 0.0),
    tag: SQUARE,
};

/// Laplace coordinates of `x` (strictly inside the convex polygon `nodes`, counter-clockwise)
/// into `out` (len = nodes.len()).
///
/// On the boundary (within a relative 1e-13) the result is the linear interpolant along the
/// nearest edge, the limit of the coordinates there; outside the polygon, where they are not
/// defined, the same interpolant clamped to that edge is returned, so bad geometry never
/// panics. With fewer than three nodes the same rule applies to the segment or the point.
pub fn laplace_coordinates(nodes: &[Vector2<f64>], x: Vector2<f64>, out: &mut [f64]) {
    debug_assert_eq!(nodes.len(), out.len());
    let n = nodes.len().min(out.len());
    let (nodes, out) = (&nodes[..n], &mut out[..n]);
    out.fill(0.0);
    if n == 0 {
        return;
    }
    if n <= STACK_NODES {
        let mut a = [NO_VERTEX; STACK_NODES + EXTRA_VERTICES];
        let mut b = [NO_VERTEX; STACK_NODES + EXTRA_VERTICES];
        laplace_with(nodes, x, out, &mut a, &mut b);
    } else {
        let mut a = vec![NO_VERTEX; n + EXTRA_VERTICES];
        let mut b = vec![NO_VERTEX; n + EXTRA_VERTICES];
        laplace_with(nodes, x, out, &mut a, &mut b);
    }
}

/// [`laplace_coordinates`] with two clipping buffers of n + EXTRA_VERTICES vertices.
fn laplace_with<'a>(
    nodes: &[Vector2<f64>],
    x: Vector2<f64>,
    out: &mut [f64],
    mut cell: &'a mut [CellVertex],
    mut spare: &'a mut [CellVertex],
) {
    let n = nodes.len();
    let reach2 = nodes
        .iter()
        .map(|p| (p - x).norm_squared())
        .fold(0.0, f64::max);
    let reach = reach2.sqrt();
    let (inside, _) = boundary_distance(nodes, x);
    // False on the boundary, outside, and for NaN input.
    let strictly_inside = inside > BOUNDARY_TOLERANCE * reach;
    if n < 3 || !strictly_inside {
        edge_interpolant(nodes, x, out);
        return;
    }
    // The common case first: every node a natural neighbour of x (always so in a cyclic
    // polygon), read off the star of x without clipping.
    if let Some(total) = full_star_weights(nodes, x, out)
        && total > 0.0
        && total.is_finite()
    {
        for w in out.iter_mut() {
            *w /= total;
        }
        return;
    }
    out.fill(0.0);
    let half = 2.0 * (reach + reach2 / (2.0 * inside));
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    for (v, (sx, sy)) in cell.iter_mut().zip(corners) {
        *v = CellVertex {
            y: Vector2::new(sx * half, sy * half),
            tag: SQUARE,
        };
    }
    let mut len = 4;
    for (i, p) in nodes.iter().enumerate() {
        let Some(clipped) = clip(&cell[..len], p - x, i as u32, spare) else {
            edge_interpolant(nodes, x, out);
            return;
        };
        len = clipped;
        std::mem::swap(&mut cell, &mut spare);
    }
    // s_i/h_i from the natural neighbours' triangles, or from the edge lengths if those do
    // not close around x (which only round-off on a degenerate polygon could cause).
    let total = star_weights(nodes, x, &cell[..len], out)
        .unwrap_or_else(|| length_weights(nodes, x, &cell[..len], out));
    if total > 0.0 && total.is_finite() {
        for w in out.iter_mut() {
            *w /= total;
        }
    } else {
        edge_interpolant(nodes, x, out);
    }
}

/// Adds s_i/h_i of every natural neighbour of x into `out` and returns their sum, from the
/// triangles (x, x_a, x_b) of consecutive natural neighbours a, b (the cell's edge tags in
/// order), or None if the tags do not make such a closed star (a square side left, or a
/// triangle of zero or negative area).
///
/// The face between x and x_i joins the circumcentres of the star triangles on either side of
/// the segment x–x_i, so s_i/h_i = ½(cot α + cot β), α and β the angles opposite to x–x_i in
/// those two triangles. In the triangle (x, x_a, x_b), with d = x_· − x and 2A = d_a × d_b, the
/// angle at x_b has cot = (|d_b|² − d_a·d_b)/(2A) and the one at x_a has
/// cot = (|d_a|² − d_a·d_b)/(2A). The lengths of the clipped edges give the same numbers, but
/// this form shares each small area between the two weights it divides, so near an edge of
/// the polygon their ratio keeps full precision; and the weights of any closed star reproduce
/// linear fields exactly (Σ_i w_i d_i = 0 term by term).
fn star_weights(
    nodes: &[Vector2<f64>],
    x: Vector2<f64>,
    cell: &[CellVertex],
    out: &mut [f64],
) -> Option<f64> {
    let len = cell.len();
    if cell.iter().any(|v| v.tag == SQUARE) {
        return None;
    }
    // Start at an edge whose tag differs from the previous edge's, then skip repeated tags
    // (a zero-length edge split by a vertex exactly on a bisector).
    let start = (0..len).find(|&k| cell[k].tag != cell[(k + len - 1) % len].tag)?;
    let mut previous = cell[start].tag;
    let mut total = 0.0;
    for step in 1..=len {
        let tag = cell[(start + step) % len].tag;
        if tag == previous {
            continue;
        }
        let (to_a, to_b) = star_triangle(nodes[previous as usize] - x, nodes[tag as usize] - x)?;
        out[previous as usize] += to_a;
        out[tag as usize] += to_b;
        total += to_a + to_b;
        previous = tag;
    }
    Some(total)
}

/// The contributions of the star triangle (x, x_a, x_b), given d_a = x_a − x and d_b = x_b − x,
/// to s_a/h_a and s_b/h_b: half the cotangents of its angles at x_b and at x_a (see
/// [`star_weights`]); None unless its area is positive.
fn star_triangle(a: Vector2<f64>, b: Vector2<f64>) -> Option<(f64, f64)> {
    let twice_area = a.perp(&b);
    if !(twice_area.is_finite() && twice_area > 0.0) {
        return None;
    }
    let (dot, half_over) = (a.dot(&b), 0.5 / twice_area);
    Some((
        (b.norm_squared() - dot) * half_over,
        (a.norm_squared() - dot) * half_over,
    ))
}

/// s_i/h_i of the star of x with every node, ½(cot α + cot β) per node as in
/// [`star_weights`], into `out`, and their sum; None if a weight is negative or a star triangle
/// is not positive. A weight is negative exactly when the star's edge x–x_i is not locally
/// Delaunay (α + β > π); when none is, the star (whose outer edges are the polygon's, on the
/// hull) is the Delaunay triangulation of the nodes and x, every node is a natural neighbour of
/// x, and these are the Laplace weights the clipped cell would give.
#[inline(always)]
fn full_star_weights(nodes: &[Vector2<f64>], x: Vector2<f64>, out: &mut [f64]) -> Option<f64> {
    let n = nodes.len();
    let mut total = 0.0;
    for k in 0..n {
        let next = (k + 1) % n;
        let (to_a, to_b) = star_triangle(nodes[k] - x, nodes[next] - x)?;
        out[k] += to_a;
        out[next] += to_b;
        total += to_a + to_b;
    }
    out.iter().all(|&w| w >= 0.0).then_some(total)
}

/// Writes s_i/h_i into `out` from the lengths of the cell's edges tagged i, and returns their
/// sum.
fn length_weights(
    nodes: &[Vector2<f64>],
    x: Vector2<f64>,
    cell: &[CellVertex],
    out: &mut [f64],
) -> f64 {
    out.fill(0.0);
    for (k, v) in cell.iter().enumerate() {
        if v.tag != SQUARE {
            out[v.tag as usize] += (cell[(k + 1) % cell.len()].y - v.y).norm();
        }
    }
    let mut total = 0.0;
    for (w, p) in out.iter_mut().zip(nodes) {
        *w /= (p - x).norm();
        total += *w;
    }
    total
}

/// Sutherland–Hodgman: clips the convex `cell` (vertices relative to x) with the half-plane
/// y·d ≤ |d|²/2 (the side of the bisector of x and x + d that holds x) into `out`, tagging the
/// new edge along the bisector with `node`. Returns the number of vertices written, or None if
/// `out` is too short (which round-off could only cause for a cell already degenerate).
fn clip(cell: &[CellVertex], d: Vector2<f64>, node: u32, out: &mut [CellVertex]) -> Option<usize> {
    let offset = 0.5 * d.norm_squared();
    let side = |y: Vector2<f64>| y.dot(&d) - offset;
    let mut len = 0;
    let count = cell.len();
    for k in 0..count {
        let (p, q) = (cell[k], cell[(k + 1) % count]);
        let (fp, fq) = (side(p.y), side(q.y));
        let crossing = || p.y + (q.y - p.y) * (fp / (fp - fq));
        match (fp <= 0.0, fq <= 0.0) {
            (true, true) => {
                *out.get_mut(len)? = p;
                len += 1;
            }
            (true, false) => {
                // Leaving: the cell goes on along the bisector from the crossing.
                *out.get_mut(len)? = p;
                *out.get_mut(len + 1)? = CellVertex {
                    y: crossing(),
                    tag: node,
                };
                len += 2;
            }
            (false, true) => {
                // Entering: from the crossing the cell follows the old edge to q.
                *out.get_mut(len)? = CellVertex {
                    y: crossing(),
                    tag: p.tag,
                };
                len += 1;
            }
            (false, false) => {}
        }
    }
    Some(len)
}

/// The smallest signed distance from x to the lines of the polygon's edges (positive inside a
/// counter-clockwise polygon) and the edge that gives it (edges of zero length are skipped).
fn boundary_distance(nodes: &[Vector2<f64>], x: Vector2<f64>) -> (f64, usize) {
    let n = nodes.len();
    let mut best = (f64::INFINITY, 0);
    for k in 0..n {
        let (a, b) = (nodes[k], nodes[(k + 1) % n]);
        let edge_length = (b - a).norm();
        if edge_length > 0.0 {
            let distance = (b - a).perp(&(x - a)) / edge_length;
            if distance < best.0 {
                best = (distance, k);
            }
        }
    }
    best
}

/// The linear interpolant along the edge nearest x, with x projected onto the edge.
fn edge_interpolant(nodes: &[Vector2<f64>], x: Vector2<f64>, out: &mut [f64]) {
    out.fill(0.0);
    let n = nodes.len();
    let (_, k) = boundary_distance(nodes, x);
    let next = (k + 1) % n;
    let edge = nodes[next] - nodes[k];
    let length2 = edge.norm_squared();
    if !(length2.is_finite() && length2 > 0.0) {
        out[k] = 1.0;
        return;
    }
    let t = ((x - nodes[k]).dot(&edge) / length2).clamp(0.0, 1.0);
    out[k] += 1.0 - t;
    out[next] += t;
}

/// A polygon element: integration cells and what the kernels need.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PolygonElement {
    /// Area of each integration cell, m² (they sum to the polygon's area).
    pub cell_area: Vec<f64>,
    /// Smoothed gradients: cell c, node i at `cell_grad[c * n + i]`, 1/m.
    pub cell_grad: Vec<Vector2<f64>>,
    /// ∫ N_i dA over each cell, m²: cell c, node i at `cell_weight[c * n + i]` (for terms such
    /// as ∫ N_i ∇·u dA, where the smoothed gradient is constant in the cell).
    pub cell_weight: Vec<f64>,
    /// ∫ N_i dA over the polygon, m² (lumped mass / ρ); sums to the area.
    pub node_weight: Vec<f64>,
}

impl PolygonElement {
    /// Number of integration cells.
    pub fn cell_count(&self) -> usize {
        self.cell_area.len()
    }
}

/// The element of the convex polygon `nodes` (counter-clockwise, n ≥ 3).
///
/// n = 3 gives exactly the P1 element of [`crate::fem::p1`]: one cell with its area and
/// gradients, weights A/3. For n ≥ 4 the cells are the fan (c, x_k, x_{k+1}), k = 0..n − 1,
/// around the mean c of the nodes (see the module documentation). Per cell, ∫ N_i dA uses the
/// edge-midpoint rule (exact for quadratics): A_cell/3 · (N_i at the midpoints of the polygon
/// edge and of the two spokes). Fewer than three nodes give an element without cells; a
/// polygon of zero area gives non-finite gradients, as [`crate::fem::p1`] does.
pub fn polygon_element(nodes: &[Vector2<f64>]) -> PolygonElement {
    let mut element = PolygonElement {
        cell_area: Vec::new(),
        cell_grad: Vec::new(),
        cell_weight: Vec::new(),
        node_weight: Vec::new(),
    };
    polygon_element_into(nodes, &mut element);
    element
}

/// [`polygon_element`] into an element whose vectors are reused (the solver builds thousands
/// per step). Polygons of up to [`crate::mesh::edt::MAX_POLYGON_NODES`] nodes allocate nothing
/// else.
pub fn polygon_element_into(nodes: &[Vector2<f64>], element: &mut PolygonElement) {
    let n = nodes.len();
    element.cell_area.clear();
    element.cell_grad.clear();
    element.cell_weight.clear();
    element.node_weight.clear();
    if n < 3 {
        element.node_weight.resize(n, 0.0);
        return;
    }
    if n == 3 {
        let e = p1(nodes[0], nodes[1], nodes[2]);
        let third = e.area / 3.0;
        element.cell_area.push(e.area);
        element.cell_grad.extend_from_slice(&e.grad);
        element.cell_weight.extend_from_slice(&[third; 3]);
        element.node_weight.extend_from_slice(&[third; 3]);
        return;
    }
    element.cell_area.resize(n, 0.0);
    element.cell_grad.resize(n * n, Vector2::zeros());
    element.cell_weight.resize(n * n, 0.0);
    element.node_weight.resize(n, 0.0);
    fan_cells_into(
        nodes,
        FanCells {
            area: &mut element.cell_area,
            grad: &mut element.cell_grad,
            weight: &mut element.cell_weight,
            node_weight: &mut element.node_weight,
        },
    );
}

/// Where [`fan_cells_into`] writes the cells of a polygon of n ≥ 4 nodes: n cells (the fan
/// around the mean of the nodes), cell k's values for node i at `k * n + i`.
pub struct FanCells<'a> {
    /// Signed area of each cell, m² (length n).
    pub area: &'a mut [f64],
    /// Smoothed gradient of each shape function on each cell, 1/m (length n²).
    pub grad: &'a mut [Vector2<f64>],
    /// ∫ N_i dA over each cell, m² (length n²).
    pub weight: &'a mut [f64],
    /// ∫ N_i dA over the polygon, m² (length n; overwritten).
    pub node_weight: &'a mut [f64],
}

/// The cells of [`polygon_element`] for a polygon of n ≥ 4 nodes, written into the caller's
/// slices (the solver's element set writes them in place, without an intermediate element).
pub fn fan_cells_into(nodes: &[Vector2<f64>], out: FanCells) {
    let n = nodes.len();
    if n > STACK_ELEMENT_NODES {
        let mut spoke_mid = vec![0.0; n * n];
        let mut local = vec![Vector2::zeros(); n];
        fan_cells(nodes, &mut local, &mut spoke_mid, out);
    } else {
        let mut spoke_mid = [0.0; STACK_ELEMENT_NODES * STACK_ELEMENT_NODES];
        let mut local = [Vector2::zeros(); STACK_ELEMENT_NODES];
        fan_cells(nodes, &mut local[..n], &mut spoke_mid[..n * n], out);
    }
}

/// Polygons up to this many nodes build their element in stack buffers.
const STACK_ELEMENT_NODES: usize = 8;

/// The fan cells of a polygon of n ≥ 4 nodes, with scratch buffers of n and n² values.
///
/// The body is inlined once per polygon size the EDT builds (4 to
/// [`crate::mesh::edt::MAX_POLYGON_NODES`]), so that its loops have constant trip counts and
/// are unrolled (see `solver::element_set::with_size`).
fn fan_cells(
    nodes: &[Vector2<f64>],
    local: &mut [Vector2<f64>],
    spoke_mid: &mut [f64],
    out: FanCells,
) {
    match nodes.len() {
        4 => fan_cells_of(4, nodes, local, spoke_mid, out),
        5 => fan_cells_of(5, nodes, local, spoke_mid, out),
        6 => fan_cells_of(6, nodes, local, spoke_mid, out),
        7 => fan_cells_of(7, nodes, local, spoke_mid, out),
        8 => fan_cells_of(8, nodes, local, spoke_mid, out),
        n => fan_cells_of(n, nodes, local, spoke_mid, out),
    }
}

/// [`fan_cells`] for n nodes (a constant at each call site above).
#[inline(always)]
fn fan_cells_of(
    n: usize,
    nodes: &[Vector2<f64>],
    local: &mut [Vector2<f64>],
    spoke_mid: &mut [f64],
    out: FanCells,
) {
    let (nodes, local, spoke_mid) = (&nodes[..n], &mut local[..n], &mut spoke_mid[..n * n]);
    let (cell_area, cell_grad, cell_weight, node_weight) = (
        &mut out.area[..n],
        &mut out.grad[..n * n],
        &mut out.weight[..n * n],
        &mut out.node_weight[..n],
    );
    node_weight.fill(0.0);
    // Everything is computed relative to the centre, so that the element's precision does
    // not depend on where it sits in the flume.
    let centre = nodes.iter().sum::<Vector2<f64>>() / n as f64;
    for (l, p) in local.iter_mut().zip(nodes) {
        *l = p - centre;
    }
    // Per spoke j (centre → x_j): N_i at its midpoint, node i at [j * n + i], both the spoke's
    // mean (midpoint rule) and its midpoint value. The points are strictly inside the
    // (convex) polygon.
    for (j, &spoke) in local.iter().enumerate() {
        interior_coordinates(local, spoke * 0.5, &mut spoke_mid[j * n..(j + 1) * n]);
    }
    // Outward normal times length of an edge traversed counter-clockwise: (e_y, −e_x).
    let outward = |e: Vector2<f64>| Vector2::new(e.y, -e.x);
    for k in 0..n {
        let next = (k + 1) % n;
        let (a, b) = (local[k], local[next]);
        let area = 0.5 * a.perp(&b);
        cell_area[k] = area;
        // The cell's boundary: spoke k outwards, the polygon edge, spoke k + 1 inwards.
        let (out_k, out_edge, out_next) = (outward(a), outward(b - a), outward(-b));
        let grads = &mut cell_grad[k * n..(k + 1) * n];
        let weights = &mut cell_weight[k * n..(k + 1) * n];
        for i in 0..n {
            // N_i on the polygon edge: its mean there, and its value at the edge's midpoint.
            let on_edge = if i == k || i == next { 0.5 } else { 0.0 };
            let flux = out_k * spoke_mid[k * n + i]
                + out_edge * on_edge
                + out_next * spoke_mid[next * n + i];
            grads[i] = flux / area;
            let weight = area / 3.0 * (on_edge + spoke_mid[k * n + i] + spoke_mid[next * n + i]);
            weights[i] = weight;
            node_weight[i] += weight;
        }
    }
}

/// Laplace coordinates at a point known to be strictly inside the polygon: the full star when
/// every node is a natural neighbour (no clipping), [`laplace_coordinates`] otherwise.
#[inline(always)]
fn interior_coordinates(nodes: &[Vector2<f64>], x: Vector2<f64>, out: &mut [f64]) {
    out.fill(0.0);
    match full_star_weights(nodes, x, out) {
        Some(total) if total > 0.0 && total.is_finite() => {
            let scale = 1.0 / total;
            for w in out.iter_mut() {
                *w *= scale;
            }
        }
        _ => laplace_coordinates(nodes, x, out),
    }
}

#[cfg(test)]
mod tests;
