//! The 3D simulation (a case with `flume.width_m`, issue 26): the [`Flow3`], its clock, the
//! Δt policy, the piston's path and the volume's bookkeeping, stepped one Δt at a time. It
//! never draws and never writes: `surflab run` (`output::run3d`) and the lab's worker read it
//! between steps, as they read the 2D [`crate::simulation::Simulation`].

use crate::case::Case;
use crate::solver3d::{Flow3, Step3, setup};
use crate::waves::paddle::PaddleMotion;

/// Why a 3D case could not be set up: the field and the reason.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Setup3Failed(pub String);

/// What the step changed of the water since the start, and the counters since they were last
/// taken ([`Simulation3::take_counts`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Ledger3 {
    /// What the moves changed of the volume since the start, m³ (Σ moved − start of step).
    pub moves_m3: f64,
    /// What the remeshes changed since the start, m³ (Σ next start − moved).
    pub remeshes_m3: f64,
    /// Fluid nodes the walls' guard put back, inserted and removed since the counts were
    /// last taken.
    pub guarded: usize,
    pub inserted: usize,
    pub removed: usize,
    /// The longest step since the counts were last taken, s: the Δt the policy set (the
    /// steps that land on a target time are shorter).
    pub longest_dt_s: f64,
}

pub struct Simulation3 {
    pub case: Case,
    pub flow: Flow3,
    pub time_s: f64,
    pub steps: u64,
    /// Volume of the kept tetrahedra at t = 0, m³.
    pub initial_volume_m3: f64,
    /// The last step's report (`None` before the first step).
    pub last: Option<Step3>,
    /// The last step's Δt, s (0 before the first).
    pub last_dt_s: f64,
    pub ledger: Ledger3,
    /// The piston's rest position and path, when the case has one.
    paddle: Option<(f64, PaddleMotion)>,
    /// Volume after the last move, m³ (the next remesh's change is measured from it).
    last_moved_m3: f64,
}

impl Simulation3 {
    /// Seeds the tank from the case and meshes it.
    pub fn new(case: &Case) -> Result<Simulation3, Setup3Failed> {
        let mut flow = setup::from_case(case).map_err(|e| Setup3Failed(e.to_string()))?;
        // The solver is told one step ahead where the piston's face is to be.
        let paddle = match (case.wavemaker.as_ref(), PaddleMotion::from_case(case)) {
            (Some(w), Some(Ok(motion))) => Some((w.x_m, motion)),
            (_, Some(Err(e))) => return Err(Setup3Failed(e.to_string())),
            _ => None,
        };
        let initial = flow.mesh_now().map_err(|e| Setup3Failed(e.to_string()))?;
        Ok(Simulation3 {
            case: case.clone(),
            flow,
            time_s: 0.0,
            steps: 0,
            initial_volume_m3: initial,
            last: None,
            last_dt_s: 0.0,
            ledger: Ledger3::default(),
            paddle,
            last_moved_m3: initial,
        })
    }

    /// Volume of the kept tetrahedra at the start of the last step (t = 0 before the first),
    /// m³.
    pub fn volume_m3(&self) -> f64 {
        self.last.map_or(self.initial_volume_m3, |s| s.volume_m3)
    }

    /// The Δt the flow's state asks for, s: `time.dt_max_s`, the CFL bound
    /// `time.cfl · h / (fastest fluid particle or moving wall)` and the surface-wave bound, as
    /// in 2D.
    pub fn dt_for(case: &Case, flow: &Flow3) -> f64 {
        let h = case.particles.spacing_m;
        let speed = flow.max_fluid_speed().max(flow.wall_speed());
        let cfl_dt = if speed > 0.0 {
            case.time.cfl * h / speed
        } else {
            f64::INFINITY
        };
        let surface_dt = case.time.surface_wave_dt_s(h, case.fluid.gravity_m_s2);
        case.time.dt_max_s.min(cfl_dt).min(surface_dt)
    }

    /// One step towards `target_s`, never past it: the Δt of [`Self::dt_for`], shortened to
    /// land on `target_s` rather than step a sliver past it. An error says why the run cannot
    /// go on (a diverged flow, a Δt below `time.dt_min_s`, a failed pressure solve), with the
    /// time and step; the state is then the one the trouble left.
    pub fn step_towards(&mut self, target_s: f64) -> Result<Step3, String> {
        let (t, steps) = (self.time_s, self.steps);
        let speed = self.flow.max_fluid_speed();
        if !speed.is_finite() {
            return Err(format!(
                "stopped at t = {t:.5} s (step {steps}): the flow diverged (a particle's speed is \
                 {speed})"
            ));
        }
        let mut dt = Self::dt_for(&self.case, &self.flow);
        if dt < self.case.time.dt_min_s {
            return Err(format!(
                "stopped at t = {t:.5} s (step {steps}): Δt = {dt:.2e} s is below \
                 time.dt_min_s = {} s (the fastest particle moves at {speed:.3} m/s)",
                self.case.time.dt_min_s
            ));
        }
        let left = target_s - t;
        if dt >= left || left < 1.5 * dt {
            dt = if dt >= left { left } else { 0.5 * left };
        }
        let t_next = if dt == left { target_s } else { t + dt };
        if let Some((x_rest, motion)) = &self.paddle {
            self.flow
                .drive_piston(x_rest + motion.displacement_m(t_next));
        }
        let s = self
            .flow
            .step(dt)
            .map_err(|e| format!("stopped at t = {t:.5} s (step {steps}): {e}"))?;
        self.time_s = t_next;
        self.steps += 1;
        self.last_dt_s = dt;
        let l = &mut self.ledger;
        l.remeshes_m3 += s.volume_m3 - self.last_moved_m3;
        l.moves_m3 += s.moved_volume_m3 - s.volume_m3;
        l.guarded += s.guarded;
        l.longest_dt_s = l.longest_dt_s.max(dt);
        l.inserted += s.nodes.inserted;
        l.removed += s.nodes.removed;
        self.last_moved_m3 = s.moved_volume_m3;
        self.last = Some(s);
        Ok(s)
    }

    /// The ledger as it stands, its counters then set back to 0 (the volume sums go on).
    pub fn take_counts(&mut self) -> Ledger3 {
        let now = self.ledger;
        self.ledger.guarded = 0;
        self.ledger.inserted = 0;
        self.ledger.removed = 0;
        self.ledger.longest_dt_s = 0.0;
        now
    }

    /// Fluid particles (nodes on no wall).
    pub fn fluid_count(&self) -> usize {
        self.flow.walls.iter().filter(|&&w| w == 0).count()
    }
}
