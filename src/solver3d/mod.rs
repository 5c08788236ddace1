//! The 3D fractional step (issue 26), first pieces: the pressure Poisson equation of one step on
//! the α-shape's tetrahedra, the end-of-step velocity, and [`Flow3`], the least time loop
//! around them. The viscous predictor, the walls' guard, node management and the wavemaker are
//! not built yet.
//!
//! Strong form, as in 2D (method.md §1): ∇²p = (ρ/Δt) ∇·u*, p = 0 on the free surface, and on
//! a wall u·n = 0 at the end of the step, i.e. ∂p/∂n = (ρ/Δt) u*·n. Weakly, with the wall
//! condition natural: Σ_e V b_i·b_j p_j = (ρ/Δt) Σ_e V b_i·ū*_e (ū*_e the element's mean
//! predicted velocity). A linear pressure is reproduced exactly, so still water's hydrostatic
//! pressure is exact on any mesh whose free surface is flat.

use crate::fem::tet::{P1Tet, p1_tet};
use crate::mesh3d::{AlphaShape, Tetrahedralisation};
use faer::Side;
use faer::prelude::Solve;
use faer::sparse::{SparseColMat, Triplet};
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
    /// faer's sparse Cholesky (its own fill-reducing ordering), factored every step.
    Cholesky,
    /// Jacobi-preconditioned conjugate gradients to a relative residual of 1e-10, from zero.
    Cg,
    /// Cholesky up to [`CHOLESKY_MAX_UNKNOWNS`], CG above.
    Auto,
}

/// Where Cholesky stops paying in 3D (`surflab bench3d`, still tank, this 2-core VM): the
/// pressure stage took 344 against 418 ms (CG) at 19 652 nodes, 1 782 against 1 833 at
/// 48 668, 9 940 against 5 067 at 97 556; the fill of a 3D factor grows faster than CG's
/// iterations.
pub const CHOLESKY_MAX_UNKNOWNS: usize = 70_000;

/// The largest system a 3D Cholesky factor is allowed: its fill grows like n^(4/3), and it
/// held 1.1 GB at 97 556 nodes, so about 5 GB here.
pub const CHOLESKY_LIMIT_UNKNOWNS: usize = 300_000;

/// The P1 element of each kept tetrahedron, in the order of `shape.kept`: built once per step
/// and shared by the volume, the pressure and the correction.
pub fn elements(
    points: &[[f64; 3]],
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
) -> Result<Vec<P1Tet>, PressureError> {
    shape
        .kept
        .iter()
        .map(|&t| {
            let v = mesh.tets[t as usize].map(|i| Vector3::from(points[i as usize]));
            p1_tet(v).ok_or(PressureError::FlatElement(t))
        })
        .collect()
}

/// The pressure (Pa) at every node (0 off the mesh and on the free surface) for the predicted
/// velocity `u_star` (m/s), density `rho` (kg/m³) and step `dt_s`, and the solver's iterations
/// (0 for Cholesky); `elements` as [`elements`] gives them.
pub fn pressure(
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    elements: &[P1Tet],
    u_star: &[Vector3<f64>],
    rho: f64,
    dt_s: f64,
    solver: Solver3,
) -> Result<(Vec<f64>, usize), PressureError> {
    let n = shape.in_mesh.len();
    // Unknowns: the nodes of the mesh that are not on the free surface.
    let mut unknown = vec![u32::MAX; n];
    let mut count = 0usize;
    for i in 0..n {
        if shape.in_mesh[i] && !shape.free_surface[i] {
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
    let mut triplets = Vec::with_capacity(16 * shape.kept.len());
    let mut rhs = vec![0.0; count];
    for (&t, e) in shape.kept.iter().zip(elements) {
        let v = mesh.tets[t as usize];
        let mean_u: Vector3<f64> =
            v.iter().map(|&i| u_star[i as usize]).sum::<Vector3<f64>>() / 4.0;
        for a in 0..4 {
            let row = unknown[v[a] as usize];
            if row == u32::MAX {
                continue;
            }
            rhs[row as usize] += rho / dt_s * e.volume * e.grad[a].dot(&mean_u);
            for b in 0..4 {
                let col = unknown[v[b] as usize];
                // Cholesky reads the lower triangle; CG needs the whole matrix.
                if col != u32::MAX && (col <= row || solver == Solver3::Cg) {
                    let k = e.volume * e.grad[a].dot(&e.grad[b]);
                    triplets.push(Triplet::new(row as usize, col as usize, k));
                }
            }
        }
    }
    let mut p = vec![0.0; n];
    if count == 0 {
        return Ok((p, 0));
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(count, count, &triplets)
        .map_err(|e| PressureError::Matrix(format!("{e:?}")))?;
    let b = faer::Mat::<f64>::from_fn(count, 1, |i, _| rhs[i]);
    let (x, iterations) = match solver {
        Solver3::Cholesky => {
            let llt = k
                .sp_cholesky(Side::Lower)
                .map_err(|_| PressureError::NotDefinite)?;
            (llt.solve(&b), 0)
        }
        Solver3::Cg | Solver3::Auto => {
            use faer::dyn_stack::{MemBuffer, MemStack};
            use faer::matrix_free::conjugate_gradient::{
                CgParams, conjugate_gradient, conjugate_gradient_scratch,
            };
            let mut dinv = faer::diag::Diag::<f64>::zeros(count);
            for (j, col) in (0..count).map(|j| (j, k.as_ref().col_range(j))) {
                let rows = &k.as_ref().symbolic().row_idx()[col.clone()];
                let vals = &k.as_ref().val()[col];
                let d = rows
                    .iter()
                    .zip(vals)
                    .find(|(r, _)| **r == j)
                    .map_or(0.0, |(_, v)| *v);
                dinv[j] = if d > 0.0 { 1.0 / d } else { 1.0 };
            }
            let precond = dinv.as_ref();
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

/// The end-of-step velocity u = u* − (Δt/ρ) ∇p, ∇p the lumped nodal gradient (m/s); nodes off
/// the mesh keep u*.
pub fn correct(
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    elements: &[P1Tet],
    u_star: &[Vector3<f64>],
    p: &[f64],
    rho: f64,
    dt_s: f64,
) -> Vec<Vector3<f64>> {
    let n = u_star.len();
    let mut mass = vec![0.0; n];
    let mut grad = vec![Vector3::zeros(); n];
    for (&t, e) in shape.kept.iter().zip(elements) {
        let v = mesh.tets[t as usize];
        let g: Vector3<f64> = (0..4).map(|j| e.grad[j] * p[v[j] as usize]).sum();
        for &i in &v {
            mass[i as usize] += e.volume / 4.0;
            grad[i as usize] += g * (e.volume / 4.0);
        }
    }
    (0..n)
        .map(|i| {
            if mass[i] > 0.0 {
                u_star[i] - grad[i] / mass[i] * (dt_s / rho)
            } else {
                u_star[i]
            }
        })
        .collect()
}

/// The state of a 3D flow of particles: the least loop that remeshes and projects every
/// step (inviscid predictor; viscosity, the wall guard and node management are not built).
#[derive(Debug, Clone)]
pub struct Flow3 {
    /// Node positions, m.
    pub x: Vec<[f64; 3]>,
    /// Node velocities, m/s (zero on walls).
    pub u: Vec<Vector3<f64>>,
    /// Per node, one bit per wall plane it lies on (0: fluid); see `mesh3d::alpha_shape`.
    pub walls: Vec<u16>,
    /// The last step's pressure, Pa.
    pub p: Vec<f64>,
    /// α h, m.
    pub alpha_h_m: f64,
    pub rho_kg_m3: f64,
    pub gravity_m_s2: Vector3<f64>,
    pub solver: Solver3,
}

/// The stages of [`Flow3::step`], in order.
pub const STAGES_3D: [&str; 6] = [
    "tetrahedralise",
    "alpha_shape",
    "elements",
    "pressure",
    "correct",
    "move",
];

/// What one step of [`Flow3`] measured.
#[derive(Debug, Clone, Copy)]
pub struct Step3 {
    /// Volume of the kept tetrahedra at the start of the step, m³.
    pub volume_m3: f64,
    pub tetrahedra: usize,
    pub slivers_kept: usize,
    /// The pressure solver's iterations (0 for Cholesky).
    pub iterations: usize,
    /// Wall time of each stage of [`STAGES_3D`], ms.
    pub stage_ms: [f64; 6],
}

impl Flow3 {
    /// One step of Δt: tetrahedralise, α-shape, elements, predict u* = u + Δt g, solve the pressure,
    /// correct, hold the walls, move the fluid nodes.
    pub fn step(&mut self, dt_s: f64) -> Result<Step3, PressureError> {
        if let Some(i) = (0..self.x.len()).find(|&i| {
            !(self.x[i].iter().all(|c| c.is_finite()) && self.u[i].iter().all(|c| c.is_finite()))
        }) {
            return Err(PressureError::Diverged(format!(
                "node {i} is at {:?} with velocity {:?}",
                self.x[i], self.u[i]
            )));
        }
        let mut stage_ms = [0.0; 6];
        let mut clock = std::time::Instant::now();
        let mut lap = |k: usize| {
            stage_ms[k] = clock.elapsed().as_secs_f64() * 1e3;
            clock = std::time::Instant::now();
        };
        let mesh = crate::mesh3d::tetrahedralise(&self.x);
        lap(0);
        let shape = crate::mesh3d::alpha_shape(&self.x, &self.walls, &mesh, self.alpha_h_m);
        lap(1);
        let elements = elements(&self.x, &mesh, &shape)?;
        let volume_m3 = elements.iter().map(|e| e.volume).sum();
        lap(2);
        // On a wall node u* is what the water beside it predicts; the wall's u·n = 0 enters
        // through the pressure's natural boundary condition.
        let u_star: Vec<Vector3<f64>> = self
            .u
            .iter()
            .map(|u| u + self.gravity_m_s2 * dt_s)
            .collect();
        let (p, iterations) = pressure(
            &mesh,
            &shape,
            &elements,
            &u_star,
            self.rho_kg_m3,
            dt_s,
            self.solver,
        )?;
        self.p = p;
        lap(3);
        self.u = correct(
            &mesh,
            &shape,
            &elements,
            &u_star,
            &self.p,
            self.rho_kg_m3,
            dt_s,
        );
        lap(4);
        for i in 0..self.x.len() {
            if self.walls[i] != 0 {
                self.u[i] = Vector3::zeros();
            } else {
                for k in 0..3 {
                    self.x[i][k] += dt_s * self.u[i][k];
                }
            }
        }
        lap(5);
        Ok(Step3 {
            volume_m3,
            tetrahedra: shape.kept.len(),
            slivers_kept: shape.slivers_kept,
            iterations,
            stage_ms,
        })
    }
}

/// A tank of still water at rest for tests and `surflab bench3d`: `mesh3d::lattice_tank` with
/// a flat top (the fluid nodes below it moved by up to ± jitter/2 h), α = 1.2, water, gravity
/// −z, Cholesky.
pub fn still_tank(nx: usize, ny: usize, nz: usize, h: f64, jitter: f64) -> Flow3 {
    let (x, walls) =
        crate::mesh3d::lattice_tank([nx, ny, nz], h, jitter, false, 0x2545_f491_4f6c_dd1d);
    let n = x.len();
    Flow3 {
        x,
        u: vec![Vector3::zeros(); n],
        walls,
        p: vec![0.0; n],
        alpha_h_m: 1.2 * h,
        rho_kg_m3: 1000.0,
        gravity_m_s2: Vector3::new(0.0, 0.0, -9.81),
        solver: Solver3::Cholesky,
    }
}

#[cfg(test)]
mod tests;
