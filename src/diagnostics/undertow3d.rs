//! Undertow stations in a 3D tank (issue 26): the 2D stations' bins and averages
//! ([`super::undertow::Stations`]) read from a vertical line at (x, z) through the kept
//! tetrahedra. Along the line's segment inside a tetrahedron the P1 velocity is linear, so
//! ∫u₁ dy is exact, as on the 2D triangles.

use super::undertow::{Station, StationFlow, add_segment};
use crate::simulation3d::Simulation3;
use nalgebra::{Matrix3, Vector3};

/// The station's line is moved by this many spacings (along x and z, by irrational factors) so
/// that it never runs along a face or an edge, where two tetrahedra would both count it.
const OFF_THE_FACES_H: f64 = 1e-9;

impl StationFlow for Simulation3 {
    fn time_s(&self) -> f64 {
        self.time_s
    }

    fn sections(&self, stations: &[Station], dz_m: f64) -> Vec<(Vec<f64>, Vec<f64>)> {
        let f = &self.flow;
        let e = OFF_THE_FACES_H * f.h_m;
        let lines: Vec<(f64, f64)> = stations
            .iter()
            .map(|s| {
                (
                    s.x_m + e * std::f64::consts::SQRT_2,
                    s.z_m + e * 3f64.sqrt(),
                )
            })
            .collect();
        let mut out: Vec<(Vec<f64>, Vec<f64>)> = stations
            .iter()
            .map(|s| (vec![0.0; s.bins], vec![0.0; s.bins]))
            .collect();
        for t in &f.tetrahedra {
            let p = t.map(|i| f.x[i as usize]);
            let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for q in &p {
                for (k, axis) in [0, 2].into_iter().enumerate() {
                    lo[k] = lo[k].min(q[axis]);
                    hi[k] = hi[k].max(q[axis]);
                }
            }
            for ((s, &(x, z)), (flux, wet)) in stations.iter().zip(&lines).zip(out.iter_mut()) {
                if x < lo[0] || x > hi[0] || z < lo[1] || z > hi[1] {
                    continue;
                }
                let u = t.map(|i| f.u[i as usize].x);
                if let Some(((y0, u0), (y1, u1))) = vertical_section(&p, &u, x, z) {
                    add_segment(s, dz_m, y0, u0, y1, u1, flux, wet);
                }
            }
        }
        out
    }

    fn elevation_m(&self, station: &Station) -> Option<f64> {
        let level = self.case.still_level_at(station.x_m)?;
        self.flow
            .surface_heights_at(station.x_m, station.z_m)
            .first()
            .map(|y| y - level)
    }

    /// The kept tetrahedra whose centroid lies beyond x, per metre of width.
    fn water_right_of_m2(&self, x_m: f64) -> f64 {
        let f = &self.flow;
        let width = self.case.flume.width_m.unwrap_or(1.0);
        f.tetrahedra
            .iter()
            .map(|t| t.map(|i| Vector3::from(f.x[i as usize])))
            .filter(|v| (v[0].x + v[1].x + v[2].x + v[3].x) / 4.0 > x_m)
            .map(|v| {
                (v[1] - v[0])
                    .dot(&(v[2] - v[0]).cross(&(v[3] - v[0])))
                    .abs()
                    / 6.0
            })
            .sum::<f64>()
            / width
    }

    /// The 3D path has no volume ledger.
    fn numerics_right_of_m2(&self, _x_m: f64) -> f64 {
        0.0
    }
}

/// The segment of the vertical line (x, ·, z) inside the tetrahedron `p`, as ((y, u) low,
/// (y, u) high) with u the P1 interpolation of the nodal `u`; `None` when the line misses it
/// or the tetrahedron is flat.
pub fn vertical_section(
    p: &[[f64; 3]; 4],
    u: &[f64; 4],
    x: f64,
    z: f64,
) -> Option<((f64, f64), (f64, f64))> {
    let v = p.map(Vector3::from);
    let inverse = Matrix3::from_columns(&[v[1] - v[0], v[2] - v[0], v[3] - v[0]]).try_inverse()?;
    // The barycentric coordinates along the line are affine in y: λ = α + β y.
    let base = inverse * Vector3::new(x - v[0].x, -v[0].y, z - v[0].z);
    let rate = inverse * Vector3::new(0.0, 1.0, 0.0);
    let alpha = [1.0 - base.sum(), base.x, base.y, base.z];
    let beta = [-rate.sum(), rate.x, rate.y, rate.z];
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..4 {
        if beta[k] == 0.0 {
            if alpha[k] < 0.0 {
                return None;
            }
        } else if beta[k] > 0.0 {
            lo = lo.max(-alpha[k] / beta[k]);
        } else {
            hi = hi.min(-alpha[k] / beta[k]);
        }
    }
    // Empty, or not a number (a tetrahedron too flat for its inverse).
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let at = |y: f64| (0..4).map(|k| (alpha[k] + beta[k] * y) * u[k]).sum::<f64>();
    Some(((lo, at(lo)), (hi, at(hi))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_vertical_line_through_a_tetrahedron_integrates_a_linear_field_exactly() {
        // The corner tetrahedron of the unit cube, u = 1 + 2x + 3y + 4z at its nodes.
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ];
        let field = |q: &[f64; 3]| 1.0 + 2.0 * q[0] + 3.0 * q[1] + 4.0 * q[2];
        let u = p.map(|q| field(&q));
        let (x, z) = (0.2, 0.3);
        let ((y0, u0), (y1, u1)) = vertical_section(&p, &u, x, z).unwrap();
        // From the bed face y = 0 to the slanted face x + y + z = 1.
        assert!(y0.abs() < 1e-15 && (y1 - 0.5).abs() < 1e-15, "{y0} {y1}");
        assert!((u0 - field(&[x, 0.0, z])).abs() < 1e-14);
        assert!((u1 - field(&[x, 0.5, z])).abs() < 1e-14);
        assert!(vertical_section(&p, &u, 0.7, 0.4).is_none());
        assert!(vertical_section(&p, &u, -0.1, 0.4).is_none());
    }
}
