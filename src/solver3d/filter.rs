//! The 3D form of the 2D solver's surface filter (`solver.surface_filter` = ε > 0,
//! `solver/filter.rs`): a fourth-difference filter of the corrected velocities of the
//! free-surface fluid nodes, along the surface, applied before the move.
//!
//! In 2D the filter walks the surface chain, u_i ← u_i − (ε/16) δ⁴u_i. With the umbrella
//! operator of the surface mesh, (L u)_i = mean of u over i's surface neighbours − u_i, the
//! chain's fourth difference is 4 L(L u), so the same filter on a triangulated surface is
//!
//! u_i ← u_i − (ε/4) (L(L u))_i.
//!
//! On a chain this is the 2D filter exactly; on a surface a wave or a ripple loses the chain's
//! share times a factor of order one that depends on the valences (4/9 on a lattice of six
//! neighbours: a wave of length λ ≫ h about (4/9) ε (kh)⁴/16 per step, a ripple of two
//! spacings 4ε/9). L is computed only at "plain" nodes: fluid nodes whose every surface edge
//! is shared by two free-surface triangles (the surface closes around them: neither a contact
//! line with a wall nor an edge of a sheet or a branch) and whose every surface neighbour is a
//! fluid node; the filter changes a plain node whose neighbours are all plain. Elsewhere
//! (within two nodes of a wall, a tear or a thin sheet's edge) the velocity is left alone, as
//! the 2D filter leaves the ends of a chain.

use nalgebra::Vector3;

/// Filters `u` along the free surface `surface` (outward triangles of node indices) with
/// strength `eps`; `walls[i] != 0` marks wall nodes. Returns how many nodes it changed.
pub fn filter_surface(
    u: &mut [Vector3<f64>],
    surface: &[[u32; 3]],
    walls: &[u16],
    eps: f64,
) -> usize {
    let mut edges: Vec<(u32, u32)> = Vec::with_capacity(3 * surface.len());
    for t in surface {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.push((a.min(b), a.max(b)));
        }
    }
    edges.sort_unstable();
    // Each distinct edge once, with how many surface triangles share it.
    let mut distinct: Vec<((u32, u32), u32)> = Vec::with_capacity(edges.len() / 2 + 1);
    for e in edges {
        match distinct.last_mut() {
            Some((last, count)) if *last == e => *count += 1,
            _ => distinct.push((e, 1)),
        }
    }
    // Per node: its neighbours (CSR), and whether every edge at it is shared by two triangles.
    let n = u.len();
    let mut closed = vec![true; n];
    let mut degree = vec![0u32; n + 1];
    for &((a, b), count) in &distinct {
        degree[a as usize] += 1;
        degree[b as usize] += 1;
        if count != 2 {
            closed[a as usize] = false;
            closed[b as usize] = false;
        }
    }
    let mut start = vec![0usize; n + 1];
    for i in 0..n {
        start[i + 1] = start[i] + degree[i] as usize;
    }
    let mut fill = start.clone();
    let mut neighbours = vec![0u32; start[n]];
    for &((a, b), _) in &distinct {
        neighbours[fill[a as usize]] = b;
        fill[a as usize] += 1;
        neighbours[fill[b as usize]] = a;
        fill[b as usize] += 1;
    }
    let around = |i: usize| &neighbours[start[i]..start[i + 1]];
    let plain: Vec<bool> = (0..n)
        .map(|i| {
            start[i + 1] > start[i]
                && walls[i] == 0
                && closed[i]
                && around(i).iter().all(|&j| walls[j as usize] == 0)
        })
        .collect();
    let umbrella = |v: &[Vector3<f64>], i: usize| {
        let nb = around(i);
        nb.iter().map(|&j| v[j as usize]).sum::<Vector3<f64>>() / nb.len() as f64 - v[i]
    };
    let mut lu = vec![Vector3::zeros(); n];
    for i in (0..n).filter(|&i| plain[i]) {
        lu[i] = umbrella(u, i);
    }
    let mut changed = 0;
    for i in 0..n {
        if plain[i] && around(i).iter().all(|&j| plain[j as usize]) {
            u[i] -= eps / 4.0 * umbrella(&lu, i);
            changed += 1;
        }
    }
    changed
}

#[cfg(test)]
mod tests {
    use super::filter_surface;
    use nalgebra::Vector3;

    /// A closed surface of (nx × nz) nodes on a torus (periodic both ways), each square split
    /// by one diagonal: every node has six neighbours, every edge two triangles.
    fn torus(nx: usize, nz: usize) -> Vec<[u32; 3]> {
        let id = |i: usize, k: usize| ((i % nx) * nz + k % nz) as u32;
        let mut t = Vec::new();
        for i in 0..nx {
            for k in 0..nz {
                let (a, b, c, d) = (id(i, k), id(i + 1, k), id(i + 1, k + 1), id(i, k + 1));
                t.push([a, b, c]);
                t.push([a, c, d]);
            }
        }
        t
    }

    /// On a closed surface lattice a constant velocity is kept, and a field that varies along
    /// x only loses 4/9 of what the 2D chain filter takes: at a node of this lattice the six
    /// neighbours hold f(i ± 1) twice and f(i) twice, so L is 2/3 of the chain's umbrella and
    /// L² 4/9 of it. A long wave keeps 1 − (4/9) ε (2 − 2 cos kh)²/16 of itself, the ripple of
    /// two spacings 1 − 4ε/9. A wall node, its six neighbours (not plain) and the twelve plain
    /// nodes around them keep their velocity.
    #[test]
    fn the_3d_filter_removes_the_ripple_and_keeps_the_wave() {
        let (nx, nz) = (40, 8);
        let surface = torus(nx, nz);
        let n = nx * nz;
        let eps = 0.5;
        let mut walls = vec![0u16; n];
        let k = 2.0 * std::f64::consts::PI / nx as f64; // h = 1
        for (shape, expected) in [
            (Box::new(|_: usize| 1.0) as Box<dyn Fn(usize) -> f64>, 1.0),
            (Box::new(move |i: usize| (k * i as f64).sin()), f64::NAN),
            (
                Box::new(|i: usize| if i.is_multiple_of(2) { 1.0 } else { -1.0 }),
                1.0 - 4.0 * eps / 9.0,
            ),
        ] {
            let mut u: Vec<Vector3<f64>> = (0..n)
                .map(|m| Vector3::new(0.0, shape(m / nz), 0.0))
                .collect();
            assert_eq!(filter_surface(&mut u, &surface, &walls, eps), n);
            for m in 0..n {
                let ratio = u[m].y / shape(m / nz);
                if expected.is_nan() {
                    // 4/9 of the chain's symbol ε (2 − 2 cos k)²/16, away from the zeros.
                    if shape(m / nz).abs() > 0.3 {
                        let chain = 1.0 - 4.0 / 9.0 * eps * (2.0 - 2.0 * k.cos()).powi(2) / 16.0;
                        assert!((ratio - chain).abs() < 1e-12, "{ratio} against {chain}");
                    }
                } else {
                    assert!(
                        (ratio - expected).abs() < 1e-12,
                        "{ratio} against {expected}"
                    );
                }
            }
        }
        walls[0] = 1;
        let mut u: Vec<Vector3<f64>> = (0..n)
            .map(|m| {
                Vector3::new(
                    0.0,
                    if (m / nz).is_multiple_of(2) {
                        1.0
                    } else {
                        -1.0
                    },
                    0.0,
                )
            })
            .collect();
        let before = u.clone();
        let changed = filter_surface(&mut u, &surface, &walls, eps);
        assert_eq!(changed, n - 19);
        let kept = (0..n).filter(|&m| u[m] == before[m]).count();
        assert_eq!((kept, u[0]), (19, before[0]));
    }
}
