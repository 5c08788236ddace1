//! Surf-zone results of a run: breaking events as they happen, and at the end the breaker
//! summary, wave height and mean water level along the flume, the undertow profiles
//! (`profiles.csv`, `summary.json`) and their pictures in the recording (profiles as lines,
//! η(x, t) and u1(x, t) as space–time images).

use super::colormap::ColorScale;
use super::rrd::RrdLogger;
use crate::diagnostics::breaking::{BreakingDetector, BreakingSummary};
use crate::diagnostics::surface::{SurfaceProfile, still_shoreline_x_m, surface_profile};
use crate::diagnostics::undertow::{Stations, UndertowSummary};
use crate::simulation::Simulation;
use rerun::archetypes::{Image, LineStrips2D, TextDocument};
use std::io::Write;
use std::path::Path;

/// Wave height and mean level at one elevation gauge over the averaging window.
#[derive(Debug, Clone, serde::Serialize)]
pub struct GaugeWave {
    pub x_m: f64,
    pub x_data_frame_m: f64,
    /// Mean zero-up-crossing height, m (null with fewer than one whole wave).
    #[serde(rename = "H_m")]
    pub height_m: Option<f64>,
    /// Mean over the periods of the range of η in each (`diagnostics::period_height_m`), m:
    /// the height to compare with a long cnoidal wave's H, whose trough ripples the
    /// zero-up-crossing count takes for waves.
    #[serde(rename = "H_period_m")]
    pub period_height_m: Option<f64>,
    /// Time-mean elevation over the wet samples, m above still water.
    pub mean_level_m: Option<f64>,
    /// Fraction of the samples at which the gauge was wet.
    pub wet_fraction: f64,
}

/// Surf-zone diagnostics in `summary.json`.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SurfSummary {
    pub averaged_from_s: f64,
    pub averaged_to_s: f64,
    pub periods: usize,
    /// H(x) and the mean level at each gauge.
    pub wave_height: Vec<GaugeWave>,
    /// Lowest mean level among the always-wet gauges offshore of the first breaking point, m.
    pub setdown_m: Option<f64>,
    /// Mean level at the most shoreward gauge beyond the breaking point that was wet at least
    /// 90 % of the time, and that gauge's x, m.
    pub setup_m: Option<f64>,
    pub setup_gauge_x_m: Option<f64>,
    /// The change of the still level that the water lost (or gained) by the solver implies,
    /// averaged over the window: (V − V₀) / (still shoreline x − paddle x), m. Set-down and
    /// set-up are measured from the initial still level; less this, from the level the water
    /// left in the flume would stand at.
    pub level_change_from_volume_m: f64,
    pub setdown_from_remaining_water_m: Option<f64>,
    pub setup_from_remaining_water_m: Option<f64>,
    pub undertow: Option<UndertowSummary>,
}

/// η and u1 along the flume at every output time, for the space–time images.
#[derive(Debug, Clone, Default)]
struct SpaceTime {
    dx_m: f64,
    eta: Vec<Vec<f32>>,
    u1: Vec<Vec<f32>>,
}

/// Everything the surf zone needs during a run.
pub struct SurfRecorder {
    pub detector: BreakingDetector,
    stations: Stations,
    space_time: Option<SpaceTime>,
    level_m: Vec<f64>,
    /// (t, V − V₀) at every frame, m².
    volume_change: Vec<(f64, f64)>,
}

impl SurfRecorder {
    pub fn new(sim: &Simulation) -> Self {
        let detector = BreakingDetector::new(sim);
        let space_time = detector.active().then(|| SpaceTime {
            dx_m: sim.case.particles.spacing_m,
            ..Default::default()
        });
        Self {
            detector,
            stations: Stations::new(&sim.case, |x, _| sim.case.bed_y_at(x)),
            space_time,
            level_m: Vec::new(),
            volume_change: Vec::new(),
        }
    }

    /// Whether the case has anything for this recorder to do.
    pub fn active(&self) -> bool {
        self.detector.active() || !self.stations.is_empty()
    }

    /// After every step of a run: the stations integrate their fluxes over time.
    pub fn step(&mut self, sim: &Simulation, dt_s: f64) {
        self.stations.accumulate(sim, dt_s);
    }

    /// Observes one output frame, whose water area the caller has measured (`volume_m2`, from
    /// `diagnostics::integrals`); returns the breaking events to log.
    pub fn record(&mut self, sim: &Simulation, volume_m2: f64) -> Vec<String> {
        self.stations.record(sim);
        if self.active() {
            self.volume_change
                .push((sim.time_s, volume_m2 - sim.initial_volume_m2));
        }
        let Some(st) = self.space_time.as_mut() else {
            return Vec::new();
        };
        let profile: SurfaceProfile = surface_profile(sim, 0.5 * st.dx_m);
        if self.level_m.is_empty() {
            self.level_m = (0..profile.crossings.len())
                .step_by(2)
                .map(|k| sim.case.still_level_at(profile.x_m(k)).unwrap_or(0.0))
                .collect();
        }
        let (eta, u1): (Vec<f32>, Vec<f32>) = (0..profile.crossings.len())
            .step_by(2)
            .zip(&self.level_m)
            .map(|(k, level)| match profile.crossings[k].first() {
                Some(&(y, u)) => ((y - level) as f32, u as f32),
                None => (f32::NAN, f32::NAN),
            })
            .unzip();
        st.eta.push(eta);
        st.u1.push(u1);
        self.detector.observe(sim, &profile)
    }

    /// The breaker summary and the surf-zone averages; `gauge_records` are the rows of
    /// gauges.csv (time, then η at each gauge first).
    pub fn finish(
        &self,
        sim: &Simulation,
        gauge_records: &[(f64, Vec<Option<f64>>)],
    ) -> (Option<BreakingSummary>, Option<SurfSummary>) {
        let case = &sim.case;
        let origin = case.surf.x_origin_m;
        let Some(w) = &case.wavemaker else {
            return (self.detector.summary(origin, 0.0), None);
        };
        // A solitary wave has no periods to average the surf zone over: its breaking summary
        // only.
        if w.theory == crate::case::WaveTheory::Solitary {
            return (self.detector.summary(origin, 0.0), None);
        }
        let breaking = self
            .detector
            .summary(origin, case.surf.spin_up_periods * w.period_s);
        if !self.active() {
            return (breaking, None);
        }
        let period = w.period_s;
        let from_s = case.surf.spin_up_periods * period;
        let last = gauge_records.last().map_or(0.0, |r| r.0);
        let periods = ((last - from_s) / period + 1e-9).floor().max(0.0);
        let to_s = from_s + periods * period;
        let window: Vec<&(f64, Vec<Option<f64>>)> = gauge_records
            .iter()
            .filter(|r| r.0 >= from_s - 1e-9 && r.0 < to_s - 1e-9)
            .collect();
        let t: Vec<f64> = window.iter().map(|r| r.0).collect();
        let wave_height: Vec<GaugeWave> = case
            .output
            .gauges_x_m
            .iter()
            .enumerate()
            .map(|(k, &x)| {
                let eta: Vec<Option<f64>> = window.iter().map(|r| r.1[k]).collect();
                let wet: Vec<f64> = eta.iter().flatten().copied().collect();
                let stats = crate::diagnostics::wave_stats(&t, &eta, from_s, periods as usize);
                GaugeWave {
                    x_m: x,
                    x_data_frame_m: x - origin,
                    height_m: stats.map(|s| s.mean_height_m),
                    period_height_m: crate::diagnostics::period_height_m(
                        &t,
                        &eta,
                        from_s,
                        period,
                        periods as usize,
                    ),
                    mean_level_m: (!wet.is_empty())
                        .then(|| wet.iter().sum::<f64>() / wet.len() as f64),
                    wet_fraction: wet.len() as f64 / eta.len().max(1) as f64,
                }
            })
            .collect();
        let x_b = breaking.as_ref().and_then(|b| b.x_b_m);
        let (mut setdown, mut setup, mut setup_x) = (None, None, None);
        if let Some(x_b) = x_b {
            setdown = wave_height
                .iter()
                .filter(|g| g.x_m < x_b && g.wet_fraction >= 0.999)
                .filter_map(|g| g.mean_level_m)
                .reduce(f64::min);
            if let Some(g) = wave_height
                .iter()
                .rfind(|g| g.x_m > x_b && g.wet_fraction >= 0.9 && g.mean_level_m.is_some())
            {
                setup = g.mean_level_m;
                setup_x = Some(g.x_m);
            }
        }
        // The width of the water surface at rest: paddle to still shoreline (or the far wall).
        let width = (still_shoreline_x_m(case) - w.x_m).max(1e-9);
        let in_window: Vec<f64> = self
            .volume_change
            .iter()
            .filter(|(t, _)| *t >= from_s - 1e-9 && *t < to_s - 1e-9)
            .map(|(_, dv)| dv / width)
            .collect();
        let level_change = if in_window.is_empty() {
            0.0
        } else {
            in_window.iter().sum::<f64>() / in_window.len() as f64
        };
        let surf = (periods >= 1.0).then(|| SurfSummary {
            averaged_from_s: from_s,
            averaged_to_s: to_s,
            periods: periods as usize,
            wave_height,
            setdown_m: setdown,
            setup_m: setup,
            setup_gauge_x_m: setup_x,
            level_change_from_volume_m: level_change,
            setdown_from_remaining_water_m: setdown.map(|v| v - level_change),
            setup_from_remaining_water_m: setup.map(|v| v - level_change),
            undertow: self.stations.summary(period, from_s, origin),
        });
        (breaking, surf)
    }

    /// Logs the space–time images (static) to the recording.
    pub fn log_space_time(&self, rrd: &RrdLogger, height_m: f64, u1: ColorScale) {
        let Some(st) = &self.space_time else {
            return;
        };
        let rec = rrd.stream();
        let eta_scale = ColorScale::symmetric(height_m.max(1e-6));
        for (name, rows, scale, what) in [
            (
                "space_time/eta",
                &st.eta,
                eta_scale,
                ("η", "m above still water"),
            ),
            ("space_time/u1", &st.u1, u1, ("u1 at the surface", "m/s")),
        ] {
            let (Some(w), h) = (rows.first().map(Vec::len), rows.len()) else {
                continue;
            };
            // Time runs down the image, x to the right; dry samples are white.
            let mut bytes = Vec::with_capacity(3 * w * h);
            for row in rows {
                for &v in row {
                    if v.is_finite() {
                        bytes.extend(scale.color(v as f64));
                    } else {
                        bytes.extend([255, 255, 255]);
                    }
                }
            }
            let _ = rec.log_static(name, &Image::from_rgb24(bytes, [w as u32, h as u32]));
            let note = format!(
                "{}(x, t): x to the right, {:.4} m per pixel from x = 0; time downwards, one row per output; colour = {}; white = dry.",
                what.0,
                st.dx_m,
                scale.describe(what.0, what.1)
            );
            let _ = rec.log_static(format!("{name}_legend"), &TextDocument::new(note));
        }
    }
}

/// Logs the undertow profiles ū(z) (static), one line per station: x = ū in m/s, y = z in m
/// above still water (the recording's `profiles` view), with the zero line and each station's
/// mean trough level.
pub fn log_profiles(rrd: &RrdLogger, surf: &SurfSummary) {
    let Some(u) = &surf.undertow else {
        return;
    };
    let rec = rrd.stream();
    for s in &u.stations {
        let line: Vec<[f32; 2]> = s
            .z_m
            .iter()
            .zip(&s.u_mean_m_s)
            .filter(|(_, u)| u.is_finite())
            .map(|(z, u)| [*u as f32, -(*z as f32)])
            .collect();
        let _ = rec.log_static(
            format!("profiles/undertow/x_{:.3}", s.x_m),
            &LineStrips2D::new([line]).with_labels([format!("x = {:.3} m", s.x_m)]),
        );
        let trough = -(s.trough_m as f32);
        let _ = rec.log_static(
            format!("profiles/trough/x_{:.3}", s.x_m),
            &LineStrips2D::new([[[-0.05f32, trough], [0.05, trough]]]),
        );
    }
    let lo = u
        .stations
        .iter()
        .flat_map(|s| s.z_m.first().copied())
        .fold(0.0, f64::min) as f32;
    let _ = rec.log_static(
        "profiles/zero",
        &LineStrips2D::new([[[0.0f32, -lo], [0.0, 0.0]]]).with_colors([[128, 128, 128]]),
    );
    let _ = rec.log_static(
        "profiles_legend",
        &TextDocument::new(
            "Undertow profiles: period-averaged u1 (m/s, positive onshore) to the right, height above still water (m) upwards; short bars mark each station's mean trough level.",
        ),
    );
}

/// Writes `profiles.csv`: long format, one value per row, `quantity,x_m,z_m,value`; z_m is
/// empty for quantities that depend on x only. Quantities: `u_mean_m_s` and `wet_fraction` per
/// station and height, `trough_m`, `crest_m`, `mean_level_m`, `flux_below_trough_m2_s`,
/// `flux_above_trough_m2_s` per station, `H_m`, `H_period_m`, `gauge_mean_level_m` per gauge.
pub fn write_profiles(path: &Path, surf: &SurfSummary) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(
        f,
        "# averaged over {} periods, t = {:.3} to {:.3} s; x in the flume's frame, z above still water",
        surf.periods, surf.averaged_from_s, surf.averaged_to_s
    )?;
    writeln!(f, "quantity,x_m,z_m,value")?;
    let num = |v: f64| {
        if v.is_finite() {
            format!("{v:.6}")
        } else {
            String::new()
        }
    };
    if let Some(u) = &surf.undertow {
        for s in &u.stations {
            for ((z, v), w) in s.z_m.iter().zip(&s.u_mean_m_s).zip(&s.wet_fraction) {
                writeln!(f, "u_mean_m_s,{:.3},{:.5},{}", s.x_m, z, num(*v))?;
                writeln!(f, "wet_fraction,{:.3},{:.5},{}", s.x_m, z, num(*w))?;
            }
            for (name, v) in [
                ("trough_m", s.trough_m),
                ("crest_m", s.crest_m),
                ("mean_level_m", s.mean_level_m),
                ("flux_below_trough_m2_s", s.flux_below_trough_m2_s),
                ("flux_above_trough_m2_s", s.flux_above_trough_m2_s),
            ] {
                writeln!(f, "{name},{:.3},,{}", s.x_m, num(v))?;
            }
        }
    }
    for g in &surf.wave_height {
        writeln!(
            f,
            "H_m,{:.3},,{}",
            g.x_m,
            num(g.height_m.unwrap_or(f64::NAN))
        )?;
        writeln!(
            f,
            "H_period_m,{:.3},,{}",
            g.x_m,
            num(g.period_height_m.unwrap_or(f64::NAN))
        )?;
        writeln!(
            f,
            "gauge_mean_level_m,{:.3},,{}",
            g.x_m,
            num(g.mean_level_m.unwrap_or(f64::NAN))
        )?;
    }
    f.flush()
}
