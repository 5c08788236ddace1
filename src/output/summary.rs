//! `summary.json`: what was run, how long it took and how it ended.

use crate::case::Case;
use serde::Serialize;
use std::collections::BTreeMap;

#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    pub case: String,
    /// The case after defaults and `--set` overrides: every resolved parameter.
    pub parameters: Case,
    /// Particles, steps and speed (their keys inline).
    #[serde(flatten)]
    pub run: RunFigures,
    /// Median ms per step of each stage.
    pub median_stage_ms: BTreeMap<String, f64>,
    pub median_pressure_iterations: f64,
    pub initial_volume_m2: f64,
    /// max |V/V₀ − 1| over the recorded outputs.
    pub volume_drift_max: f64,
    pub final_volume_ratio: f64,
    /// `ok`, or why the run stopped.
    pub status: String,
    /// Each surface-elevation gauge: x, and its wave height and period over the last whole
    /// waves (null when fewer than one whole wave passed).
    pub gauges: Vec<GaugeSummary>,
    /// Breaking on a beach: Iribarren number, predicted and observed type, breaking point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub breaking: Option<crate::diagnostics::breaking::BreakingSummary>,
    /// Wave height, mean level and undertow averaged over whole periods after the spin-up.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surf: Option<super::surf::SurfSummary>,
    /// With `wavemaker.absorb_long_waves`: how far absorbing has moved the paddle by the end,
    /// m (positive: towards the water).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paddle_absorbed_m: Option<f64>,
    /// With `wavemaker.absorb_reflected_waves`: the amplitude of the reflected wave arriving at
    /// the paddle over the last period its gauges read, m, and where they stand.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paddle_arriving_amplitude_m: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paddle_reflection_gauges_x_m: Option<[f64; 2]>,
}

/// The size and speed of a run, which every `summary.json` has, 2D or 3D (flattened into it,
/// so that the keys are the same in both).
#[derive(Debug, Clone, Serialize)]
pub struct RunFigures {
    /// Particles at the end (insertion and removal change the count).
    pub particles: usize,
    pub fluid_particles: usize,
    pub wall_nodes: usize,
    pub steps: u64,
    pub simulated_s: f64,
    pub wall_s: f64,
    /// Simulated seconds per wall second.
    pub real_time_factor: f64,
    /// Σ particles over steps / wall seconds (the wall time includes recording).
    pub particle_steps_per_s: f64,
    pub median_ms_per_step: f64,
}

impl RunFigures {
    /// From the counts at the end, the simulated and wall seconds, Σ particles over the steps
    /// and the median step.
    pub fn new(
        particles: usize,
        fluid_particles: usize,
        steps: u64,
        simulated_s: f64,
        wall_s: f64,
        particle_steps: f64,
        median_ms_per_step: f64,
    ) -> RunFigures {
        RunFigures {
            particles,
            fluid_particles,
            wall_nodes: particles - fluid_particles,
            steps,
            simulated_s,
            wall_s,
            real_time_factor: simulated_s / wall_s.max(1e-9),
            particle_steps_per_s: particle_steps / wall_s.max(1e-9),
            median_ms_per_step,
        }
    }

    /// The line `surflab run` and `surflab validate` print at the end of a run.
    pub fn line(&self) -> String {
        format!(
            "{} particles ({} fluid, {} wall nodes), {} steps, {:.3} s simulated in {:.2} s wall \
             (real-time factor {:.3}), {:.0} particle-steps/s, median {:.2} ms/step",
            self.particles,
            self.fluid_particles,
            self.wall_nodes,
            self.steps,
            self.simulated_s,
            self.wall_s,
            self.real_time_factor,
            self.particle_steps_per_s,
            self.median_ms_per_step,
        )
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct GaugeSummary {
    pub x_m: f64,
    #[serde(flatten)]
    pub stats: Option<crate::diagnostics::WaveStats>,
}

/// Median of a sample (NaN for none); it lives with the observers.
pub use crate::diagnostics::median;
