//! The side panel: presets, wave and flume controls, live read-outs and warnings, run controls
//! and the worker's speed. It talks to the worker only through typed commands.

use super::controls::{Controls, Derived, Preset};
use super::worker::{Command, SinkFactory, UiFrames, WorkerHandle};
use crate::case::WaveTheory;
use crate::waves::linear::PaddleKind;
use egui::{RichText, Ui};
use std::path::PathBuf;
use std::time::Duration;

/// The panel's state: the presets, the settings being edited, and the worker.
pub struct Panel {
    pub presets: Vec<Preset>,
    pub preset: usize,
    /// The settings shown (being edited).
    pub controls: Controls,
    /// The settings the worker runs.
    pub applied: Controls,
    pub derived: Derived,
    pub worker: WorkerHandle,
    /// Record to this file when recording is on.
    pub record_path: PathBuf,
    pub recording: bool,
    /// Frames per second of the window, measured.
    pub ui_fps: f64,
    last_frame: Option<std::time::Instant>,
    /// Ticked once per frame drawn; the worker paces itself by it.
    ui_frames: std::sync::Arc<UiFrames>,
}

impl Panel {
    /// A panel on `presets[preset]` with a worker feeding `sinks`; the worker starts paused
    /// unless `autorun`.
    pub fn new(
        presets: Vec<Preset>,
        preset: usize,
        sinks: SinkFactory,
        record_path: PathBuf,
        autorun: bool,
    ) -> Result<Panel, String> {
        let p = presets
            .get(preset)
            .ok_or_else(|| "no case to open".to_owned())?;
        let case = crate::case::Case::from_toml_str(&p.text, &p.path, &p.name, &[])
            .map_err(|e| e.to_string())?;
        let controls = Controls::from_case(&case);
        let derived = Derived::compute(&controls, p);
        let ui_frames = std::sync::Arc::new(UiFrames::default());
        let worker = WorkerHandle::spawn(case, sinks, Duration::from_millis(30), ui_frames.clone());
        if autorun {
            worker.send(Command::Run);
        }
        Ok(Panel {
            presets,
            preset,
            applied: controls.clone(),
            controls,
            derived,
            worker,
            record_path,
            recording: false,
            ui_fps: 0.0,
            last_frame: None,
            ui_frames,
        })
    }

    fn current(&self) -> &Preset {
        &self.presets[self.preset]
    }

    /// Switches to another preset and resets the worker on it.
    pub fn select_preset(&mut self, k: usize) {
        if k >= self.presets.len() {
            return;
        }
        self.preset = k;
        let p = &self.presets[k];
        match crate::case::Case::from_toml_str(&p.text, &p.path, &p.name, &[]) {
            Ok(case) => {
                self.controls = Controls::from_case(&case);
                self.applied = self.controls.clone();
                self.worker.send(Command::Reset(Box::new(case)));
            }
            Err(e) => self.derived.refusal = Some(e.to_string()),
        }
        self.derived = Derived::compute(&self.controls, self.current());
    }

    /// Sends the edited settings to the worker if they make a valid case: a new flume when
    /// the geometry or particles change, a retune otherwise. An invalid case is refused (the
    /// reason is in `derived.refusal`) and the worker keeps what it runs.
    pub fn apply(&mut self) {
        self.derived = Derived::compute(&self.controls, self.current());
        if self.controls == self.applied {
            return;
        }
        let Ok(case) = self.controls.case(self.current()) else {
            return;
        };
        let cmd = if self.applied.needs_rebuild(&self.controls) {
            Command::Reset(Box::new(case))
        } else {
            Command::Retune(Box::new(case))
        };
        self.worker.send(cmd);
        self.applied = self.controls.clone();
    }

    /// Draws the panel.
    pub fn ui(&mut self, ui: &mut Ui) {
        let now = std::time::Instant::now();
        if let Some(last) = self.last_frame {
            let dt = (now - last).as_secs_f64();
            if dt > 0.0 {
                self.ui_fps = 0.9 * self.ui_fps + 0.1 / dt;
            }
        }
        self.last_frame = Some(now);
        self.ui_frames.tick();
        self.worker.poll();
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.heading("surflab");
            self.preset_ui(ui);
            ui.separator();
            self.controls_ui(ui);
            // Edited here or from outside (tests, presets): apply what differs.
            if self.controls != self.applied {
                self.apply();
            }
            ui.separator();
            self.readouts_ui(ui);
            ui.separator();
            self.run_ui(ui);
            ui.separator();
            self.speed_ui(ui);
        });
        if self.worker.status.running {
            ui.ctx().request_repaint();
        } else {
            ui.ctx().request_repaint_after(Duration::from_millis(250));
        }
    }

    fn preset_ui(&mut self, ui: &mut Ui) {
        let mut chosen = self.preset;
        egui::ComboBox::from_label("case")
            .selected_text(self.current().name.clone())
            .show_ui(ui, |ui| {
                for (k, p) in self.presets.iter().enumerate() {
                    ui.selectable_value(&mut chosen, k, &p.name);
                }
            });
        if chosen != self.preset {
            self.select_preset(chosen);
        }
    }

    fn controls_ui(&mut self, ui: &mut Ui) {
        let c = &mut self.controls;
        egui::Grid::new("controls").num_columns(2).show(ui, |ui| {
            if let Some(h) = c.height_m.as_mut() {
                ui.label("wave height H (m)");
                ui.add(
                    egui::DragValue::new(h)
                        .speed(0.001)
                        .range(0.001..=1.0)
                        .max_decimals(3),
                );
                ui.end_row();
            }
            if let (Some(t), Some(theory)) = (c.period_s.as_mut(), c.theory)
                && theory != WaveTheory::Solitary
            {
                ui.label("period T (s)");
                ui.add(
                    egui::DragValue::new(t)
                        .speed(0.01)
                        .range(0.2..=20.0)
                        .max_decimals(2),
                );
                ui.end_row();
            }
            if let Some(paddle) = c.paddle.as_mut() {
                ui.label("wavemaker");
                ui.horizontal(|ui| {
                    ui.selectable_value(paddle, PaddleKind::Piston, "piston");
                    ui.selectable_value(paddle, PaddleKind::Flap, "flap");
                });
                ui.end_row();
            }
            if let Some(theory) = c.theory.as_mut() {
                ui.label("theory");
                ui.horizontal(|ui| {
                    ui.selectable_value(theory, WaveTheory::Linear, "linear");
                    ui.selectable_value(theory, WaveTheory::Cnoidal, "cnoidal");
                    ui.selectable_value(theory, WaveTheory::Solitary, "solitary");
                });
                ui.end_row();
            }
            if let Some(s) = c.slope.as_mut() {
                ui.label("beach slope tan β");
                ui.add(
                    egui::DragValue::new(s)
                        .speed(0.002)
                        .range(0.01..=2.0)
                        .max_decimals(3),
                );
                ui.end_row();
            }
            ui.label("α (alpha-shape)");
            ui.add(
                egui::DragValue::new(&mut c.alpha)
                    .speed(0.01)
                    .range(1.01..=3.0)
                    .max_decimals(2),
            );
            ui.end_row();
            // The 3D path has no EDT polygons (a case refuses δ there).
            if c.width_m.is_none() {
                ui.label("δ (EDT polygons)");
                ui.add(
                    egui::DragValue::new(&mut c.delta)
                        .speed(0.002)
                        .range(0.0..=1.0)
                        .max_decimals(3),
                )
                .on_hover_text(
                    "Delaunay triangles whose circumcentres lie within δ of their mean radius \
                     merge into one polygon element (thesis eq. 2.2); 0 keeps triangles",
                );
                ui.end_row();
            }
            if let Some(w) = c.width_m.as_mut() {
                ui.label("tank width (m)");
                ui.add(
                    egui::DragValue::new(w)
                        .speed(0.002)
                        .range(0.001..=10.0)
                        .max_decimals(3),
                )
                .on_hover_text(
                    "Width of the 3D tank across the flume (z); every change starts the tank \
                     again, and the node count grows with it",
                );
                ui.end_row();
            }
            ui.label("resolution h (m)");
            ui.add(
                egui::DragValue::new(&mut c.spacing_m)
                    .speed(0.001)
                    .range(0.002..=0.2)
                    .max_decimals(4),
            );
            ui.end_row();
        });
    }

    fn readouts_ui(&mut self, ui: &mut Ui) {
        let d = &self.derived;
        let fmt = |v: Option<f64>, digits: usize, unit: &str| {
            v.map_or("–".to_owned(), |v| format!("{v:.digits$}{unit}"))
        };
        egui::Grid::new("readouts").num_columns(2).show(ui, |ui| {
            ui.label("L₀ = gT²/2π");
            ui.label(fmt(d.l0_m, 3, " m"));
            ui.end_row();
            ui.label("L at the paddle");
            ui.label(fmt(d.wavelength_m, 3, " m"));
            ui.end_row();
            ui.label("kh");
            ui.label(fmt(d.kh, 3, ""));
            ui.end_row();
            ui.label("H/L");
            ui.label(fmt(d.steepness, 4, ""));
            ui.end_row();
            ui.label("Iribarren Ir");
            ui.label(format!(
                "Ir = {}",
                d.iribarren.map_or("–".to_owned(), |v| format!("{v:.2}"))
            ));
            ui.end_row();
            ui.label("predicted breaker");
            ui.label(RichText::new(d.predicted.map_or("–", |b| b.name())).strong());
            ui.end_row();
            ui.label("paddle stroke");
            ui.label(fmt(d.stroke_m, 4, " m"));
            ui.end_row();
        });
        if let Some(r) = &d.refusal {
            ui.colored_label(ui.visuals().error_fg_color, format!("refused: {r}"));
        }
    }

    fn run_ui(&mut self, ui: &mut Ui) {
        let running = self.worker.status.running;
        ui.horizontal(|ui| {
            if ui
                .add_enabled(!running, egui::Button::new("▶ Run"))
                .clicked()
            {
                self.worker.send(Command::Run);
            }
            if ui
                .add_enabled(running, egui::Button::new("⏸ Pause"))
                .clicked()
            {
                self.worker.send(Command::Pause);
            }
            if ui.button("⏭ Step").clicked() {
                self.worker.send(Command::Step);
            }
            if ui.button("⟲ Reset").clicked() {
                self.reset();
            }
        });
        let mut recording = self.recording;
        ui.checkbox(
            &mut recording,
            format!("record to {}", self.record_path.display()),
        );
        if recording != self.recording {
            self.recording = recording;
            self.worker
                .send(Command::Record(recording.then(|| self.record_path.clone())));
        }
        let s = &self.worker.status;
        if let Some(e) = &s.error {
            ui.colored_label(ui.visuals().error_fg_color, format!("stopped: {e}"));
        }
        if !self.worker.alive() {
            ui.colored_label(ui.visuals().error_fg_color, "the solver thread has stopped");
        }
    }

    /// Starts again from t = 0 with the applied settings.
    pub fn reset(&mut self) {
        let case = self.applied.case(self.current()).or_else(|_| {
            let p = self.current();
            crate::case::Case::from_toml_str(&p.text, &p.path, &p.name, &[])
        });
        if let Ok(case) = case {
            self.worker.send(Command::Reset(Box::new(case)));
        }
    }

    fn speed_ui(&mut self, ui: &mut Ui) {
        let s = &self.worker.status;
        ui.label(format!(
            "{}: t = {:.3} s, {} steps, {} particles ({} fluid)",
            s.case_name, s.t_s, s.steps, s.particles, s.fluid_particles
        ));
        ui.label(format!(
            "real-time factor {:.2}, {:.1} ms/step, {} steps/frame, window {:.0} fps",
            s.real_time_factor, s.ms_per_step, s.steps_per_frame, self.ui_fps
        ));
        if s.running && s.solver_share < 0.999 {
            ui.label(format!(
                "solver paced to {:.0} % of the time to keep the window at {:.0}–{:.0} fps \
                 (measured {:.0})",
                100.0 * s.solver_share,
                s.ui_fps_band.0,
                s.ui_fps_band.1,
                s.ui_fps_seen
            ));
        }
        if s.three_d {
            ui.label(format!(
                "volume V/V₀ = {:.4}; mesh {} tetrahedra (3D)",
                s.volume_ratio, s.triangles
            ));
        } else {
            ui.label(format!(
                "volume V/V₀ = {:.4}; mesh {} triangles, {} EDT polygons",
                s.volume_ratio, s.triangles, s.polygons
            ));
        }
        ui.label(format!(
            "observed breaker: {}",
            s.breaker.as_deref().unwrap_or("none yet")
        ));
        egui::CollapsingHeader::new("ms per stage").show(ui, |ui| {
            for (name, ms) in &s.stage_ms {
                ui.label(format!("{name}: {ms:.2} ms"));
            }
        });
    }
}
