//! Still water, one step: from rest, the predicted velocity is g Δt everywhere; the pressure
//! must be hydrostatic and the corrected velocity zero.
use super::*;
use crate::mesh3d::{alpha_shape, tetrahedralise};

const RHO: f64 = 1000.0;
const G: f64 = 9.81;
const DT: f64 = 0.01;

/// The points and wall masks of [`still_tank`].
fn tank(nx: usize, ny: usize, nz: usize, h: f64, jitter: f64) -> (Vec<[f64; 3]>, Vec<u16>) {
    let flow = still_tank(nx, ny, nz, h, jitter);
    (flow.x, flow.walls)
}

/// (worst |p − ρ g (η − z)| / (ρ g depth), worst speed after the step in m/s)
fn one_step_at_rest(
    p: &[[f64; 3]],
    walls: &[u16],
    h: f64,
    eta: f64,
    depth: f64,
    solver: Solver3,
) -> (f64, f64) {
    let mesh = tetrahedralise(p);
    let shape = alpha_shape(p, walls, &mesh, 1.2 * h);
    let u_star = vec![Vector3::new(0.0, 0.0, -G * DT); p.len()];
    let elements = elements(p, &mesh, &shape).unwrap();
    let (pressure, _) = pressure(&mesh, &shape, &elements, &u_star, RHO, DT, solver).unwrap();
    let u = correct(&mesh, &shape, &elements, &u_star, &pressure, RHO, DT);
    let mut worst_p = 0.0f64;
    let mut worst_u = 0.0f64;
    for i in 0..p.len() {
        if !shape.in_mesh[i] {
            continue;
        }
        let hydrostatic = RHO * G * (eta - p[i][2]);
        let exact = if shape.free_surface[i] {
            0.0
        } else {
            hydrostatic
        };
        worst_p = worst_p.max((pressure[i] - exact).abs() / (RHO * G * depth));
        worst_u = worst_u.max(u[i].norm());
    }
    (worst_p, worst_u)
}

#[test]
fn a_lattice_tank_is_hydrostatic_and_stays_at_rest() {
    let h = 0.02;
    let (p, walls) = tank(8, 8, 6, h, 0.0);
    let depth = 5.0 * h;
    let (err_p, speed) = one_step_at_rest(&p, &walls, h, depth, depth, Solver3::Cholesky);
    println!(
        "lattice tank 8×8×6, h = 2 cm: pressure error {err_p:.1e} of ρ g d, speed after one \
         10 ms step {speed:.1e} m/s"
    );
    assert!(err_p < 1e-12 && speed < 1e-12);
}

#[test]
fn a_jittered_tank_with_a_flat_top_is_hydrostatic_and_stays_at_rest() {
    // An irregular mesh (the interior nodes moved by ± 0.15 h) under a flat free
    // surface: the hydrostatic pressure is linear, so P1 must give it to round-off. (A rough
    // surface is not at rest: its bumps start to fall, physically.)
    let h = 0.02;
    let (p, walls) = tank(10, 10, 8, h, 0.3);
    let depth = 7.0 * h;
    let (err_p, speed) = one_step_at_rest(&p, &walls, h, depth, depth, Solver3::Cholesky);
    // Conjugate gradients to 1e-10 give the same answer to that tolerance.
    let (err_cg, speed_cg) = one_step_at_rest(&p, &walls, h, depth, depth, Solver3::Cg);
    assert!(err_cg < 1e-8 && speed_cg < 1e-8, "{err_cg} {speed_cg}");
    println!(
        "jittered tank 10×10×8 (± 0.15 h), flat top: pressure error {err_p:.1e} of ρ g d, \
         speed after one 10 ms step {speed:.1e} m/s"
    );
    assert!(err_p < 1e-10 && speed < 1e-10);
}

#[test]
fn still_water_stays_still_over_two_seconds_of_remeshing() {
    // The bar for 3D still water: max speed < 0.5 % √(g d), pressure within 2 % of
    // hydrostatic, volume drift < 0.1 %, over 2 s of remeshing every step.
    let h = 0.02;
    let mut flow = still_tank(10, 10, 8, h, 0.3);
    let n = flow.x.len();
    let depth = 7.0 * h;
    let first = flow.step(DT).unwrap();
    let (mut speed, mut drift, mut slivers) = (0.0f64, 0.0f64, first.slivers_kept);
    for _ in 1..200 {
        let s = flow.step(DT).unwrap();
        drift = drift.max((s.volume_m3 / first.volume_m3 - 1.0).abs());
        slivers = slivers.max(s.slivers_kept);
        speed = speed.max(flow.u.iter().map(|u| u.norm()).fold(0.0, f64::max));
    }
    let mut err_p = 0.0f64;
    for i in 0..n {
        if flow.walls[i] == 0 || flow.p[i] != 0.0 {
            let exact = (RHO * G * (depth - flow.x[i][2])).max(0.0);
            err_p = err_p.max((flow.p[i] - exact).abs() / (RHO * G * depth));
        }
    }
    println!(
        "3D still water, 800 nodes (interior jittered ± 0.15 h), 200 steps of 10 ms: max speed \
         {speed:.1e} m/s ({:.1e} of √(g d)), pressure error {err_p:.1e} of ρ g d, volume drift \
         {drift:.1e}, {} tetrahedra, up to {slivers} slivers kept",
        speed / (G * depth).sqrt(),
        first.tetrahedra
    );
    assert!(speed < 0.005 * (G * depth).sqrt());
    assert!(err_p < 0.02);
    assert!(drift < 1e-3);
}

#[test]
fn a_diverged_flow_stops_with_a_message() {
    let mut flow = still_tank(4, 4, 4, 0.02, 0.0);
    flow.u[21] = Vector3::new(f64::NAN, 0.0, 0.0);
    let err = flow.step(DT).unwrap_err().to_string();
    assert!(err.contains("diverged") && err.contains("node 21"), "{err}");
}
