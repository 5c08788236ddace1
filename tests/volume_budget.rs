//! The volume budget adds up: V₀ plus the area changed by remeshing, by the motion of the
//! nodes and by the volume recovery is the area of the mesh, step after step (dam break,
//! h = 1 cm, to 0.15 s, with node insertion and removal on), with and without the research
//! switches; with the volume relaxation, its per-strip ledger adds up to the same.

mod common;

use surflab::diagnostics;
use surflab::simulation::Simulation;

fn budget_closes(overrides: &[&str]) -> f64 {
    let mut o = vec!["particles.spacing_m=0.01"];
    o.extend_from_slice(overrides);
    let case = common::case("dam_break.toml", &o);
    let mut sim = Simulation::new(&case).unwrap();
    let v0 = sim.initial_volume_m2;
    let relaxing = overrides
        .iter()
        .any(|o| o.starts_with("solver.volume_relaxation_s"));
    let mut worst: f64 = 0.0;
    let mut drift: f64 = 0.0;
    sim.advance_to(0.15, |s, _| {
        let m = diagnostics::integrals(s);
        let b = s.area_budget;
        let closed = v0 + b.remesh_m2 + b.motion_m2 + b.recovered_m2;
        worst = worst.max((closed - m.volume_m2).abs() / v0);
        if relaxing {
            // The strip ledger of the relaxation books every change too.
            let ledger: f64 = s.solver.area_ledger_m2().iter().sum();
            worst = worst.max((v0 + ledger - m.volume_m2).abs() / v0);
        }
        drift = m.volume_m2 / v0 - 1.0;
    })
    .unwrap();
    let b = sim.area_budget;
    println!(
        "{overrides:?}: {} steps, V/V0 − 1 = {drift:+.3e}: remesh {:+.3e}, motion {:+.3e}, recovered {:+.3e} (of V0); budget closes to {worst:.1e}",
        sim.steps,
        b.remesh_m2 / v0,
        b.motion_m2 / v0,
        b.recovered_m2 / v0
    );
    worst
}

#[test]
fn volume_budget_adds_up() {
    assert!(budget_closes(&[]) < 1e-12);
    assert!(budget_closes(&["solver.area_correction=true"]) < 1e-12);
    assert!(budget_closes(&["solver.volume_recovery=true"]) < 1e-12);
    assert!(budget_closes(&["solver.volume_relaxation_s=0.05"]) < 1e-12);
}
