//! The study's figure: one panel per kind of check (the fraction of its bar against α, one
//! line per δ, the bar drawn at 1), and, for a surf case, panels of the breaking point, the
//! set-up and the volume drift. Drawn with plotters like the breaker-type map.

use super::{StudyRun, kinds};
use crate::sweep::figure::{FONT, encode_png, register_font};
use plotters::coord::Shift;
use plotters::prelude::*;

/// δ's line colours, in order of δ (repeated past six values).
const DELTA_COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

const PANEL_W: u32 = 520;
const PANEL_H: u32 = 380;
const COLUMNS: usize = 3;
const LEGEND_H: u32 = 48;
const TITLE_H: u32 = 44;

/// A figure a run may have, in the panel's unit.
type Quantity = fn(&StudyRun) -> Option<f64>;

struct Panel {
    caption: String,
    y_desc: &'static str,
    /// A horizontal reference line: the bar.
    bar: Option<f64>,
    /// (δ, the points (α, y) in order of α).
    lines: Vec<(f64, Vec<(f64, f64)>)>,
}

fn deltas(runs: &[StudyRun]) -> Vec<f64> {
    let mut d: Vec<f64> = runs.iter().map(|r| r.delta).collect();
    d.sort_by(f64::total_cmp);
    d.dedup();
    d
}

fn lines(
    runs: &[StudyRun],
    value: impl Fn(&StudyRun) -> Option<f64>,
) -> Vec<(f64, Vec<(f64, f64)>)> {
    deltas(runs)
        .into_iter()
        .map(|d| {
            let mut points: Vec<(f64, f64)> = runs
                .iter()
                .filter(|r| r.delta == d && r.status == "ok")
                .filter_map(|r| Some((r.alpha, value(r).filter(|v| v.is_finite())?)))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            (d, points)
        })
        .filter(|(_, p)| !p.is_empty())
        .collect()
}

fn panels(runs: &[StudyRun]) -> Vec<Panel> {
    // A yes/no check (its bar `= 1`, e.g. the breaker type) has no fraction to draw: the
    // table says where it failed.
    let yes_no = |kind: &str| {
        runs.iter()
            .flat_map(|r| &r.kinds)
            .any(|k| k.kind == kind && k.bar.starts_with("= "))
    };
    let mut out: Vec<Panel> = kinds(runs)
        .into_iter()
        .filter(|kind| !yes_no(kind))
        .map(|kind| Panel {
            lines: lines(runs, |r| {
                r.kinds
                    .iter()
                    .find(|k| k.kind == kind)
                    .map(|k| k.worst_fraction)
            }),
            caption: kind,
            y_desc: "fraction of the bar (1 = on the bar)",
            bar: Some(1.0),
        })
        .collect();
    let extra: [(&str, &'static str, Quantity); 3] = [
        ("breaking point x_b", "x_b (m)", |r| r.x_b_m),
        ("set-up at the set-up gauge", "set-up (mm)", |r| {
            r.setup_m.map(|v| 1000.0 * v)
        }),
        (
            "volume drift, max |V/V₀ − 1|",
            "volume drift (%)",
            |r| r.volume_drift_max.map(|v| 100.0 * v),
        ),
    ];
    let has_volume_check = out.iter().any(|p| p.caption.contains("volume"));
    for (caption, y_desc, value) in extra {
        if caption.starts_with("volume") && has_volume_check {
            continue;
        }
        let lines = lines(runs, value);
        if !lines.is_empty() {
            out.push(Panel {
                caption: caption.to_owned(),
                y_desc,
                bar: None,
                lines,
            });
        }
    }
    out
}

fn size(n_panels: usize) -> (u32, u32) {
    let columns = n_panels.clamp(1, COLUMNS);
    let rows = n_panels.div_ceil(COLUMNS).max(1);
    (
        PANEL_W * columns as u32,
        TITLE_H + PANEL_H * rows as u32 + LEGEND_H,
    )
}

/// The figure as SVG text.
pub fn svg(runs: &[StudyRun]) -> Result<String, String> {
    register_font()?;
    let panels = panels(runs);
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, size(panels.len())).into_drawing_area();
        draw(&root, runs, &panels).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(text)
}

/// The figure as PNG bytes.
pub fn png(runs: &[StudyRun]) -> Result<Vec<u8>, String> {
    register_font()?;
    let panels = panels(runs);
    let (w, h) = size(panels.len());
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        draw(&root, runs, &panels).map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    encode_png(&rgb, w, h)
}

type DrawResult<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    runs: &[StudyRun],
    panels: &[Panel],
) -> DrawResult<DB> {
    root.fill(&WHITE)?;
    let case = runs.first().map_or("", |r| r.case_name.as_str());
    let title = format!("α/δ study: {case}, {} runs", runs.len());
    let root = root.titled(&title, (FONT, 24))?;
    let (_, height) = root.dim_in_pixel();
    let (charts, legend) = root.split_vertically(height as i32 - LEGEND_H as i32);
    let rows = panels.len().div_ceil(COLUMNS).max(1);
    let columns = panels.len().clamp(1, COLUMNS);
    let areas = charts.split_evenly((rows, columns));
    for (panel, area) in panels.iter().zip(&areas) {
        draw_panel(area, panel)?;
    }
    draw_legend(&legend, &deltas(runs))
}

fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, panel: &Panel) -> DrawResult<DB> {
    let points = || panel.lines.iter().flat_map(|(_, p)| p.iter());
    let (mut x0, mut x1) =
        points().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
    if x1 - x0 < 1e-9 {
        (x0, x1) = (x0 - 0.1, x1 + 0.1);
    }
    let pad = 0.06 * (x1 - x0);
    let (mut y0, mut y1) =
        points().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
    if let Some(bar) = panel.bar {
        (y0, y1) = (y0.min(0.0), y1.max(1.1 * bar));
    }
    if y1 - y0 < 1e-12 {
        (y0, y1) = (y0 - 0.5, y1 + 0.5);
    }
    let ypad = 0.08 * (y1 - y0);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.caption, (FONT, 16))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(64)
        .build_cartesian_2d((x0 - pad)..(x1 + pad), (y0 - ypad)..(y1 + ypad))?;
    chart
        .configure_mesh()
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.1))
        .x_desc("α")
        .y_desc(panel.y_desc)
        .label_style((FONT, 13))
        .axis_desc_style((FONT, 14))
        .draw()?;
    if let Some(bar) = panel.bar {
        chart.draw_series(LineSeries::new(
            [(x0 - pad, bar), (x1 + pad, bar)],
            BLACK.mix(0.6).stroke_width(2),
        ))?;
    }
    for (k, (_, line)) in panel.lines.iter().enumerate() {
        let color = DELTA_COLORS[k % DELTA_COLORS.len()];
        chart.draw_series(LineSeries::new(line.iter().copied(), color.stroke_width(2)))?;
        chart.draw_series(PointSeries::of_element(
            line.iter().copied(),
            4,
            color.filled(),
            &|c, s, st| EmptyElement::at(c) + Circle::new((0, 0), s, st),
        ))?;
    }
    Ok(())
}

fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    deltas: &[f64],
) -> DrawResult<DB> {
    let style = (FONT, 15).into_font().color(&BLACK);
    let (mut x, y) = (24, 14);
    for (k, d) in deltas.iter().enumerate() {
        let color = DELTA_COLORS[k % DELTA_COLORS.len()];
        area.draw(&PathElement::new(
            vec![(x, y + 8), (x + 28, y + 8)],
            color.stroke_width(3),
        ))?;
        let label = format!("δ = {d}");
        area.draw(&Text::new(label.clone(), (x + 36, y), style.clone()))?;
        x += 36 + area.estimate_text_size(&label, &style)?.0 as i32 + 28;
    }
    let label = "black line: the bar (1 = the check's tolerance used up)";
    area.draw(&Text::new(label, (x + 12, y), style))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::{KindResult, StudyRun};
    use super::*;

    fn run(alpha: f64, delta: f64, fraction: f64, x_b: Option<f64>) -> StudyRun {
        StudyRun {
            dir: format!("alpha={alpha},delta={delta}").into(),
            case_name: "flap".into(),
            alpha,
            delta,
            status: "ok".into(),
            kinds: vec![KindResult {
                kind: "wave height".into(),
                worst_fraction: fraction,
                passed: fraction <= 1.0,
                bar: "0.0600 m ± 5 %".into(),
            }],
            note: None,
            volume_drift_max: Some(0.004),
            observed: None,
            x_b_m: x_b,
            setup_m: None,
            median_ms_per_step: Some(80.0),
            particles: Some(19_500),
        }
    }

    #[test]
    fn one_line_per_delta_and_a_panel_per_kind() {
        let runs = [
            run(1.1, 0.0, 0.5, None),
            run(1.4, 0.0, 0.2, None),
            run(1.1, 0.03, 0.7, None),
            run(1.6, 0.03, 1.2, Some(6.1)),
            // A yes/no kind: not drawn.
            StudyRun {
                kinds: vec![KindResult {
                    kind: "breaker type".into(),
                    worst_fraction: 0.0,
                    passed: true,
                    bar: "= 1".into(),
                }],
                ..run(1.4, 0.03, 0.0, None)
            },
            // A run that diverged: in the table, not on the figure.
            StudyRun {
                status: "stopped: diverged".into(),
                ..run(1.2, 0.03, 9.0, Some(8.5))
            },
        ];
        let p = panels(&runs);
        // wave height, x_b, volume drift (no volume check among the kinds).
        assert_eq!(p.len(), 3);
        assert_eq!(p[0].lines.len(), 2);
        assert_eq!(p[0].lines[1].1, vec![(1.1, 0.7), (1.6, 1.2)]);
        assert_eq!(p[1].lines.len(), 1, "x_b only where a run has one");
        let svg = svg(&runs).unwrap();
        assert!(svg.contains("α/δ study: flap, 6 runs") && svg.contains("δ = 0.03"));
        let png = png(&runs).unwrap();
        assert!(png.starts_with(b"\x89PNG"));
    }
}
