//! 3D remeshing (issue 26), the first stage: the Delaunay tetrahedralisation of a particle
//! cloud (`delaunay`) and the α-shape on it (`alpha`: kept tetrahedra, free surface, slivers).
//! `solver3d` steps on them; `surflab bench-tetra` times the tetrahedralisation alone.

pub mod alpha;
pub mod delaunay;
mod exact;
mod order;

pub use alpha::{
    AlphaShape, ContactLine, InSolid, SLIVER_QUALITY, WATER_ALPHA_FACTOR, alpha_shape,
    alpha_shape_with, quality,
};
pub use delaunay::{NONE, Tetrahedralisation, Tetrahedraliser, circumsphere, tetrahedralise};

/// A xorshift sequence in [0, 1) from a non-zero seed: the test and benchmark clouds'.
fn xorshift(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `n` points uniform in the unit cube (a xorshift sequence from `seed`, non-zero).
pub fn random_cloud(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut r = xorshift(seed);
    (0..n).map(|_| [r(), r(), r()]).collect()
}

/// The clouds `surflab bench-tetra` times: `n` random points in the unit cube (a fixed
/// sequence), or the cubic lattice of about `n` nodes (every cube's corners co-spherical: the
/// exact predicates' slow path).
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
        random_cloud(n, 0x2545_f491_4f6c_dd1d)
    }
}

/// A tank of still water on an nx × ny × nz lattice at spacing `h_m`, y up (x along the tank,
/// z across it, as in the 3D cases): one layer of wall nodes on the bed and the four sides
/// (bits 0–4 of a node's wall mask: bed y = 0, x = 0, x = max, z = 0, z = max), fluid nodes
/// inside, the top layer free. `jitter` moves the fluid nodes by up to ± jitter/2 h (a xorshift
/// sequence from `seed`), the top layer's too when `jitter_top`. Returns the points and their
/// wall masks (see [`alpha_shape`]).
pub fn lattice_tank(
    [nx, ny, nz]: [usize; 3],
    h_m: f64,
    jitter: f64,
    jitter_top: bool,
    seed: u64,
) -> (Vec<[f64; 3]>, Vec<u16>) {
    let mut r = xorshift(seed);
    let (mut p, mut walls) = (Vec::new(), Vec::new());
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..nz {
                let mask = (j == 0) as u16
                    | ((i == 0) as u16) << 1
                    | ((i + 1 == nx) as u16) << 2
                    | ((k == 0) as u16) << 3
                    | ((k + 1 == nz) as u16) << 4;
                let moved = mask == 0 && (jitter_top || j + 1 < ny);
                let d = if moved { jitter * h_m } else { 0.0 };
                p.push([
                    i as f64 * h_m + d * (r() - 0.5),
                    j as f64 * h_m + d * (r() - 0.5),
                    k as f64 * h_m + d * (r() - 0.5),
                ]);
                walls.push(mask);
            }
        }
    }
    (p, walls)
}

#[cfg(test)]
mod tests;
