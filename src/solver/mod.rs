//! The fractional-step PFEM solver: one call of [`Solver::step`] remeshes the particle cloud and
//! advances it by Δt. See `step.rs` for the list of stages.
//!
//! The solver owns only scratch buffers; the state is the caller's [`Particles`]. It never does
//! I/O: what happened in a step comes back as a [`StepReport`], and numerical trouble as a
//! [`StepError`].

mod cg;
mod correct;
mod element_set;
mod elements;
mod filter;
mod motion;
mod nodes;
pub(crate) mod ordering;
mod pieces;
mod predict;
pub mod pressure;
pub(crate) mod relax;
mod step;
mod surface;
mod volume;

use crate::case::{Case, DtPolicy, Fluid, ParticleSettings, SolverSettings, Spacing, TimeSettings};
use crate::mesh::{Mesh, MeshError};
use nalgebra::Vector2;

pub use pressure::PressureSystem;

/// The solver's parameters: the case's `[solver]` table as written (its one source of truth,
/// with its defaults and its validation in `case::solver`), and what the solver resolves from
/// the rest of the case: lengths in metres, gravity as a vector, the time-step policy, the
/// absorber and the divergence guard.
#[derive(Debug, Clone)]
pub struct SolverParams {
    /// The `[solver]` table: α, δ, the fractional step, stabilisation, the pressure solver,
    /// node management and the optional surface and volume corrections.
    pub settings: SolverSettings,
    pub density_kg_m3: f64,
    pub viscosity_pa_s: f64,
    pub gravity_m_s2: Vector2<f64>,
    /// Particle spacing h, m (the coarsest, where a case refines part of the flume).
    pub spacing_m: f64,
    /// The local spacing h(x) (`particles.refine`); uniform h without refinement. The lengths
    /// the settings give in units of h (α, insertion, removal, merging, wall margin, Robin
    /// length) are taken in units of the spacing where they are measured.
    pub spacing: Spacing,
    /// Smallest Δt the solver may fall back to when a step would invert elements.
    pub dt_min_s: f64,
    /// May the solver shorten Δt on its own (CFL policy) when a step would invert elements?
    pub adaptive_dt: bool,
    /// Damping layer: (start x, length, β in 1/s).
    pub absorber: Option<(f64, f64, f64)>,
    /// A fluid speed above this stops the run as diverged, m/s (ten times the speed of a fall
    /// from the top of the flume, sqrt(2 g H)).
    pub speed_limit_m_s: f64,
    /// Use a second thread for half of the triangulation and for the symbolic Cholesky
    /// analysis (off: one core only, as in the lab, which leaves the other to the window).
    pub two_threads: bool,
}

impl SolverParams {
    /// The largest circumradius the α-shape keeps, α h (boundary triangles use the smaller
    /// α_b h), so the triangulation needs to report nothing larger.
    pub fn alpha_radius_m(&self) -> f64 {
        self.settings.alpha * self.spacing.coarsest_m()
    }

    /// Closest approach of a fluid particle at `x_m` to the solid, m (`wall_margin_h` h(x)).
    pub fn wall_margin_m(&self, x_m: f64) -> f64 {
        self.settings.wall_margin_h * self.spacing.at(x_m)
    }

    /// The α-shape's and the EDT's parameters.
    pub fn shape(&self) -> crate::mesh::ShapeParams {
        crate::mesh::ShapeParams {
            alpha: self.settings.alpha,
            alpha_boundary: self.settings.alpha_boundary,
            delta: self.settings.delta,
            spacing: self.spacing,
        }
    }

    pub fn from_case(case: &Case) -> SolverParams {
        let mut p = Self::resolve(&case.fluid, &case.particles, &case.solver, &case.time);
        p.speed_limit_m_s = 10.0 * (2.0 * case.fluid.gravity_m_s2 * case.flume.height_m).sqrt();
        p.absorber = case.absorber.as_ref().map(|a| {
            (
                case.flume.length_m - a.length_m,
                a.length_m,
                a.strength_per_s,
            )
        });
        p
    }

    /// Resolves the case's settings (units, derived lengths) into solver parameters.
    pub fn resolve(
        fluid: &Fluid,
        particles: &ParticleSettings,
        s: &SolverSettings,
        time: &TimeSettings,
    ) -> SolverParams {
        SolverParams {
            settings: s.clone(),
            density_kg_m3: fluid.density_kg_m3,
            viscosity_pa_s: fluid.viscosity_pa_s,
            gravity_m_s2: Vector2::new(0.0, -fluid.gravity_m_s2),
            spacing_m: particles.spacing_m,
            spacing: particles.spacing(),
            dt_min_s: time.dt_min_s,
            adaptive_dt: time.dt_policy == DtPolicy::Cfl,
            absorber: None,
            speed_limit_m_s: f64::INFINITY,
            two_threads: true,
        }
    }
}

/// The stages of a step, in the order they run (see `step.rs`); each has one timer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Node insertion, removal and merging before the remesh.
    Nodes,
    /// Delaunay triangulation of all nodes (spade).
    Remesh,
    /// α-shape, all-wall filter, free surface.
    AlphaShape,
    /// The per-strip water-area ledger, when on: booking the remesh and the move, and the
    /// divergence targets that pay it back.
    Relax,
    /// Element geometry, lumped mass, Smagorinsky viscosity, τ.
    Elements,
    /// Momentum predictor ũ.
    Predict,
    /// The pressure system: its pattern (right after the α-shape) and its values.
    Assemble,
    /// Pressure linear solve.
    PressureSolve,
    /// Velocity correction and pressure-gradient projection.
    Correct,
    /// Moving the surface nodes by their short-scale motion and back, for the second pass of
    /// `geometry_theta` (the pass itself is timed in its stages).
    Geometry,
    /// The fourth-difference filter of the surface velocities, when on.
    Filter,
    /// Particle motion and wall guard.
    Move,
    /// The global volume recovery on the free surface, when on.
    Recover,
}

impl Stage {
    pub const ALL: [Stage; 13] = [
        Stage::Nodes,
        Stage::Remesh,
        Stage::AlphaShape,
        Stage::Relax,
        Stage::Elements,
        Stage::Predict,
        Stage::Assemble,
        Stage::PressureSolve,
        Stage::Correct,
        Stage::Geometry,
        Stage::Filter,
        Stage::Move,
        Stage::Recover,
    ];

    /// The name in outputs (`timing_ms/<name>`, `median_stage_ms`, `surflab bench`).
    pub fn name(self) -> &'static str {
        match self {
            Stage::Nodes => "nodes",
            Stage::Remesh => "remesh",
            Stage::AlphaShape => "alpha_shape",
            Stage::Relax => "relax",
            Stage::Elements => "elements",
            Stage::Predict => "predict",
            Stage::Assemble => "assemble",
            Stage::PressureSolve => "pressure_solve",
            Stage::Correct => "correct",
            Stage::Geometry => "geometry",
            Stage::Filter => "filter",
            Stage::Move => "move",
            Stage::Recover => "recover",
        }
    }
}

/// Wall-clock milliseconds spent in each stage of one step (or summed over several).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StageTimings {
    ms: [f64; Stage::ALL.len()],
}

impl StageTimings {
    /// Runs `f` and adds its wall time to `stage`.
    pub fn time<T>(&mut self, stage: Stage, f: impl FnOnce() -> T) -> T {
        let start = std::time::Instant::now();
        let out = f();
        self.ms[stage as usize] += start.elapsed().as_secs_f64() * 1e3;
        out
    }

    pub fn ms(&self, stage: Stage) -> f64 {
        self.ms[stage as usize]
    }

    /// (name, ms) pairs in step order.
    pub fn named(&self) -> [(&'static str, f64); Stage::ALL.len()] {
        Stage::ALL.map(|s| (s.name(), self.ms(s)))
    }

    pub fn total_ms(&self) -> f64 {
        self.ms.iter().sum()
    }

    /// Stage by stage, `f(self, other)` (for sums and means over steps).
    pub fn zip_with(&self, other: &StageTimings, f: impl Fn(f64, f64) -> f64) -> StageTimings {
        StageTimings {
            ms: std::array::from_fn(|k| f(self.ms[k], other.ms[k])),
        }
    }
}

/// What one step did.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepReport {
    /// The Δt actually taken (it may be shorter than asked when elements would invert).
    pub dt_s: f64,
    pub timings: StageTimings,
    pub pressure_unknowns: usize,
    pub pressure_iterations: usize,
    pub kept_triangles: usize,
    /// EDT polygon elements among them (0 with δ = 0).
    pub polygons: usize,
    pub free_surface_nodes: usize,
    pub isolated_particles: usize,
    /// Fluid particles put back by the wall guard.
    pub guarded_particles: usize,
    /// Times Δt was halved in this step.
    pub dt_halvings: usize,
    /// Change of the water area (m²/m) made by this step's remesh, relative to the last step's
    /// mesh at the same positions: the α-shape's doing.
    pub remesh_area_change_m2: f64,
    /// Change of the area of this step's mesh when its nodes moved: the velocity field's
    /// divergence error.
    pub motion_area_change_m2: f64,
    /// Area put back on the free surface by the volume recovery, m²/m.
    pub recovered_area_m2: f64,
    /// Particles inserted and removed before the remesh.
    pub nodes_inserted: usize,
    pub nodes_removed: usize,
}

/// Numerical trouble that stops a run.
#[derive(Debug, thiserror::Error)]
pub enum StepError {
    #[error(transparent)]
    Mesh(#[from] MeshError),
    #[error("non-finite {quantity} at node {node} (x = {x:.4} m, y = {y:.4} m)")]
    NonFinite {
        quantity: &'static str,
        node: usize,
        x: f64,
        y: f64,
    },
    #[error("pressure solve failed: {0}")]
    Pressure(String),
    #[error("elements still invert with Δt = {dt_s:.3e} s, the smallest allowed step")]
    Inverted { dt_s: f64 },
    #[error(
        "diverged: a particle reached {speed_m_s:.3e} m/s at x = {x:.4} m, y = {y:.4} m, beyond the {limit_m_s:.3} m/s no flow in this flume can reach"
    )]
    Diverged {
        speed_m_s: f64,
        limit_m_s: f64,
        x: f64,
        y: f64,
    },
}

/// Scratch buffers reused from step to step.
#[derive(Default)]
pub struct Solver {
    pub params: SolverParams,
    /// The kept mesh of the last step (for observers: gauges, boundary, volume).
    pub mesh: Mesh,
    /// The Delaunay triangulations of stage 2 and their candidates, kept for their memory.
    triangulator: crate::mesh::Triangulator,
    /// The elements (triangles and EDT polygons) and their integration cells.
    cells: element_set::ElementSet,
    /// Per element.
    mu_e: Vec<f64>,
    tau_e: Vec<f64>,
    /// Per node.
    mass: Vec<f64>,
    tau_mass: Vec<f64>,
    /// pⁿ, with this step's Dirichlet values on its Dirichlet nodes (see `elements.rs`).
    p_old: Vec<f64>,
    u_tilde: Vec<Vector2<f64>>,
    u_new: Vec<Vector2<f64>>,
    p_new: Vec<f64>,
    pi_new: Vec<Vector2<f64>>,
    dirichlet: Vec<bool>,
    /// The pressure of the Dirichlet nodes, Pa (0 but at wall contact points; see
    /// `contact_pressure`).
    p_fixed: Vec<f64>,
    /// Area of the last step's mesh after its move (`None` before the first step).
    pub(crate) moved_area: Option<f64>,
    /// The water area to keep when `volume_recovery` is on (the initial one), m².
    pub volume_target_m2: Option<f64>,
    /// Per node: the divergence its continuity equation asks for, 1/s (`relax.rs`; 0 unless
    /// `volume_relaxation_s` > 0).
    divergence_target: Vec<f64>,
    ledger: relax::AreaLedger,
    pressure: PressureSystem,
    /// The symbolic Cholesky analysis of this step, running on the second core.
    symbolic_job: Option<pressure::SymbolicJob>,
    /// The second core's thread, started at the first step that may use it.
    second_core: Option<crate::second_core::SecondCore>,
    cg: cg::Scratch,
    /// The positions xⁿ while the second pass of `geometry_theta` runs on moved ones.
    geometry_saved: Vec<Vector2<f64>>,
}

/// The case's defaults, so that the two never disagree.
impl Default for SolverParams {
    fn default() -> Self {
        Self::resolve(
            &Fluid::default(),
            &ParticleSettings::default(),
            &SolverSettings::default(),
            &TimeSettings::default(),
        )
    }
}

impl Solver {
    pub fn new(params: SolverParams) -> Solver {
        Solver {
            params,
            ..Default::default()
        }
    }

    /// Takes the parameters of a changed case (α, and whatever else the case now says) from the
    /// next step on: the same derivation as at the start, [`SolverParams::from_case`]. Changes
    /// of the flume or the spacing need a new simulation instead. The thread setting is kept.
    pub fn retune(&mut self, case: &Case) {
        let two_threads = self.params.two_threads;
        self.params = SolverParams::from_case(case);
        self.params.two_threads = two_threads;
    }

    /// Work on one core only (the lab leaves the other to the window).
    pub fn use_one_core(&mut self) {
        self.params.two_threads = false;
        self.start_second_core();
    }

    /// Starts the second core's thread if the solver may use two cores and it is not running
    /// (and ends it if the solver may not): `self.second_core` is then `Some` exactly when
    /// the step may use it.
    fn start_second_core(&mut self) {
        if !self.params.two_threads {
            self.second_core = None;
        } else if self.second_core.is_none() {
            self.second_core = crate::second_core::SecondCore::start();
        }
    }

    /// Stage 1, the Delaunay triangles the α-shape may keep, on the second core as well when
    /// the solver may use two.
    fn triangulate(&mut self, particles: &Particles) -> Result<(), MeshError> {
        self.start_second_core();
        let max_r_m = self.params.alpha_radius_m();
        self.triangulator
            .run(particles, max_r_m, self.second_core.as_ref())
    }

    /// The pressure system of the last step (for the solver comparison in `bench`).
    pub fn pressure_system(&self) -> &PressureSystem {
        &self.pressure
    }
}

impl Solver {
    /// Stages 1–2 only: mesh the current cloud without advancing it (for t = 0 and observers).
    pub fn remesh(&mut self, particles: &Particles, flume: &Flume) -> Result<(), MeshError> {
        self.triangulate(particles)?;
        crate::mesh::alpha_shape(
            &self.triangulator.triangles,
            particles,
            &self.params.shape(),
            flume.paddle_now.as_ref(),
            &mut self.mesh,
        );
        Ok(())
    }
}

use crate::geometry::Flume;
use crate::particles::Particles;

impl Solver {
    /// The pressure force in divergence form, ∫ p ∇N_i = ∮ N_i p n − ∫ N_i ∇p, includes the
    /// traction of the pressure on the boundary edges. On the free surface p = 0 (or nearly,
    /// held weakly) and it vanishes, but an edge from a fluid node to a wall contact point runs
    /// from the water line to a wall node that holds the hydrostatic pressure of its height
    /// (`pressure.rs`), and that traction would push the water line along the wall. This
    /// removes it, `force_i −= ∫_edge N_i p n ds` (p linear along the edge, n outward).
    /// The free-surface edges from a wall contact point to a fluid node, as [from, to] along
    /// their kept triangle (counter-clockwise).
    pub(crate) fn contact_edges<'a>(
        &'a self,
        particles: &'a Particles,
    ) -> impl Iterator<Item = [usize; 2]> + 'a {
        let fs = &self.mesh.free_surface;
        self.mesh
            .boundary_edges
            .iter()
            .map(|&[a, b]| [a as usize, b as usize])
            .filter(move |&[a, b]| fs[a] && fs[b] && particles.is_fluid(a) != particles.is_fluid(b))
    }

    pub(crate) fn cancel_contact_traction(
        &self,
        particles: &Particles,
        p: impl Fn(usize) -> f64,
        force: &mut [Vector2<f64>],
    ) {
        for [a, b] in self.contact_edges(particles) {
            let d = particles.position[b] - particles.position[a];
            // Kept triangles are counter-clockwise and the edge runs along its triangle, so
            // the outward normal is d turned clockwise; |n| = ℓ absorbs the edge length.
            let n_len = Vector2::new(d.y, -d.x);
            let (pa, pb) = (p(a), p(b));
            force[a] -= n_len * ((2.0 * pa + pb) / 6.0);
            force[b] -= n_len * ((pa + 2.0 * pb) / 6.0);
        }
    }
}
