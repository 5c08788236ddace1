//! The solver's thread. The panel sends it typed [`Command`]s and reads its [`Status`]; it owns
//! the simulation and the recording stream, so the window never waits for a step.
//!
//! While running, it steps for about one display frame's worth of wall time (the budget adapts
//! to how long steps take), then logs one frame and reports. It also watches how many frames
//! the window draws ([`UiFrames`]): when the window falls under its band while drawing (on a
//! machine without a GPU the window's rasterizer competes with the solver for the same cores),
//! the worker rests between its frames, for a share of the time that it adapts until the
//! window is back in it ([`super::pacer`]). A numerical failure or a panic in a step stops the
//! run and shows in the status; the thread lives on and obeys the next command.

use super::pacer::Pacer;
use crate::case::Case;
use crate::diagnostics::breaking::BreakingDetector;
use crate::output::recorder::{Frame, FrameRecorder};
use crate::output::rrd::{RrdLogger, Viewing};
use crate::output::surf::{SurfRecorder, log_profiles};
use crate::simulation::Simulation;
use crate::solver::StageTimings;
use rerun::sink::LogSink;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender};
use std::time::{Duration, Instant};

mod tank;

/// What the panel asks of the worker.
#[derive(Debug, Clone)]
pub enum Command {
    Run,
    Pause,
    /// One step, then pause.
    Step,
    /// Start again from t = 0 with this case (also for changes that need a new flume).
    Reset(Box<Case>),
    /// Apply a change that does not need a new flume (wave height and period, α) at the next step.
    Retune(Box<Case>),
    /// Record to this .rrd file from now on (`None`: stop recording).
    Record(Option<PathBuf>),
    Shutdown,
}

/// What the worker reports after each frame and each command.
#[derive(Debug, Clone, Default)]
pub struct Status {
    pub case_name: String,
    /// A 3D tank (`flume.width_m`): `triangles` then counts tetrahedra.
    pub three_d: bool,
    pub running: bool,
    pub t_s: f64,
    pub steps: u64,
    pub particles: usize,
    pub fluid_particles: usize,
    /// Kept triangles and the EDT polygons merged from them, at the last step.
    pub triangles: usize,
    pub polygons: usize,
    /// Simulated seconds per wall second over the last frames.
    pub real_time_factor: f64,
    /// Mean ms per step over the last frame, overall and per stage.
    pub ms_per_step: f64,
    pub stage_ms: Vec<(&'static str, f64)>,
    /// Steps taken per logged frame (adapted to the frame budget).
    pub steps_per_frame: usize,
    pub volume_ratio: f64,
    /// The .rrd being written, if any.
    pub recording: Option<PathBuf>,
    /// Why the run stopped (a failure or a panic), until the next reset.
    pub error: Option<String>,
    /// Frames logged since the start.
    pub frames: u64,
    /// The last breaker seen on the beach: type, where and when (None before the first).
    pub breaker: Option<String>,
    /// Share of the wall time the solver works while running (1: flat out; less while it rests
    /// so that the window keeps its frame rate).
    pub solver_share: f64,
    /// The window's frame rate the worker last measured (0 before the first measurement).
    pub ui_fps_seen: f64,
    /// The band of frame rates the worker holds the window in (frames/s; [`super::pacer`]).
    pub ui_fps_band: (f64, f64),
}

/// Frames the window has drawn: the panel ticks it once per frame, the worker reads it to pace
/// itself.
#[derive(Debug, Default)]
pub struct UiFrames(AtomicU64);

impl UiFrames {
    pub fn tick(&self) {
        self.0.fetch_add(1, Ordering::Relaxed);
    }

    pub fn count(&self) -> u64 {
        self.0.load(Ordering::Relaxed)
    }
}

/// The surf zone as the lab sees it: the recorder a headless run uses, fed with the frames the
/// lab logs, and the gauge rows it needs for its averages.
struct Surf {
    recorder: SurfRecorder,
    gauge_records: Vec<(f64, Vec<Option<f64>>)>,
    /// Whole periods after the spin-up already shown, and whether the blueprint has the surf
    /// views yet.
    periods_shown: usize,
    views_sent: bool,
}

impl Surf {
    fn new(sim: &Simulation) -> Surf {
        Surf {
            recorder: SurfRecorder::new(sim),
            gauge_records: Vec::new(),
            periods_shown: 0,
            views_sent: false,
        }
    }

    /// After each whole period past the spin-up: the undertow profiles and the space–time
    /// pictures so far, in the views a headless run's recording has.
    fn log_averages(&mut self, sim: &Simulation, logger: &RrdLogger) {
        let Some(w) = &sim.case.wavemaker else { return };
        let start = self.gauge_records.first().map_or(0.0, |r| r.0);
        let from_s = start.max(sim.case.surf.spin_up_periods * w.period_s);
        let periods = ((sim.time_s - from_s) / w.period_s).floor();
        if periods < 1.0 || periods as usize <= self.periods_shown {
            return;
        }
        self.periods_shown = periods as usize;
        let (_, summary) = self.recorder.finish(sim, &self.gauge_records);
        if let Some(s) = &summary {
            log_profiles(logger, s);
        }
        self.recorder
            .log_space_time(logger, w.height_m, logger.scale());
        if !self.views_sent {
            self.views_sent = logger.add_surf_views().is_ok();
        }
    }
}

/// The solver thread's nice value. The window's frame goes through several threads in turn
/// (the UI, and on a machine without a GPU the rasterizer's); each waits for the one before, so
/// a solver step holding a core delays the whole frame. At nice 10 the scheduler gives those
/// threads the core first, and the solver takes what they leave (on a 2-core VM with lavapipe
/// about a quarter of a core either way). Paced as it is (see [`Pacer`]), it still runs.
pub const SOLVER_NICE: i32 = 10;

/// Lowers the calling thread's priority to [`SOLVER_NICE`], never raising it (Linux, where the
/// nice value belongs to the thread; elsewhere nothing). A refusal is harmless and ignored.
pub fn lower_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: get/setpriority only read their integer arguments; gettid has no preconditions.
    unsafe {
        let tid = libc::gettid() as libc::id_t;
        if libc::getpriority(libc::PRIO_PROCESS, tid) < SOLVER_NICE {
            let _ = libc::setpriority(libc::PRIO_PROCESS, tid, SOLVER_NICE);
        }
    }
}

/// The cores this process may use (1 when the system does not say).
fn available_cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Whether the solver keeps its second thread (the remesh's second half and the pressure
/// matrix's symbolic analysis) on a machine with `cores` cores. The window's frame takes a
/// core's worth of threads (the UI, and without a GPU the rasterizer's): with four cores or more
/// both fit beside it; with two or three the solver steps on one core and leaves the rest to
/// the window.
pub fn solver_gets_two_cores(cores: usize) -> bool {
    cores >= 4
}

/// What a frame's steps (run under `catch_unwind`) leave for the status: the failure, if any,
/// and whether it was a panic (then the state may be half-updated and is dropped).
fn frame_failure(outcome: std::thread::Result<Result<(), String>>) -> (Option<String>, bool) {
    match outcome {
        Ok(Ok(())) => (None, false),
        Ok(Err(e)) => (Some(e), false),
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "unknown panic".into());
            (Some(format!("the solver panicked: {what}")), true)
        }
    }
}

/// Sinks the recording stream always feeds (the embedded viewer; nothing in tests).
pub type SinkFactory = Arc<dyn Fn() -> Vec<Box<dyn LogSink>> + Send + Sync>;

/// The panel's end of the worker.
pub struct WorkerHandle {
    tx: Sender<Command>,
    rx: Receiver<Status>,
    thread: Option<std::thread::JoinHandle<()>>,
    /// The latest status received.
    pub status: Status,
}

impl WorkerHandle {
    /// Starts the worker on `case` (paused) with a wall-time budget per frame.
    pub fn spawn(
        case: Case,
        sinks: SinkFactory,
        frame_budget: Duration,
        ui_frames: Arc<UiFrames>,
    ) -> WorkerHandle {
        let (tx, cmd_rx) = std::sync::mpsc::channel();
        let (status_tx, rx) = std::sync::mpsc::channel();
        let thread = std::thread::Builder::new()
            .name("surflab-solver".into())
            .spawn(move || {
                lower_priority();
                let mut w = Worker::new(case, sinks, status_tx, frame_budget, ui_frames);
                w.run(cmd_rx);
            })
            .expect("spawn the solver thread");
        WorkerHandle {
            tx,
            rx,
            thread: Some(thread),
            status: Status::default(),
        }
    }

    /// Sends a command (ignored if the worker has gone).
    pub fn send(&self, c: Command) {
        let _ = self.tx.send(c);
    }

    /// Takes every status that arrived; returns true if any did.
    pub fn poll(&mut self) -> bool {
        let mut any = false;
        while let Ok(s) = self.rx.try_recv() {
            self.status = s;
            any = true;
        }
        any
    }

    /// Is the thread still alive?
    pub fn alive(&self) -> bool {
        self.thread.as_ref().is_some_and(|t| !t.is_finished())
    }
}

impl Drop for WorkerHandle {
    fn drop(&mut self) {
        let _ = self.tx.send(Command::Shutdown);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

struct Worker {
    sim: Option<Simulation>,
    /// A 3D case runs here instead of in `sim` (one of the two at most).
    tank: Option<tank::Tank>,
    case: Case,
    sinks: SinkFactory,
    recorder: Option<FrameRecorder>,
    recording: Option<PathBuf>,
    status_tx: Sender<Status>,
    status: Status,
    frame_budget: Duration,
    last_timings: Option<StageTimings>,
    rtf_window: (f64, f64),
    /// When the last frame was logged, in wall and simulated time: frames go to the viewer at
    /// most every `LOG_INTERVAL` of wall time and every `output.interval_s` of simulated time.
    last_logged: Option<(Instant, f64)>,
    /// Watches the logged frames for breaking and averages the undertow and the wave heights
    /// (idle without a beach and a wavemaker), as a headless run does.
    surf: Option<Surf>,
    pacer: Pacer,
}

/// Shortest wall time between two logged frames (about 10 frames of data per second): the
/// viewer ingests less and its plots grow more slowly, and the window stays smoother (on the
/// teaching beach at 9 s: 22 frames/s with 100 ms, 20 with 60 ms). Frames are also at least
/// the case's `output.interval_s` of simulated time apart, the cadence of a headless run's
/// recording: where the solver runs far below real time (a software rasterizer taking the
/// cores), the plots then grow with the simulated time, not with the wall time.
const LOG_INTERVAL: Duration = Duration::from_millis(100);

impl Worker {
    fn new(
        case: Case,
        sinks: SinkFactory,
        status_tx: Sender<Status>,
        frame_budget: Duration,
        ui_frames: Arc<UiFrames>,
    ) -> Worker {
        let mut w = Worker {
            sim: None,
            tank: None,
            case: case.clone(),
            sinks,
            recorder: None,
            recording: None,
            status_tx,
            status: Status::default(),
            frame_budget,
            last_timings: None,
            rtf_window: (0.0, 0.0),
            last_logged: None,
            surf: None,
            pacer: Pacer::new(ui_frames),
        };
        w.reset(case);
        w
    }

    fn run(&mut self, rx: Receiver<Command>) {
        loop {
            // Paused: wait for a command. Running: take what has arrived (waiting out the rest
            // the pacer asks for, if any) and step.
            let first = if self.status.running {
                let rest = self.pacer.rest;
                if rest.is_zero() {
                    rx.try_recv().ok()
                } else {
                    match rx.recv_timeout(rest) {
                        Ok(c) => Some(c),
                        Err(RecvTimeoutError::Timeout) => None,
                        Err(RecvTimeoutError::Disconnected) => return,
                    }
                }
            } else {
                match rx.recv_timeout(Duration::from_millis(200)) {
                    Ok(c) => Some(c),
                    Err(RecvTimeoutError::Timeout) => continue,
                    Err(RecvTimeoutError::Disconnected) => return,
                }
            };
            let mut next = first;
            while let Some(c) = next {
                if !self.obey(c) {
                    return;
                }
                next = rx.try_recv().ok();
            }
            if self.status.running {
                let started = Instant::now();
                self.frame(usize::MAX);
                if let Some(fps) = self.pacer.after_frame(started.elapsed()) {
                    self.status.ui_fps_seen = fps;
                }
                self.status.solver_share = self.pacer.state.share;
                self.status.ui_fps_band = self.pacer.state.band();
            } else {
                self.pacer.restart();
            }
        }
    }

    /// Returns false on shutdown.
    fn obey(&mut self, c: Command) -> bool {
        match c {
            Command::Run => {
                if (self.sim.is_some() || self.tank.is_some()) && self.status.error.is_none() {
                    self.status.running = true;
                }
            }
            Command::Pause => self.status.running = false,
            Command::Step => {
                self.status.running = false;
                if self.status.error.is_none() {
                    self.frame(1);
                }
            }
            Command::Reset(case) => self.reset(*case),
            Command::Retune(case) => self.retune(*case),
            Command::Record(path) => {
                self.recording = path;
                self.open_logger();
            }
            Command::Shutdown => return false,
        }
        self.report();
        true
    }

    fn reset(&mut self, case: Case) {
        self.case = case;
        self.status = Status {
            case_name: self.case.name.clone(),
            recording: self.recording.clone(),
            solver_share: self.pacer.state.share,
            ui_fps_band: self.pacer.state.band(),
            ..Status::default()
        };
        self.last_timings = None;
        self.rtf_window = (0.0, 0.0);
        self.tank = None;
        if self.case.flume.width_m.is_some() {
            let case = self.case.clone();
            self.reset_tank(&case);
            self.open_logger();
            self.log();
            self.report();
            return;
        }
        match Simulation::new(&self.case) {
            Ok(mut sim) => {
                if !solver_gets_two_cores(available_cores()) {
                    sim.use_one_core();
                }
                self.surf = Some(Surf::new(&sim));
                self.sim = Some(sim);
            }
            Err(e) => {
                self.sim = None;
                self.status.error = Some(format!("cannot set up the case: {e}"));
            }
        }
        self.open_logger();
        self.log();
        self.report();
    }

    /// Wave height and period, α: taken at the next step, without a new flume.
    fn retune(&mut self, case: Case) {
        let Some(sim) = self.sim.as_mut().filter(|_| case.flume.width_m.is_none()) else {
            return self.reset(case);
        };
        sim.retune(&case);
        // A new wave: breakers are counted afresh, from the next full-height wave on, and the
        // averages start again.
        let mut surf = Surf::new(sim);
        surf.recorder.detector = BreakingDetector::new(sim).starting_at(sim.time_s);
        self.surf = Some(surf);
        self.case = case;
    }

    /// A new recording (the viewer shows it as the newest), fed to the viewer and, when
    /// recording, to the .rrd file.
    fn open_logger(&mut self) {
        self.recorder = None;
        if self.sim.is_none() && self.tank.is_none() {
            return;
        }
        let mut sinks = (self.sinks)();
        if let Some(path) = &self.recording {
            match rerun::sink::FileSink::new(path) {
                Ok(f) => sinks.push(Box::new(f)),
                Err(e) => {
                    self.status.error = Some(format!("cannot record to {}: {e}", path.display()));
                    self.recording = None;
                }
            }
        }
        self.status.recording = self.recording.clone();
        let stream = match rerun::RecordingStreamBuilder::new("surflab").set_sinks(sinks) {
            Ok(s) => s,
            Err(e) => {
                self.status.error = Some(format!("cannot open the recording: {e}"));
                return;
            }
        };
        let Some(sim) = &self.sim else {
            return self.open_tank_logger(stream);
        };
        stream.set_log_time_enabled(false);
        let opened =
            FrameRecorder::to_stream(stream, sim, Viewing::Live).map_err(|e| e.to_string());
        match opened {
            Ok(r) => self.recorder = Some(r),
            Err(e) => self.status.error = Some(format!("cannot open the recording: {e}")),
        }
    }

    /// Steps for one frame's budget (at most `max_steps`), then logs a frame.
    fn frame(&mut self, max_steps: usize) {
        if self.tank.is_some() {
            return self.tank_frame(max_steps);
        }
        let Some(sim) = self.sim.as_mut() else {
            self.status.running = false;
            return;
        };
        let started = Instant::now();
        let t_start = sim.time_s;
        let mut steps = 0usize;
        let mut sum = StageTimings::default();
        let end = self.case.time.end_s.max(sim.time_s + 1e-9);
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            while steps < max_steps && started.elapsed() < self.frame_budget {
                let until = if sim.time_s >= end - 1e-12 {
                    f64::INFINITY
                } else {
                    end
                };
                match sim.step_towards(until.min(sim.time_s + 1.0)) {
                    Ok(r) => {
                        steps += 1;
                        sum = sum.zip_with(&r.timings, |a, b| a + b);
                    }
                    Err(e) => {
                        return Err(format!(
                            "stopped at t = {:.4} s (step {}): {e}",
                            sim.time_s, sim.steps
                        ));
                    }
                }
            }
            Ok(())
        }));
        let (failure, panicked) = frame_failure(outcome);
        if panicked {
            // The state may be half-updated: drop it; a reset starts afresh.
            self.sim = None;
        }
        if let Some(sim) = &self.sim {
            self.smooth_real_time_factor(sim.time_s - t_start, started);
            if steps > 0 {
                let n = steps as f64;
                self.status.ms_per_step = sum.total_ms() / n;
                self.status.stage_ms = sum.named().iter().map(|(k, v)| (*k, v / n)).collect();
                self.last_timings = Some(sum);
            }
        }
        let t_s = self.sim.as_ref().map(|s| s.time_s);
        self.end_frame(steps, failure, t_s, max_steps);
    }

    /// After a frame's `steps` (at most `max_steps`): the status's step count and failure, then
    /// a logged frame when one is due (`LOG_INTERVAL` of wall time and `output.interval_s` of
    /// simulated time after the last; always after a failure or a single step), and the report.
    /// `t_s`: the simulated time, `None` when the state was dropped.
    fn end_frame(&mut self, steps: usize, failure: Option<String>, t_s: Option<f64>, max: usize) {
        self.status.steps_per_frame = steps;
        let stopped = failure.is_some();
        if let Some(f) = failure {
            self.status.error = Some(f);
            self.status.running = false;
        }
        let interval_s = self.case.output.interval_s;
        let due = match (self.last_logged, t_s) {
            (Some((wall, t_last)), Some(t)) => {
                wall.elapsed() >= LOG_INTERVAL && t - t_last >= interval_s - 1e-12
            }
            _ => true,
        };
        if due || stopped || max != usize::MAX {
            self.log();
        }
        self.report();
    }

    /// Adds a frame that simulated `sim_dt_s` and started at `started` (its work and the rest
    /// the pacer took before it) to the real-time factor, smoothed over a few frames.
    fn smooth_real_time_factor(&mut self, sim_dt_s: f64, started: Instant) {
        let wall = (started.elapsed() + self.pacer.rest).as_secs_f64();
        self.rtf_window = (
            0.8 * self.rtf_window.0 + sim_dt_s,
            0.8 * self.rtf_window.1 + wall,
        );
    }

    fn log(&mut self) {
        if self.tank.is_some() {
            return self.log_tank();
        }
        let (Some(sim), Some(recorder)) = (&self.sim, self.recorder.as_mut()) else {
            return;
        };
        let frame = Frame::of(sim);
        let timings = self.last_timings.map(|t| {
            let n = self.status.steps_per_frame.max(1) as f64;
            t.zip_with(&t, |a, _| a / n)
        });
        let mut surf = self.surf.as_mut().filter(|s| s.recorder.active());
        let events = surf.as_mut().map_or_else(Vec::new, |s| {
            s.recorder.record(sim, frame.integrals.volume_m2)
        });
        if let Err(e) = recorder.log(sim, &frame, timings.as_ref(), &events) {
            self.status.error = Some(format!("recording failed: {e}"));
        }
        if let Some(s) = surf.as_ref()
            && let Err(e) = recorder.log_breaking(sim, &s.recorder.detector)
        {
            self.status.error = Some(format!("recording failed: {e}"));
        }
        if let Some(surf) = surf {
            surf.gauge_records.push((sim.time_s, frame.gauges.clone()));
            surf.log_averages(sim, recorder.logger());
            if let Some(b) = surf.recorder.detector.breakers.last() {
                self.status.breaker = Some(format!(
                    "{} at x = {:.2} m (still depth {:.3} m, height {:.3} m), t = {:.1} s",
                    b.observed.name(),
                    b.x_b_m,
                    b.h_b_m,
                    b.height_b_m,
                    b.t_b_s
                ));
            }
        }
        self.status.volume_ratio = frame.integrals.volume_m2 / sim.initial_volume_m2;
        self.status.frames += 1;
        self.last_logged = Some((Instant::now(), sim.time_s));
    }

    fn report(&mut self) {
        self.report_tank();
        if let Some(sim) = &self.sim {
            self.status.t_s = sim.time_s;
            self.status.steps = sim.steps;
            self.status.particles = sim.particles.len();
            self.status.fluid_particles = sim.particles.fluid_count();
            self.status.triangles = sim.solver.mesh.triangles.len();
            self.status.polygons = sim.solver.mesh.polygons.len();
        }
        self.status.real_time_factor = if self.rtf_window.1 > 0.0 {
            self.rtf_window.0 / self.rtf_window.1
        } else {
            0.0
        };
        self.status.case_name = self.case.name.clone();
        let _ = self.status_tx.send(self.status.clone());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_solver_shares_two_or_three_cores_with_the_window_and_takes_two_of_four() {
        assert!(!solver_gets_two_cores(1));
        assert!(!solver_gets_two_cores(2));
        assert!(!solver_gets_two_cores(3));
        assert!(solver_gets_two_cores(4));
        assert!(solver_gets_two_cores(16));
    }

    /// The solver thread runs at nice 10; the thread that spawned it keeps its own priority.
    #[cfg(target_os = "linux")]
    #[test]
    fn the_solver_thread_yields_to_the_window() {
        // SAFETY: getpriority only reads its integer arguments; gettid has no preconditions.
        let nice_of_this_thread =
            || unsafe { libc::getpriority(libc::PRIO_PROCESS, libc::gettid() as libc::id_t) };
        let before = nice_of_this_thread();
        let solver = std::thread::spawn(move || {
            lower_priority();
            nice_of_this_thread()
        })
        .join()
        .unwrap();
        // Lowering priority needs no privilege, so it must have happened, unless the thread
        // already ran at a lower priority, which it keeps.
        assert_eq!(
            solver,
            SOLVER_NICE.max(before),
            "solver thread at nice {solver}"
        );
        assert_eq!(
            nice_of_this_thread(),
            before,
            "the caller's priority changed"
        );
    }
}
