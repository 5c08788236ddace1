//! Surface-elevation gauges and the initial standing-wave surface: the gauge reads the seeded
//! cosine surface η(x) = A cos(πx/L) at t = 0, reads zero on still water, and `surflab run`
//! writes gauges.csv with the column names `t_s, eta_<x>`.

mod common;

use surflab::diagnostics::surface_elevation;
use surflab::simulation::Simulation;

#[test]
fn gauge_reads_the_initial_cosine_surface() {
    let case = common::case("sloshing.toml", &[]);
    let sim = Simulation::new(&case).unwrap();
    let a = case.water[0].surface_amplitude_m;
    let mut worst: f64 = 0.0;
    for x in [0.05, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95] {
        let eta = surface_elevation(&sim, x).expect("wet");
        let expected = a * (std::f64::consts::PI * x).cos();
        worst = worst.max((eta - expected).abs());
    }
    println!("initial surface: worst |η − A cos(πx/L)| = {worst:.2e} m (A = {a} m)");
    // Between particles the surface is linear: the error is the chord error of the cosine,
    // A (π h / L)² / 8 ≈ 6e-7 m at h = 1 cm.
    assert!(worst < 1e-5, "{worst}");
}

#[test]
fn gauge_reads_zero_on_still_water_and_is_none_when_dry() {
    let case = common::case("dam_break.toml", &["particles.spacing_m=0.01"]);
    let sim = Simulation::new(&case).unwrap();
    let eta = surface_elevation(&sim, 0.07).expect("inside the column");
    assert!(eta.abs() < 1e-12, "{eta}");
    assert!(surface_elevation(&sim, 0.4).is_none(), "dry floor");
}

#[test]
fn run_writes_gauges_csv() {
    let case = common::case(
        "sloshing.toml",
        &["time.end_s=0.05", "particles.spacing_m=0.04"],
    );
    let outcome = common::run_case(&case, "gauges", false);
    assert!(outcome.ok(), "{}", outcome.summary.status);
    let text = std::fs::read_to_string(outcome.out_dir.join("gauges.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t_s,eta_0.050"));
    assert_eq!(lines.count(), 6, "t = 0 and five outputs");
}
