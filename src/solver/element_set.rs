//! The finite elements of a step and their integration cells.
//!
//! An element is a kept triangle of the mesh (P1) or, with `solver.delta` > 0, an EDT polygon
//! (`mesh::edt`) with the MFEM shape functions of `fem::polygon`. The kernels of the step
//! (`elements.rs`, `predict.rs`, `pressure.rs`, `correct.rs`) loop over the elements and,
//! within each, over its integration cells (a polygon's pressure terms use the operators
//! summed over its cells, see `op_start`): a triangle is one cell with its constant P1
//! gradients; a polygon of n nodes is the fan of n cells to its centre, each with the smoothed
//! gradients of all n shape functions. In a cell, ∫_cell f ∇N_i = A_cell f̄ b_i, with f̄ the
//! cell mean of the interpolated field (P1: the mean of the three nodes) and b_i the cell's
//! gradient; ∫_cell N_i f = A_cell w_i f for a field constant on the cell, w_i the cell's mean
//! shape function (1/3 on a triangle).
//!
//! Pressure force and divergence on a polygon. On a triangle the force ∫ p ∇N_i = A p̄ b_i and
//! the divergence ∫ N_i ∇·u are exact for the P1 fields, so a hydrostatic pressure balances
//! the lumped weight exactly. On a polygon the smoothed gradients are exact for linear fields
//! but A_c p̄_c b_i,c is not ∫_c p ∇N_i, and the tank of `sloshing.toml` (a deformed lattice,
//! whose quads are nearly but not exactly cyclic) reached 6 times its physical speed within
//! 0.01 s with that form. So a polygon takes the force integrated by parts,
//! ∫ p ∇N_i = ∮ N_i p n − ∫ N_i ∇p: the boundary term exact for the linear traces on its
//! edges ([`polygon_boundary`]), the second Σ_c A_c w_i,c ∇p_c, which for a linear p is
//! exactly ∇p times the lumped weight; and the divergence is its transpose,
//! ∫ N_i ∇·u = ∮ N_i u·n − Σ_c A_c b_i,c·ū_c, so that the projection stays symmetric.
//!
//! The topology (nodes of each element, the node → element index, the place of each element in
//! the pressure pattern) is set right after the α-shape; the geometry (areas, gradients,
//! weights) by the `elements` stage, on the positions it is given (the second pass of
//! `geometry_theta` moves them). With δ = 0 the elements are the kept triangles in their order
//! and every P1 formula is evaluated exactly as before polygons existed, so results are
//! bit-for-bit those of plain Delaunay meshes.

use crate::fem;
use crate::mesh::Mesh;
use nalgebra::{Matrix2, Vector2};

const NONE: u32 = u32::MAX;

#[derive(Debug, Default, Clone)]
pub(super) struct ElementSet {
    /// Element e's nodes, counter-clockwise: `node[node_start[e]..node_start[e + 1]]`.
    node_start: Vec<u32>,
    node: Vec<u32>,
    /// Element e's cells: `cell_start[e]..cell_start[e + 1]`.
    cell_start: Vec<u32>,
    /// Per cell: its area (m², positive) and where its n gradients and weights start.
    area: Vec<f64>,
    value_start: Vec<u32>,
    /// Per cell and node of its element: ∇N_i on the cell (1/m) and the cell mean of N_i.
    grad: Vec<Vector2<f64>>,
    weight: Vec<f64>,
    /// Per kept triangle of the mesh: the element it belongs to.
    element_of_triangle: Vec<u32>,
    /// Per element: where a polygon's operators start in `lap` and `gop` (n² each) and in
    /// `node_w` (n), NONE for a triangle. L_ab = Σ_c A_c b_a,c·b_b,c (dimensionless),
    /// G_ab = Σ_c A_c w_a,c b_b,c (∫ N_a ∇N_b, m), W_a = Σ_c A_c w_a,c (∫ N_a, m²): the
    /// pressure terms of a polygon are sums of these, built once per geometry instead of per
    /// cell in every kernel.
    op_start: Vec<u32>,
    w_start: Vec<u32>,
    lap: Vec<f64>,
    gop: Vec<Vector2<f64>>,
    node_w: Vec<f64>,
    /// The elements around each node: `around[around_start[i]..around_start[i + 1]]`.
    around_start: Vec<u32>,
    around: Vec<u32>,
}

/// One integration cell, with the nodes of its element.
#[derive(Clone, Copy)]
pub(super) struct Cell<'a> {
    pub nodes: &'a [u32],
    pub area: f64,
    pub grad: &'a [Vector2<f64>],
    weight: &'a [f64],
}

impl<'a> Cell<'a> {
    /// The same cell with its slices cut to `n` nodes (its element's count; see
    /// [`with_size`]).
    #[inline(always)]
    pub fn sized(&self, n: usize) -> Cell<'a> {
        Cell {
            nodes: &self.nodes[..n],
            area: self.area,
            grad: &self.grad[..n],
            weight: &self.weight[..n],
        }
    }

    /// The node indices as `usize`.
    #[inline]
    pub fn node(&self, a: usize) -> usize {
        self.nodes[a] as usize
    }

    /// The cell mean of the interpolant of the nodal values `f`.
    #[inline]
    pub fn mean(&self, f: impl Fn(usize) -> f64) -> f64 {
        if self.nodes.len() == 3 {
            (f(self.node(0)) + f(self.node(1)) + f(self.node(2))) / 3.0
        } else {
            (0..self.nodes.len())
                .map(|a| self.weight[a] * f(self.node(a)))
                .sum()
        }
    }

    /// The cell mean of a vector field.
    #[inline]
    pub fn mean_vector(&self, f: impl Fn(usize) -> Vector2<f64>) -> Vector2<f64> {
        if self.nodes.len() == 3 {
            (f(self.node(0)) + f(self.node(1)) + f(self.node(2))) / 3.0
        } else {
            (0..self.nodes.len())
                .map(|a| f(self.node(a)) * self.weight[a])
                .sum()
        }
    }

    /// ∇f on the cell.
    #[inline]
    pub fn gradient(&self, f: impl Fn(usize) -> f64) -> Vector2<f64> {
        (0..self.nodes.len())
            .map(|a| self.grad[a] * f(self.node(a)))
            .sum()
    }

    /// ∇u on the cell, G[(a, b)] = ∂u_a/∂x_b.
    #[inline(always)]
    pub fn velocity_gradient(&self, u: impl Fn(usize) -> Vector2<f64>) -> Matrix2<f64> {
        if self.nodes.len() == 3 {
            u(self.node(0)) * self.grad[0].transpose()
                + u(self.node(1)) * self.grad[1].transpose()
                + u(self.node(2)) * self.grad[2].transpose()
        } else {
            let mut g = Matrix2::zeros();
            for a in 0..self.nodes.len() {
                g += u(self.node(a)) * self.grad[a].transpose();
            }
            g
        }
    }

    /// `factor` ∫_cell N_a: factor·A/3 on a triangle.
    #[inline]
    pub fn integral(&self, a: usize, factor: f64) -> f64 {
        if self.nodes.len() == 3 {
            factor * self.area / 3.0
        } else {
            factor * self.area * self.weight[a]
        }
    }
}

/// The edges of a polygon element (nodes counter-clockwise): for each edge from node a to node
/// b (local numbers), its outward normal times its length, ν = (Δy, −Δx). With fields linear
/// along the edge, ∮_edge N_a f n = ν (f_a/3 + f_b/6) and ∮_edge N_b f n = ν (f_a/6 + f_b/3).
pub(super) fn polygon_boundary<'a>(
    nodes: &'a [u32],
    position: &'a [Vector2<f64>],
) -> impl Iterator<Item = (usize, usize, Vector2<f64>)> + 'a {
    let n = nodes.len();
    (0..n).map(move |a| {
        let b = (a + 1) % n;
        let d = position[nodes[b] as usize] - position[nodes[a] as usize];
        (a, b, Vector2::new(d.y, -d.x))
    })
}

/// Calls `f(n)` with `n` a constant in each arm for the polygon sizes the EDT builds (4 to
/// [`crate::mesh::edt::MAX_POLYGON_NODES`]), so that a kernel inlined into it has constant loop
/// bounds and is unrolled (the polygon kernels' generic loops were most of δ's cost).
#[inline(always)]
pub(super) fn with_size<R>(n: usize, f: impl FnOnce(usize) -> R) -> R {
    match n {
        4 => f(4),
        5 => f(5),
        6 => f(6),
        7 => f(7),
        8 => f(8),
        _ => f(n),
    }
}

/// The operators of a polygon element (see `ElementSet::op_start`), local node a at row a.
pub(super) struct PolygonOperators<'a> {
    pub nodes: &'a [u32],
    /// L_ab = Σ_c A_c b_a·b_b.
    pub lap: &'a [f64],
    /// G_ab = ∫ N_a ∇N_b.
    pub gop: &'a [Vector2<f64>],
    /// W_a = ∫ N_a.
    pub node_w: &'a [f64],
}

impl<'a> PolygonOperators<'a> {
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The same operators with every slice cut to `n` nodes (the element's own count), so that
    /// inside [`with_size`] their lengths are constants.
    #[inline(always)]
    pub fn sized(&self, n: usize) -> PolygonOperators<'a> {
        PolygonOperators {
            nodes: &self.nodes[..n],
            lap: &self.lap[..n * n],
            gop: &self.gop[..n * n],
            node_w: &self.node_w[..n],
        }
    }

    /// Calls `f` with these operators cut to their node count inside [`with_size`], so that a
    /// kernel `f` marked `#[inline(always)]` runs with constant loop bounds.
    #[inline(always)]
    pub fn specialised<R>(&self, f: impl FnOnce(&PolygonOperators<'a>) -> R) -> R {
        with_size(
            self.len(),
            #[inline(always)]
            |n| f(&self.sized(n)),
        )
    }

    #[inline(always)]
    pub fn node(&self, a: usize) -> usize {
        self.nodes[a] as usize
    }

    /// Adds `scale` ∫ f ∇N_a = `scale` (∮ N_a f n − ∫ N_a ∇f) to `out` at each node a (the
    /// pressure force of `predict.rs` and the impulse of `correct.rs`; see the module doc).
    #[inline(always)]
    pub fn add_pressure_term(
        &self,
        position: &[Vector2<f64>],
        scale: f64,
        f: impl Fn(usize) -> f64,
        out: &mut [Vector2<f64>],
    ) {
        for a in 0..self.len() {
            out[self.node(a)] -= scale * self.gradient_row(a, &f);
        }
        for (a, b, nu) in polygon_boundary(self.nodes, position) {
            let (ia, ib) = (self.node(a), self.node(b));
            let (fa, fb) = (scale * f(ia), scale * f(ib));
            out[ia] += nu * (fa / 3.0 + fb / 6.0);
            out[ib] += nu * (fa / 6.0 + fb / 3.0);
        }
    }

    // The rows below are plain loops rather than iterator sums: inside `with_size` they then
    // inline and unroll completely (an iterator's `fold` stayed an out-of-line call per row).

    /// Σ_b L_ab f_b.
    #[inline(always)]
    pub fn lap_row(&self, a: usize, f: impl Fn(usize) -> f64) -> f64 {
        let n = self.len();
        let mut sum = 0.0;
        for b in 0..n {
            sum += self.lap[a * n + b] * f(self.node(b));
        }
        sum
    }

    /// Σ_b G_ab f_b = ∫ N_a ∇f.
    #[inline(always)]
    pub fn gradient_row(&self, a: usize, f: impl Fn(usize) -> f64) -> Vector2<f64> {
        let n = self.len();
        let mut sum = Vector2::zeros();
        for b in 0..n {
            sum += self.gop[a * n + b] * f(self.node(b));
        }
        sum
    }

    /// Σ_b G_ba·v_b = ∫ ∇N_a·v (v interpolated).
    #[inline(always)]
    pub fn divergence_row(&self, a: usize, v: impl Fn(usize) -> Vector2<f64>) -> f64 {
        let n = self.len();
        let mut sum = 0.0;
        for b in 0..n {
            sum += self.gop[b * n + a].dot(&v(self.node(b)));
        }
        sum
    }
}

impl ElementSet {
    /// The elements of the kept mesh: its polygons, and its triangles that are in none, in the
    /// order of their (first) triangle.
    pub fn set_topology(&mut self, mesh: &Mesh, n_nodes: usize) {
        self.node_start.clear();
        self.node.clear();
        self.element_of_triangle.clear();
        self.node_start.push(0);
        for (k, t) in mesh.triangles.iter().enumerate() {
            let p = mesh.polygon_of_triangle.get(k).copied().unwrap_or(NONE);
            let e = (self.node_start.len() - 1) as u32;
            if p == NONE {
                self.node.extend_from_slice(t);
            } else {
                let poly = &mesh.polygons[p as usize];
                if poly.triangles[0] as usize != k {
                    // The polygon was made at its first triangle.
                    let first = poly.triangles[0] as usize;
                    let e_first = self.element_of_triangle[first];
                    self.element_of_triangle.push(e_first);
                    continue;
                }
                self.node.extend_from_slice(&poly.nodes);
            }
            self.node_start.push(self.node.len() as u32);
            self.element_of_triangle.push(e);
        }
        // Node → elements.
        let count = self.len();
        self.around_start.clear();
        self.around_start.resize(n_nodes + 1, 0);
        for &v in &self.node {
            self.around_start[v as usize + 1] += 1;
        }
        for i in 0..n_nodes {
            self.around_start[i + 1] += self.around_start[i];
        }
        let mut cursor = self.around_start[..n_nodes].to_vec();
        self.around.clear();
        self.around.resize(self.node.len(), 0);
        for e in 0..count {
            let (from, to) = (self.node_start[e] as usize, self.node_start[e + 1] as usize);
            for &v in &self.node[from..to] {
                self.around[cursor[v as usize] as usize] = e as u32;
                cursor[v as usize] += 1;
            }
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.node_start.len().saturating_sub(1)
    }

    pub fn nodes(&self, e: usize) -> &[u32] {
        &self.node[self.node_start[e] as usize..self.node_start[e + 1] as usize]
    }

    /// The elements that have node `i`.
    pub fn around(&self, i: usize) -> &[u32] {
        match (self.around_start.get(i), self.around_start.get(i + 1)) {
            (Some(&a), Some(&b)) => &self.around[a as usize..b as usize],
            _ => &[],
        }
    }

    /// The element a kept triangle belongs to.
    pub fn element_of_triangle(&self, k: usize) -> usize {
        self.element_of_triangle[k] as usize
    }

    /// The cells of element `e`.
    pub fn cells(&self, e: usize) -> impl Iterator<Item = Cell<'_>> + '_ {
        let nodes = self.nodes(e);
        let n = nodes.len();
        (self.cell_start[e] as usize..self.cell_start[e + 1] as usize).map(move |c| {
            let s = self.value_start[c] as usize;
            Cell {
                nodes,
                area: self.area[c],
                grad: &self.grad[s..s + n],
                weight: &self.weight[s..s + n],
            }
        })
    }

    /// Starts the geometry of a step (after [`ElementSet::set_topology`]).
    pub fn clear_geometry(&mut self) {
        self.cell_start.clear();
        self.cell_start.push(0);
        self.area.clear();
        self.value_start.clear();
        self.value_start.push(0);
        self.grad.clear();
        self.weight.clear();
        self.op_start.clear();
        self.w_start.clear();
        self.lap.clear();
        self.gop.clear();
        self.node_w.clear();
    }

    /// Adds the next element's single P1 cell (its area made positive; see `elements.rs`).
    pub fn push_triangle(&mut self, e: &fem::P1) {
        self.area.push(e.area.abs());
        self.grad.extend_from_slice(&e.grad);
        self.weight.extend_from_slice(&[1.0 / 3.0; 3]);
        self.value_start.push(self.grad.len() as u32);
        self.cell_start.push(self.area.len() as u32);
        self.op_start.push(NONE);
        self.w_start.push(NONE);
    }

    /// Adds the next element, the polygon of the nodes at `x` (counter-clockwise, 4 to
    /// [`crate::mesh::edt::MAX_POLYGON_NODES`] of them): its fan cells (`fem::polygon`), written
    /// in place, and its operators. Writes ∫ N_i over the polygon into `node_weight` (length n)
    /// and returns the sum of the cells' signed areas, m².
    pub fn push_polygon(&mut self, x: &[Vector2<f64>], node_weight: &mut [f64]) -> f64 {
        debug_assert!(x.len() >= 4, "a polygon element has 4 or more nodes");
        with_size(
            x.len(),
            #[inline(always)]
            |n| self.push_polygon_of(n, x, node_weight),
        )
    }

    /// [`ElementSet::push_polygon`] for n nodes: the vectors are grown once and written by
    /// index.
    #[inline(always)]
    fn push_polygon_of(&mut self, n: usize, x: &[Vector2<f64>], node_weight: &mut [f64]) -> f64 {
        let (op, start) = (self.lap.len(), self.node_w.len());
        self.op_start.push(op as u32);
        self.w_start.push(start as u32);
        self.lap.resize(op + n * n, 0.0);
        self.gop.resize(op + n * n, Vector2::zeros());
        self.node_w.resize(start + n, 0.0);
        let (first_cell, first_value) = (self.area.len(), self.grad.len());
        self.area.resize(first_cell + n, 0.0);
        self.grad.resize(first_value + n * n, Vector2::zeros());
        self.weight.resize(first_value + n * n, 0.0);
        self.value_start
            .extend((1..=n).map(|c| (first_value + c * n) as u32));
        let (area, grad, weight) = (
            &mut self.area[first_cell..first_cell + n],
            &mut self.grad[first_value..first_value + n * n],
            &mut self.weight[first_value..first_value + n * n],
        );
        fem::polygon::fan_cells_into(
            &x[..n],
            fem::polygon::FanCells {
                area: &mut *area,
                grad: &mut *grad,
                weight: &mut *weight,
                node_weight: &mut node_weight[..n],
            },
        );
        let signed_total: f64 = area.iter().sum();
        let lap = &mut self.lap[op..op + n * n];
        let gop = &mut self.gop[op..op + n * n];
        let node_w = &mut self.node_w[start..start + n];
        for c in 0..n {
            // As for a triangle: on the moved geometry of `geometry_theta` a thin cell may have
            // turned over; its smoothed gradients (flux over signed area) stay right.
            let signed_area = area[c];
            let cell_area = signed_area.abs();
            area[c] = cell_area;
            let grad = &grad[c * n..(c + 1) * n];
            // The cell means of the shape functions, ∫_cell N_i / A_cell, in place.
            let per_area = 1.0 / signed_area;
            let mean = &mut weight[c * n..(c + 1) * n];
            for m in mean.iter_mut() {
                *m *= per_area;
            }
            // The operators (positive areas, cell means); L is symmetric.
            for a in 0..n {
                let (b_a, w_a) = (grad[a], cell_area * mean[a]);
                node_w[a] += w_a;
                for b in a..n {
                    let l = cell_area * b_a.dot(&grad[b]);
                    lap[a * n + b] += l;
                    if b != a {
                        lap[b * n + a] += l;
                    }
                }
                for b in 0..n {
                    gop[a * n + b] += grad[b] * w_a;
                }
            }
        }
        self.cell_start.push(self.area.len() as u32);
        signed_total
    }

    /// A polygon's operators (L, G, W of `op_start`'s doc), or None for a triangle.
    pub fn polygon_operators(&self, e: usize) -> Option<PolygonOperators<'_>> {
        let (op, start) = (self.op_start[e], self.w_start[e]);
        if op == NONE {
            return None;
        }
        let n = self.nodes(e).len();
        let (op, start) = (op as usize, start as usize);
        Some(PolygonOperators {
            nodes: self.nodes(e),
            lap: &self.lap[op..op + n * n],
            gop: &self.gop[op..op + n * n],
            node_w: &self.node_w[start..start + n],
        })
    }

    /// The elements of a mesh with its geometry (for tests).
    #[cfg(test)]
    pub fn from_mesh(mesh: &Mesh, position: &[Vector2<f64>]) -> ElementSet {
        let mut set = ElementSet::default();
        set.set_topology(mesh, position.len());
        set.clear_geometry();
        for e in 0..set.len() {
            let x: Vec<Vector2<f64>> = set.nodes(e).iter().map(|&i| position[i as usize]).collect();
            if x.len() == 3 {
                set.push_triangle(&fem::p1(x[0], x[1], x[2]));
            } else {
                let mut node_weight = vec![0.0; x.len()];
                set.push_polygon(&x, &mut node_weight);
            }
        }
        set
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::mesh::{ShapeParams, alpha_shape, triangulate};
    use crate::particles::Particles;

    /// A 12 × 8 block of water on a lattice of spacing h whose left half is exact (co-circular
    /// squares, which δ > 0 merges) and whose right half is jittered (triangles), meshed with
    /// the solver's own remesh.
    pub(in crate::solver) fn mixed_mesh(delta: f64) -> (Particles, Mesh) {
        let h = 0.1;
        let mut state = 7u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let fluid: Vec<Vector2<f64>> = (0..13 * 9)
            .map(|k| {
                let (i, j) = ((k % 13) as f64, (k / 13) as f64);
                let jitter = if i > 6.0 && j > 0.0 && j < 8.0 && i < 12.0 {
                    0.25
                } else {
                    0.0
                };
                Vector2::new((i + jitter * next()) * h, (j + jitter * next()) * h)
            })
            .collect();
        let p = Particles::new(&[], &fluid);
        let shape = ShapeParams {
            alpha: 1.3,
            alpha_boundary: 1.3,
            delta,
            spacing: crate::case::Spacing::uniform(h),
        };
        let tri = triangulate(&p, shape.alpha * h, false).unwrap();
        let mut mesh = Mesh::default();
        alpha_shape(&tri, &p, &shape, None, &mut mesh);
        (p, mesh)
    }

    /// The patch test: on a mesh of P1 triangles and MFEM polygons, the assembled
    /// Laplacian Σ_cells A b_i·b_j of a linear pressure field vanishes at every node whose
    /// patch is inside the block, and every cell's gradient of the field is exact.
    #[test]
    fn the_assembled_laplacian_and_gradient_pass_the_patch_test_on_a_mixed_mesh() {
        let (p, mesh) = mixed_mesh(0.01);
        let n = p.len();
        let set = ElementSet::from_mesh(&mesh, &p.position);
        let polygons = (0..set.len()).filter(|&e| set.nodes(e).len() > 3).count();
        let triangles = set.len() - polygons;
        assert!(
            polygons >= 30 && triangles >= 60,
            "{polygons} polygons, {triangles} triangles"
        );
        let field = |x: Vector2<f64>| 3.0 + 2.0 * x.x - 5.0 * x.y;
        let pressure: Vec<f64> = p.position.iter().map(|&x| field(x)).collect();
        let mut lp = vec![0.0; n];
        let mut diag = vec![0.0; n];
        let (mut worst_grad, mut worst_row): (f64, f64) = (0.0, 0.0);
        for e in 0..set.len() {
            for cell in set.cells(e) {
                let g = cell.gradient(|i| pressure[i]);
                worst_grad = worst_grad.max((g - Vector2::new(2.0, -5.0)).norm() / 5.0);
                for a in 0..cell.nodes.len() {
                    lp[cell.node(a)] += cell.area * cell.grad[a].dot(&g);
                    diag[cell.node(a)] += cell.area * cell.grad[a].norm_squared();
                }
            }
        }
        let mut interior = 0;
        for i in 0..n {
            if mesh.in_mesh[i] && !mesh.free_surface[i] {
                interior += 1;
                worst_row = worst_row.max(lp[i].abs() / (diag[i] * 5.0 * 0.1));
            }
        }
        println!(
            "patch test: {polygons} polygons, {triangles} triangles, {interior} interior nodes; \
             worst cell gradient error {worst_grad:.2e} (relative), worst Laplacian row {worst_row:.2e} \
             (relative to diagonal × |∇p| h)"
        );
        assert!(interior > 50);
        assert!(worst_grad < 1e-10, "{worst_grad:e}");
        assert!(worst_row < 1e-10, "{worst_row:e}");
    }

    /// δ = 0 gives the kept triangles as elements, in order, each one P1 cell.
    #[test]
    fn without_delta_the_elements_are_the_triangles() {
        let (p, mesh) = mixed_mesh(0.0);
        assert!(mesh.polygons.is_empty());
        let set = ElementSet::from_mesh(&mesh, &p.position);
        assert_eq!(set.len(), mesh.triangles.len());
        for (k, t) in mesh.triangles.iter().enumerate() {
            assert_eq!(set.nodes(k), t);
            assert_eq!(set.element_of_triangle(k), k);
            let e = fem::p1(
                p.position[t[0] as usize],
                p.position[t[1] as usize],
                p.position[t[2] as usize],
            );
            let cells: Vec<Cell> = set.cells(k).collect();
            assert_eq!(cells.len(), 1);
            assert_eq!(cells[0].area, e.area.abs());
            assert_eq!(cells[0].grad, &e.grad[..]);
        }
    }
}
