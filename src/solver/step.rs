//! One PFEM time step, as a list of stages (thesis §2.5; method.md §1):
//!
//! 0. `nodes`: split stretched triangles of the last mesh, remove crowded interior nodes, merge
//!    colliding surface nodes (if asked);
//! 1. `remesh`: Delaunay triangulation of every node;
//! 2. `alpha_shape`: keep triangles with R < α·h, drop all-wall ones, find the free surface;
//!    then (optional) `relax`: book what the remesh changed in the per-strip area ledger, and
//!    ask the deep nodes of each strip for the divergence s that pays its balance back
//!    (`relax.rs`);
//! 3. `elements`: areas, gradients, lumped mass, Smagorinsky μ_e, τ;
//! 4. `predict`: ũ from momentum without the pressure increment;
//! 5. `assemble` + `pressure_solve`: (Δt/ρ L + L_τ) pⁿ⁺¹ = −Dũ + Ms + γ(Δt/ρ)L pⁿ − Qπⁿ (s the
//!    divergence target of stage 2), p = 0 on the
//!    free surface, strongly or weakly (the pattern is built right after the α-shape, so that its symbolic
//!    factorisation runs on the second core during stages 3–5);
//! 6. `correct`: uⁿ⁺¹ = ũ + Δt M⁻¹ Dᵀ(pⁿ⁺¹ − γpⁿ), and π from pⁿ⁺¹;
//!    then (optional) the fourth-difference filter of the surface velocities (`filter.rs`);
//! 7. `move`: xⁿ⁺¹ = xⁿ + Δt uⁿ⁺¹ (thesis eq. 2.59), then the wall guard, then (optional)
//!    the volume recovery on the free surface (`volume.rs`), then (with `relax`) book what the move
//!    changed in the ledger.
//!
//! If the new velocities would turn a kept triangle inside out within Δt, and the Δt policy
//! allows it, stages 4–6 are redone with Δt/2.

use super::{Solver, StageTimings, StepError, StepReport};
use crate::geometry::Flume;
use crate::mesh;
use crate::particles::Particles;
use std::time::Instant;

/// Runs `f` and adds its wall time in ms to `slot`.
fn timed<T>(slot: &mut f64, f: impl FnOnce() -> T) -> T {
    let start = Instant::now();
    let out = f();
    *slot += start.elapsed().as_secs_f64() * 1e3;
    out
}

impl Solver {
    /// Advances `particles` by (at most) `dt_s`.
    pub fn step(
        &mut self,
        particles: &mut Particles,
        flume: &Flume,
        dt_s: f64,
    ) -> Result<StepReport, StepError> {
        let mut t = StageTimings::default();
        let (alpha, alpha_b, h) = (
            self.params.alpha,
            self.params.alpha_boundary,
            self.params.spacing_m,
        );

        self.relax_start(particles);
        let changes = timed(&mut t.nodes_ms, || self.manage_nodes(particles));
        let (max_r_m, two_threads) = (self.params.alpha_radius_m(), self.params.two_threads);
        let tri = timed(&mut t.remesh_ms, || {
            mesh::triangulate(particles, max_r_m, two_threads)
        })?;
        timed(&mut t.alpha_shape_ms, || {
            mesh::alpha_shape(
                &tri,
                particles,
                alpha,
                alpha_b,
                h,
                flume.paddle_now.as_ref(),
                &mut self.mesh,
            )
        });
        drop(tri);
        timed(&mut t.elements_ms, || self.relax_targets(particles));
        timed(&mut t.assemble_ms, || self.prepare_pressure(particles));
        let area_before_move = self.mesh.area(&particles.position);
        let remesh_change = self.moved_area.map_or(0.0, |a| area_before_move - a);

        let mut dt = dt_s;
        let mut halvings = 0;
        let iterations = loop {
            timed(&mut t.elements_ms, || {
                self.element_properties(particles, dt)
            });
            timed(&mut t.predict_ms, || self.predict(particles, dt));
            timed(&mut t.assemble_ms, || self.assemble_pressure(particles, dt));
            let iterations = timed(&mut t.pressure_solve_ms, || self.solve_pressure(particles))?;
            timed(&mut t.correct_ms, || self.correct(particles, dt));
            let inverted = self.would_invert(particles, dt);
            if !inverted || !self.params.adaptive_dt {
                break iterations;
            }
            if dt * 0.5 < self.params.dt_min_s {
                return Err(StepError::Inverted { dt_s: dt });
            }
            dt *= 0.5;
            halvings += 1;
        };

        timed(&mut t.correct_ms, || self.filter_surface(particles));
        let guarded = timed(&mut t.move_ms, || self.move_particles(particles, flume, dt))?;
        let area_after_move = self.mesh.area(&particles.position);
        let recovered = match self.volume_target_m2 {
            Some(target) if self.params.volume_recovery => timed(&mut t.move_ms, || {
                self.recover_volume(particles, flume, area_after_move, target)
            }),
            _ => 0.0,
        };
        self.moved_area = Some(area_after_move + recovered);
        timed(&mut t.move_ms, || self.relax_after_move(particles));

        Ok(StepReport {
            dt_s: dt,
            timings: t,
            pressure_unknowns: self.pressure.unknowns(),
            pressure_iterations: iterations,
            kept_triangles: self.mesh.triangles.len(),
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
