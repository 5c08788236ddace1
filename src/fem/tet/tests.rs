//! The P1 tetrahedron: single-element identities, then patch tests on a 3D Delaunay mesh of a
//! random cloud (the 3D mesher's output): a linear field's nodal gradient and divergence are
//! exact at every node, and the assembled Laplacian annihilates it at every interior node.
use super::*;
use crate::mesh3d::{NONE, bench_cloud, tetrahedralise};

fn sample() -> [Vector3<f64>; 4] {
    [
        Vector3::new(0.1, 0.2, 0.05),
        Vector3::new(0.9, 0.35, 0.1),
        Vector3::new(0.3, 1.1, 0.2),
        Vector3::new(0.4, 0.5, 0.8),
    ]
}

#[test]
fn gradients_reproduce_linear_fields_on_one_tetrahedron() {
    let x = sample();
    let e = p1_tet(x).unwrap();
    let sum: Vector3<f64> = e.grad.iter().sum();
    assert!(sum.norm() < 1e-14);
    assert!((velocity_gradient(&e, x) - Matrix3::identity()).norm() < 1e-13);
    // The volume by the scalar triple product.
    let v = (x[1] - x[0])
        .cross(&(x[2] - x[0]))
        .dot(&(x[3] - x[0]))
        .abs()
        / 6.0;
    assert!((e.volume - v).abs() < 1e-15);
    // Node order does not change the volume or the gradients' node-by-node values.
    let f = p1_tet([x[1], x[0], x[2], x[3]]).unwrap();
    assert!((f.volume - e.volume).abs() < 1e-15);
    assert!((f.grad[0] - e.grad[1]).norm() < 1e-13);
    let k = laplacian(&e);
    for i in 0..4 {
        assert!(k[i].iter().sum::<f64>().abs() < 1e-13);
        for j in 0..4 {
            assert_eq!(k[i][j], k[j][i]);
        }
    }
}

#[test]
fn a_flat_tetrahedron_is_refused() {
    let x = sample().map(|p| Vector3::new(p.x, p.y, 0.25));
    assert!(p1_tet(x).is_none());
}

#[test]
fn shear_strain_and_viscous_forces_balance() {
    // u = (z, 0, 0): S has ½ at (0, 2) and (2, 0), |S| = 1; the forces sum to zero.
    let x = sample();
    let e = p1_tet(x).unwrap();
    let u = x.map(|p| Vector3::new(p.z, 0.0, 0.0));
    let (s, mag) = strain_rate(&velocity_gradient(&e, u));
    assert!((s[(0, 2)] - 0.5).abs() < 1e-13 && s[(0, 0)].abs() < 1e-13);
    assert!((mag - 1.0).abs() < 1e-13);
    let f: Vector3<f64> = viscous_forces(&e, 1e-3, &s).iter().sum();
    assert!(f.norm() < 1e-18);
}

#[test]
fn the_regular_tetrahedron_has_its_edge_as_size() {
    let a = 0.02;
    let v = a * a * a / (6.0 * 2f64.sqrt());
    assert!((tet_size(v) - a).abs() < 1e-15);
}

#[test]
fn patch_tests_on_a_delaunay_mesh() {
    let cloud = bench_cloud(600, false);
    let mesh = tetrahedralise(&cloud);
    let x: Vec<Vector3<f64>> = cloud.iter().map(|p| Vector3::from(*p)).collect();
    let n = x.len();
    let grad_p = Vector3::new(2.0, -3.0, 0.5);
    let p: Vec<f64> = x.iter().map(|q| 1.0 + grad_p.dot(q)).collect();
    // u linear with divergence 1.5 − 0.5 + 2 = 3.
    let u: Vec<Vector3<f64>> = x
        .iter()
        .map(|q| Vector3::new(1.5 * q.x + q.y, -0.5 * q.y + 0.2 * q.z, q.x + 2.0 * q.z))
        .collect();
    let mut mass = vec![0.0; n];
    let mut grad = vec![Vector3::zeros(); n];
    let mut div = vec![0.0; n];
    let mut kp = vec![0.0; n];
    let mut scale = vec![0.0; n];
    let mut boundary = vec![false; n];
    let mut total = 0.0;
    for (t, v) in mesh.tets.iter().enumerate() {
        let e = p1_tet(v.map(|i| x[i as usize])).expect("a Delaunay tetrahedron is not flat");
        total += e.volume;
        let k = laplacian(&e);
        let g: Vector3<f64> = (0..4).map(|j| e.grad[j] * p[v[j] as usize]).sum();
        let d: f64 = (0..4).map(|j| e.grad[j].dot(&u[v[j] as usize])).sum();
        for i in 0..4 {
            let vi = v[i] as usize;
            mass[vi] += e.volume / 4.0;
            grad[vi] += g * e.volume / 4.0;
            div[vi] += d * e.volume / 4.0;
            kp[vi] += (0..4).map(|j| k[i][j] * p[v[j] as usize]).sum::<f64>();
            scale[vi] += e.volume * e.grad[i].norm() * grad_p.norm();
            if mesh.neighbours[t][i] == NONE {
                for j in (0..4).filter(|&j| j != i) {
                    boundary[v[j] as usize] = true;
                }
            }
        }
    }
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    let mut interior = 0;
    for i in 0..n {
        worst.0 = worst
            .0
            .max((grad[i] / mass[i] - grad_p).norm() / grad_p.norm());
        worst.1 = worst.1.max((div[i] / mass[i] - 3.0).abs() / 3.0);
        if !boundary[i] {
            interior += 1;
            worst.2 = worst.2.max(kp[i].abs() / scale[i]);
        }
    }
    println!(
        "{} tetrahedra, volume {total:.4}, {interior} interior nodes of {n}: nodal gradient {:.1e}, \
         divergence {:.1e}, Laplacian row {:.1e} (relative)",
        mesh.tets.len(),
        worst.0,
        worst.1,
        worst.2
    );
    assert!(interior > 200);
    assert!(worst.0 < 1e-12 && worst.1 < 1e-12, "{worst:?}");
    assert!(worst.2 < 1e-10, "{worst:?}");
}
