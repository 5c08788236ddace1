//! Still water in a closed tank (1.0 m long, 0.5 m deep) for 2 s of simulated time:
//! spurious velocities, hydrostatic pressure and volume after hundreds of remeshes.

mod common;

use surflab::diagnostics;
use surflab::simulation::Simulation;

#[test]
fn still_water_stays_still_hydrostatic_and_conserves_volume() {
    check("no-slip walls", &[]);
}

#[test]
fn still_water_with_slip_walls() {
    check("slip walls", &["flume.walls=slip"]);
}

/// At h = 4 cm the wall nodes of the 0.7 m wall are 3.89 cm apart and the water line lies
/// 5.6 mm below one of them, so the kept triangle at each wall reaches above the water. Before
/// the contact point got its hydrostatic pressure and the pressure force its gradient form,
/// the water line sank along the wall at 0.05 m/s within 0.5 s and the tank lost 2 % by 3 s
/// (now 7e-15 m/s).
#[test]
fn still_water_with_the_water_line_between_wall_nodes() {
    check(
        "water line between wall nodes",
        &["particles.spacing_m=0.04"],
    );
}

/// The EDT with δ = 0.05 on the lattice-seeded tank: every interior square of the lattice is
/// co-circular, so the mesh is mostly 4-node MFEM polygons (issue 24).
#[test]
fn still_water_with_edt_polygons() {
    let polygons = check("EDT polygons, δ = 0.05", &["solver.delta=0.05"]);
    assert!(polygons > 300, "only {polygons} polygons at the end");
}

/// `particles.refine`: the spacing falls from 2 cm at x = 0.4 m to 1 cm at 0.6 m and stays
/// there; the graded lattice and wall nodes stay at rest and hydrostatic, and the α-shape,
/// insertion and removal, judging every length by the local spacing, leave the nodes alone.
#[test]
fn still_water_with_a_refined_stretch() {
    let overrides = [
        "particles.refine.x_m=0.6",
        "particles.refine.spacing_m=0.01",
    ];
    let case = common::case("still_water.toml", &overrides);
    let start = Simulation::new(&case).unwrap().particles.len();
    check("refined to 1 cm from x = 0.6 m", &overrides);
    let mut sim = Simulation::new(&case).unwrap();
    sim.advance_to(0.5, |_, _| {}).expect("runs");
    assert_eq!(
        sim.particles.len(),
        start,
        "no node inserted or removed at rest"
    );
}

/// Runs the tank and checks the bars; returns the EDT polygons of the last mesh.
fn check(label: &str, overrides: &[&str]) -> usize {
    let case = common::case("still_water.toml", overrides);
    let depth = case.water[0].depth_m;
    let g = case.fluid.gravity_m_s2;
    let mut sim = Simulation::new(&case).unwrap();
    let v0 = sim.initial_volume_m2;
    let mut max_speed: f64 = 0.0;
    let mut drift: f64 = 0.0;
    sim.advance_to(case.time.end_s, |s, _| {
        let m = diagnostics::integrals(s);
        max_speed = max_speed.max(m.max_speed_m_s);
        drift = drift.max((m.volume_m2 / v0 - 1.0).abs());
    })
    .expect("still water runs");
    let bound = 0.005 * (g * depth).sqrt();
    let (p_err, used) = diagnostics::hydrostatic_error(&sim, 0.5 * depth, (0.25, 0.75));
    println!(
        "still water, {label}: {} steps over {} s, {} EDT polygons at the end; max speed {:.3e} m/s (bound {:.3e} = 0.5 % of sqrt(g d)); \
         mid-depth pressure error {:.3} % over {used} particles; volume drift max {:.4} %",
        sim.steps,
        sim.time_s,
        sim.solver.mesh.polygons.len(),
        max_speed,
        bound,
        100.0 * p_err,
        100.0 * drift
    );
    assert!(
        sim.steps >= 200,
        "hundreds of remeshes expected, got {}",
        sim.steps
    );
    assert!(max_speed < bound);
    assert!(used > 10);
    assert!(p_err < 0.02);
    assert!(drift < 0.001);
    sim.solver.mesh.polygons.len()
}

/// The free surface of the projection step grows a 2h ripple out of round-off (about ×10 per
/// second once it shows): with p = 0 strong and Δt = 5 ms the tank reaches 3e-3 m/s by 20 s
/// and loses 92 % of its water by 40 s; with Δt = 2.5 ms it starts at 20 s and has lost 20 %
/// by 40 s. The wave cases therefore run with the weak surface condition and the surface-wave
/// bound on Δt, which this test holds to round-off for 30 s (measured: 9e-14 m/s at 40 s).
#[test]
fn still_water_stays_still_for_30_s_with_the_wave_cases_settings() {
    let case = common::case(
        "still_water.toml",
        &["solver.weak_surface_length_h=0.3", "time.end_s=30"],
    );
    let dt_bound = case
        .time
        .surface_wave_dt_s(case.particles.spacing_m, case.fluid.gravity_m_s2);
    let mut sim = Simulation::new(&case).unwrap();
    let v0 = sim.initial_volume_m2;
    let mut max_speed: f64 = 0.0;
    let mut max_dt: f64 = 0.0;
    sim.advance_to(case.time.end_s, |s, r| {
        max_speed = max_speed.max(diagnostics::integrals(s).max_speed_m_s);
        max_dt = max_dt.max(r.dt_s);
    })
    .expect("still water runs");
    let drift = diagnostics::integrals(&sim).volume_m2 / v0 - 1.0;
    println!(
        "still water, 30 s, weak surface (0.3 h), Δt ≤ {:.2} ms (bound {:.2} ms): {} steps; max speed {max_speed:.2e} m/s; volume drift {drift:.2e}",
        1e3 * max_dt,
        1e3 * dt_bound,
        sim.steps
    );
    assert!(max_dt <= dt_bound * (1.0 + 1e-12));
    assert!(max_speed < 1e-9, "a surface mode grew: {max_speed:.3e} m/s");
    assert!(drift.abs() < 1e-9);
}

/// Issue 22's first bar: still water at h = 2 cm and Δt = 10 ms (the flow's CFL step, no
/// surface-wave bound, no filter, no merging) for 60 s of remeshing: max speed below 1e-6 m/s,
/// volume drift below 1e-6. With the explicit geometry the same tank grows a surface ripple at
/// 1.45/s and has lost 27 % of its water by 30 s (docs/validation/surface_mode.md); the second
/// pass on the surface moved by its short-scale motion (`solver.geometry_theta` = 1) holds it
/// at round-off.
#[test]
fn still_water_holds_at_the_10_ms_step_with_the_short_scale_pass() {
    let case = common::case(
        "still_water.toml",
        &[
            "solver.weak_surface_length_h=0.3",
            "solver.geometry_theta=1",
            "time.surface_wave_courant=0",
            "time.dt_policy=fixed",
            "time.dt_max_s=0.01",
            "time.end_s=60",
        ],
    );
    assert!(case.solver.surface_filter.is_none() && case.solver.merge_surface_distance_h.is_none());
    let mut sim = Simulation::new(&case).unwrap();
    let v0 = sim.initial_volume_m2;
    let (mut max_speed, mut drift, mut min_dt): (f64, f64, f64) = (0.0, 0.0, f64::MAX);
    sim.advance_to(case.time.end_s, |s, r| {
        let m = diagnostics::integrals(s);
        max_speed = max_speed.max(m.max_speed_m_s);
        drift = drift.max((m.volume_m2 / v0 - 1.0).abs());
        // The last step lands on end_s (two half steps where the round-off of the sum of
        // 6000 steps leaves a sliver).
        if s.time_s < case.time.end_s - 0.015 {
            min_dt = min_dt.min(r.dt_s);
        }
    })
    .expect("still water runs");
    println!(
        "still water, 60 s at Δt = {:.1} ms (smallest step before the last {:.1} ms), weak surface, short-scale pass θₓ = 1: {} steps; \
         max speed {max_speed:.2e} m/s; volume drift max {drift:.2e}",
        1e3 * case.time.dt_max_s,
        1e3 * min_dt,
        sim.steps
    );
    assert!(
        min_dt >= 0.01 * (1.0 - 1e-9),
        "the step was cut to {min_dt} s"
    );
    assert!(max_speed < 1e-6, "a surface mode grew: {max_speed:.3e} m/s");
    assert!(drift < 1e-6, "volume drift {drift:.3e}");
}

/// At the CFL policy's longest step (10 ms, still water) with output every 40 ms, the steps
/// land on the output times in four steps each: the round-off of the summed steps does not
/// split a step into two halves (before, 41 of the 50 intervals took 10, 10, 10, 5, 5 ms: 241 steps).
#[test]
fn steps_land_on_output_times_without_half_steps() {
    let case = common::case(
        "still_water.toml",
        &[
            "particles.spacing_m=0.05",
            "time.dt_max_s=0.01",
            "time.surface_wave_courant=0",
        ],
    );
    let mut sim = Simulation::new(&case).unwrap();
    let (interval_s, intervals) = (0.04, 50);
    let mut shortest_s = f64::INFINITY;
    for k in 1..=intervals {
        sim.advance_to(k as f64 * interval_s, |_, r| {
            shortest_s = shortest_s.min(r.dt_s)
        })
        .unwrap();
    }
    println!(
        "{} steps over {intervals} intervals of {interval_s} s; shortest step {:.6} ms",
        sim.steps,
        1e3 * shortest_s
    );
    assert_eq!(sim.steps, 4 * intervals);
    assert!((shortest_s - 0.01).abs() < 1e-9, "{shortest_s}");
}
