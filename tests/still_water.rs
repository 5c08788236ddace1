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

fn check(label: &str, overrides: &[&str]) {
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
        "still water, {label}: {} steps over {} s; max speed {:.3e} m/s (bound {:.3e} = 0.5 % of sqrt(g d)); \
         mid-depth pressure error {:.3} % over {used} particles; volume drift max {:.4} %",
        sim.steps,
        sim.time_s,
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
}
