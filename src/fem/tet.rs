//! Linear (P1) tetrahedron kernels for the 3D path (issue 26): the same element matrices as the
//! triangle's in `fem`, one dimension up.
//!
//! With J = [x₁ − x₀, x₂ − x₀, x₃ − x₀] (columns), the gradients of N₁, N₂, N₃ are the rows of
//! J⁻¹ and ∇N₀ = −(∇N₁ + ∇N₂ + ∇N₃); V = |det J| / 6. Lumped mass ρV/4 per node, Laplacian
//! V b_i·b_j, divergence (V/4) b_j, viscous force −2μ_e V S_e b_i. The orientation of the
//! nodes does not matter (the 3D mesher's tetrahedra have det J < 0).

use nalgebra::{Matrix3, Vector3};

/// Volume and shape-function gradients of one tetrahedron.
#[derive(Debug, Clone, Copy)]
pub struct P1Tet {
    /// Volume, m³ (positive whatever the node order).
    pub volume: f64,
    pub grad: [Vector3<f64>; 4],
}

/// Volume and gradients of the tetrahedron (x₀, x₁, x₂, x₃); `None` when it is flat (the
/// Jacobian is not invertible).
pub fn p1_tet(x: [Vector3<f64>; 4]) -> Option<P1Tet> {
    let j = Matrix3::from_columns(&[x[1] - x[0], x[2] - x[0], x[3] - x[0]]);
    let det = j.determinant();
    let inv = j.try_inverse()?;
    let (g1, g2, g3) = (
        inv.row(0).transpose(),
        inv.row(1).transpose(),
        inv.row(2).transpose(),
    );
    Some(P1Tet {
        volume: det.abs() / 6.0,
        grad: [-(g1 + g2 + g3), g1, g2, g3],
    })
}

/// Element size: the edge of the regular tetrahedron of the same volume, h_e = (6√2 V)^⅓.
pub fn tet_size(volume: f64) -> f64 {
    (6.0 * 2f64.sqrt() * volume.abs()).cbrt()
}

/// Velocity gradient G = Σ u_j ⊗ b_j, G[(a, b)] = ∂u_a/∂x_b.
pub fn velocity_gradient(e: &P1Tet, u: [Vector3<f64>; 4]) -> Matrix3<f64> {
    (0..4).map(|j| u[j] * e.grad[j].transpose()).sum()
}

/// Strain rate S = ½(G + Gᵀ) and its magnitude |S| = sqrt(2 S:S).
pub fn strain_rate(g: &Matrix3<f64>) -> (Matrix3<f64>, f64) {
    let s = 0.5 * (g + g.transpose());
    let mag = (2.0 * s.component_mul(&s).sum()).sqrt();
    (s, mag)
}

/// The element's Laplacian, V b_i·b_j (symmetric, rows summing to zero).
pub fn laplacian(e: &P1Tet) -> [[f64; 4]; 4] {
    let mut k = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            k[i][j] = e.volume * e.grad[i].dot(&e.grad[j]);
        }
    }
    k
}

/// The element's viscous nodal forces, −2 μ_e V S b_i (N).
pub fn viscous_forces(e: &P1Tet, mu_e: f64, s: &Matrix3<f64>) -> [Vector3<f64>; 4] {
    e.grad.map(|b| -2.0 * mu_e * e.volume * (s * b))
}

#[cfg(test)]
mod tests;
