//! `sweep.rrd`: the rows in a Rerun recording. `map/observed` is the scatter of (ξ₀, type
//! index) coloured by the observed type, one point per run, labelled with its run directory;
//! `map/predicted` the thesis table's type at the same ξ₀ (larger, faint); `map/battjes` the
//! band limits ξ₀ = 0.5 and 3.3. With ξ_b, the same under `map_b` (limits 0.4 and 2.0).
//! `table` is the table as markdown. All static: a sweep has no time axis.

use super::figure::{BREAKING_POINT_LIMITS, DEEP_WATER_LIMITS, TYPE_COLORS, TYPES, type_index};
use super::table::{Row, markdown};
use rerun::archetypes::{Points2D, TextDocument};
use rerun::blueprint::{
    Blueprint, BlueprintActivation, Horizontal, Spatial2DView, TextDocumentView,
};
use rerun::components::{Color, Radius};
use rerun::{RecordingStream, RecordingStreamBuilder, RecordingStreamError};
use std::path::Path;

/// Writes the recording of `rows` to `path`.
pub fn write(path: &Path, case_name: &str, keys: &[String], rows: &[Row]) -> Result<(), String> {
    let rec = RecordingStreamBuilder::new("surflab-sweep")
        .save(path)
        .map_err(|e| e.to_string())?;
    log_rows(&rec, case_name, keys, rows).map_err(|e| e.to_string())?;
    rec.flush_blocking().map_err(|e| e.to_string())?;
    Ok(())
}

fn log_rows(
    rec: &RecordingStream,
    case_name: &str,
    keys: &[String],
    rows: &[Row],
) -> Result<(), RecordingStreamError> {
    let deep: Vec<(f64, &Row)> = rows
        .iter()
        .filter_map(|r| Some((r.iribarren?, r)))
        .collect();
    let at_breaking: Vec<(f64, &Row)> = rows
        .iter()
        .filter_map(|r| Some((r.iribarren_b?, r)))
        .collect();
    log_map(rec, "map", &deep, DEEP_WATER_LIMITS, true)?;
    let mut views: Vec<rerun::blueprint::ContainerLike> = vec![
        Spatial2DView::new("breaker type index against ξ₀")
            .with_origin("/map")
            .into(),
    ];
    if !at_breaking.is_empty() {
        log_map(rec, "map_b", &at_breaking, BREAKING_POINT_LIMITS, false)?;
        views.push(
            Spatial2DView::new("breaker type index against ξ_b")
                .with_origin("/map_b")
                .into(),
        );
    }
    let legend: String = TYPES
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let [r, g, b] = TYPE_COLORS[k];
            format!("- y = {k}: **{t}** (colour #{r:02x}{g:02x}{b:02x})\n")
        })
        .collect();
    let text = format!(
        "{}\n## The map\n\nx: ξ₀ (`map`) or ξ_b (`map_b`), dimensionless; y: the observed type's \
         index:\n\n{legend}\nThe faint larger point under each run is the type the thesis table \
         predicts for ξ₀. Grey lines: Battjes's (1974) limits, ξ₀ = 0.5 and 3.3, ξ_b = 0.4 and 2.0.\n",
        markdown(case_name, keys, rows)
    );
    rec.log_static("table", &TextDocument::from_markdown(text))?;
    views.push(TextDocumentView::new("table").with_origin("/table").into());
    Blueprint::new(Horizontal::new(views)).send(rec, BlueprintActivation::default())?;
    Ok(())
}

fn log_map(
    rec: &RecordingStream,
    entity: &str,
    points: &[(f64, &Row)],
    limits: [f64; 2],
    with_prediction: bool,
) -> Result<(), RecordingStreamError> {
    let observed: Vec<([f32; 2], [u8; 3], String)> = points
        .iter()
        .filter_map(|(x, r)| {
            let k = type_index(r.observed.as_deref()?)?;
            Some(([*x as f32, k as f32], TYPE_COLORS[k], r.dir.clone()))
        })
        .collect();
    rec.log_static(
        format!("{entity}/observed"),
        &Points2D::new(observed.iter().map(|p| p.0))
            .with_colors(observed.iter().map(|p| p.1))
            .with_labels(observed.iter().map(|p| p.2.clone()))
            .with_radii([Radius::new_scene_units(0.05)])
            .with_draw_order(20.0),
    )?;
    if with_prediction {
        let predicted: Vec<([f32; 2], Color)> = points
            .iter()
            .filter_map(|(x, r)| {
                let k = type_index(r.predicted.as_deref()?)?;
                let [red, green, blue] = TYPE_COLORS[k];
                Some((
                    [*x as f32, k as f32],
                    Color::from_unmultiplied_rgba(red, green, blue, 90),
                ))
            })
            .collect();
        rec.log_static(
            format!("{entity}/predicted"),
            &Points2D::new(predicted.iter().map(|p| p.0))
                .with_colors(predicted.iter().map(|p| p.1))
                .with_radii([Radius::new_scene_units(0.1)])
                .with_draw_order(10.0),
        )?;
    }
    crate::output::breaker_map::log_axes(rec, entity, limits)?;
    Ok(())
}
