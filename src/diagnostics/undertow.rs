//! Undertow stations: the horizontal flow through vertical sections of the flume, integrated
//! exactly over the linear triangles, binned in height, then averaged over whole wave periods.
//!
//! After every step of a run (or, fed only at the output times, at each of those) and at each
//! station, every kept triangle that straddles the station's x cuts
//! the vertical line in a segment along which u is linear; its integral ∫u dy is split among
//! fixed height bins. Averaging the binned integrals over whole periods gives the Eulerian mean
//! flux density (dry time counts as zero flow), and dividing by the wet time gives the mean
//! velocity ū(z) of the water that was there. The flux below the mean trough level is the
//! undertow; above it the waves carry water onshore; in a closed flume the two cancel when
//! the water shoreward of the station neither grows nor drains, which the station's budget
//! (the mesh's area shoreward of it, and the volume ledger's share of it) checks.

use crate::case::Case;
use crate::simulation::Simulation;

/// One station's bins.
#[derive(Debug, Clone)]
pub struct Station {
    pub x_m: f64,
    /// Across the tank, m (0 in 2D).
    pub z_m: f64,
    /// Absolute height of the lowest bin's bottom (the bed), m.
    pub bottom_m: f64,
    pub bins: usize,
}

/// What the stations read of a flow, 2D ([`Simulation`]) or 3D
/// (`crate::simulation3d::Simulation3`).
pub trait StationFlow {
    /// The flow's time, s.
    fn time_s(&self) -> f64;
    /// Per station: ∫u dy (m²/s) and the wet height (m) in each bin of height `dz_m` now.
    fn sections(&self, stations: &[Station], dz_m: f64) -> Vec<(Vec<f64>, Vec<f64>)>;
    /// The surface's height above still water at the station, m (`None`: dry).
    fn elevation_m(&self, station: &Station) -> Option<f64>;
    /// The water shoreward of x = `x_m`, m² (per metre of width in 3D; 0 where it is not kept).
    fn water_right_of_m2(&self, x_m: f64) -> f64;
    /// The volume ledger's balance shoreward of x = `x_m`, m² (0 without a ledger).
    fn numerics_right_of_m2(&self, x_m: f64) -> f64;
}

impl StationFlow for Simulation {
    fn time_s(&self) -> f64 {
        self.time_s
    }

    /// One pass over the triangles (this runs every step): each is cut by the stations within
    /// its x range.
    fn sections(&self, stations: &[Station], dz_m: f64) -> Vec<(Vec<f64>, Vec<f64>)> {
        let p = &self.particles;
        let mut out: Vec<(Vec<f64>, Vec<f64>)> = stations
            .iter()
            .map(|s| (vec![0.0; s.bins], vec![0.0; s.bins]))
            .collect();
        for t in &self.solver.mesh.triangles {
            let xs = t.map(|i| p.position[i as usize].x);
            let lo = xs[0].min(xs[1]).min(xs[2]);
            let hi = xs[0].max(xs[1]).max(xs[2]);
            for (s, (flux, wet)) in stations.iter().zip(out.iter_mut()) {
                if s.x_m < lo || s.x_m >= hi {
                    continue;
                }
                if let Some(((y0, u0), (y1, u1))) = section(t, &p.position, &p.velocity, s.x_m) {
                    add_segment(s, dz_m, y0, u0, y1, u1, flux, wet);
                }
            }
        }
        out
    }

    fn elevation_m(&self, station: &Station) -> Option<f64> {
        super::surface_elevation(self, station.x_m)
    }

    fn water_right_of_m2(&self, x_m: f64) -> f64 {
        Simulation::water_area_right_of_m2(self, x_m)
    }

    fn numerics_right_of_m2(&self, x_m: f64) -> f64 {
        self.numerics_area_change_right_of_m2(x_m)
    }
}

/// One output time at every station.
#[derive(Debug, Clone)]
struct Sample {
    t_s: f64,
    /// The time the fluxes are averaged over, ending at `t_s` (0: the flow at `t_s`).
    span_s: f64,
    /// Per station: surface elevation above still water (`None` when dry).
    eta_m: Vec<Option<f64>>,
    /// Per station and bin: ∫u dy over the wet part of the bin, m²/s.
    flux: Vec<Vec<f32>>,
    /// Per station and bin: wet height of the bin, m.
    wet: Vec<Vec<f32>>,
    /// Per station: the mesh's water area shoreward of it, m².
    shore_area_m2: Vec<f64>,
    /// Per station: the volume ledger's balance (area the numerics made, net of what the
    /// relaxation paid back) in the strips shoreward of it, m².
    shore_ledger_m2: Vec<f64>,
}

/// Records the stations of a case at every output time.
#[derive(Debug, Clone)]
pub struct Stations {
    stations: Vec<Station>,
    dz_m: f64,
    level_m: Vec<f64>,
    samples: Vec<Sample>,
    /// Per station and bin: ∫∫u dy dt and ∫(wet height) dt since the last sample, and the time
    /// they span (see [`Stations::accumulate`]).
    flux_dt: Vec<Vec<f64>>,
    wet_dt: Vec<Vec<f64>>,
    span_s: f64,
}

/// The averages at one station.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StationSummary {
    pub x_m: f64,
    /// Across a 3D tank, m (0 in 2D).
    pub across_m: f64,
    /// `x_m − surf.x_origin_m`.
    pub x_data_frame_m: f64,
    /// Still-water depth, m.
    pub depth_m: f64,
    /// Means over the periods of the lowest and highest surface elevation in each period, and
    /// the time-mean elevation (over wet samples), m above still water.
    pub trough_m: f64,
    pub crest_m: f64,
    pub mean_level_m: f64,
    /// Period-mean volume fluxes, m²/s (positive onshore): below the mean trough, above it,
    /// and their sum.
    pub flux_below_trough_m2_s: f64,
    pub flux_above_trough_m2_s: f64,
    pub net_flux_m2_s: f64,
    /// |net| / onshore flux above trough (the issue asks for ≤ 0.05).
    pub net_over_onshore: f64,
    /// Mean ū over the water below the trough, m/s (negative: offshore).
    pub undertow_mean_m_s: f64,
    /// The water budget shoreward of the station over the same window, m²/s: the growth rate
    /// of the mesh's water area there (mean over the last period minus the first, over the
    /// time between them), and the part of it the numerics made (the volume ledger's growth
    /// there). In a closed flume net flux = storage − numerics.
    pub shore_storage_m2_s: f64,
    pub shore_numerics_m2_s: f64,
    /// Bin centres, m above still water, with ū (mean over wet time, m/s; NaN when never
    /// wet) and the wet fraction of the time.
    pub z_m: Vec<f64>,
    pub u_mean_m_s: Vec<f64>,
    pub wet_fraction: Vec<f64>,
}

/// The averaging window and the stations' results.
#[derive(Debug, Clone, serde::Serialize)]
pub struct UndertowSummary {
    pub averaged_from_s: f64,
    pub averaged_to_s: f64,
    pub periods: usize,
    pub stations: Vec<StationSummary>,
}

impl Stations {
    /// The stations of `case` (`surf.stations_x_m`, and across a 3D tank `stations_z_m`), bins
    /// from the bed (`bed_at(x, z)`, m) to 2H (at least 3 h) above still water.
    pub fn new(case: &Case, bed_at: impl Fn(f64, f64) -> f64) -> Self {
        let h = case.particles.spacing_m;
        let dz = case.surf.profile_dz_m.unwrap_or(0.5 * h);
        let height = case.wavemaker.as_ref().map_or(0.0, |w| w.height_m);
        let mut level_m = Vec::new();
        let stations: Vec<Station> = case
            .surf
            .stations_x_m
            .iter()
            .enumerate()
            .map(|(k, &x)| {
                let z = case.surf.stations_z_m.get(k).copied().unwrap_or(0.0);
                let bed = bed_at(x, z);
                let level = case.still_level_at(x).unwrap_or(bed);
                level_m.push(level);
                let top = level + (2.0 * height).max(3.0 * h);
                Station {
                    x_m: x,
                    z_m: z,
                    bottom_m: bed,
                    bins: ((top - bed) / dz).ceil().max(1.0) as usize,
                }
            })
            .collect();
        Self {
            flux_dt: stations.iter().map(|s| vec![0.0; s.bins]).collect(),
            wet_dt: stations.iter().map(|s| vec![0.0; s.bins]).collect(),
            span_s: 0.0,
            stations,
            dz_m: dz,
            level_m,
            samples: Vec::new(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.stations.is_empty()
    }

    /// Records the flow through every station at the current time.
    pub fn record(&mut self, sim: &impl StationFlow) {
        if self.stations.is_empty() {
            return;
        }
        let mut sample = Sample {
            t_s: sim.time_s(),
            span_s: self.span_s,
            eta_m: Vec::with_capacity(self.stations.len()),
            flux: Vec::with_capacity(self.stations.len()),
            wet: Vec::with_capacity(self.stations.len()),
            shore_area_m2: Vec::with_capacity(self.stations.len()),
            shore_ledger_m2: Vec::with_capacity(self.stations.len()),
        };
        // Without steps fed since the last sample, the flow at this instant.
        let now = (self.span_s <= 0.0).then(|| sim.sections(&self.stations, self.dz_m));
        for (j, s) in self.stations.iter().enumerate() {
            // The time mean since the last sample when the caller fed every step.
            let (flux, wet): (Vec<f32>, Vec<f32>) = if let Some(now) = &now {
                let (flux_now, wet_now) = &now[j];
                (
                    flux_now.iter().map(|&v| v as f32).collect(),
                    wet_now.iter().map(|&v| v as f32).collect(),
                )
            } else {
                (
                    self.flux_dt[j]
                        .iter()
                        .map(|v| (v / self.span_s) as f32)
                        .collect(),
                    self.wet_dt[j]
                        .iter()
                        .map(|v| (v / self.span_s) as f32)
                        .collect(),
                )
            };
            sample.shore_area_m2.push(sim.water_right_of_m2(s.x_m));
            sample.shore_ledger_m2.push(sim.numerics_right_of_m2(s.x_m));
            sample.eta_m.push(sim.elevation_m(s));
            sample.flux.push(flux);
            sample.wet.push(wet);
        }
        self.samples.push(sample);
        for v in self.flux_dt.iter_mut().chain(self.wet_dt.iter_mut()) {
            v.fill(0.0);
        }
        self.span_s = 0.0;
    }

    /// After a step of `dt_s`: adds the flow through every station, times `dt_s`, to the
    /// integrals the next sample averages. A run that calls this every step gets fluxes
    /// integrated over time step by step; without it each sample is the flow at its instant,
    /// and a wave whose period is a whole number of output intervals is always seen at the
    /// same phases.
    pub fn accumulate(&mut self, sim: &impl StationFlow, dt_s: f64) {
        if self.stations.is_empty() {
            return;
        }
        for (j, (flux, wet)) in sim
            .sections(&self.stations, self.dz_m)
            .into_iter()
            .enumerate()
        {
            for (acc, v) in self.flux_dt[j].iter_mut().zip(flux) {
                *acc += v * dt_s;
            }
            for (acc, v) in self.wet_dt[j].iter_mut().zip(wet) {
                *acc += v * dt_s;
            }
        }
        self.span_s += dt_s;
    }

    /// Averages over whole periods of `period_s` from `from_s` to the last sample;
    /// `None` when no whole period was recorded after `from_s`.
    pub fn summary(&self, period_s: f64, from_s: f64, x_origin_m: f64) -> Option<UndertowSummary> {
        if self.stations.is_empty() {
            return None;
        }
        let last = self.samples.last()?.t_s;
        let periods = ((last - from_s) / period_s + 1e-9).floor();
        if periods < 1.0 {
            return None;
        }
        let to_s = from_s + periods * period_s;
        // Equal output intervals: the samples of [from, to) weigh the same (a sample averaged
        // over a span counts where its span starts).
        let used: Vec<&Sample> = self
            .samples
            .iter()
            .filter(|s| {
                let start = s.t_s - s.span_s;
                start >= from_s - 1e-9 && start < to_s - 1e-9
            })
            .collect();
        let n = used.len() as f64;
        let stations = self
            .stations
            .iter()
            .enumerate()
            .map(|(j, st)| {
                let level = self.level_m[j];
                // Per period: lowest and highest elevation.
                let (mut troughs, mut crests) = (Vec::new(), Vec::new());
                for k in 0..periods as usize {
                    let a = from_s + k as f64 * period_s;
                    let etas: Vec<f64> = used
                        .iter()
                        .filter(|s| s.t_s >= a - 1e-9 && s.t_s < a + period_s - 1e-9)
                        .filter_map(|s| s.eta_m[j])
                        .collect();
                    if !etas.is_empty() {
                        troughs.push(etas.iter().copied().fold(f64::INFINITY, f64::min));
                        crests.push(etas.iter().copied().fold(f64::NEG_INFINITY, f64::max));
                    }
                }
                let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
                let wet_eta: Vec<f64> = used.iter().filter_map(|s| s.eta_m[j]).collect();
                let trough = mean(&troughs);
                let trough_abs = level + trough;
                let (mut below, mut total) = (0.0, 0.0);
                let (mut below_u, mut below_wet) = (0.0, 0.0);
                let mut z = Vec::with_capacity(st.bins);
                let mut u = Vec::with_capacity(st.bins);
                let mut wet_fraction = Vec::with_capacity(st.bins);
                for b in 0..st.bins {
                    let bottom = st.bottom_m + b as f64 * self.dz_m;
                    let f: f64 = used.iter().map(|s| s.flux[j][b] as f64).sum();
                    let w: f64 = used.iter().map(|s| s.wet[j][b] as f64).sum();
                    total += f / n;
                    let share = ((trough_abs - bottom) / self.dz_m).clamp(0.0, 1.0);
                    below += share * f / n;
                    below_u += share * f;
                    below_wet += share * w;
                    z.push(bottom + 0.5 * self.dz_m - level);
                    u.push(if w > 0.0 { f / w } else { f64::NAN });
                    wet_fraction.push(w / (n * self.dz_m));
                }
                let above = total - below;
                let period_mean = |k: usize, f: &dyn Fn(&Sample) -> f64| {
                    let a = from_s + k as f64 * period_s;
                    let v: Vec<f64> = used
                        .iter()
                        .filter(|s| s.t_s >= a - 1e-9 && s.t_s < a + period_s - 1e-9)
                        .map(|s| f(s))
                        .collect();
                    mean(&v)
                };
                let last_k = periods as usize - 1;
                let span = (last_k as f64 * period_s).max(1e-300);
                let rate = |f: &dyn Fn(&Sample) -> f64| {
                    if last_k == 0 {
                        0.0
                    } else {
                        (period_mean(last_k, f) - period_mean(0, f)) / span
                    }
                };
                let storage = rate(&|s: &Sample| s.shore_area_m2[j]);
                let numerics = rate(&|s: &Sample| s.shore_ledger_m2[j]);
                StationSummary {
                    x_m: st.x_m,
                    across_m: st.z_m,
                    x_data_frame_m: st.x_m - x_origin_m,
                    depth_m: level - st.bottom_m,
                    trough_m: trough,
                    crest_m: mean(&crests),
                    mean_level_m: mean(&wet_eta),
                    flux_below_trough_m2_s: below,
                    flux_above_trough_m2_s: above,
                    net_flux_m2_s: total,
                    net_over_onshore: total.abs() / above.abs().max(1e-300),
                    undertow_mean_m_s: below_u / below_wet.max(1e-300),
                    shore_storage_m2_s: storage,
                    shore_numerics_m2_s: numerics,
                    z_m: z,
                    u_mean_m_s: u,
                    wet_fraction,
                }
            })
            .collect();
        Some(UndertowSummary {
            averaged_from_s: from_s,
            averaged_to_s: to_s,
            periods: periods as usize,
            stations,
        })
    }
}

/// The segment of the vertical line x = `x_m` inside triangle `t`, as ((y, u) low, (y, u) high)
/// with u the horizontal velocity interpolated along the edges; `None` when the line misses it.
/// Edges count the crossing on lo ≤ x < hi, so a line through a node is not counted twice.
fn section(
    t: &[u32; 3],
    position: &[nalgebra::Vector2<f64>],
    velocity: &[nalgebra::Vector2<f64>],
    x_m: f64,
) -> Option<((f64, f64), (f64, f64))> {
    let mut hits = [(0.0, 0.0); 2];
    let mut count = 0;
    for e in 0..3 {
        let (a, b) = (t[e] as usize, t[(e + 1) % 3] as usize);
        let (pa, pb) = (position[a], position[b]);
        let (lo, hi) = if pa.x <= pb.x {
            (pa.x, pb.x)
        } else {
            (pb.x, pa.x)
        };
        if !(lo <= x_m && x_m < hi) {
            continue;
        }
        let f = (x_m - pa.x) / (pb.x - pa.x);
        if count < 2 {
            hits[count] = (
                pa.y + f * (pb.y - pa.y),
                velocity[a].x + f * (velocity[b].x - velocity[a].x),
            );
        }
        count += 1;
    }
    if count != 2 {
        return None;
    }
    let (p, q) = (hits[0], hits[1]);
    Some(if p.0 <= q.0 { (p, q) } else { (q, p) })
}

/// Adds ∫u dy of the segment (y0, u0)–(y1, u1), u linear in y, to the bins of `s`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn add_segment(
    s: &Station,
    dz: f64,
    y0: f64,
    u0: f64,
    y1: f64,
    u1: f64,
    flux: &mut [f64],
    wet: &mut [f64],
) {
    if y1 <= y0 {
        return;
    }
    let first = (((y0 - s.bottom_m) / dz).floor().max(0.0)) as usize;
    let mut b = first;
    while b < s.bins {
        let lo = (s.bottom_m + b as f64 * dz).max(y0);
        let hi = (s.bottom_m + (b + 1) as f64 * dz).min(y1);
        if lo >= y1 {
            break;
        }
        if hi > lo {
            let mid = 0.5 * (lo + hi);
            let u = u0 + (u1 - u0) * (mid - y0) / (y1 - y0);
            flux[b] += u * (hi - lo);
            wet[b] += hi - lo;
        }
        b += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector2;

    #[test]
    fn section_of_a_triangle_integrates_a_linear_field_exactly() {
        // u = 2 y over a triangle cut by x = 0.25: from y = 0 to y = 0.75.
        let position = [
            Vector2::new(0.0, 0.0),
            Vector2::new(1.0, 0.0),
            Vector2::new(0.0, 1.0),
        ];
        let velocity: Vec<Vector2<f64>> = position
            .iter()
            .map(|p| Vector2::new(2.0 * p.y, 0.0))
            .collect();
        let ((y0, u0), (y1, u1)) = section(&[0, 1, 2], &position, &velocity, 0.25).unwrap();
        assert!((y0 - 0.0).abs() < 1e-12 && (y1 - 0.75).abs() < 1e-12);
        let s = Station {
            x_m: 0.25,
            z_m: 0.0,
            bottom_m: 0.0,
            bins: 10,
        };
        let (mut flux, mut wet) = (vec![0.0; 10], vec![0.0; 10]);
        add_segment(&s, 0.1, y0, u0, y1, u1, &mut flux, &mut wet);
        // ∫₀^0.75 2y dy = 0.5625; wet height 0.75.
        let total: f64 = flux.iter().sum();
        let height: f64 = wet.iter().sum();
        assert!((total - 0.5625).abs() < 1e-6, "{total}");
        assert!((height - 0.75).abs() < 1e-6, "{height}");
        assert!(section(&[0, 1, 2], &position, &velocity, 1.5).is_none());
    }
}
