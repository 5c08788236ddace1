//! The breaker-type map as Rerun draws it: observed type (one row per type) against the
//! Iribarren number, with Battjes's (1974) bands shaded. `surflab sweep` puts one point per run
//! on it (`sweep.rrd`); a run's own recording and the lab's window show the run's point on it
//! (the "breaker map" tab), so that a student who turns the period up sees the point move
//! across the bands.
//!
//! The same names, colours and limits serve the sweep's plotters figure.

use rerun::archetypes::{LineStrips2D, Points2D, Transform3D};
use rerun::components::{Color, Radius};
use rerun::{RecordingStream, RecordingStreamError};

/// The types on the y axis, bottom to top.
pub const TYPES: [&str; 5] = ["spilling", "plunging", "collapsing", "surging", "none"];

/// Colour of each type in [`TYPES`] (points, hollow markers, the recordings).
pub const TYPE_COLORS: [[u8; 3]; 5] = [
    [31, 119, 180],
    [44, 160, 44],
    [255, 127, 14],
    [214, 39, 40],
    [110, 110, 110],
];

/// Battjes (1974): limits in ξ₀ and in ξ_b.
pub const DEEP_WATER_LIMITS: [f64; 2] = [0.5, 3.3];
pub const BREAKING_POINT_LIMITS: [f64; 2] = [0.4, 2.0];

/// The names of Battjes's three bands, below, between and above the limits.
pub const BAND_NAMES: [&str; 3] = ["spilling", "plunging", "collapsing / surging"];

/// The right edge of the map's shaded bands, in ξ: a little past the sweep's ξ₀ = 4.
pub const MAP_XI_MAX: f64 = 4.5;

/// The y position of a type name (`None` for a name the map does not know).
pub fn type_index(name: &str) -> Option<usize> {
    TYPES.iter().position(|t| *t == name)
}

/// Logs the static frame of a map under `entity`: y pointing up (Rerun's 2D views draw +y
/// down), Battjes's `limits` as grey lines, the three bands shaded in the colours of their
/// types, and each row named at its left.
pub fn log_axes(
    rec: &RecordingStream,
    entity: &str,
    limits: [f64; 2],
) -> Result<(), RecordingStreamError> {
    rec.log_static(entity, &Transform3D::from_scale((1.0, -1.0, 1.0)))?;
    let top = (TYPES.len() - 1) as f32 + 0.5;
    rec.log_static(
        format!("{entity}/battjes"),
        &LineStrips2D::new(
            limits
                .iter()
                .map(|l| vec![[*l as f32, -0.5], [*l as f32, top]]),
        )
        .with_colors([[120, 120, 120]])
        .with_radii([Radius::new_ui_points(1.0)]),
    )?;
    let edges = [0.0, limits[0], limits[1], MAP_XI_MAX.max(limits[1] + 0.5)];
    // The bands' colours: spilling's, plunging's and collapsing's, faint.
    let fills = [0, 1, 2].map(|k| {
        let [r, g, b] = TYPE_COLORS[k];
        Color::from_unmultiplied_rgba(r, g, b, 40)
    });
    // A 2D box is drawn as an outline; a line as wide as the band, in scene units, fills it.
    rec.log_static(
        format!("{entity}/bands"),
        &LineStrips2D::new((0..3).map(|k| {
            let x = (0.5 * (edges[k] + edges[k + 1])) as f32;
            vec![[x, -0.5], [x, top]]
        }))
        .with_radii(
            (0..3).map(|k| Radius::new_scene_units((0.5 * (edges[k + 1] - edges[k])) as f32)),
        )
        .with_colors(fills)
        .with_labels(BAND_NAMES.map(|n| format!("Battjes: {n}")))
        .with_draw_order(0.0),
    )?;
    rec.log_static(
        format!("{entity}/rows"),
        &Points2D::new((0..TYPES.len()).map(|k| [-0.15, k as f32]))
            .with_colors(TYPE_COLORS)
            .with_labels(TYPES)
            .with_radii([Radius::new_ui_points(2.0)]),
    )?;
    Ok(())
}
