//! A run that meets numerical trouble must stop with a status naming it, exit non-zero, and
//! leave its timeseries.csv, summary.json and run.rrd readable.
//!
//! The trouble is made on purpose: a density of 1e-310 kg/m³ (subnormal) makes Δt/ρ overflow
//! to infinity, so the very first pressure system is not finite.

mod common;

use std::process::Command;

#[test]
fn nan_stops_the_run_and_keeps_what_was_recorded() {
    let dir = common::out_dir("nan");
    let out = Command::new(env!("CARGO_BIN_EXE_surflab"))
        .current_dir(common::root())
        .args(["run", "cases/still_water.toml", "--quiet", "--out"])
        .arg(&dir)
        .args([
            "--set",
            "fluid.density_kg_m3=1e-310",
            "--set",
            "time.end_s=0.2",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    println!("exit {:?}: {stderr}", out.status.code());
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr.contains("did not finish"));
    common::assert_stopped_and_kept(&dir);
}

/// A finite but absurd velocity also stops the run: here the limit is lowered to 1 mm/s so
/// that the dam break, which falls at 1 m/s within 0.1 s, meets it.
#[test]
fn divergence_stops_the_run_with_its_reason() {
    let case = common::case("dam_break.toml", &["particles.spacing_m=0.01"]);
    let mut sim = surflab::simulation::Simulation::new(&case).unwrap();
    let default_limit = sim.solver.params.speed_limit_m_s;
    println!("speed limit of the dam-break flume: {default_limit:.1} m/s");
    assert!(default_limit > 10.0 && default_limit.is_finite());
    sim.solver.params.speed_limit_m_s = 1e-3;
    let err = sim.advance_to(0.1, |_, _| {}).unwrap_err();
    println!("{err}");
    assert!(err.to_string().starts_with("diverged: a particle reached"));
}
