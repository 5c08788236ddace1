//! The recording's blueprint: the flume over the window's width with its companion tabs, the
//! plots below, one unit each, and the flume view's opening window.

use super::{RrdError, RrdLogger, SIM_TIMELINE, Viewing};
use rerun::EntityPath;
use rerun::blueprint::components::PanelState;
use rerun::blueprint::{
    Blueprint, BlueprintActivation, BlueprintPanel, Horizontal, SelectionPanel, Spatial2DView,
    Tabs, TextDocumentView, TextLogView, TimePanel, TimeSeriesView, Vertical,
};
use rerun::{RecordingStream, RecordingStreamBuilder};

impl RrdLogger {
    pub(super) fn send_blueprint(&self) -> Result<(), RrdError> {
        let flume: rerun::blueprint::ContainerLike = Spatial2DView::new("flume")
            .with_origin("/")
            .with_contents(["/world/**"])
            .into();
        let flume_view = match &flume {
            rerun::blueprint::ContainerLike::View(v) => Some(v.blueprint_path()),
            _ => None,
        };
        // The flume over the window's width, with its companions as tabs: the breaker map,
        // and each surf-zone picture with its legend below it.
        let mut top: Vec<rerun::blueprint::ContainerLike> = vec![flume];
        if self.breaker_map.get() {
            top.push(
                Spatial2DView::new("breaker map")
                    .with_origin("/breaker_map")
                    .into(),
            );
        }
        if self.surf_views.get() {
            let with_legend = |title: &str, origin: &str| -> rerun::blueprint::ContainerLike {
                Vertical::new([
                    Spatial2DView::new(title).with_origin(origin).into(),
                    TextDocumentView::new("legend")
                        .with_origin(format!("{origin}_legend"))
                        .into(),
                ])
                .with_row_shares([6.0, 1.0])
                .with_name(title)
                .into()
            };
            top.extend([
                with_legend("undertow ū(z)", "/profiles"),
                with_legend("η(x, t)", "/space_time/eta"),
                with_legend("u1(x, t)", "/space_time/u1"),
            ]);
        }
        let top: rerun::blueprint::ContainerLike = Tabs::new(top).into();
        // One plot per unit: the gauges, and the run's integrals one quantity at a time.
        let gauges =
            TimeSeriesView::new("gauges: η (m), u and w (m/s)").with_origin("/scalars/gauges");
        let info = Tabs::new([
            TimeSeriesView::new("volume V/V₀")
                .with_origin("/scalars/volume")
                .into(),
            TimeSeriesView::new("kinetic energy (J/m)")
                .with_origin("/scalars/energy")
                .into(),
            TimeSeriesView::new("max speed (m/s)")
                .with_origin("/scalars/speed")
                .into(),
            TimeSeriesView::new("front x (m)")
                .with_origin("/scalars/front")
                .into(),
            TimeSeriesView::new("ms per stage")
                .with_origin("/scalars/timing_ms")
                .into(),
            TextDocumentView::new("legend")
                .with_origin("/legend")
                .into(),
            TextLogView::new("log").with_origin("/").into(),
        ]);
        let plots = Horizontal::new([gauges.into(), info.into()]).with_column_shares([1.0, 1.0]);
        let root = Vertical::new([top, plots.into()]).with_row_shares([3.0, 2.0]);
        // The viewer's own side panels start collapsed: the flume and the plots get the room.
        let blueprint = Blueprint::new(root)
            .with_blueprint_panel(BlueprintPanel::new().with_state(PanelState::Collapsed))
            .with_selection_panel(SelectionPanel::new().with_state(PanelState::Collapsed))
            .with_time_panel(TimePanel::new().with_timeline(SIM_TIMELINE).with_state(
                match self.viewing {
                    Viewing::Review => PanelState::Collapsed,
                    Viewing::Live => PanelState::Hidden,
                },
            ));
        match (self.flume_window_m.get(), flume_view) {
            (Some(window), Some(view)) => {
                send_with_bounds(&self.rec, &blueprint, &[(view, window)])
            }
            _ => Ok(blueprint.send(&self.rec, BlueprintActivation::default())?),
        }
    }
}

/// Sends `blueprint` to `rec` with each 2D view of `views` (its blueprint path, and a window
/// [x0, x1, y0, y1] in metres, physical y up) opened on its window. Rerun 0.36's Rust blueprint
/// API cannot set a 2D view's visual bounds (`../shared/stack.md`), but the viewer reads them
/// from the blueprint store like any other view property. So the blueprint is sent into a
/// memory sink, the bounds are logged into the same blueprint store (same recording id, the
/// `blueprint` timeline at 0, the view's path), and all of it goes to the recording with the
/// blueprint's own activation command. The views' spaces must hold their entities under a
/// y-flip (Rerun's 2D views draw +y downwards), as the flume's `world` and the 3D recording's
/// planes do.
pub(crate) fn send_with_bounds(
    rec: &RecordingStream,
    blueprint: &Blueprint,
    views: &[(EntityPath, [f64; 4])],
) -> Result<(), RrdError> {
    use rerun::external::re_sdk_types::blueprint::archetypes::VisualBounds2D;
    use rerun::external::re_sdk_types::datatypes::{Range1D, Range2D};
    use rerun::log::LogMsg;
    let app = rec
        .store_info()
        .map_or_else(|| "surflab".into(), |i| i.application_id().clone());
    let sent = captured(RecordingStreamBuilder::new(app.clone()), |capture| {
        Ok(blueprint.send(capture, BlueprintActivation::default())?)
    })?;
    let mut messages = Vec::new();
    let mut activation = None;
    for msg in sent {
        match msg {
            LogMsg::BlueprintActivationCommand(cmd) => activation = Some(cmd),
            m if m.store_id().kind() == rerun::StoreKind::Blueprint => messages.push(m),
            _ => {}
        }
    }
    let (Some(activation), Some(store)) =
        (activation, messages.first().map(|m| m.store_id().clone()))
    else {
        return Ok(blueprint.send(rec, BlueprintActivation::default())?);
    };
    let builder = RecordingStreamBuilder::new(app)
        .recording_id(store.recording_id().clone())
        .blueprint();
    let logged = captured(builder, |bounds| {
        bounds.set_time_sequence("blueprint", 0);
        for (view, [x0, x1, y0, y1]) in views {
            // In the view's space the flip makes physical y point down.
            bounds.log(
                format!("{view}/VisualBounds2D"),
                &VisualBounds2D::new(Range2D {
                    x_range: Range1D([*x0, *x1]),
                    y_range: Range1D([-y1, -y0]),
                }),
            )?;
        }
        Ok(())
    })?;
    messages.extend(
        logged
            .into_iter()
            .filter(|m| !matches!(m, LogMsg::SetStoreInfo(_))),
    );
    rec.send_blueprint(messages, activation);
    Ok(())
}

/// What `log` sends to a new stream of `builder` with a memory sink. A memory sink holds a
/// handle to its own stream, so such a stream is never dropped and its two threads live as
/// long as the process (rerun 0.36.3); the sink is swapped out before the stream goes, which
/// lets it go. Measured on a sweep's process: 28 streams left after four runs before, 16 now,
/// which are rerun's own (`Blueprint::send` captures the blueprint in the same way, one stream
/// per send, out of our reach).
fn captured(
    builder: RecordingStreamBuilder,
    log: impl FnOnce(&RecordingStream) -> Result<(), RrdError>,
) -> Result<Vec<rerun::log::LogMsg>, RrdError> {
    let (rec, storage) = builder.memory()?;
    let logged = log(&rec).and_then(|()| {
        rec.flush_blocking()
            .map_err(|e| RrdError::InvalidInput(format!("the blueprint could not be flushed: {e}")))
    });
    let messages = storage.take();
    rec.disconnect();
    logged.map(|()| messages)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The capturing stream is gone when `captured` returns: no handle to it is left.
    #[test]
    fn a_captured_stream_does_not_outlive_the_capture() {
        let mut weak = None;
        let messages = captured(RecordingStreamBuilder::new("surflab-test"), |rec| {
            weak = Some(rec.clone_weak());
            Ok(rec.log("x", &rerun::Scalars::single(1.0))?)
        })
        .unwrap();
        assert!(messages.len() > 1, "{}", messages.len());
        let left = weak.unwrap().ref_count();
        println!("handles to the capturing stream after the capture: {left}");
        assert_eq!(left, 0);
    }
}
