//! The 3D benchmarks of the binary (issue 26): `surflab bench-tetra` (the tetrahedralisation
//! alone), `surflab bench3d` (the 3D step on a still tank of a given size) and `surflab bench`
//! of a 3D case. Each prints milliseconds per step by stage; the stepping and timing are shared.

use super::summary::median;
use crate::case::Case;
use crate::solver3d::{Flow3, PressureError, STAGES_3D, Solver3, setup, still_tank};
use anyhow::{Context, Result, bail};
use std::time::Instant;

/// What `steps` steps of a 3D flow took.
#[derive(Debug, Clone)]
pub struct Timing3 {
    /// Median ms per step of each stage of [`STAGES_3D`].
    pub stage_ms: Vec<f64>,
    /// Median ms per step.
    pub step_ms: f64,
    /// Median pressure-solver iterations (0 for Cholesky).
    pub iterations: f64,
    /// Kept tetrahedra at the last step.
    pub tetrahedra: usize,
    pub simulated_s: f64,
    pub wall_s: f64,
}

/// Steps `flow` `steps` times at the Δt `dt_s` gives for its state, timing each stage; with
/// `progress`, a line per step on stderr.
pub fn time_steps(
    flow: &mut Flow3,
    steps: u64,
    mut dt_s: impl FnMut(&Flow3) -> f64,
    progress: bool,
) -> Result<Timing3, PressureError> {
    let mut per_stage: Vec<Vec<f64>> = vec![Vec::new(); STAGES_3D.len()];
    let (mut totals, mut iterations) = (Vec::new(), Vec::new());
    let (mut t, mut tetrahedra) = (0.0, 0);
    let started = Instant::now();
    for k in 1..=steps {
        let dt = dt_s(flow);
        let s = flow.step(dt)?;
        t += dt;
        let total: f64 = s.stage_ms.iter().sum();
        if progress {
            eprintln!("  step {k}/{steps}: {total:.0} ms");
        }
        for (stage, ms) in per_stage.iter_mut().zip(s.stage_ms) {
            stage.push(ms);
        }
        totals.push(total);
        iterations.push(s.iterations as f64);
        tetrahedra = s.tetrahedra;
    }
    Ok(Timing3 {
        stage_ms: per_stage.iter().map(|v| median(v)).collect(),
        step_ms: median(&totals),
        iterations: median(&iterations),
        tetrahedra,
        simulated_s: t,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// Prints the stage medians and the step's, `decimals` after the point.
fn print_stages(timing: &Timing3, decimals: usize) {
    for (name, ms) in STAGES_3D.iter().zip(&timing.stage_ms) {
        println!("  {name:<15} {ms:9.decimals$}");
    }
    println!("  {:<15} {:9.decimals$}", "step", timing.step_ms);
}

/// `surflab bench-tetra`: µs per point of the tetrahedralisation of `points` random points (or
/// a lattice), `repeat` times, and their median.
pub fn bench_tetra(points: usize, lattice: bool, repeat: u32) -> Result<()> {
    let limit = crate::case::max_nodes();
    if points < 4 || points > limit {
        bail!("--points must be between 4 and {limit} (--max-particles), got {points}");
    }
    if repeat == 0 {
        bail!("--repeat must be at least 1");
    }
    let cloud = crate::mesh3d::bench_cloud(points, lattice);
    let kind = if lattice { "lattice" } else { "random" };
    println!(
        "surflab bench-tetra: {} {kind} points, one thread",
        cloud.len()
    );
    // One mesher for all repeats, as a stepper keeps one: the first repeat also pays for
    // the fresh memory (page faults), the later ones reuse it.
    let mut mesher = crate::mesh3d::Tetrahedraliser::default();
    let mut us_per_point = Vec::new();
    for r in 1..=repeat {
        let t0 = Instant::now();
        let mesh = mesher.tetrahedralise(&cloud);
        let us = t0.elapsed().as_secs_f64() * 1e6 / cloud.len() as f64;
        println!(
            "  repeat {r}: {us:.2} µs per point, {} tetrahedra ({:.2} per point)",
            mesh.tets.len(),
            mesh.tets.len() as f64 / cloud.len() as f64
        );
        us_per_point.push(us);
    }
    if repeat > 1 {
        println!(
            "median {:.2} µs per point with the memory reused (repeats 2–{repeat}); \
             {:.2} with fresh memory (repeat 1)",
            median(&us_per_point[1..]),
            us_per_point[0]
        );
    } else {
        println!("{:.2} µs per point with fresh memory", us_per_point[0]);
    }
    Ok(())
}

/// `surflab bench3d`: `steps` steps of 10 ms of a still tank of about `nodes` nodes (twice as
/// long and wide as deep, h = 2 cm, interior jittered ± 0.15 h) with the pressure solver
/// `solver` (cholesky, cg or auto).
pub fn bench_still_tank(nodes: usize, steps: u64, solver: &str) -> Result<()> {
    let limit = crate::case::max_nodes();
    if !(100..=limit).contains(&nodes) {
        bail!("--nodes must be between 100 and {limit} (--max-particles), got {nodes}");
    }
    if steps == 0 {
        bail!("--steps must be at least 1");
    }
    let solver = match solver {
        "cholesky" => Solver3::Cholesky,
        "cg" => Solver3::Cg,
        "auto" => Solver3::Auto,
        other => bail!("--solver must be cholesky, cg or auto, got {other:?}"),
    };
    if solver == Solver3::Cholesky && nodes > crate::solver3d::CHOLESKY_LIMIT_UNKNOWNS {
        bail!(
            "--solver cholesky is limited to {} nodes in 3D (the factor's fill); use cg or auto",
            crate::solver3d::CHOLESKY_LIMIT_UNKNOWNS
        );
    }
    let nz = ((nodes as f64 / 4.0).cbrt().round() as usize).max(3);
    let mut flow = still_tank(2 * nz, nz, 2 * nz, 0.02, 0.3);
    flow.solver = solver;
    // Node management at a case's defaults, so that its stage is timed too.
    let defaults = crate::case::SolverSettings::default();
    flow.insert_radius_m = defaults
        .insert_radius_h
        .map(|r| crate::solver3d::nodes::insert_radius_3d(r, flow.h_m));
    flow.remove_distance_m = defaults.remove_distance_h.map(|d| d * flow.h_m);
    let n = flow.x.len();
    println!(
        "surflab bench3d: still tank {} × {nz} × {} nodes (y up; {n}), h = 2 cm, Δt = 10 ms, \
         {solver:?}",
        2 * nz,
        2 * nz
    );
    let timing = time_steps(&mut flow, steps, |_| 0.01, true)?;
    println!(
        "{} tetrahedra kept; median ms per step by stage:",
        timing.tetrahedra
    );
    print_stages(&timing, 1);
    if timing.iterations > 0.0 {
        println!("median CG iterations: {:.0}", timing.iterations);
    }
    println!(
        "particle-steps/s: {:.0}   real-time factor at Δt = 10 ms: {:.3}",
        n as f64 / (timing.step_ms * 1e-3),
        10.0 / timing.step_ms
    );
    Ok(())
}

/// `surflab bench` of a 3D case: `steps` steps at the run's Δt (`Simulation3::dt_for`), ms per
/// step by stage, particle-steps per second and the real-time factor; `json` prints one JSON
/// object instead.
pub fn bench_case(case: &Case, steps: u64, json: bool) -> Result<()> {
    let mut flow = setup::from_case(case)?;
    flow.mesh_now()?;
    let n = flow.x.len();
    let timing = time_steps(
        &mut flow,
        steps,
        |f| crate::simulation3d::Simulation3::dt_for(case, f),
        false,
    )
    .with_context(|| format!("stepping {}", case.name))?;
    let (t, wall) = (timing.simulated_s, timing.wall_s);
    let particle_steps_per_s = (n as u64 * steps) as f64 / wall;
    if json {
        let stages: std::collections::BTreeMap<&str, f64> = STAGES_3D
            .iter()
            .copied()
            .zip(timing.stage_ms.iter().copied())
            .collect();
        let obj = serde_json::json!({
            "case": case.name,
            "three_d": true,
            "particles_initial": n,
            "fluid_particles": flow.walls.iter().filter(|&&w| w == 0).count(),
            "steps": steps,
            "simulated_s": t,
            "wall_s": wall,
            "median_ms_per_step": timing.step_ms,
            "stage_ms": stages,
            "median_cg_iterations": timing.iterations,
            "particle_steps_per_s": particle_steps_per_s,
            "real_time_factor": t / wall,
        });
        println!("{obj}");
        return Ok(());
    }
    println!(
        "{} (3D): {n} nodes, {steps} steps to t = {t:.4} s; median ms per step by stage:",
        case.name
    );
    print_stages(&timing, 2);
    if timing.iterations > 0.0 {
        println!("median CG iterations: {:.0}", timing.iterations);
    }
    println!(
        "particle-steps/s: {particle_steps_per_s:.0}   real-time factor: {:.3}",
        t / wall
    );
    Ok(())
}
