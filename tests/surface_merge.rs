//! `solver.merge_surface_distance_h`: two free-surface particles that collide (as where a jet
//! lands) are merged into one at their midpoint; still water, whose surface particles stay h
//! apart, is left alone.

mod common;

use surflab::simulation::Simulation;

#[test]
fn colliding_surface_particles_merge_and_still_water_is_left_alone() {
    let h = 0.04;
    let case = common::case(
        "still_water.toml",
        &[
            "particles.spacing_m=0.04",
            "solver.merge_surface_distance_h=0.2",
        ],
    );
    let mut sim = Simulation::new(&case).unwrap();
    sim.advance_to(0.5, |_, _| {}).unwrap();
    let n0 = sim.particles.fluid_count();
    println!("still water, 0.5 s: {n0} fluid particles");
    assert_eq!(n0, Simulation::new(&case).unwrap().particles.fluid_count());

    // Two neighbouring surface particles of the last mesh, mid-tank; push one onto the other.
    let p = &sim.particles;
    let m = &sim.solver.mesh;
    let surface =
        |i: usize| p.is_fluid(i) && m.free_surface[i] && (0.3..0.7).contains(&p.position[i].x);
    let (i, j) = m
        .triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a as usize, b as usize))
        .find(|&(a, b)| surface(a) && surface(b))
        .expect("a surface edge");
    let xi = sim.particles.position[i];
    sim.particles.position[j] = xi + nalgebra::Vector2::new(0.1 * h, 0.0);
    let midpoint = xi + nalgebra::Vector2::new(0.05 * h, 0.0);
    sim.step_towards(1.0).unwrap();
    let n1 = sim.particles.fluid_count();
    let closest = (0..sim.particles.len())
        .filter(|&k| sim.particles.is_fluid(k))
        .map(|k| (sim.particles.position[k] - midpoint).norm())
        .fold(f64::INFINITY, f64::min);
    println!("after the push: {n1} fluid particles; closest to the midpoint {closest:.2e} m");
    assert_eq!(n1, n0 - 1, "one particle of the pair is gone");
    assert!(
        closest < 0.05 * h,
        "the survivor stands at the midpoint: {closest}"
    );
}
