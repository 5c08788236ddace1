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

use crate::fem::tet::p1_tet;
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
}

/// The pressure (Pa) at every node (0 off the mesh and on the free surface) for the predicted
/// velocity `u_star` (m/s), density `rho` (kg/m³) and step `dt_s`.
pub fn pressure(
    points: &[[f64; 3]],
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    u_star: &[Vector3<f64>],
    rho: f64,
    dt_s: f64,
) -> Result<Vec<f64>, PressureError> {
    let n = points.len();
    // Unknowns: the nodes of the mesh that are not on the free surface.
    let mut unknown = vec![u32::MAX; n];
    let mut count = 0usize;
    for i in 0..n {
        if shape.in_mesh[i] && !shape.free_surface[i] {
            unknown[i] = count as u32;
            count += 1;
        }
    }
    let mut triplets = Vec::with_capacity(16 * shape.kept.len());
    let mut rhs = vec![0.0; count];
    for &t in &shape.kept {
        let v = mesh.tets[t as usize];
        let x = v.map(|i| Vector3::from(points[i as usize]));
        let e = p1_tet(x).ok_or(PressureError::FlatElement(t))?;
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
                if col != u32::MAX && col <= row {
                    let k = e.volume * e.grad[a].dot(&e.grad[b]);
                    triplets.push(Triplet::new(row as usize, col as usize, k));
                }
            }
        }
    }
    let mut p = vec![0.0; n];
    if count == 0 {
        return Ok(p);
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(count, count, &triplets)
        .map_err(|e| PressureError::Matrix(format!("{e:?}")))?;
    let llt = k
        .sp_cholesky(Side::Lower)
        .map_err(|_| PressureError::NotDefinite)?;
    let b = faer::Mat::<f64>::from_fn(count, 1, |i, _| rhs[i]);
    let x = llt.solve(&b);
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
    Ok(p)
}

/// The end-of-step velocity u = u* − (Δt/ρ) ∇p, ∇p the lumped nodal gradient (m/s); nodes off
/// the mesh keep u*.
pub fn correct(
    points: &[[f64; 3]],
    mesh: &Tetrahedralisation,
    shape: &AlphaShape,
    u_star: &[Vector3<f64>],
    p: &[f64],
    rho: f64,
    dt_s: f64,
) -> Result<Vec<Vector3<f64>>, PressureError> {
    let n = points.len();
    let mut mass = vec![0.0; n];
    let mut grad = vec![Vector3::zeros(); n];
    for &t in &shape.kept {
        let v = mesh.tets[t as usize];
        let e = p1_tet(v.map(|i| Vector3::from(points[i as usize])))
            .ok_or(PressureError::FlatElement(t))?;
        let g: Vector3<f64> = (0..4).map(|j| e.grad[j] * p[v[j] as usize]).sum();
        for &i in &v {
            mass[i as usize] += e.volume / 4.0;
            grad[i as usize] += g * (e.volume / 4.0);
        }
    }
    Ok((0..n)
        .map(|i| {
            if mass[i] > 0.0 {
                u_star[i] - grad[i] / mass[i] * (dt_s / rho)
            } else {
                u_star[i]
            }
        })
        .collect())
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
}

/// What one step of [`Flow3`] measured.
#[derive(Debug, Clone, Copy)]
pub struct Step3 {
    /// Volume of the kept tetrahedra at the start of the step, m³.
    pub volume_m3: f64,
    pub tetrahedra: usize,
    pub slivers_kept: usize,
}

impl Flow3 {
    /// One step of Δt: tetrahedralise, α-shape, predict u* = u + Δt g, solve the pressure,
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
        let mesh = crate::mesh3d::tetrahedralise(&self.x);
        let shape = crate::mesh3d::alpha_shape(&self.x, &self.walls, &mesh, self.alpha_h_m);
        let volume_m3 = shape
            .kept
            .iter()
            .map(|&t| {
                let v = mesh.tets[t as usize].map(|i| Vector3::from(self.x[i as usize]));
                p1_tet(v).map_or(0.0, |e| e.volume)
            })
            .sum();
        // On a wall node u* is what the water beside it predicts; the wall's u·n = 0 enters
        // through the pressure's natural boundary condition.
        let u_star: Vec<Vector3<f64>> = self
            .u
            .iter()
            .map(|u| u + self.gravity_m_s2 * dt_s)
            .collect();
        self.p = pressure(&self.x, &mesh, &shape, &u_star, self.rho_kg_m3, dt_s)?;
        self.u = correct(
            &self.x,
            &mesh,
            &shape,
            &u_star,
            &self.p,
            self.rho_kg_m3,
            dt_s,
        )?;
        for i in 0..self.x.len() {
            if self.walls[i] != 0 {
                self.u[i] = Vector3::zeros();
            } else {
                for k in 0..3 {
                    self.x[i][k] += dt_s * self.u[i][k];
                }
            }
        }
        Ok(Step3 {
            volume_m3,
            tetrahedra: shape.kept.len(),
            slivers_kept: shape.slivers_kept,
        })
    }
}

#[cfg(test)]
mod tests;
