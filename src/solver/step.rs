//! One PFEM time step, as a list of stages (thesis §2.5; method.md §1). Each stage has one
//! timer, named as here ([`Stage`]); optional stages cost nothing when off.
//!
//! 1. `nodes`: split stretched triangles of the last mesh, remove crowded interior nodes, merge
//!    colliding surface nodes (if asked);
//! 2. `remesh`: Delaunay triangulation of every node;
//! 3. `alpha_shape`: with δ > 0 merge nearly co-circular triangles into EDT polygons, keep
//!    triangles (and polygons) with R < α·h, drop all-wall ones, find the free surface;
//! 4. `relax` (optional, `relax.rs`): book what the remesh changed in the per-strip area
//!    ledger, and ask the deep nodes of each strip for the divergence s that pays its balance
//!    back; after stages 12–13 it books what the move changed (and before the first
//!    step's stage 1, it books the initial mesh);
//! 5. `assemble`, first part: the pattern of the pressure matrix, built here so that its
//!    symbolic factorisation runs on the second core during stages 6–7;
//! 6. `elements`: areas, gradients (P1 on triangles, MFEM on polygons: `element_set.rs`),
//!    lumped mass, Smagorinsky μ_e, τ;
//! 7. `predict`: ũ from momentum without the pressure increment (before it, once per step, the
//!    slip wall nodes take the velocity of the water beside them);
//! 8. `assemble`, second part, and `pressure_solve`: (Δt/ρ L + L_τ) pⁿ⁺¹ = −Dũ + Ms +
//!    γ(Δt/ρ)L pⁿ − Qπⁿ (s the divergence target of stage 4), p = 0 on the free surface,
//!    strongly or weakly;
//! 9. `correct`: uⁿ⁺¹ = ũ + Δt M⁻¹ Dᵀ(pⁿ⁺¹ − γpⁿ), and π from pⁿ⁺¹;
//! 10. `geometry` (optional, `geometry_theta` θₓ): move the free-surface nodes by θₓ Δt
//!     times the short-scale part of uⁿ⁺¹ (`motion.rs`) and redo stages 6–9 there (the
//!     pattern of the pressure matrix and its symbolic analysis are the same), then put the
//!     nodes back on xⁿ for stage 12: the second pass computes the restoring force of a
//!     surface ripple where the step takes it, not where it was (see the doc of
//!     `solver.geometry_theta`);
//! 11. `filter` (optional, `filter.rs`): the fourth-difference filter of the surface
//!     velocities;
//! 12. `move`: xⁿ⁺¹ = xⁿ + Δt uⁿ⁺¹ (thesis eq. 2.59; with `midpoint_move`,
//!     xⁿ + Δt (I − Δt ∇uⁿ⁺¹/2)⁻¹ uⁿ⁺¹, `motion.rs`), then the wall guard;
//! 13. `recover` (optional, `volume.rs`): the global volume recovery on the free surface.
//!
//! If the new velocities would turn a kept triangle inside out within Δt, and the Δt policy
//! allows it, stages 6–10 are redone with Δt/2.

use super::{Solver, Stage, StageTimings, StepError, StepReport};
use crate::geometry::Flume;
use crate::mesh;
use crate::particles::Particles;

impl Solver {
    /// Advances `particles` by (at most) `dt_s`.
    pub fn step(
        &mut self,
        particles: &mut Particles,
        flume: &Flume,
        dt_s: f64,
    ) -> Result<StepReport, StepError> {
        let mut t = StageTimings::default();
        let shape = self.params.shape();

        t.time(Stage::Relax, || self.relax_start(particles));
        let changes = t.time(Stage::Nodes, || self.manage_nodes(particles));
        t.time(Stage::Remesh, || self.triangulate(particles))?;
        t.time(Stage::AlphaShape, || {
            mesh::alpha_shape(
                &self.triangulator.triangles,
                particles,
                &shape,
                flume.paddle_now.as_ref(),
                &mut self.mesh,
            )
        });
        t.time(Stage::Relax, || self.relax_targets(particles));
        t.time(Stage::Predict, || {
            self.slip_walls_take_the_water_velocity(particles)
        });
        t.time(Stage::Assemble, || self.prepare_pressure(particles));
        let area_before_move = self.mesh.area(&particles.position);
        let remesh_change = self.moved_area.map_or(0.0, |a| area_before_move - a);

        let mut dt = dt_s;
        let mut halvings = 0;
        let iterations = loop {
            t.time(Stage::Elements, || self.element_properties(particles, dt));
            t.time(Stage::Predict, || self.predict(particles, dt));
            t.time(Stage::Assemble, || self.assemble_pressure(particles, dt));
            let iterations = t.time(Stage::PressureSolve, || self.solve_pressure(particles))?;
            t.time(Stage::Correct, || self.correct(particles, dt));
            let mut inverted = self.would_invert(particles, dt);
            if !inverted && let Some(theta_x) = self.params.settings.geometry_theta {
                t.time(Stage::Geometry, || {
                    self.shift_geometry(particles, theta_x * dt)
                });
                t.time(Stage::Elements, || self.element_properties(particles, dt));
                t.time(Stage::Predict, || self.predict(particles, dt));
                t.time(Stage::Assemble, || self.assemble_pressure(particles, dt));
                let solved = t.time(Stage::PressureSolve, || self.solve_pressure(particles));
                t.time(Stage::Correct, || self.correct(particles, dt));
                t.time(Stage::Geometry, || self.restore_geometry(particles));
                solved?;
                // The inversion check reads the element areas only to leave slivers out; those
                // of the shifted geometry serve.
                inverted = self.would_invert(particles, dt);
            }
            if !inverted || !self.params.adaptive_dt {
                break iterations;
            }
            if dt * 0.5 < self.params.dt_min_s {
                return Err(StepError::Inverted { dt_s: dt });
            }
            dt *= 0.5;
            halvings += 1;
        };

        t.time(Stage::Filter, || self.filter_surface(particles));
        let guarded = t.time(Stage::Move, || self.move_particles(particles, flume, dt))?;
        let area_after_move = self.mesh.area(&particles.position);
        let recovered = match self.volume_target_m2 {
            Some(target) if self.params.settings.volume_recovery => t.time(Stage::Recover, || {
                self.recover_volume(particles, flume, area_after_move, target)
            }),
            _ => 0.0,
        };
        self.moved_area = Some(area_after_move + recovered);
        t.time(Stage::Relax, || self.relax_after_move(particles));

        Ok(StepReport {
            dt_s: dt,
            timings: t,
            pressure_unknowns: self.pressure.unknowns(),
            pressure_iterations: iterations,
            kept_triangles: self.mesh.triangles.len(),
            polygons: self.mesh.polygons.len(),
            free_surface_nodes: self.mesh.free_surface.iter().filter(|f| **f).count(),
            isolated_particles: (0..particles.len())
                .filter(|&i| particles.is_fluid(i) && !self.mesh.in_mesh[i])
                .count(),
            guarded_particles: guarded,
            dt_halvings: halvings,
            remesh_area_change_m2: remesh_change,
            motion_area_change_m2: area_after_move - area_before_move,
            recovered_area_m2: recovered,
            nodes_inserted: changes.inserted,
            nodes_removed: changes.removed,
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::case::Case;
    use crate::simulation::Simulation;

    /// On slip walls a wall node beside the water takes the water's velocity along its wall;
    /// one beside none (dry, or in a wetted corner's all-wall triangles only) takes its wall's
    /// own, not the velocity it was left with. On the 1:4 beach run with slip walls, such a
    /// node in the corner where the beach meets the end wall carried 174 m/s from step to step
    /// into the pressure of a puddle there, and the run stopped at 7.4 s (docs/sweep.md).
    #[test]
    fn slip_wall_nodes_beside_no_water_take_their_walls_velocity() {
        use crate::particles::NodeKind;
        use nalgebra::Vector2;
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/sloshing.toml");
        let case = Case::load(&path, &["flume.walls=slip".to_string()]).unwrap();
        let mut sim = Simulation::new(&case).unwrap();
        sim.step_towards(0.01).unwrap();
        let (water, stale) = (Vector2::new(0.1, 0.2), Vector2::new(9.0, -9.0));
        let p = &mut sim.particles;
        for i in 0..p.len() {
            p.velocity[i] = if p.kind[i] == NodeKind::Fluid {
                water
            } else {
                stale
            };
        }
        sim.solver.slip_walls_take_the_water_velocity(p);
        let mut beside_water = vec![false; p.len()];
        for t in &sim.solver.mesh.triangles {
            if t.iter().any(|&j| p.kind[j as usize] == NodeKind::Fluid) {
                t.iter().for_each(|&j| beside_water[j as usize] = true);
            }
        }
        let mut seen = [0; 3];
        for i in (0..p.len()).filter(|&i| p.kind[i] == NodeKind::Wall) {
            let tangent = p.wall_tangent[i];
            let expected = if tangent == Vector2::zeros() {
                // A corner: no direction to slide in; left to the predictor's constraint.
                seen[2] += 1;
                stale
            } else if beside_water[i] {
                seen[1] += 1;
                water.dot(&tangent) * tangent
            } else {
                seen[0] += 1;
                Vector2::zeros()
            };
            assert!(
                (p.velocity[i] - expected).norm() < 1e-15,
                "{i}: {:?}",
                p.velocity[i]
            );
        }
        println!(
            "wall nodes: {} beside no water, {} beside it, {} corners",
            seen[0], seen[1], seen[2]
        );
        assert!(seen.iter().all(|&n| n > 0), "{seen:?}");
    }

    /// One thread or two, a run is the same to the last bit: the triangulation's two pieces
    /// come out in the same order either way, and the symbolic analysis of the pressure matrix
    /// is the same on either thread (the lab steps on one core of two, `run` on both).
    #[test]
    fn a_run_does_not_depend_on_the_threads() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/teaching_beach.toml");
        let case = Case::load(&path, &[]).unwrap();
        let run = |one_core: bool| {
            let mut sim = Simulation::new(&case).unwrap();
            if one_core {
                sim.use_one_core();
            }
            while sim.time_s < 0.5 {
                sim.step_towards(0.5).unwrap();
            }
            (
                sim.particles.position.clone(),
                sim.particles.velocity.clone(),
            )
        };
        let (two, one) = (run(false), run(true));
        // Above the size at which the cloud is cut in two pieces.
        assert!(
            two.0.len() > 2 * crate::mesh::SPLIT_MIN_NODES,
            "{}",
            two.0.len()
        );
        assert!(
            two.1.iter().any(|u| u.norm() > 1e-3),
            "the paddle has moved the water"
        );
        assert_eq!(two, one);
    }

    /// The split's pressure mode that alternates from step to step (`pressure.rs`: with β = 1
    /// the three-level recurrence has a root μ = −1 where 3w = 2(2a + t), which modes of the
    /// surface layer cross; β = 2 weights the Robin term of the teaching beach's weak surface).
    /// Each step, the node whose pressure changed most (of those with a pressure unknown, wall
    /// nodes included: a node pinned to p = 0 loses its old pressure); an event is a change
    /// of more than 2 kPa (three times the hydrostatic pressure at the depth where it happens,
    /// 0–7 cm) of the opposite sign to the last step's largest, within 10 cm of it (the largest
    /// wanders along the surface while the mode alternates). (events, largest change in Pa)
    /// over the teaching beach's first `end_s` seconds.
    fn alternation(overrides: &[&str], end_s: f64) -> (usize, f64) {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/teaching_beach.toml");
        let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        let mut sim = Simulation::new(&Case::load(&path, &overrides).unwrap()).unwrap();
        let (mut events, mut largest) = (0, 0.0f64);
        let mut last: Option<(nalgebra::Vector2<f64>, f64)> = None;
        while sim.time_s < end_s - 1e-9 {
            sim.step_towards(end_s).unwrap();
            let (s, p) = (&sim.solver, &sim.particles);
            let change = |i: usize| s.p_new[i] - s.p_old[i];
            let top = (0..p.len())
                .filter(|&i| s.pressure.row_of_node[i] != u32::MAX)
                .max_by(|&i, &j| change(i).abs().total_cmp(&change(j).abs()));
            let now = top
                .filter(|&i| change(i).abs() > 2000.0)
                .map(|i| (p.position[i], change(i)));
            if let (Some((x, dp)), Some((x0, dp0))) = (now, last)
                && dp * dp0 < 0.0
                && (x - x0).norm() < 0.1
            {
                events += 1;
                largest = largest.max(dp.abs().min(dp0.abs()));
            }
            last = now;
        }
        (events, largest)
    }

    #[test]
    fn the_surface_layer_pressure_does_not_alternate_with_the_weighted_split() {
        let end_s = 10.0;
        let (one, one_max) = alternation(&["solver.increment_weight=1"], end_s);
        let (two, two_max) = alternation(&["solver.increment_weight=2"], end_s);
        println!(
            "teaching beach, first {end_s} s: β = 1: {one} steps alternate by > 2 kPa (largest \
             {one_max:.0} Pa); β = 2: {two} (largest {two_max:.0} Pa)"
        );
        // The usual split has the mode (so the measure sees it) ...
        assert!(one >= 20, "β = 1: {one} alternating steps");
        // ... and the weighted one does not.
        assert_eq!(two, 0, "β = 2: largest alternating change {two_max:.0} Pa");
    }
}
