//! `surflab view FILE.rrd [FILE.rrd …]`: recordings in the embedded viewer, without a separately
//! installed Rerun.
//!
//! One file opens as it was recorded, blueprint included. Several files are merged into one
//! recording, each run's entities under its own name (the run's folder, or the file's stem when
//! it is not called `run.rrd`), so that two runs (say α = 1.2 and α = 1.4) play on the same
//! `sim_time` timeline side by side. Every file is decoded before the window opens, so a missing
//! or corrupt file is an error that names it.

use super::window::{
    ShotOutcome, embedded_viewer, install_crash_handler, save_screenshot, tokio_runtime,
    window_options,
};
use crate::output::rrd::SIM_TIMELINE;
use anyhow::{Context, Result, bail};
use rerun::blueprint::components::PanelState;
use rerun::blueprint::{
    Blueprint, BlueprintActivation, BlueprintPanel, Horizontal, SelectionPanel, Spatial2DView,
    TimePanel, TimeSeriesView, Vertical,
};
use rerun::external::re_log_channel::{self, LogSource};
use rerun::external::re_log_encoding::DecoderApp;
use rerun::external::re_viewer;
use rerun::log::{Chunk, LogMsg};
use rerun::sink::{CallbackSink, LogSink};
use rerun::{EntityPath, RecordingStreamBuilder, StoreKind};
use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What to open.
#[derive(Debug, Clone, Default)]
pub struct ViewOptions {
    pub files: Vec<PathBuf>,
    /// Save a PNG of the window once the recordings are loaded, then exit (the test harness).
    pub screenshot: Option<PathBuf>,
}

/// A decoded recording file.
struct Recording {
    name: String,
    messages: Vec<LogMsg>,
}

/// Every message of an .rrd file.
fn read_recording(path: &Path) -> Result<Vec<LogMsg>> {
    let file = std::fs::File::open(path).with_context(|| format!("opening {}", path.display()))?;
    let messages = DecoderApp::decode_eager(BufReader::new(file))
        .with_context(|| format!("{}: not a Rerun recording (.rrd)", path.display()))?
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("{}: the recording is damaged", path.display()))?;
    if !messages.iter().any(|m| matches!(m, LogMsg::ArrowMsg(..))) {
        bail!("{}: the recording holds no data", path.display());
    }
    Ok(messages)
}

/// The name a run's entities go under when several are merged: the run's folder for a
/// `run.rrd`, else the file's stem; made unique by a suffix.
fn run_names(files: &[PathBuf]) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for f in files {
        let stem = f.file_stem().map(|s| s.to_string_lossy().into_owned());
        let folder = f
            .parent()
            .and_then(|p| p.file_name())
            .map(|s| s.to_string_lossy().into_owned());
        let base = match (stem.as_deref(), folder) {
            (Some("run") | None, Some(folder)) => folder,
            (Some(stem), _) => stem.to_owned(),
            (None, None) => "run".to_owned(),
        };
        let mut name = base.clone();
        let mut k = 2;
        while names.contains(&name) {
            name = format!("{base}_{k}");
            k += 1;
        }
        names.push(name);
    }
    names
}

/// The data chunks of a recording's messages with their entity paths under `name`
/// (`/world/fluid` → `/<name>/world/fluid`); the blueprint is left out, the viewer lays out the
/// merged recording itself.
fn chunks_under(name: &str, messages: &[LogMsg]) -> Result<Vec<Chunk>> {
    let mut chunks = Vec::new();
    for msg in messages {
        if msg.store_id().kind() != StoreKind::Recording {
            continue;
        }
        if let LogMsg::ArrowMsg(_, arrow) = msg {
            let chunk = Chunk::from_arrow_msg(arrow).context("decoding a chunk")?;
            let mut parts = vec![name.into()];
            parts.extend(chunk.entity_path().iter().cloned());
            chunks.push(chunk.clone_with_new_entity_path(EntityPath::new(parts)));
        }
    }
    Ok(chunks)
}

/// The layout of merged runs: their flumes one above the other on the shared timeline, and
/// below them each run's volume V/V₀ side by side.
fn side_by_side(names: &[String]) -> Blueprint {
    let flumes = Vertical::new(names.iter().map(|n| {
        Spatial2DView::new(n)
            .with_origin(format!("/{n}"))
            .with_contents([format!("/{n}/world/**")])
            .into()
    }));
    let plots = Horizontal::new(names.iter().map(|n| {
        TimeSeriesView::new(format!("{n}: volume V/V₀"))
            .with_origin(format!("/{n}/scalars/volume"))
            .into()
    }));
    Blueprint::new(Vertical::new([flumes.into(), plots.into()]).with_row_shares([3.0, 1.0]))
        .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
        .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
        .with_time_panel(TimePanel::new().with_timeline(SIM_TIMELINE))
}

/// Opens the viewer on the recordings and blocks until the window is closed.
pub fn view(opts: ViewOptions) -> Result<()> {
    if opts.files.is_empty() {
        bail!("give at least one .rrd file");
    }
    let names = run_names(&opts.files);
    let mut recordings = Vec::new();
    for (path, name) in opts.files.iter().zip(&names) {
        recordings.push(Recording {
            name: name.clone(),
            messages: read_recording(path)?,
        });
    }
    install_crash_handler();
    let runtime = tokio_runtime()?;
    let (tx, rx) = re_log_channel::log_channel(LogSource::Sdk);
    if let [one] = recordings.as_slice() {
        for m in &one.messages {
            let _ = tx.send(m.clone().into());
        }
    } else {
        let tx = std::sync::Mutex::new(tx);
        let sink: Box<dyn LogSink> = Box::new(CallbackSink::new(move |msgs: &[LogMsg]| {
            if let Ok(tx) = tx.lock() {
                for m in msgs {
                    let _ = tx.send(m.clone().into());
                }
            }
        }));
        let rec = RecordingStreamBuilder::new("surflab")
            .set_sinks(vec![sink])
            .context("starting the merged recording")?;
        for r in &recordings {
            rec.send_chunks(chunks_under(&r.name, &r.messages)?);
        }
        side_by_side(&names)
            .send(&rec, BlueprintActivation::default())
            .context("laying out the merged recording")?;
        rec.flush_blocking().context("merging the recordings")?;
    }
    eprintln!(
        "surflab: viewing {} recording{}{}",
        recordings.len(),
        if recordings.len() == 1 { "" } else { "s" },
        if recordings.len() > 1 {
            format!(", merged on one timeline under {}", names.join(", "))
        } else {
            String::new()
        }
    );

    let screenshot = opts.screenshot.clone();
    eframe::run_native(
        "surflab view",
        window_options("surflab view", screenshot.is_some()),
        Box::new(move |cc| {
            let mut app = embedded_viewer(cc, &runtime, screenshot.is_some())?;
            app.add_log_receiver(rx);
            Ok(Box::new(ViewApp {
                viewer: app,
                screenshot,
                opened: Instant::now(),
                loaded_frames: 0,
                requested: false,
                _runtime: runtime,
            }))
        }),
    )
    .map_err(|e| anyhow::anyhow!("the window failed: {e}"))
}

struct ViewApp {
    viewer: re_viewer::App,
    screenshot: Option<PathBuf>,
    opened: Instant,
    /// Frames drawn since the recording's data arrived.
    loaded_frames: u32,
    requested: bool,
    _runtime: tokio::runtime::Runtime,
}

impl eframe::App for ViewApp {
    fn logic(&mut self, ctx: &egui::Context, frame: &mut eframe::Frame) {
        self.viewer.logic(ctx, frame);
    }

    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        self.viewer.ui(ui, frame);
        self.screenshot_step(ui.ctx());
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        self.viewer.save(storage);
    }
}

impl ViewApp {
    /// With `--screenshot`: once the data is in the viewer and it has drawn a few frames (or
    /// after a minute), save a PNG, say what was loaded, and close.
    fn screenshot_step(&mut self, ctx: &egui::Context) {
        let Some(path) = self.screenshot.clone() else {
            return;
        };
        let chunks = self
            .viewer
            .recording_db()
            .map_or(0, |db| db.num_physical_chunks());
        if chunks > 0 {
            self.loaded_frames += 1;
        }
        let ready = self.loaded_frames >= 30 || self.opened.elapsed() > Duration::from_secs(60);
        if ready && !self.requested {
            self.requested = true;
            if let Some(db) = self.viewer.recording_db() {
                let entities: Vec<String> =
                    db.sorted_entity_paths().map(|p| p.to_string()).collect();
                eprintln!(
                    "surflab: the active recording has {} chunks on {} entities: {}",
                    db.num_physical_chunks(),
                    entities.len(),
                    entities.join(" ")
                );
            } else {
                eprintln!("surflab: no recording became active");
            }
            ctx.send_viewport_cmd(egui::ViewportCommand::Screenshot(Default::default()));
        }
        match save_screenshot(ctx, &path) {
            ShotOutcome::Waiting => {}
            ShotOutcome::Saved | ShotOutcome::Failed => {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
        ctx.request_repaint();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_are_named_by_their_folder_and_made_unique() {
        let files: Vec<PathBuf> = [
            "runs/a12/run.rrd",
            "runs/a14/run.rrd",
            "x/lab.rrd",
            "y/lab.rrd",
        ]
        .iter()
        .map(PathBuf::from)
        .collect();
        assert_eq!(run_names(&files), ["a12", "a14", "lab", "lab_2"]);
    }
}
