//! The simulation: particles, flume, solver, clock and Δt policy. It never draws and never
//! writes; observers read it between steps.

use crate::case::{Case, DtPolicy, WallCondition};
use crate::geometry::{self, Flume};
use crate::mesh::MeshError;
use crate::particles::Particles;
use crate::solver::{Solver, SolverParams, StepError, StepReport};
use crate::wavemaker::Wavemaker;
use crate::waves::WaveError;
use crate::waves::paddle::PaddleMotion;

/// Why a case could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error("the wavemaker cannot make this wave: {0}")]
    Wave(#[from] WaveError),
    #[error(
        "flume.width_m = {0} m makes this a 3D case: the 2D flume does not run it (`surflab run` \
         and `surflab validate` take it to the 3D path)"
    )]
    ThreeD(f64),
}

pub struct Simulation {
    pub case: Case,
    pub flume: Flume,
    pub particles: Particles,
    pub solver: Solver,
    pub time_s: f64,
    pub steps: u64,
    /// Water volume (area of the kept mesh) at t = 0, m² per metre of width.
    pub initial_volume_m2: f64,
    /// The paddle, when the case has a wavemaker.
    pub wavemaker: Option<Wavemaker>,
    /// Where the water area went since t = 0.
    pub area_budget: AreaBudget,
}

/// Sums of the per-step area changes the solver reports, m² per metre of width (signed: a
/// loss is negative). Their total is the volume drift V − V₀.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct AreaBudget {
    /// Triangles the α-shape added or removed when the nodes were re-triangulated.
    pub remesh_m2: f64,
    /// The moves of the nodes within a step (the discrete divergence of the velocity).
    pub motion_m2: f64,
    /// What `solver.volume_recovery` put back.
    pub recovered_m2: f64,
}

impl Simulation {
    /// Seeds the flume from the case, with hydrostatic pressure in every region, and meshes it.
    pub fn new(case: &Case) -> Result<Simulation, SetupError> {
        if let Some(width) = case.flume.width_m {
            return Err(SetupError::ThreeD(width));
        }
        let mut flume = Flume::from_case(case);
        let walls = flume.wall_nodes_with_tangents(&case.particles.spacing());
        let fluid = geometry::seed_fluid(case, &flume);
        let mut positions: Vec<_> = walls.iter().map(|(p, _)| *p).collect();
        let wavemaker = Wavemaker::from_case(case, &flume, positions.len()).transpose()?;
        if let Some(w) = &wavemaker {
            positions.extend(w.rest_nodes());
            flume.paddle_now = Some(w.face(0.0, 1.0));
            flume.paddle = flume.paddle_now;
        }
        let mut particles = Particles::new(&positions, &fluid);
        if case.flume.walls == WallCondition::Slip {
            for (i, (_, tangent)) in walls.iter().enumerate() {
                particles.wall_tangent[i] = *tangent;
            }
        }
        let rho_g = case.fluid.density_kg_m3 * case.fluid.gravity_m_s2;
        let spacing = case.particles.spacing();
        for i in 0..particles.len() {
            let x = particles.position[i];
            let h = spacing.at(x.x);
            let level = case
                .water
                .iter()
                .filter(|w| w.spans(x.x, 0.5 * h))
                .map(|w| w.level_at(x.x.clamp(w.x_start_m, w.x_end_m)))
                .fold(f64::NEG_INFINITY, f64::max);
            // Hydrostatic pressure, and π = −∇p = (0, ρg) on every node of the water, the
            // surface row included, so that the FIC term starts balanced.
            if level >= x.y - 1e-9 * h {
                particles.pressure[i] = rho_g * (level - x.y).max(0.0);
                particles.pressure_gradient_projection[i] = nalgebra::Vector2::new(0.0, rho_g);
            } else if level >= x.y - h {
                // A wall node less than h above the water line can belong to a kept triangle
                // at the wall (a contact point): its π must match too.
                particles.pressure_gradient_projection[i] = nalgebra::Vector2::new(0.0, rho_g);
            }
        }
        let mut solver = Solver::new(SolverParams::from_case(case));
        // Twice: the second pass applies the contact-line rule with the first pass's surface.
        solver.remesh(&particles, &flume)?;
        solver.remesh(&particles, &flume)?;
        let initial_volume_m2 = solver.mesh.area(&particles.position);
        solver.volume_target_m2 = Some(initial_volume_m2);
        // The first step's remeshing change is measured against this mesh.
        solver.moved_area = Some(initial_volume_m2);
        Ok(Simulation {
            case: case.clone(),
            flume,
            particles,
            solver,
            time_s: 0.0,
            steps: 0,
            initial_volume_m2,
            wavemaker,
            area_budget: AreaBudget::default(),
        })
    }

    /// Takes a changed case from the next step on, without a new flume: the solver's parameters
    /// (α, …) and the paddle's wave (height, period), which ramps from where the paddle stands.
    /// The case must describe the same flume and particles (the lab rebuilds for those).
    pub fn retune(&mut self, case: &Case) {
        self.solver.retune(case);
        if let (Some(w), Some(Ok(motion))) =
            (self.wavemaker.as_mut(), PaddleMotion::from_case(case))
        {
            w.retune(motion, self.time_s);
        }
        self.case = case.clone();
    }

    /// Steps on one core only (see [`Solver::use_one_core`]).
    pub fn use_one_core(&mut self) {
        self.solver.use_one_core();
    }

    /// The Δt the policy asks for, shortened so that the step lands on `until_s`.
    pub fn next_dt(&self, until_s: f64) -> f64 {
        let t = &self.case.time;
        // The finest spacing sets the surface-wave bound; each particle's own h(x) its CFL step.
        let spacing = self.solver.params.spacing;
        let surface_dt = t.surface_wave_dt_s(spacing.finest_m(), self.case.fluid.gravity_m_s2);
        let dt = match t.dt_policy {
            // Equal substeps, so the steps still land on multiples of the fixed Δt.
            DtPolicy::Fixed => t.dt_max_s / (t.dt_max_s / surface_dt).ceil().max(1.0),
            DtPolicy::Cfl => {
                let p = &self.particles;
                let fluid = (0..p.len()).filter(|&i| p.is_fluid(i));
                let cfl_dt = if spacing.refined_from_m().is_finite() {
                    // The largest |u|/h(x) over the fluid particles.
                    let rate = fluid
                        .map(|i| p.velocity[i].norm() / spacing.at(p.position[i].x))
                        .fold(0.0, f64::max);
                    t.cfl / rate.max(1e-12 / spacing.coarsest_m())
                } else {
                    let u_max = fluid
                        .map(|i| p.velocity[i].norm_squared())
                        .fold(0.0, f64::max)
                        .sqrt();
                    t.cfl * spacing.coarsest_m() / u_max.max(1e-12)
                };
                cfl_dt.min(surface_dt).clamp(t.dt_min_s, t.dt_max_s)
            }
        };
        let remaining = until_s - self.time_s;
        // The sum of the steps drifts from the output times by round-off: a remainder a few ulps
        // over Δt (or 2Δt) is one step (or two), not one step and two half steps.
        let slack = 1.0 + 1e-9;
        if remaining <= dt * slack {
            remaining
        } else if remaining * slack < 2.0 * dt {
            // Two even steps rather than a full one and a sliver.
            0.5 * remaining
        } else {
            dt
        }
    }

    /// Heights of every crossing of the vertical line x = `x_m` with the free surface (the
    /// boundary edges of the kept mesh with a fluid node), m, in no order; empty when dry.
    pub fn surface_heights_at(&self, x_m: f64) -> Vec<f64> {
        let p = &self.particles;
        self.solver
            .mesh
            .boundary_edges
            .iter()
            .filter(|[a, b]| p.is_fluid(*a as usize) || p.is_fluid(*b as usize))
            .filter_map(|[a, b]| {
                let (pa, pb) = (p.position[*a as usize], p.position[*b as usize]);
                let (lo, hi) = if pa.x <= pb.x { (pa, pb) } else { (pb, pa) };
                if x_m < lo.x || x_m > hi.x || hi.x == lo.x {
                    return None;
                }
                Some(lo.y + (hi.y - lo.y) * (x_m - lo.x) / (hi.x - lo.x))
            })
            .collect()
    }

    /// The water area shoreward of the vertical line x = `x_m`: the part of the kept mesh
    /// right of it, m² per metre of width.
    pub fn water_area_right_of_m2(&self, x_m: f64) -> f64 {
        self.solver
            .mesh_area_right_of_m2(&self.particles.position, x_m)
    }

    /// What the numerics changed of the water area shoreward of x = `x_m` since t = 0, net of
    /// what the volume relaxation paid back, m² per metre of width (signed: a loss is
    /// negative): the per-strip area ledger of `solver.volume_relaxation_s` summed over its
    /// strips (20 h wide) whose centre lies at or right of `x_m`. 0 when the relaxation is off.
    pub fn numerics_area_change_right_of_m2(&self, x_m: f64) -> f64 {
        self.solver.area_ledger_right_of_m2(x_m)
    }

    /// Height of the highest crossing of the vertical line x = `x_m` with the free surface, m
    /// above the floor; `None` when dry.
    pub fn surface_top_at(&self, x_m: f64) -> Option<f64> {
        self.surface_heights_at(x_m).into_iter().reduce(f64::max)
    }

    /// Before a step: the paddle's absorbers read η (m above the still level at the paddle) at
    /// their gauges.
    fn read_paddle_gauges(&mut self) {
        let Some(w) = &self.wavemaker else { return };
        let level = w.still_level_m();
        let eta = |x: f64| self.surface_top_at(x).map(|y| y - level);
        let long = w
            .absorbs()
            .then(|| eta(w.probe_x_m(self.time_s, self.case.particles.spacing_m)));
        let reflected = w
            .reflection_gauges_x_m()
            .map(|[a, b]| eta(a).zip(eta(b)).map(|(a, b)| [a, b]));
        let Some(w) = &mut self.wavemaker else { return };
        if let Some(eta) = long {
            w.absorb(self.time_s, eta);
        }
        if let Some(read) = reflected {
            w.absorb_reflection(self.time_s, read);
        }
    }

    /// One step towards `until_s`.
    pub fn step_towards(&mut self, until_s: f64) -> Result<StepReport, StepError> {
        let dt = self.next_dt(until_s);
        self.read_paddle_gauges();
        if let Some(w) = &self.wavemaker {
            w.prescribe(&mut self.particles, &mut self.flume, self.time_s, dt);
        }
        let report = self.solver.step(&mut self.particles, &self.flume, dt)?;
        self.time_s += report.dt_s;
        if (until_s - self.time_s).abs() < 1e-12 * until_s.max(1.0) {
            self.time_s = until_s;
        }
        if let Some(w) = &self.wavemaker {
            w.snap(&mut self.particles, self.time_s);
        }
        self.steps += 1;
        self.area_budget.remesh_m2 += report.remesh_area_change_m2;
        self.area_budget.motion_m2 += report.motion_area_change_m2;
        self.area_budget.recovered_m2 += report.recovered_area_m2;
        Ok(report)
    }

    /// Steps until `until_s`, calling `on_step` after each step.
    pub fn advance_to(
        &mut self,
        until_s: f64,
        mut on_step: impl FnMut(&Simulation, &StepReport),
    ) -> Result<(), StepError> {
        while self.time_s < until_s {
            let report = self.step_towards(until_s)?;
            on_step(self, &report);
        }
        Ok(())
    }
}
