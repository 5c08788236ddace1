//! The breaker-type map: observed type against ξ₀ with Battjes's (1974) bands shaded and the
//! thesis table's prediction marked, and a second panel against ξ_b when the runs broke.
//! Drawn with plotters to `breaker_map.svg` and `breaker_map.png`; the PNG's text uses the
//! committed DejaVu Sans (`assets/fonts/`), never a system font.

use super::table::Row;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::sync::OnceLock;

pub(crate) const FONT: &str = "sans-serif";
static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

use crate::output::breaker_map::BAND_NAMES;
pub use crate::output::breaker_map::{
    BREAKING_POINT_LIMITS, DEEP_WATER_LIMITS, TYPE_COLORS, TYPES, type_index,
};

/// Battjes's bands' fills, below, between and above the limits.
const BAND_COLORS: [RGBColor; 3] = [
    RGBColor(198, 219, 239),
    RGBColor(199, 233, 192),
    RGBColor(253, 208, 162),
];

fn type_color(k: usize) -> RGBColor {
    let [r, g, b] = TYPE_COLORS[k];
    RGBColor(r, g, b)
}

pub(crate) fn register_font() -> Result<(), String> {
    static REGISTERED: OnceLock<Result<(), String>> = OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            plotters::style::register_font(FONT, FontStyle::Normal, DEJAVU_SANS)
                .map_err(|_| "the committed DejaVu Sans is not a readable font".to_owned())
        })
        .clone()
}

/// One panel: the x quantity's name, the band limits, and (x, observed, predicted) per run.
struct Panel {
    caption: &'static str,
    x_desc: &'static str,
    limits: [f64; 2],
    /// The x quantity's symbol, for the limits' labels.
    symbol: &'static str,
    points: Vec<(f64, usize, Option<usize>)>,
    x_min_max: f64,
}

fn panels(rows: &[Row]) -> Vec<Panel> {
    let observed = |r: &Row| r.observed.as_deref().and_then(type_index);
    let predicted = |r: &Row| r.predicted.as_deref().and_then(type_index);
    let deep: Vec<_> = rows
        .iter()
        .filter_map(|r| Some((r.iribarren?, observed(r)?, predicted(r))))
        .collect();
    let at_breaking: Vec<_> = rows
        .iter()
        .filter_map(|r| Some((r.iribarren_b?, observed(r)?, None)))
        .collect();
    let mut out = vec![Panel {
        caption: "against the deep-water Iribarren number ξ₀",
        x_desc: "ξ₀ = tan β / √(H₀/L₀)  (dimensionless)",
        limits: DEEP_WATER_LIMITS,
        symbol: "ξ₀",
        points: deep,
        // Room for the last band's name beyond ξ₀ = 3.3.
        x_min_max: 4.5,
    }];
    if !at_breaking.is_empty() {
        out.push(Panel {
            caption: "against the Iribarren number at breaking ξ_b",
            x_desc: "ξ_b = tan β / √(H_b/L₀)  (dimensionless)",
            limits: BREAKING_POINT_LIMITS,
            symbol: "ξ_b",
            points: at_breaking,
            x_min_max: 3.0,
        });
    }
    out
}

/// Figure size in pixels for `rows`: one panel 1000 wide, two side by side 1700.
fn size(rows: &[Row]) -> (u32, u32) {
    if panels(rows).len() > 1 {
        (1700, 720)
    } else {
        (1000, 720)
    }
}

/// The map as SVG text.
pub fn svg(case_name: &str, rows: &[Row]) -> Result<String, String> {
    register_font()?;
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size(rows)).into_drawing_area();
        draw(&root, case_name, rows).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(text)
}

/// The map as PNG bytes.
pub fn png(case_name: &str, rows: &[Row]) -> Result<Vec<u8>, String> {
    register_font()?;
    let (w, h) = size(rows);
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        draw(&root, case_name, rows).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    encode_png(&rgb, w, h)
}

/// 8-bit RGB pixels, `w` × `h`, as PNG bytes.
pub(crate) fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, String> {
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(rgb).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())?;
    Ok(bytes)
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    case_name: &str,
    rows: &[Row],
) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let plotted = rows
        .iter()
        .filter(|r| r.iribarren.is_some() && r.observed.is_some())
        .count();
    let title = format!(
        "Breaker-type map: {case_name} ({plotted} of {} runs on the map)",
        rows.len()
    );
    let root = root.titled(&title, (FONT, 28))?;
    let (_, height) = root.dim_in_pixel();
    let (charts, legend) = root.split_vertically(height as i32 - 72);
    let panels = panels(rows);
    let areas = charts.split_evenly((1, panels.len()));
    for (panel, area) in panels.iter().zip(&areas) {
        draw_panel(area, panel)?;
    }
    draw_legend(&legend)
}

fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, panel: &Panel) -> DrawResult<DB> {
    let x_max = panel
        .points
        .iter()
        .map(|p| 1.15 * p.0)
        .fold(panel.x_min_max, f64::max);
    let (y_min, y_max) = (-0.5, 5.0);
    let mut chart = ChartBuilder::on(area)
        .caption(panel.caption, (FONT, 21))
        .margin(14)
        .x_label_area_size(58)
        .y_label_area_size(118)
        .build_cartesian_2d(0.0..x_max, y_min..y_max)?;
    // Battjes's bands, shaded, with their names along the top.
    let edges = [0.0, panel.limits[0], panel.limits[1], x_max];
    for k in 0..3 {
        let (lo, hi) = (edges[k], edges[k + 1].min(x_max));
        if lo >= x_max {
            continue;
        }
        chart.draw_series(std::iter::once(Rectangle::new(
            [(lo, y_min), (hi, y_max)],
            BAND_COLORS[k].filled(),
        )))?;
        let centred = (FONT, 16)
            .into_font()
            .color(&BLACK.mix(0.75))
            .pos(Pos::new(HPos::Center, VPos::Center));
        chart.draw_series(std::iter::once(Text::new(
            BAND_NAMES[k],
            (0.5 * (lo + hi), 4.7),
            centred,
        )))?;
    }
    for limit in panel.limits.iter().filter(|l| **l < x_max) {
        chart.draw_series(LineSeries::new(
            [(*limit, y_min), (*limit, y_max)],
            BLACK.mix(0.45).stroke_width(1),
        ))?;
        let note = (FONT, 14)
            .into_font()
            .color(&BLACK.mix(0.6))
            .pos(Pos::new(HPos::Left, VPos::Center));
        chart.draw_series(std::iter::once(Text::new(
            format!(" {} = {limit}", panel.symbol),
            (*limit, 4.35),
            note,
        )))?;
    }
    chart
        .configure_mesh()
        .disable_y_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.12))
        .y_labels(6)
        .y_label_formatter(&|v: &f64| {
            let k = v.round();
            if (v - k).abs() < 1e-6 && (0.0..TYPES.len() as f64).contains(&k) {
                TYPES[k as usize].to_owned()
            } else {
                String::new()
            }
        })
        .x_desc(panel.x_desc)
        .y_desc("observed breaker type")
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 18))
        .draw()?;
    // The thesis table's prediction (hollow) under each run's observed type (filled).
    for &(x, _, predicted) in &panel.points {
        if let Some(p) = predicted {
            chart.draw_series(PointSeries::of_element(
                [(x, p as f64)],
                10,
                type_color(p).stroke_width(2),
                &|c, s, st| EmptyElement::at(c) + Circle::new((0, 0), s, st),
            ))?;
        }
    }
    for (k, _) in TYPES.iter().enumerate() {
        let points: Vec<(f64, f64)> = panel
            .points
            .iter()
            .filter(|p| p.1 == k)
            .map(|p| (p.0, k as f64))
            .collect();
        chart.draw_series(PointSeries::of_element(
            points,
            6,
            type_color(k).filled(),
            &|c, s, st| EmptyElement::at(c) + Circle::new((0, 0), s, st),
        ))?;
    }
    if panel.points.is_empty() {
        let centred = (FONT, 18)
            .into_font()
            .color(&BLACK.mix(0.8))
            .pos(Pos::new(HPos::Center, VPos::Center));
        chart.draw_series(std::iter::once(Text::new(
            "no run has an Iribarren number (no wavemaker or no beach)",
            (0.5 * x_max, 2.0),
            centred,
        )))?;
    }
    Ok(())
}

/// The legend as a strip under the panels, two rows: the bands; the two markers.
fn draw_legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
    let style = (FONT, 17).into_font().color(&BLACK);
    let gap = 36;
    // Row 1: Battjes's bands.
    let (mut x, y) = (30, 8);
    let lead = "Battjes (1974) bands:";
    area.draw(&Text::new(lead, (x, y), style.clone()))?;
    x += area.estimate_text_size(lead, &style)?.0 as i32 + 16;
    for (k, name) in BAND_NAMES.iter().enumerate() {
        area.draw(&Rectangle::new(
            [(x, y - 1), (x + 26, y + 17)],
            BAND_COLORS[k].filled(),
        ))?;
        area.draw(&Text::new(*name, (x + 34, y), style.clone()))?;
        x += 34 + area.estimate_text_size(name, &style)?.0 as i32 + gap;
    }
    // Row 2: what the markers are.
    let (mut x, y) = (30, 36);
    let label = "observed type, one point per run";
    area.draw(&Circle::new((x + 10, y + 8), 6, BLACK.mix(0.75).filled()))?;
    area.draw(&Text::new(label, (x + 28, y), style.clone()))?;
    x += 28 + area.estimate_text_size(label, &style)?.0 as i32 + gap;
    let label = "type the thesis table predicts for ξ₀ (hollow, in that type's colour)";
    area.draw(&Circle::new(
        (x + 10, y + 8),
        10,
        BLACK.mix(0.75).stroke_width(2),
    ))?;
    area.draw(&Text::new(label, (x + 28, y), style))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(xi: f64, xi_b: Option<f64>, observed: &str, predicted: &str) -> Row {
        let json = serde_json::json!({
            "status": "ok",
            "breaking": {
                "iribarren": xi, "iribarren_b": xi_b, "observed": observed,
                "predicted": predicted
            }
        });
        let point = super::super::spec::Point {
            index: 0,
            overrides: vec![format!("wavemaker.period_s={xi}")],
            values: vec![format!("{xi}")],
            dir_name: "p".into(),
        };
        super::super::table::row_from_summary(&point, &json, std::path::Path::new("/nonexistent"))
    }

    #[test]
    fn the_map_draws_to_svg_and_png() {
        let rows = [
            row(0.4, Some(0.35), "spilling", "spilling"),
            row(1.9, Some(1.8), "plunging", "collapsing"),
            row(3.6, None, "surging", "surging"),
            row(2.8, Some(2.4), "none", "collapsing"),
        ];
        let svg = svg("slope025", &rows).unwrap();
        assert!(svg.contains("Breaker-type map: slope025"));
        assert!(svg.contains("ξ_b"), "a second panel against ξ_b");
        let png = png("slope025", &rows).unwrap();
        assert!(png.starts_with(b"\x89PNG") && png.len() > 10_000);
        // Without ξ_b, one panel.
        assert_eq!(panels(&rows[2..3]).len(), 1);
        assert_eq!(size(&rows[2..3]).0, 1000);
    }
}
