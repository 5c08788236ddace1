//! 3D remeshing (issue 26), the first stage: the Delaunay tetrahedralisation of a particle
//! cloud (`delaunay`) and the α-shape on it (`alpha`: kept tetrahedra, free surface, slivers).
//! The 3D solver path (fractional step, walls, nodes) is not built yet; `surflab bench-tetra`
//! times the tetrahedralisation alone.

pub mod alpha;
pub mod delaunay;

pub use alpha::{AlphaShape, SLIVER_QUALITY, alpha_shape, quality};
pub use delaunay::{NONE, Tetrahedralisation, circumsphere, tetrahedralise};

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
