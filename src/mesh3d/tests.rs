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
    let fluid = vec![0u16; p.len()];
    let mesh = tetrahedralise(&p);
    assert_eq!(
        alpha_shape(&p, &fluid, &mesh, 1.2 * h).kept.len(),
        mesh.tets.len()
    );
    assert!(alpha_shape(&p, &fluid, &mesh, 0.8 * h).kept.is_empty());
}

/// The tank of [`lattice_tank`] with its top jittered too.
fn tank(nx: usize, ny: usize, nz: usize, h: f64, jitter: f64) -> (Vec<[f64; 3]>, Vec<u16>) {
    lattice_tank([nx, ny, nz], h, jitter, true, 0x9e37_79b9_7f4a_7c15)
}

fn kept_volume(p: &[[f64; 3]], mesh: &Tetrahedralisation, shape: &AlphaShape) -> f64 {
    shape
        .kept
        .iter()
        .map(|&t| volume(p, mesh.tets[t as usize]))
        .sum()
}

#[test]
fn a_lattice_tank_keeps_its_water_and_frees_its_top() {
    let (nx, ny, nz, h) = (8, 5, 8, 0.02);
    let (p, wall) = tank(nx, ny, nz, h, 0.0);
    let mesh = tetrahedralise(&p);
    let shape = alpha_shape(&p, &wall, &mesh, 1.2 * h);
    let (lx, ly, lz) = (7.0 * h, 4.0 * h, 7.0 * h);
    let water = kept_volume(&p, &mesh, &shape);
    // The surface: area and outward normal, +y everywhere.
    let mut area = 0.0;
    for f in &shape.surface {
        let [a, b, c] = f.map(|i| p[i as usize]);
        let nrm = [
            (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
            (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]),
        ];
        assert!(nrm[1] > 0.0 && nrm[0].abs() < 1e-15 && nrm[2].abs() < 1e-15);
        area += 0.5 * nrm[1];
    }
    let top = (0..p.len())
        .filter(|&i| (p[i][1] - ly).abs() < 1e-12)
        .count();
    let free = shape.free_surface.iter().filter(|&&f| f).count();
    println!(
        "tank {nx}×{ny}×{nz}: {} of {} tetrahedra kept, volume {water:.3e} of {:.3e} m³, \
         surface {area:.3e} of {:.3e} m², {free} free-surface nodes of {top} on top, slivers {}",
        shape.kept.len(),
        mesh.tets.len(),
        lx * ly * lz,
        lx * lz,
        shape.slivers_kept + shape.slivers_dropped
    );
    assert!((water - lx * ly * lz).abs() < 1e-12 * lx * ly * lz);
    assert!((area - lx * lz).abs() < 1e-12 * lx * lz);
    assert_eq!(free, top);
    assert!(shape.in_mesh.iter().all(|&m| m));
    assert_eq!(shape.slivers_kept + shape.slivers_dropped, 0);
}

#[test]
fn an_all_wall_tank_without_water_keeps_nothing() {
    let h = 0.02;
    let (p, _) = tank(6, 4, 6, h, 0.0);
    let all_wall = vec![1u16; p.len()];
    let mesh = tetrahedralise(&p);
    let shape = alpha_shape(&p, &all_wall, &mesh, 1.2 * h);
    assert!(shape.kept.is_empty() && shape.surface.is_empty());
}

#[test]
fn slivers_of_a_jittered_tank_are_kept_inside_and_peeled_off_the_surface() {
    let (nx, ny, nz, h) = (12, 8, 12, 0.02);
    let (p, wall) = tank(nx, ny, nz, h, 0.3);
    let mesh = tetrahedralise(&p);
    let shape = alpha_shape(&p, &wall, &mesh, 1.2 * h);
    let box_volume = (11.0 * h) * (7.0 * h) * (11.0 * h);
    let water = kept_volume(&p, &mesh, &shape);
    let slivers_left_on_surface = shape
        .kept
        .iter()
        .filter(|&&t| {
            let v = mesh.tets[t as usize].map(|i| &p[i as usize]);
            quality(v) < SLIVER_QUALITY
                && shape
                    .surface
                    .iter()
                    .any(|f| f.iter().all(|i| mesh.tets[t as usize].contains(i)))
        })
        .count();
    println!(
        "jittered tank (±0.15 h): {} tetrahedra, {} kept; slivers kept inside {}, dropped from \
         the surface {}; volume {:.4} of the box",
        mesh.tets.len(),
        shape.kept.len(),
        shape.slivers_kept,
        shape.slivers_dropped,
        water / box_volume
    );
    assert_eq!(slivers_left_on_surface, 0);
    assert!(
        shape.slivers_kept > 0 && shape.slivers_dropped > 0,
        "the jitter made no sliver inside or on the surface: the test tests nothing"
    );
    assert!((water / box_volume - 1.0).abs() < 0.01);
}

#[test]
fn quality_of_the_regular_and_kuhn_tetrahedra() {
    let s = 2f64.sqrt();
    let regular = [
        [1.0, 0.0, -1.0 / s],
        [-1.0, 0.0, -1.0 / s],
        [0.0, 1.0, 1.0 / s],
        [0.0, -1.0, 1.0 / s],
    ];
    assert!((quality([&regular[0], &regular[1], &regular[2], &regular[3]]) - 1.0).abs() < 1e-14);
    let kuhn = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 1.0, 1.0],
    ];
    let q = quality([&kuhn[0], &kuhn[1], &kuhn[2], &kuhn[3]]);
    assert!(
        (q - 2f64.sqrt() / (10.0f64 / 6.0).powf(1.5)).abs() < 1e-14,
        "{q}"
    );
    let flat = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    assert_eq!(quality([&flat[0], &flat[1], &flat[2], &flat[3]]), 0.0);
}

/// How many tetrahedra of `mesh` (fluid nodes only) the α-shape keeps after a step whose free
/// surface was `was_free`.
fn kept_after(p: &[[f64; 3]], mesh: &Tetrahedralisation, was_free: &[bool], alpha_h: f64) -> usize {
    let contact = ContactLine {
        was_free,
        up_axis: 1,
    };
    let walls = vec![0u16; p.len()];
    alpha_shape_with(p, &walls, mesh, alpha_h, Some(contact), None)
        .kept
        .len()
}

#[test]
fn a_surface_sliver_with_a_node_of_the_water_stays_and_a_skin_is_peeled() {
    // Three surface nodes on a circle of radius 0.6 h and a fourth 0.03 h under that circle:
    // a sliver (q 0.046) of small circumradius, alone, so every face is on the surface.
    let (h, r, d) = (0.02, 0.012, 0.0006);
    let s = 3f64.sqrt() / 2.0;
    let p = vec![
        [r, 0.0, 0.0],
        [-r / 2.0, 0.0, r * s],
        [-r / 2.0, 0.0, -r * s],
        [-r, -d, 0.0],
    ];
    let q = quality([&p[0], &p[1], &p[2], &p[3]]);
    let mesh = tetrahedralise(&p);
    let kept = |was_free: &[bool]| kept_after(&p, &mesh, was_free, 1.2 * h);
    let (water, skin) = (kept(&[true, true, true, false]), kept(&[true; 4]));
    println!("sliver q {q:.3}: kept with a node of the water {water}, as a skin {skin}");
    assert!(q < SLIVER_QUALITY && mesh.tets.len() == 1);
    assert_eq!((water, skin), (1, 0));
}

#[test]
fn a_stretched_tetrahedron_holding_a_node_of_the_water_stays_water() {
    // A regular tetrahedron whose circumradius is 1.2 α h: air when its four nodes were on
    // the last free surface, water when one was inside it (up to WATER_ALPHA_FACTOR α h).
    let alpha_h = 0.024;
    let c = 1.2 * alpha_h / 3f64.sqrt();
    let p = vec![[c, c, c], [c, -c, -c], [-c, c, -c], [-c, -c, c]];
    let mesh = tetrahedralise(&p);
    let kept = |was_free: &[bool]| kept_after(&p, &mesh, was_free, alpha_h);
    let (water, air) = (kept(&[true, false, true, true]), kept(&[true; 4]));
    println!("R = 1.2 α h: kept with a node of the water {water}, with four surface nodes {air}");
    assert!(WATER_ALPHA_FACTOR > 1.2 && mesh.tets.len() == 1);
    assert_eq!((water, air), (1, 0));
}
