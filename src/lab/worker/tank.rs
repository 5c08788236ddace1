//! The worker on a 3D case (`flume.width_m`, issue 26): the same commands, frames and status as
//! on the 2D flume, with a [`Simulation3`] stepped and the 3D recording ([`Recorder3`]) fed to
//! the viewer. A change of any setting starts the tank again (there is no retune in 3D), and
//! there is no surf zone to watch (no beach in 3D yet).

use super::{Worker, frame_failure};
use crate::case::Case;
use crate::output::rrd3d::Recorder3;
use crate::output::run3d::Row3;
use crate::simulation3d::Simulation3;
use crate::solver3d::STAGES_3D;
use rerun::RecordingStream;
use std::time::Instant;

/// A 3D tank in the lab: the simulation and its recording.
pub(super) struct Tank {
    pub sim: Simulation3,
    recorder: Option<Recorder3>,
}

impl Worker {
    /// Sets up the 3D `case` in place of whatever ran (called by `reset` for a case with a
    /// width).
    pub(super) fn reset_tank(&mut self, case: &Case) {
        self.sim = None;
        self.surf = None;
        match Simulation3::new(case) {
            Ok(sim) => {
                self.tank = Some(Tank {
                    sim,
                    recorder: None,
                })
            }
            Err(e) => {
                self.tank = None;
                self.status.error = Some(format!("cannot set up the case: {e}"));
            }
        }
    }

    /// The 3D recording on a new stream (the viewer's sinks, and the .rrd when recording).
    pub(super) fn open_tank_logger(&mut self, stream: RecordingStream) {
        let Some(tank) = self.tank.as_mut() else {
            return;
        };
        tank.recorder = None;
        match Recorder3::to_stream(stream, &tank.sim.case, &tank.sim.flow) {
            Ok(r) => tank.recorder = Some(r),
            Err(e) => self.status.error = Some(format!("cannot open the recording: {e}")),
        }
    }

    /// Steps the tank for one frame's budget (at most `max_steps`), then logs a frame when one
    /// is due. A step takes longer than a frame's budget from a few thousand particles on, so
    /// the window then gets one step a frame.
    pub(super) fn tank_frame(&mut self, max_steps: usize) {
        let Some(tank) = self.tank.as_mut() else {
            self.status.running = false;
            return;
        };
        let sim = &mut tank.sim;
        let started = Instant::now();
        let t_start = sim.time_s;
        let mut steps = 0usize;
        let mut stage_sum = [0.0f64; STAGES_3D.len()];
        let end = sim.case.time.end_s;
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            while steps < max_steps && started.elapsed() < self.frame_budget {
                // Past the case's end time the tank runs on, as the 2D flume does.
                let target = if sim.time_s < end - 1e-12 {
                    end.min(sim.time_s + 1.0)
                } else {
                    sim.time_s + 1.0
                };
                let s = sim.step_towards(target)?;
                steps += 1;
                for (sum, ms) in stage_sum.iter_mut().zip(s.stage_ms) {
                    *sum += ms;
                }
            }
            Ok::<(), String>(())
        }));
        let (failure, panicked) = frame_failure(outcome);
        if panicked {
            // The state may be half-updated: drop it; a reset starts afresh.
            self.tank = None;
        }
        if let Some(tank) = &self.tank {
            self.smooth_real_time_factor(tank.sim.time_s - t_start, started);
            if steps > 0 {
                let n = steps as f64;
                self.status.ms_per_step = stage_sum.iter().sum::<f64>() / n;
                self.status.stage_ms = STAGES_3D
                    .iter()
                    .zip(stage_sum)
                    .map(|(k, v)| (*k, v / n))
                    .collect();
            }
        }
        let t_s = self.tank.as_ref().map(|t| t.sim.time_s);
        self.end_frame(steps, failure, t_s, max_steps);
    }

    /// One frame of the tank to the viewer (and the .rrd when recording).
    pub(super) fn log_tank(&mut self) {
        let Some(tank) = self.tank.as_mut() else {
            return;
        };
        let v0 = tank.sim.initial_volume_m3;
        let row = Row3::of(&mut tank.sim);
        if let Some(r) = tank.recorder.as_mut()
            && let Err(e) = r.log(&tank.sim.flow, &row, v0)
        {
            self.status.error = Some(format!("recording failed: {e}"));
        }
        self.status.volume_ratio = row.volume_m3 / v0;
        self.status.frames += 1;
        self.last_logged = Some((Instant::now(), tank.sim.time_s));
    }

    /// The tank's part of the status: time, particles, tetrahedra (in `triangles`).
    pub(super) fn report_tank(&mut self) {
        let Some(tank) = &self.tank else { return };
        let sim = &tank.sim;
        self.status.three_d = true;
        self.status.t_s = sim.time_s;
        self.status.steps = sim.steps;
        self.status.particles = sim.flow.x.len();
        self.status.fluid_particles = sim.fluid_count();
        self.status.triangles = sim.last.map_or(0, |s| s.tetrahedra);
        self.status.polygons = 0;
    }
}
