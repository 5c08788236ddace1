//! The step's pressure equation on the α-shape's tetrahedra and the end-of-step velocity
//! (issue 26). Strong form, as in 2D (method.md §1): ∇²p = (ρ/Δt) ∇·u*, p = 0 on the free
//! surface, and on a wall u·n = 0 at the end of the step, i.e. ∂p/∂n = (ρ/Δt) u*·n. Weakly,
//! with the wall condition natural: Σ_e V b_i·b_j p_j = (ρ/Δt) Σ_e V b_i·ū*_e (ū*_e the
//! element's mean predicted velocity). A linear pressure is reproduced exactly, so still
//! water's hydrostatic pressure is exact on any mesh whose free surface is flat.

use crate::fem::tet::{P1Tet, p1_tet};
use crate::mesh3d::{AlphaShape, Tetrahedralisation};
use faer::Side;
use faer::sparse::SparseColMat;
use nalgebra::Vector3;

/// Why a pressure solve could not be made.
#[derive(Debug, thiserror::Error)]
pub enum PressureError {
    #[error("a kept tetrahedron ({0}) is flat: its gradients do not exist")]
    FlatElement(u32),
    #[error("the pressure matrix could not be built: {0}")]
    Matrix(String),
    #[error("the pressure matrix is not positive definite: a body of water has no free surface")]
    NotDefinite,
    #[error("the flow diverged: {0}")]
    Diverged(String),
    #[error(
        "{unknowns} pressure unknowns are too many for a 3D Cholesky factor (limit {limit}, its \
         fill would exhaust the memory): use CG"
    )]
    TooLarge { unknowns: usize, limit: usize },
}

/// How the pressure equation is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver3 {
    /// faer's sparse Cholesky, factored every step: faer's own fill-reducing ordering below
    /// [`NESTED_DISSECTION_UNKNOWNS`], nested dissection of the nodes' positions from there.
    Cholesky,
    /// Conjugate gradients preconditioned by incomplete Cholesky (IC(0), `ic0`) to a relative
    /// residual of 1e-10, from zero.
    Cg,
    /// Cholesky up to [`CHOLESKY_MAX_UNKNOWNS`], CG above.
    Auto,
}

/// Where Cholesky stops paying in 3D, against CG with the incomplete-Cholesky preconditioner
/// (the matrix assembled in compressed columns; one sitting, this 2-core VM). On a compact tank
/// CG wins at every size: the still tank of `surflab bench3d` (pressure stage) 11.5 against
/// 7.6 ms (40 iterations) at 3 000 nodes, 23 against 16 (46) at 5 000, 65 against 46 (60) at
/// 10 976, 153–162 against 100–102 (74) at 19 652, 698–784 against 349–354 (104) at 48 668. On
/// a thin one the factor's fill is nearly that of 2D and CG needs more iterations: the dam
/// break's first 60 steps (about 4 000 unknowns) 22 against 25 ms (102 iterations), and its
/// whole run (up to about 10 000 unknowns) 75 s with Cholesky throughout against 79 s with CG
/// from 5 000 unknowns. Hence Cholesky up to 10 000.
pub const CHOLESKY_MAX_UNKNOWNS: usize = 10_000;

/// From this many unknowns the 3D Cholesky factor is ordered by nested dissection of the
/// nodes' positions (`solver::ordering`); below, faer's own ordering is faster (`surflab
/// bench3d --solver cholesky`, pressure stage, one sitting: 5 000 nodes 33 against 39 ms,
/// 7 000 57 against 61, 10 976 117 against 112, 19 652 311 against 248, 48 668 1 817 against
/// 944).
pub const NESTED_DISSECTION_UNKNOWNS: usize = 10_000;

/// The largest system a 3D Cholesky factor is allowed: its fill grows like n^(4/3), and it
/// held 1.1 GB at 97 556 nodes, so about 5 GB here.
pub const CHOLESKY_LIMIT_UNKNOWNS: usize = 300_000;

/// Below this quality (6√2 V / l_rms³) a kept tetrahedron is flat: it is left out of the
/// operators. Its Laplacian entries V b_i·b_j grow like its base area over its thickness, so
/// four nodes of a seeding lattice's cube that round-off has made a tetrahedron of 1e-17 m
/// thickness put entries of 1e12 into the pressure matrix (still water jumped from 1e-16 to
/// 1.5e-2 m/s in one step when the first such sliver appeared). Leaving out a tetrahedron of
/// little volume changes the operators' consistency by the order of its thickness; its faces
/// stay interior for the α-shape. At 1e-3 the 3D dam break diverged at T = 2.63 (4.7 km/s); at
/// 0.01 it ran to its end; at 0.05 (every sliver) a node lost all its elements and the
/// pressure matrix its definiteness at T = 3.26 (`docs/three_d.md`).
pub const FLAT_QUALITY: f64 = 0.01;

/// The P1 element of each kept tetrahedron, in the order of `shape.kept`: built once per step
/// and shared by the volume, the pressure and the correction. A flat one (quality below
/// [`FLAT_QUALITY`]) gets zero volume and gradients, so that it adds nothing.
pub fn elements(
    points: &[[f64; 3]],
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
) -> Result<Vec<P1Tet>, PressureError> {
    shape
        .kept
        .iter()
        .zip(&shape.kept_quality)
        .map(|(&t, &quality)| {
            let nodes = mesh.tets[t as usize].map(|i| &points[i as usize]);
            if quality < FLAT_QUALITY {
                return Ok(P1Tet {
                    volume: 0.0,
                    grad: [Vector3::zeros(); 4],
                });
            }
            p1_tet(nodes.map(|p| Vector3::from(*p))).ok_or(PressureError::FlatElement(t))
        })
        .collect()
}

/// The weak free surface of [`pressure`]: the free-surface nodes keep their continuity row and
/// p = 0 holds weakly, as the Robin condition ∂p/∂n + p/λ = 0 on the free-surface triangles.
#[derive(Debug, Clone, Copy)]
pub struct WeakSurface<'a> {
    /// The node positions, m (for the triangles' areas and normals).
    pub points: &'a [[f64; 3]],
    /// λ, m.
    pub length_m: f64,
}

/// The FIC stabilisation of [`pressure`] (method.md §1, as the 2D solver's): the Laplacian's
/// coefficient Δt/ρ becomes Δt/ρ + τ_e in each tetrahedron, and the right side gains
/// −τ_e V b_i·π̄_e, π the nodes' projection of −∇p from the last step ([`projection`]), so
/// that the added term τ ∇·(∇p + π) vanishes where the pressure gradient is smooth (a
/// hydrostatic pressure stays exact).
#[derive(Debug, Clone, Copy)]
pub struct Fic<'a> {
    /// τ of each kept tetrahedron, in the order of `elements`, m³·s/kg.
    pub tau_e: &'a [f64],
    /// π per node (the last step's), Pa/m.
    pub pi: &'a [Vector3<f64>],
}

/// The lumped nodal gradient of `p` over the kept tetrahedra, Pa/m (0 on a node in none).
///
/// With `strong_surface` (p imposed on the free surface's nodes), a tetrahedron whose four
/// nodes are all on the free surface — a skin over a curved surface — is left out of the
/// average of a node that has other tetrahedra: its gradient is that of the four imposed
/// values (zero, or a wall's contact-point pressures), not the water's, and averaged in it
/// took that share of the pressure's support from the surface node, which fell. On the
/// narrow piston tank cut to 1.6 m the water kept at 5 s went from 0.9846 to 0.9945
/// (`docs/three_d.md`, *The piston*). A node in skins only keeps their (zero) gradient.
pub fn nodal_gradient(
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    elements: &[P1Tet],
    p: &[f64],
    strong_surface: bool,
) -> Vec<Vector3<f64>> {
    let skin = |v: &[u32; 4]| strong_surface && v.iter().all(|&i| shape.free_surface[i as usize]);
    weighted_gradient(mesh, shape, elements, p, |_, e| e.volume / 4.0, skin)
}

/// The nodes' projection of −∇p: π_i = −Σ_e τ_e (V/4) ∇p_e / Σ_e τ_e (V/4) over the kept
/// tetrahedra around node i (0 on a node with no weight, and everywhere when every τ_e is 0).
pub fn projection(
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    elements: &[P1Tet],
    tau_e: &[f64],
    p: &[f64],
) -> Vec<Vector3<f64>> {
    let weight = |k: usize, e: &P1Tet| tau_e[k] * e.volume / 4.0;
    let mut pi = weighted_gradient(mesh, shape, elements, p, weight, |_| false);
    pi.iter_mut().for_each(|g| *g = -*g);
    pi
}

/// Σ_e w_e ∇p_e / Σ_e w_e per node over the kept tetrahedra around it (0 where Σ w_e is 0),
/// `weight(k, e)` giving w of the k-th kept tetrahedron; the tetrahedra `left_out` says are
/// counted only at a node that has no other.
fn weighted_gradient(
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    elements: &[P1Tet],
    p: &[f64],
    weight: impl Fn(usize, &P1Tet) -> f64,
    left_out: impl Fn(&[u32; 4]) -> bool,
) -> Vec<Vector3<f64>> {
    let n = p.len();
    // [counted, left out]: the weights and the weighted gradients.
    let mut sum = vec![[0.0; 2]; n];
    let mut grad = vec![[Vector3::zeros(); 2]; n];
    for (k, (&t, e)) in shape.kept.iter().zip(elements).enumerate() {
        let v = mesh.tets[t as usize];
        let g: Vector3<f64> = (0..4).map(|j| e.grad[j] * p[v[j] as usize]).sum();
        let w = weight(k, e);
        let which = left_out(&v) as usize;
        for &i in &v {
            sum[i as usize][which] += w;
            grad[i as usize][which] += g * w;
        }
    }
    grad.iter()
        .zip(&sum)
        .map(|(g, w)| match (w[0] > 0.0, w[1] > 0.0) {
            (true, _) => g[0] / w[0],
            (false, true) => g[1] / w[1],
            _ => Vector3::zeros(),
        })
        .collect()
}

/// The pressure (Pa) at every node (0 off the mesh, and on the free surface unless `weak`) for
/// the predicted velocity `u_star` (m/s), density `rho` (kg/m³) and step `dt_s`, and the
/// solver's iterations (0 for Cholesky); `elements` as [`elements`] gives them, `points` the
/// nodes' positions (m; the Cholesky factor's ordering cuts the nodes by position).
///
/// `fixed` (Pa per node) is the pressure imposed on the nodes without a row (0 if `None`): the
/// free surface's, 0 but at a wall's contact points (`Flow3::contact_pressure`).
///
/// `inflow` (m³/s per node, from `Flow3::wall_inflow`) is what moving walls push into the water:
/// the boundary term (ρ/Δt) ∮ φᵢ U·n_in dA of a wall whose u·n is U·n at the end of the step.
///
/// With `weak`, the free-surface boundary terms of the weak form stay: the Robin term
/// Σ (A/3) p_i / λ on the diagonal (lumped) and −(ρ/Δt) ∮ φᵢ u*·n on the right (exact over
/// each free-surface triangle of area A and outward normal n), so that a hydrostatic pressure is
/// still exact under a flat surface.
///
/// With `fic`, the FIC stabilisation ([`Fic`]) scales each tetrahedron's Laplacian (the
/// imposed pressures' share included) and the Robin term (by its nodes' mean τ) by
/// 1 + ρτ/Δt.
///
/// With `p_old` (the incremental split, γ = 1: `u_star` then carries −(Δt/ρ) ∇pⁿ), the right
/// side gains Σ_e V b_i·∇pⁿ_e, so that the equation is the increment's, p − pⁿ, while p = 0
/// (or the contact pressure) is imposed on the current free surface.
///
/// With `target` (1/s per node, the volume relaxation's, `relax`), the continuity equation asks
/// for ∇·u = s instead of 0: D ũ becomes D ũ − M s, M the lumped volume of each tetrahedron's
/// nodes (V/4).
#[allow(clippy::too_many_arguments)]
pub fn pressure(
    points: &[[f64; 3]],
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    elements: &[P1Tet],
    u_star: &[Vector3<f64>],
    rho: f64,
    dt_s: f64,
    solver: Solver3,
    weak: Option<WeakSurface>,
    inflow: Option<&[f64]>,
    fixed: Option<&[f64]>,
    fic: Option<Fic>,
    p_old: Option<&[f64]>,
    target: Option<&[f64]>,
) -> Result<(Vec<f64>, usize), PressureError> {
    let fixed_at = |i: u32| fixed.map_or(0.0, |f| f[i as usize]);
    let n = shape.in_mesh.len();
    // 1 + ρτ/Δt per tetrahedron (1 without the stabilisation).
    let scale: Vec<f64> = match fic {
        Some(f) => f.tau_e.iter().map(|t| 1.0 + rho * t / dt_s).collect(),
        None => vec![1.0; elements.len()],
    };
    // Unknowns: the nodes of the mesh that are not on the free surface (all of them with the
    // weak surface).
    // A node whose elements are all flat ([`FLAT_QUALITY`]) has no row: it is left out.
    let mut support = vec![0.0; n];
    for (&t, e) in shape.kept.iter().zip(elements) {
        for &i in &mesh.tets[t as usize] {
            support[i as usize] += e.volume;
        }
    }
    let has_row = |i: usize| {
        shape.in_mesh[i] && support[i] > 0.0 && (weak.is_some() || !shape.free_surface[i])
    };
    let sealed_top = super::pieces::sealed_tops(
        points,
        mesh,
        shape,
        elements,
        &support,
        &has_row,
        weak.is_some(),
    );
    let mut unknown = vec![u32::MAX; n];
    let mut count = 0usize;
    for i in 0..n {
        if has_row(i) && !sealed_top[i] {
            unknown[i] = count as u32;
            count += 1;
        }
    }
    let solver = match solver {
        Solver3::Auto if count <= CHOLESKY_MAX_UNKNOWNS => Solver3::Cholesky,
        Solver3::Auto => Solver3::Cg,
        other => other,
    };
    if solver == Solver3::Cholesky && count > CHOLESKY_LIMIT_UNKNOWNS {
        return Err(PressureError::TooLarge {
            unknowns: count,
            limit: CHOLESKY_LIMIT_UNKNOWNS,
        });
    }
    // The whole matrix for CG (which multiplies by it) and for the nested-dissection ordering
    // (which reads its graph); the lower triangle, which the factor reads, otherwise.
    let whole = solver == Solver3::Cg || count >= NESTED_DISSECTION_UNKNOWNS;
    let mut rhs = vec![0.0; count];
    for (k, (&t, e)) in shape.kept.iter().zip(elements).enumerate() {
        let v = mesh.tets[t as usize];
        let mean_u: Vector3<f64> =
            v.iter().map(|&i| u_star[i as usize]).sum::<Vector3<f64>>() / 4.0;
        // The stabilisation's flux −τ π̄ (zero without it) and the incremental split's
        // (Δt/ρ) ∇pⁿ.
        let mut flux = fic.map_or(Vector3::zeros(), |f| {
            -f.tau_e[k] * v.iter().map(|&i| f.pi[i as usize]).sum::<Vector3<f64>>() / 4.0
        });
        if let Some(p_old) = p_old {
            let g: Vector3<f64> = (0..4).map(|j| e.grad[j] * p_old[v[j] as usize]).sum();
            flux += dt_s / rho * g;
        }
        for a in 0..4 {
            let row = unknown[v[a] as usize];
            if row == u32::MAX {
                continue;
            }
            rhs[row as usize] += rho / dt_s * e.volume * e.grad[a].dot(&(mean_u + flux));
            if let Some(s) = target {
                rhs[row as usize] += rho / dt_s * e.volume / 4.0 * s[v[a] as usize];
            }
            for b in 0..4 {
                // A node of imposed pressure (0 but at a contact point) moves to the right.
                if unknown[v[b] as usize] == u32::MAX {
                    let fixed = fixed_at(v[b]);
                    if fixed != 0.0 {
                        rhs[row as usize] -=
                            scale[k] * e.volume * e.grad[a].dot(&e.grad[b]) * fixed;
                    }
                }
            }
        }
    }
    let mut matrix = Assembly::new(mesh, shape, elements, &scale, &unknown, count, whole);
    if let Some(w) = weak {
        // Each node's volume-weighted mean of 1 + ρτ/Δt, for the Robin term of its faces.
        let mut node_scale = vec![(0.0, 0.0); n];
        for ((&t, e), &c) in shape.kept.iter().zip(elements).zip(&scale) {
            for &i in &mesh.tets[t as usize] {
                node_scale[i as usize].0 += c * e.volume;
                node_scale[i as usize].1 += e.volume;
            }
        }
        let node_scale = |i: u32| match node_scale[i as usize] {
            (c, v) if v > 0.0 => c / v,
            _ => 1.0,
        };
        for f in &shape.surface {
            let [a, b, c] = f.map(|i| Vector3::from(w.points[i as usize]));
            let normal2 = (b - a).cross(&(c - a));
            let area = 0.5 * normal2.norm();
            if area == 0.0 {
                continue;
            }
            let normal = normal2 / (2.0 * area);
            // ∮ φᵢ u*·n over the triangle, exact for the linear u*·n: A/12 (2 uᵢ + u_j + u_k)·n.
            // Lumped (A/3 uᵢ·n) it answers a node-to-node ripple of the surface's normal
            // velocity, which the exact integral does not see (3D sloshing with λ = 0.3 h kept
            // 0.817 of its water at 2 s lumped, 0.912 exact; docs/three_d.md).
            let un = f.map(|i| u_star[i as usize].dot(&normal));
            for (k, &i) in f.iter().enumerate() {
                let row = unknown[i as usize];
                if row == u32::MAX {
                    continue;
                }
                matrix.add_to_diagonal(row as usize, node_scale(i) * area / 3.0 / w.length_m);
                let flux = area / 12.0 * (un[0] + un[1] + un[2] + un[k]);
                rhs[row as usize] -= rho / dt_s * flux;
            }
        }
    }
    if let Some(q) = inflow {
        for (i, &q) in q.iter().enumerate() {
            if unknown[i] != u32::MAX {
                rhs[unknown[i] as usize] += rho / dt_s * q;
            }
        }
    }
    let mut p: Vec<f64> = (0..n)
        .map(|i| {
            if shape.in_mesh[i] && unknown[i] == u32::MAX {
                fixed_at(i as u32)
            } else {
                0.0
            }
        })
        .collect();
    if count == 0 {
        return Ok((p, 0));
    }
    let k = matrix.into_matrix();
    let b = faer::Mat::<f64>::from_fn(count, 1, |i, _| rhs[i]);
    let (x, iterations) = match solver {
        Solver3::Cholesky => (cholesky_solve(&k, points, &unknown, b)?, 0),
        Solver3::Cg | Solver3::Auto => {
            use faer::dyn_stack::{MemBuffer, MemStack};
            use faer::matrix_free::conjugate_gradient::{
                CgParams, conjugate_gradient, conjugate_gradient_scratch,
            };
            let ic = super::ic0::Ic0::new(&k).map_err(PressureError::Diverged)?;
            let precond = &ic;
            let par = faer::Par::Seq;
            let mut mem = MemBuffer::new(conjugate_gradient_scratch(precond, k.as_ref(), 1, par));
            let mut x = faer::Mat::<f64>::zeros(count, 1);
            let params = CgParams {
                rel_tolerance: 1e-10,
                max_iters: 20 * count + 100,
                ..Default::default()
            };
            let info = conjugate_gradient(
                x.as_mut(),
                precond,
                k.as_ref(),
                b.as_ref(),
                params,
                |_| {},
                par,
                MemStack::new(&mut mem),
            )
            .map_err(|e| PressureError::Diverged(format!("conjugate gradients: {e:?}")))?;
            (x, info.iter_count)
        }
    };
    for i in 0..n {
        if unknown[i] != u32::MAX {
            p[i] = x[(unknown[i] as usize, 0)];
            if !p[i].is_finite() {
                return Err(PressureError::Diverged(format!(
                    "the pressure at node {i} is {}",
                    p[i]
                )));
            }
        }
    }
    Ok((p, iterations))
}

/// The pressure matrix Σ_e s_e V b_i·b_j over the kept tetrahedra (s_e the FIC scale
/// 1 + ρτ_e/Δt, or 1), on the unknowns, in compressed
/// columns built straight from the tetrahedra around each node (no triplets to sort): column
/// r holds the unknowns that share a kept tetrahedron with r's node, in order; with `whole`
/// all of them, else those ≥ r (the lower triangle, which the factor reads).
struct Assembly {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    val: Vec<f64>,
    /// Where each column's diagonal entry is.
    diag: Vec<usize>,
}

impl Assembly {
    fn new(
        mesh: &Tetrahedralisation,
        shape: &AlphaShape,
        elements: &[P1Tet],
        scale: &[f64],
        unknown: &[u32],
        count: usize,
        whole: bool,
    ) -> Assembly {
        // The kept tetrahedra (as indices into `shape.kept`) around each unknown's node, with
        // the node's place in the tetrahedron.
        let mut start = vec![0usize; count + 1];
        for &t in &shape.kept {
            for &i in &mesh.tets[t as usize] {
                let r = unknown[i as usize];
                if r != u32::MAX {
                    start[r as usize + 1] += 1;
                }
            }
        }
        for r in 0..count {
            start[r + 1] += start[r];
        }
        let mut around = vec![(0u32, 0u8); start[count]];
        let mut fill = start.clone();
        for (k, &t) in shape.kept.iter().enumerate() {
            for (a, &i) in mesh.tets[t as usize].iter().enumerate() {
                let r = unknown[i as usize];
                if r != u32::MAX {
                    around[fill[r as usize]] = (k as u32, a as u8);
                    fill[r as usize] += 1;
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(count + 1);
        col_ptr.push(0);
        let (mut row_idx, mut val) = (Vec::new(), Vec::new());
        let mut diag = Vec::with_capacity(count);
        // `slot[c]`: where unknown c sits in the column being built (valid while `mark[c]` is
        // that column).
        let (mut mark, mut slot) = (vec![u32::MAX; count], vec![0usize; count]);
        for r in 0..count {
            let first = row_idx.len();
            for &(k, _) in &around[start[r]..start[r + 1]] {
                for &j in &mesh.tets[shape.kept[k as usize] as usize] {
                    let c = unknown[j as usize];
                    if c != u32::MAX && mark[c as usize] != r as u32 && (whole || c as usize >= r) {
                        mark[c as usize] = r as u32;
                        row_idx.push(c as usize);
                    }
                }
            }
            row_idx[first..].sort_unstable();
            val.resize(row_idx.len(), 0.0);
            for (s, &c) in row_idx[first..].iter().enumerate() {
                slot[c] = first + s;
            }
            diag.push(slot[r]);
            for &(k, a) in &around[start[r]..start[r + 1]] {
                let e = &elements[k as usize];
                let v = mesh.tets[shape.kept[k as usize] as usize];
                let vol = scale[k as usize] * e.volume;
                for (b, &j) in v.iter().enumerate() {
                    let c = unknown[j as usize];
                    if c != u32::MAX && mark[c as usize] == r as u32 {
                        val[slot[c as usize]] += vol * e.grad[a as usize].dot(&e.grad[b]);
                    }
                }
            }
            col_ptr.push(row_idx.len());
        }
        Assembly {
            col_ptr,
            row_idx,
            val,
            diag,
        }
    }

    fn add_to_diagonal(&mut self, r: usize, v: f64) {
        self.val[self.diag[r]] += v;
    }

    fn into_matrix(self) -> SparseColMat<usize, f64> {
        let n = self.diag.len();
        let symbolic =
            faer::sparse::SymbolicSparseColMat::new_checked(n, n, self.col_ptr, None, self.row_idx);
        SparseColMat::new(symbolic, self.val)
    }
}

/// Solves K x = b by a sparse Cholesky factor of the symmetric positive definite `k` (its
/// lower triangle read; both triangles stored from [`NESTED_DISSECTION_UNKNOWNS`] unknowns on)
/// whose unknown r is node i where `unknown[i]` = r, at `points[i]`: from
/// [`NESTED_DISSECTION_UNKNOWNS`] on, nested-dissection ordering by position (as the 2D
/// pressure's) and a supernodal factor; below, faer's own ordering and choice. One thread.
fn cholesky_solve(
    k: &SparseColMat<usize, f64>,
    points: &[[f64; 3]],
    unknown: &[u32],
    mut b: faer::Mat<f64>,
) -> Result<faer::Mat<f64>, PressureError> {
    use faer::prelude::Solve;
    if k.nrows() < NESTED_DISSECTION_UNKNOWNS {
        let llt = k
            .sp_cholesky(Side::Lower)
            .map_err(|_| PressureError::NotDefinite)?;
        return Ok(llt.solve(&b));
    }
    let mut position = vec![[0.0; 3]; k.nrows()];
    for (i, &r) in unknown.iter().enumerate() {
        if r != u32::MAX {
            position[r as usize] = points[i];
        }
    }
    let pattern = k.symbolic();
    let symbolic =
        crate::solver::ordering::symbolic_cholesky(&position, pattern.col_ptr(), pattern.row_idx())
            .map_err(PressureError::Matrix)?;
    let mut factor = Vec::new();
    crate::solver::ordering::factor_and_solve(&symbolic, k.as_ref(), &mut factor, b.as_mut())
        .map_err(|_| PressureError::NotDefinite)?;
    Ok(b)
}

/// The end-of-step velocity u = u* − (Δt/ρ) ∇p (m/s), `grad` the lumped nodal gradient of p
/// ([`nodal_gradient`], 0 off the mesh, where u* stays). With the incremental split p is the
/// increment pⁿ⁺¹ − pⁿ.
pub fn correct(
    u_star: &[Vector3<f64>],
    grad: &[Vector3<f64>],
    rho: f64,
    dt_s: f64,
) -> Vec<Vector3<f64>> {
    u_star
        .iter()
        .zip(grad)
        .map(|(u, g)| u - g * (dt_s / rho))
        .collect()
}

#[cfg(test)]
mod split_tests {
    use crate::case::TauFormula;
    use crate::solver3d::still_tank;
    use nalgebra::Vector3;

    /// The incremental split with the FIC term (the case's defaults, `solver.gamma` = 1 and
    /// `solver.tau` = "inertial") keeps still water at rest on a jittered mesh remeshed every
    /// step: from the hydrostatic pressure and π = (0, ρg, 0), the increment is zero and the
    /// stabilisation's τ ∇·(∇p + π) vanishes, so the answer is the hydrostatic one to
    /// round-off, as the plain split's (`tests.rs`).
    #[test]
    fn the_incremental_split_with_fic_keeps_still_water_at_rest() {
        let (h, g, rho, dt) = (0.02, 9.81, 1000.0, 0.01);
        let mut flow = still_tank(10, 8, 10, h, 0.3);
        let depth = 7.0 * h;
        flow.tau = TauFormula::Inertial;
        flow.gamma = 1.0;
        for i in 0..flow.x.len() {
            let y = flow.x[i][1];
            flow.p[i] = (rho * g * (depth - y)).max(0.0);
            if y <= depth + h {
                flow.pi[i] = Vector3::new(0.0, rho * g, 0.0);
            }
        }
        let first = flow.step(dt).unwrap();
        let (mut speed, mut drift) = (0.0f64, 0.0f64);
        for _ in 1..100 {
            let s = flow.step(dt).unwrap();
            drift = drift.max((s.volume_m3 / first.volume_m3 - 1.0).abs());
            speed = speed.max(flow.u.iter().map(|u| u.norm()).fold(0.0, f64::max));
        }
        let mut err_p = 0.0f64;
        for i in (0..flow.x.len()).filter(|&i| flow.in_mesh[i]) {
            let exact = (rho * g * (depth - flow.x[i][1])).max(0.0);
            err_p = err_p.max((flow.p[i] - exact).abs() / (rho * g * depth));
        }
        println!(
            "3D still water, incremental split with FIC, 100 steps of 10 ms: max speed \
             {speed:.1e} m/s, pressure error {err_p:.1e} of ρ g d, volume drift {drift:.1e}"
        );
        assert!(speed < 1e-10 && err_p < 1e-10 && drift < 1e-12);
    }
}

#[cfg(test)]
mod skin_tests {
    use super::{elements, nodal_gradient};
    use crate::mesh3d::{AlphaShape, tetrahedralise};

    #[test]
    fn a_skin_of_free_surface_nodes_is_left_out_of_a_nodes_gradient() {
        // Two tetrahedra on the triangle a, b, c (free surface): d above it, also on the
        // surface (so a, b, c, d is a skin of imposed zeros), and e below it in the water at
        // 1 kPa. The gradient at a, b and c is the water tetrahedron's, not half of it; d,
        // in the skin only, keeps the skin's zero; with the weak surface (the nodes keep
        // their rows) both count, as before.
        let r = 1.0f64;
        let corner = |k: f64| {
            let t = 2.0 * std::f64::consts::PI * k / 3.0;
            [r * t.cos(), 0.0, r * t.sin()]
        };
        let points = [
            corner(0.0),
            corner(1.0),
            corner(2.0),
            [0.0, 1.5, 0.0],
            [0.0, -1.5, 0.0],
        ];
        let mesh = tetrahedralise(&points);
        assert_eq!(mesh.tets.len(), 2, "the bipyramid is two tetrahedra");
        let shape = AlphaShape {
            kept: vec![0, 1],
            kept_quality: vec![1.0, 1.0],
            free_surface: vec![true, true, true, true, false],
            in_mesh: vec![true; 5],
            ..Default::default()
        };
        let elements = elements(&points, &mesh, &shape).unwrap();
        let p = [0.0, 0.0, 0.0, 0.0, 1000.0];
        let strong = nodal_gradient(&mesh, &shape, &elements, &p, true);
        let weak = nodal_gradient(&mesh, &shape, &elements, &p, false);
        // The water tetrahedron's gradient: 1 kPa over 1.5 m, downwards.
        let water = -1000.0 / 1.5;
        for i in 0..3 {
            assert!((strong[i].y - water).abs() < 1e-9, "{i}: {:?}", strong[i]);
            assert!((weak[i].y - 0.5 * water).abs() < 1e-9, "{i}: {:?}", weak[i]);
        }
        assert_eq!(strong[3].norm(), 0.0);
        assert!((strong[4].y - water).abs() < 1e-9);
        println!(
            "surface node: {:.1} Pa/m without the skin, {:.1} with it (water {water:.1})",
            strong[0].y, weak[0].y
        );
    }
}
