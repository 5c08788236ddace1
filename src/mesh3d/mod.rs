//! 3D remeshing (issue 26), the first stage: the Delaunay tetrahedralisation of a particle
//! cloud and the α-shape's radius test on it. The 3D solver path (kernels, fractional step,
//! walls) is not built yet; `surflab bench-tetra` times this stage alone.

pub mod delaunay;

pub use delaunay::{NONE, Tetrahedralisation, circumsphere, tetrahedralise};

/// The tetrahedra an α-shape keeps by its radius test: circumradius < `alpha_h_m` (α times the
/// particle spacing h, in metres). The wall rules of the 2D mesher (all-wall elements) are the
/// solver path's, not this test's.
pub fn alpha_kept(points: &[[f64; 3]], mesh: &Tetrahedralisation, alpha_h_m: f64) -> Vec<u32> {
    (0..mesh.tets.len() as u32)
        .filter(|&t| {
            let v = mesh.tets[t as usize].map(|i| &points[i as usize]);
            circumsphere(v[0], v[1], v[2], v[3]).1 < alpha_h_m
        })
        .collect()
}

/// The clouds `surflab bench-tetra` times: `n` random points in the unit cube (a fixed
/// xorshift sequence), or the cubic lattice of about `n` nodes (every cube's corners
/// co-spherical: the exact predicates' slow path).
pub fn bench_cloud(n: usize, lattice: bool) -> Vec<[f64; 3]> {
    if lattice {
        let side = (n as f64).cbrt().round().max(2.0) as usize;
        let h = 1.0 / (side - 1) as f64;
        let mut p = Vec::with_capacity(side * side * side);
        for i in 0..side {
            for j in 0..side {
                for k in 0..side {
                    p.push([i as f64 * h, j as f64 * h, k as f64 * h]);
                }
            }
        }
        p
    } else {
        let mut s: u64 = 0x2545_f491_4f6c_dd1d;
        let mut r = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        (0..n).map(|_| [r(), r(), r()]).collect()
    }
}

#[cfg(test)]
mod tests;
