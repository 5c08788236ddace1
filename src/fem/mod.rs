//! Linear (P1) triangle kernels: pure functions of the element's nodes.
//!
//! On a triangle with nodes x₀, x₁, x₂ (counter-clockwise) and area A, the shape functions N_i
//! are linear and their gradients b_i = ∇N_i are constant:
//! b₀ = (y₁ − y₂, x₂ − x₁)/(2A), b₁ = (y₂ − y₀, x₀ − x₂)/(2A), b₂ = (y₀ − y₁, x₁ − x₀)/(2A).
//! Σ b_i = 0 (a constant field has no gradient) and Σ x_i ⊗ b_i = I (x has unit gradient).
//!
//! The element matrices of the fractional step (thesis eqs. 2.19–2.29, method.md §1) follow:
//! lumped mass ρA/3 per node, Laplacian A b_i·b_j, divergence (A/3) b_j, viscous force
//! −2μ_e A S_e b_i, with S_e the element's strain rate.

pub mod polygon;
pub mod tet;

use crate::case::TauFormula;
use nalgebra::{Matrix2, Vector2};

/// Area and shape-function gradients of one triangle.
#[derive(Debug, Clone, Copy)]
pub struct P1 {
    /// Signed area: positive for counter-clockwise nodes.
    pub area: f64,
    pub grad: [Vector2<f64>; 3],
}

/// Area and gradients of the triangle (x₀, x₁, x₂).
#[inline]
pub fn p1(x0: Vector2<f64>, x1: Vector2<f64>, x2: Vector2<f64>) -> P1 {
    let twice_area = (x1.x - x0.x) * (x2.y - x0.y) - (x2.x - x0.x) * (x1.y - x0.y);
    let inv = 1.0 / twice_area;
    P1 {
        area: 0.5 * twice_area,
        grad: [
            Vector2::new(x1.y - x2.y, x2.x - x1.x) * inv,
            Vector2::new(x2.y - x0.y, x0.x - x2.x) * inv,
            Vector2::new(x0.y - x1.y, x1.x - x0.x) * inv,
        ],
    }
}

/// Signed area of triangle `t` of the node array.
#[inline]
pub fn triangle_area(position: &[Vector2<f64>], t: &[u32; 3]) -> f64 {
    let [a, b, c] = t.map(|i| position[i as usize]);
    0.5 * ((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y))
}

/// Element size: the edge of the equilateral triangle with the same area, h_e = sqrt(4A/√3).
#[inline]
pub fn element_size(area: f64) -> f64 {
    (4.0 * area.abs() / 3f64.sqrt()).sqrt()
}

/// Velocity gradient G = ∇u = Σ u_j ⊗ b_j, G[(a, b)] = ∂u_a/∂x_b.
#[inline]
pub fn velocity_gradient(e: &P1, u: [Vector2<f64>; 3]) -> Matrix2<f64> {
    u[0] * e.grad[0].transpose() + u[1] * e.grad[1].transpose() + u[2] * e.grad[2].transpose()
}

/// Strain rate S = ½(G + Gᵀ) and its magnitude |S| = sqrt(2 S:S).
#[inline]
pub fn strain_rate(g: &Matrix2<f64>) -> (Matrix2<f64>, f64) {
    let s = 0.5 * (g + g.transpose());
    let mag = (2.0 * s.component_mul(&s).sum()).sqrt();
    (s, mag)
}

/// Effective dynamic viscosity with the Smagorinsky eddy viscosity (thesis eqs. 1.20–1.21):
/// μ_e = μ + ρ (C_s h_e)² |S|.
#[inline]
pub fn smagorinsky_viscosity(mu: f64, rho: f64, cs: f64, h_e: f64, strain_magnitude: f64) -> f64 {
    mu + rho * (cs * h_e).powi(2) * strain_magnitude
}

/// FIC/PSPG stabilisation parameter τ of one element, in m³·s/kg (the units of Δt/ρ).
/// See method.md §1: the thesis's τ = 3h²/(8μ) is the Stokes limit and swamps the pressure
/// equation for water; the default adds the transient term 2ρ/Δt.
#[inline]
pub fn tau(formula: TauFormula, rho: f64, mu_e: f64, h_e: f64, dt: f64, speed: f64) -> f64 {
    match formula {
        TauFormula::Inertial => 1.0 / (8.0 * mu_e / (3.0 * h_e * h_e) + 2.0 * rho / dt),
        TauFormula::Kratos => {
            1.0 / (rho * speed / h_e + rho / dt + 8.0 * mu_e.min(0.1) / (h_e * h_e))
        }
        TauFormula::Thesis => 3.0 * h_e * h_e / (8.0 * mu_e.max(f64::MIN_POSITIVE)),
        TauFormula::None => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> [Vector2<f64>; 3] {
        [
            Vector2::new(0.1, 0.2),
            Vector2::new(0.9, 0.35),
            Vector2::new(0.3, 1.1),
        ]
    }

    #[test]
    fn gradients_reproduce_linear_fields() {
        let [a, b, c] = tri();
        let e = p1(a, b, c);
        assert!(e.area > 0.0);
        let sum = e.grad[0] + e.grad[1] + e.grad[2];
        assert!(sum.norm() < 1e-14);
        // The gradient of the identity field is I.
        let g = velocity_gradient(&e, [a, b, c]);
        assert!((g - Matrix2::identity()).norm() < 1e-14);
        // A linear field f = 2x − 3y has gradient (2, −3).
        let f = |p: Vector2<f64>| 2.0 * p.x - 3.0 * p.y;
        let grad: Vector2<f64> = e.grad[0] * f(a) + e.grad[1] * f(b) + e.grad[2] * f(c);
        assert!((grad - Vector2::new(2.0, -3.0)).norm() < 1e-13);
    }

    #[test]
    fn laplacian_rows_sum_to_zero_and_are_symmetric() {
        let [a, b, c] = tri();
        let e = p1(a, b, c);
        for i in 0..3 {
            let row: f64 = (0..3).map(|j| e.area * e.grad[i].dot(&e.grad[j])).sum();
            assert!(row.abs() < 1e-13);
        }
    }

    #[test]
    fn strain_rate_of_pure_shear() {
        // u = (y, 0): S = [[0, ½], [½, 0]], |S| = sqrt(2·(¼+¼)) = 1.
        let [a, b, c] = tri();
        let e = p1(a, b, c);
        let u = [a, b, c].map(|p| Vector2::new(p.y, 0.0));
        let (s, mag) = strain_rate(&velocity_gradient(&e, u));
        assert!((s[(0, 1)] - 0.5).abs() < 1e-13 && s[(0, 0)].abs() < 1e-13);
        assert!((mag - 1.0).abs() < 1e-13);
    }

    #[test]
    fn tau_default_is_bounded_by_its_limits() {
        let dt = 1e-3;
        let t = tau(TauFormula::Inertial, 1000.0, 1e-3, 0.01, dt, 1.0);
        assert!(t < dt / 2000.0 && t > 0.99 * dt / 2000.0, "{t}");
        let thesis = tau(TauFormula::Thesis, 1000.0, 1e-3, 0.01, dt, 1.0);
        assert!((thesis - 0.0375).abs() < 1e-12);
        assert_eq!(element_size(3f64.sqrt() / 4.0), 1.0);
    }
}
