//! The window: `re_viewer::App` in an eframe window, with the panel on the right.

use super::controls::{Preset, presets_in};
use super::panel::Panel;
use super::worker::SinkFactory;
use rerun::external::re_log_channel::{self, LogSource};
use rerun::external::re_viewer;
use rerun::log::LogMsg;
use rerun::sink::{CallbackSink, LogSink};
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How to open the lab.
#[derive(Debug, Clone, Default)]
pub struct LabOptions {
    /// The case to open (default: `cases/teaching_beach.toml`, else the first preset).
    pub case: Option<PathBuf>,
    /// Save a PNG of the window to this path once the solver has run `screenshot_after_s`
    /// simulated seconds, then exit.
    pub screenshot: Option<PathBuf>,
    pub screenshot_after_s: f64,
    /// Where the "record" checkbox writes.
    pub record_path: PathBuf,
}

/// The folder of presets: that of the given case, else `cases/` here, else the source tree's.
fn presets_for(case: Option<&PathBuf>) -> Vec<Preset> {
    let mut dirs: Vec<PathBuf> = Vec::new();
    if let Some(dir) = case.and_then(|c| c.parent()) {
        dirs.push(if dir.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            dir.to_owned()
        });
    }
    dirs.push(PathBuf::from("cases"));
    dirs.push(PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases"));
    let mut presets = dirs
        .iter()
        .map(|d| presets_in(d))
        .find(|p| !p.is_empty())
        .unwrap_or_default();
    // A case outside the folders scanned is still offered.
    if let Some(c) = case
        && !presets.iter().any(|p| same_file(&p.path, c))
        && let Ok(text) = std::fs::read_to_string(c)
    {
        let name = c
            .file_stem()
            .map_or("case".into(), |s| s.to_string_lossy().into_owned());
        presets.push(Preset {
            name,
            path: c.clone(),
            text,
        });
    }
    presets
}

fn same_file(a: &std::path::Path, b: &std::path::Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Opens the lab window and blocks until it is closed.
pub fn run(opts: LabOptions) -> anyhow::Result<()> {
    let presets = presets_for(opts.case.as_ref());
    anyhow::ensure!(
        !presets.is_empty(),
        "no case files found (looked in the case's folder and in cases/)"
    );
    let start = match &opts.case {
        Some(c) => presets
            .iter()
            .position(|p| same_file(&p.path, c))
            .unwrap_or(0),
        None => presets
            .iter()
            .position(|p| p.name == "teaching_beach")
            .unwrap_or(0),
    };
    // Fail before opening a window if the chosen case is bad.
    {
        let p = &presets[start];
        crate::case::Case::from_toml_str(&p.text, &p.path, &p.name, &[])?;
    }

    install_crash_handler();
    let runtime = tokio_runtime()?;
    let (tx, rx) = re_log_channel::log_channel(LogSource::Sdk);
    let tx = Arc::new(Mutex::new(tx));
    let sinks: SinkFactory = Arc::new(move || {
        let tx = tx.clone();
        let sink: Box<dyn LogSink> = Box::new(CallbackSink::new(move |msgs: &[LogMsg]| {
            if let Ok(tx) = tx.lock() {
                for m in msgs {
                    let _ = tx.send(m.clone().into());
                }
            }
        }));
        vec![sink]
    });

    let screenshot = opts.screenshot.clone();
    let screenshot_mode = screenshot.is_some();
    let after = opts.screenshot_after_s;
    let record_path = opts.record_path.clone();
    // A screenshot run first measures the window with the solver paused, then starts it.
    let autorun = !screenshot_mode;
    eframe::run_native(
        "surflab",
        window_options("surflab", screenshot_mode),
        Box::new(move |cc| {
            let mut app = embedded_viewer(cc, &runtime, screenshot_mode)?;
            app.add_log_receiver(rx);
            let panel = Panel::new(presets, start, sinks, record_path, autorun)
                .map_err(|e| anyhow::anyhow!(e))?;
            Ok(Box::new(LabApp {
                viewer: app,
                panel,
                screenshot: screenshot.map(|path| Screenshot {
                    path,
                    after_s: after,
                    requested: false,
                    opened: Instant::now(),
                    paused_frames: 0,
                    paused_since: None,
                    frames_running: 0,
                    running_since: None,
                }),
                _runtime: runtime,
            }))
        }),
    )
    .map_err(|e| anyhow::anyhow!("the window failed: {e}"))
}

/// The eframe options of a viewer window titled `title`; a screenshot run does not save the
/// window's size and place.
pub(super) fn window_options(title: &str, screenshot_mode: bool) -> eframe::NativeOptions {
    let mut native = re_viewer::native::eframe_options(None);
    native.viewport = native
        .viewport
        .with_title(title)
        .with_inner_size([1280.0, 800.0]);
    native.persist_window = !screenshot_mode;
    native
}

/// The Rerun viewer inside an eframe window being created. A screenshot run starts from the
/// viewer's defaults, whatever an earlier window saved.
pub(super) fn embedded_viewer(
    cc: &eframe::CreationContext<'_>,
    runtime: &tokio::runtime::Runtime,
    screenshot_mode: bool,
) -> Result<re_viewer::App, Box<dyn std::error::Error + Send + Sync>> {
    setup_renderer(cc)?;
    let startup = re_viewer::StartupOptions {
        hide_welcome_screen: true,
        persist_state: !screenshot_mode,
        ..Default::default()
    };
    Ok(re_viewer::App::new(
        re_viewer::MainThreadToken::i_promise_i_am_on_the_main_thread(),
        re_viewer::build_info(),
        re_viewer::AppEnvironment::Custom("surflab".into()),
        startup,
        cc,
        None,
        re_viewer::AsyncRuntimeHandle::new_native(runtime.handle().clone()),
    ))
}

pub(super) fn install_crash_handler() {
    rerun::external::re_crash_handler::install_crash_handlers(re_viewer::build_info());
}

/// What `re_viewer::customize_eframe_and_setup_renderer` does, except that on a software
/// rasterizer (lavapipe, llvmpipe: no GPU) the flume view renders without 4× multisampling.
/// There the rasterizer threads take most of the window's CPU time, and every sample of the
/// 2D view is shaded on the CPU.
fn setup_renderer(
    cc: &eframe::CreationContext<'_>,
) -> Result<(), re_viewer::external::re_renderer::RenderContextError> {
    use re_viewer::external::re_renderer::{MsaaMode, RenderConfig, RenderContext};
    if let Some(state) = &cc.wgpu_render_state {
        let on_cpu = state.adapter.get_info().device_type == eframe::wgpu::DeviceType::Cpu;
        let render_ctx = RenderContext::new(
            &state.adapter,
            state.device.clone(),
            state.queue.clone(),
            state.target_format,
            |caps| {
                let mut config = RenderConfig::best_for_device_caps(caps);
                if on_cpu && std::env::var_os("SURFLAB_MSAA").is_none() {
                    config.msaa_mode = MsaaMode::Off;
                }
                config
            },
        )?;
        state.renderer.write().callback_resources.insert(render_ctx);
    }
    re_viewer::external::re_ui::apply_style_and_install_loaders(&cc.egui_ctx);
    Ok(())
}

pub(super) fn tokio_runtime() -> anyhow::Result<tokio::runtime::Runtime> {
    Ok(tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()?)
}

/// How long a screenshot run measures the window with the solver paused.
const PAUSED_MEASURE: Duration = Duration::from_secs(5);

struct Screenshot {
    path: PathBuf,
    after_s: f64,
    requested: bool,
    opened: Instant,
    /// Frames drawn with the solver paused, before it starts, and since when: what the
    /// machine's renderer gives the window on its own.
    paused_frames: u32,
    paused_since: Option<Instant>,
    /// Frames drawn since the solver first reported simulated time, and when that was.
    frames_running: u32,
    running_since: Option<Instant>,
}

struct LabApp {
    viewer: re_viewer::App,
    panel: Panel,
    screenshot: Option<Screenshot>,
    _runtime: tokio::runtime::Runtime,
}

impl eframe::App for LabApp {
    fn logic(&mut self, ctx: &egui::Context, frame: &mut eframe::Frame) {
        self.viewer.logic(ctx, frame);
    }

    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        egui::Panel::right("surflab_panel")
            .default_size(330.0)
            .show(ui, |ui| self.panel.ui(ui));
        self.viewer.ui(ui, frame);
        self.screenshot_step(ui.ctx());
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        self.viewer.save(storage);
    }
}

impl LabApp {
    /// `--screenshot`: once the solver has run long enough (or a wall-clock limit passed, or it
    /// stopped), ask for a screenshot; when it arrives, save it and close.
    fn screenshot_step(&mut self, ctx: &egui::Context) {
        let Some(shot) = self.screenshot.as_mut() else {
            return;
        };
        // First PAUSED_MEASURE of drawing with the solver paused (after a second to settle),
        // then the solver runs.
        let since = *shot
            .paused_since
            .get_or_insert_with(|| Instant::now() + Duration::from_secs(1));
        if shot.running_since.is_none() && self.panel.worker.status.t_s == 0.0 {
            let now = Instant::now();
            if now >= since {
                shot.paused_frames += 1;
            }
            if now >= since + PAUSED_MEASURE && !self.panel.worker.status.running {
                let s = (now - since).as_secs_f64();
                eprintln!(
                    "surflab: with the solver paused the window drew {} frames in {s:.1} s ({:.1} \
                     frames/s)",
                    shot.paused_frames,
                    f64::from(shot.paused_frames) / s
                );
                self.panel.worker.send(super::worker::Command::Run);
            }
        }
        let status = &self.panel.worker.status;
        if status.t_s > 0.0 && !shot.requested {
            shot.running_since.get_or_insert_with(Instant::now);
            shot.frames_running += 1;
        }
        let waited = shot.opened.elapsed();
        let ready = status.t_s >= shot.after_s
            || status.error.is_some()
            || waited > Duration::from_secs_f64(120.0 + 20.0 * shot.after_s);
        if ready && !shot.requested {
            // Let the viewer draw the last data first.
            shot.requested = true;
            ctx.send_viewport_cmd(egui::ViewportCommand::Screenshot(Default::default()));
        }
        match save_screenshot(ctx, &shot.path) {
            ShotOutcome::Waiting => {}
            outcome => {
                if outcome == ShotOutcome::Saved {
                    let running_s = shot
                        .running_since
                        .map_or(0.0, |t| t.elapsed().as_secs_f64());
                    eprintln!(
                        "surflab: at t = {:.3} s simulated the window drew {} frames in {running_s:.1} s \
                         while the solver ran ({:.1} frames/s); solver: real-time factor {:.2}, {:.1} ms/step",
                        status.t_s,
                        shot.frames_running,
                        f64::from(shot.frames_running) / running_s.max(1e-9),
                        status.real_time_factor,
                        status.ms_per_step
                    );
                }
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
        ctx.request_repaint();
    }
}

/// What became of a requested screenshot this frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ShotOutcome {
    /// Not arrived yet.
    Waiting,
    Saved,
    Failed,
}

/// Saves the screenshot to `path` when it has arrived in this frame's events (after a
/// `ViewportCommand::Screenshot`), and says so on stderr.
pub(super) fn save_screenshot(ctx: &egui::Context, path: &std::path::Path) -> ShotOutcome {
    let image = ctx.input(|i| {
        i.raw.events.iter().find_map(|e| match e {
            egui::Event::Screenshot { image, .. } => Some(image.clone()),
            _ => None,
        })
    });
    let Some(image) = image else {
        return ShotOutcome::Waiting;
    };
    let [w, h] = image.size;
    let bytes: Vec<u8> = image.pixels.iter().flat_map(|c| c.to_array()).collect();
    let result = image::RgbaImage::from_raw(w as u32, h as u32, bytes)
        .ok_or_else(|| "bad screenshot buffer".to_owned())
        .and_then(|img| img.save(path).map_err(|e| e.to_string()));
    match result {
        Ok(()) => {
            eprintln!("surflab: saved {} ({w}×{h})", path.display());
            ShotOutcome::Saved
        }
        Err(e) => {
            eprintln!("surflab: cannot save {}: {e}", path.display());
            ShotOutcome::Failed
        }
    }
}
