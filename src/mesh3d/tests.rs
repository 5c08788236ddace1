//! Tests of the tetrahedralisation against brute force: every tetrahedron positive and with an
//! empty circumsphere (exact predicates, every point), the adjacency symmetric, and the
//! boundary faces convex-hull facets (no point beyond them), which together make the result the
//! Delaunay tetrahedralisation of the whole hull.
use super::*;
use robust::{Coord3D, insphere, orient3d};

fn coord(p: &[f64; 3]) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

/// A xorshift cloud in the unit cube.
fn random_cloud(n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut s = seed;
    let mut r = move || {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n).map(|_| [r(), r(), r()]).collect()
}

fn lattice(nx: usize, ny: usize, nz: usize, h: f64) -> Vec<[f64; 3]> {
    let mut p = Vec::with_capacity(nx * ny * nz);
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..nz {
                p.push([i as f64 * h, j as f64 * h, k as f64 * h]);
            }
        }
    }
    p
}

/// The volume of a tetrahedron in `robust`'s orientation (positive when `orient3d` is: the
/// fourth node below the first three seen counter-clockwise, i.e. det[b−a, c−a, d−a] < 0).
fn volume(p: &[[f64; 3]], v: [u32; 4]) -> f64 {
    let [a, b, c, d] = v.map(|i| p[i as usize]);
    let s = |u: [f64; 3]| [u[0] - a[0], u[1] - a[1], u[2] - a[2]];
    let (x, y, z) = (s(b), s(c), s(d));
    (x[0] * (y[1] * z[2] - y[2] * z[1]) - x[1] * (y[0] * z[2] - y[2] * z[0])
        + x[2] * (y[0] * z[1] - y[1] * z[0]))
        / -6.0
}

/// Checks the result against brute force; returns (total volume, co-spherical ties met).
fn check_delaunay(p: &[[f64; 3]], mesh: &Tetrahedralisation) -> (f64, usize) {
    let mut total = 0.0;
    let mut ties = 0;
    let mut used = vec![false; p.len()];
    for (t, v) in mesh.tets.iter().enumerate() {
        let c = v.map(|i| coord(&p[i as usize]));
        assert!(
            orient3d(c[0], c[1], c[2], c[3]) > 0.0,
            "tet {t} not positive"
        );
        total += volume(p, *v);
        for (q, pq) in p.iter().enumerate() {
            let s = insphere(c[0], c[1], c[2], c[3], coord(pq));
            assert!(s <= 0.0, "point {q} inside the circumsphere of tet {t}");
            if s == 0.0 && !v.contains(&(q as u32)) {
                ties += 1;
            }
        }
        for i in 0..4 {
            used[v[i] as usize] = true;
            let n = mesh.neighbours[t][i];
            if n == NONE {
                // A boundary face must be a hull facet: no point beyond its plane.
                let mut w = *v;
                for q in 0..p.len() as u32 {
                    w[i] = q;
                    let s = orient3d(
                        coord(&p[w[0] as usize]),
                        coord(&p[w[1] as usize]),
                        coord(&p[w[2] as usize]),
                        coord(&p[w[3] as usize]),
                    );
                    assert!(
                        s >= 0.0,
                        "boundary face {t}/{i} is not on the hull: {q} beyond"
                    );
                }
            } else {
                let back = &mesh.neighbours[n as usize];
                let j = back.iter().position(|&m| m == t as u32).expect("symmetric");
                let mut face: Vec<u32> = (0..4).filter(|&k| k != i).map(|k| v[k]).collect();
                let w = mesh.tets[n as usize];
                let mut other: Vec<u32> = (0..4).filter(|&k| k != j).map(|k| w[k]).collect();
                face.sort_unstable();
                other.sort_unstable();
                assert_eq!(face, other, "tets {t} and {n} do not share their face");
            }
        }
    }
    for &d in &mesh.duplicates {
        used[d as usize] = true;
    }
    assert!(used.iter().all(|&u| u), "a point is in no tetrahedron");
    (total, ties)
}

#[test]
fn a_random_cloud_is_its_delaunay_tetrahedralisation() {
    let p = random_cloud(2000, 7);
    let mesh = tetrahedralise(&p);
    let (total, _) = check_delaunay(&p, &mesh);
    println!(
        "2000 random points: {} tetrahedra ({:.2} per point), volume {total:.4}",
        mesh.tets.len(),
        mesh.tets.len() as f64 / 2000.0
    );
    assert!(mesh.duplicates.is_empty());
    // A Delaunay tetrahedralisation of n random points has about 6.5 n tetrahedra.
    assert!((6.0..7.0).contains(&(mesh.tets.len() as f64 / 2000.0)));
}

#[test]
fn a_lattice_with_all_its_ties_fills_its_box() {
    // 10 × 10 × 20 nodes: every cube's eight corners are co-spherical.
    let h = 0.1;
    let p = lattice(10, 10, 20, h);
    let mesh = tetrahedralise(&p);
    let (total, ties) = check_delaunay(&p, &mesh);
    let exact = (9.0 * h) * (9.0 * h) * (19.0 * h);
    println!(
        "lattice of 2000: {} tetrahedra, {ties} co-spherical ties, volume {total:.15} of {exact}",
        mesh.tets.len()
    );
    assert!(ties > 0, "the lattice's ties were not exercised");
    assert!((total - exact).abs() < 1e-12 * exact);
    // Each cube is split into 5 or 6 tetrahedra.
    let cubes = 9 * 9 * 19;
    assert!(mesh.tets.len() >= 5 * cubes && mesh.tets.len() <= 6 * cubes);
}

#[test]
fn duplicates_are_reported_and_left_out() {
    let mut p = random_cloud(300, 11);
    p.push(p[17]);
    p.push(p[42]);
    let mesh = tetrahedralise(&p);
    let dups = &mesh.duplicates;
    // Either copy may be the one left out, whichever the insertion order met second.
    assert_eq!(dups.len(), 2);
    assert!(dups.contains(&17) != dups.contains(&300));
    assert!(dups.contains(&42) != dups.contains(&301));
    check_delaunay(&p, &mesh);
}

#[test]
fn degenerate_clouds_give_no_tetrahedra() {
    assert!(tetrahedralise(&random_cloud(3, 1)).tets.is_empty());
    let flat: Vec<[f64; 3]> = random_cloud(50, 5)
        .into_iter()
        .map(|q| [q[0], q[1], 0.25])
        .collect();
    assert!(tetrahedralise(&flat).tets.is_empty());
}

#[test]
fn a_cloud_far_from_the_origin_keeps_its_tetrahedra() {
    // A 0.5 m block of 1 cm particles 30 m down a flume: the rounding of absolute coordinates.
    let p: Vec<[f64; 3]> = random_cloud(1000, 3)
        .into_iter()
        .map(|q| [30.0 + 0.5 * q[0], 2.5 + 0.5 * q[1], 0.4 + 0.5 * q[2]])
        .collect();
    let mesh = tetrahedralise(&p);
    check_delaunay(&p, &mesh);
}

#[test]
fn the_alpha_test_keeps_a_lattices_cubes() {
    // A cube's tetrahedra have circumradius √3 h / 2 ≈ 0.87 h: kept at α = 1.2, dropped at 0.8.
    let h = 0.1;
    let p = lattice(5, 5, 5, h);
    let mesh = tetrahedralise(&p);
    assert_eq!(alpha_kept(&p, &mesh, 1.2 * h).len(), mesh.tets.len());
    assert!(alpha_kept(&p, &mesh, 0.8 * h).is_empty());
}
