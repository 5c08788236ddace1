//! Sizes of a run, estimated from the case before anything is seeded: no input may exhaust the
//! machine. A spacing of 1e-300 m, a flume 700 km high or an output every 1e-200 s is refused
//! here, with the field, the count and the limit, instead of allocating until the kernel kills
//! the process or looping without end.
//!
//! The node limit is a property of the machine, not of the case: it defaults to
//! [`DEFAULT_MAX_NODES`] and `surflab --max-particles N` changes it for the whole process.

use super::Case;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Default ceiling on fluid particles plus wall and paddle nodes. Measured with `surflab bench`
/// on the still tank, the process holds about 1.7 KB more per node (peak 144 MB at 20 381
/// nodes, 247 MB at 80 761), so 2 million nodes need about 3.5 GB, a seventh of a 24 GiB
/// machine; a step took 0.53 s at 80 761 nodes, so one at the ceiling takes ten seconds or more.
pub const DEFAULT_MAX_NODES: usize = 2_000_000;

/// Ceiling on recorded frames (`time.end_s / output.interval_s`): every frame keeps a row of
/// the time series in memory and a frame of every particle in the recording.
pub const MAX_FRAMES: f64 = 1.0e6;

/// Ceiling on the number of steps the run needs at least (`time.end_s / time.dt_max_s`): a
/// billion steps is weeks of computing at the fastest step this solver takes.
pub const MAX_STEPS: f64 = 1.0e9;

static MAX_NODES: AtomicUsize = AtomicUsize::new(DEFAULT_MAX_NODES);

/// Changes the node ceiling for this process (`--max-particles`, for machines bigger than the
/// one the default is set for).
pub fn set_max_nodes(n: usize) {
    MAX_NODES.store(n, Ordering::Relaxed);
}

/// The node ceiling in force.
pub fn max_nodes() -> usize {
    MAX_NODES.load(Ordering::Relaxed)
}

/// What a case will seed, estimated from its fields alone (upper bounds, computed in floating
/// point so that absurd inputs give large numbers rather than overflow).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SizeEstimate {
    /// Fluid particles of the initial lattice (every lattice point of every water region).
    pub fluid: f64,
    /// Wall nodes along the outline, plus the paddle's column.
    pub walls: f64,
    /// Recorded frames, the first one included.
    pub frames: f64,
    /// The fewest steps the run can take (Δt never exceeds `time.dt_max_s`).
    pub min_steps: f64,
}

impl SizeEstimate {
    pub fn nodes(&self) -> f64 {
        self.fluid + self.walls
    }
}

impl Case {
    /// Estimates the run's sizes without seeding (see [`SizeEstimate`]). Assumes the fields
    /// passed the sign checks of validation (positive spacing and lengths).
    pub fn size_estimate(&self) -> SizeEstimate {
        self.estimate(self.flume.width_m)
    }

    /// [`Self::size_estimate`] for a tank of `width_m` (`None`: the 2D flume).
    fn estimate(&self, width_m: Option<f64>) -> SizeEstimate {
        let h = self.particles.spacing_m;
        let fluid = self
            .water
            .iter()
            .map(|w| {
                let nx = ((w.x_end_m - w.x_start_m) / h).round().max(1.0);
                let ny = ((w.depth_m + w.surface_amplitude_m.abs()) / h)
                    .round()
                    .max(1.0);
                (nx + 1.0) * (ny + 1.0)
            })
            .sum();
        let f = &self.flume;
        let mut outline = vec![[0.0, f.height_m]];
        outline.extend(f.bed_points());
        outline.push([f.length_m, f.height_m]);
        let mut walls = 1.0;
        for s in outline.windows(2) {
            let len = (s[1][0] - s[0][0]).hypot(s[1][1] - s[0][1]);
            if len > 0.0 {
                walls += (len / h).round().max(1.0);
            }
        }
        if self.wavemaker.is_some() {
            walls += (f.height_m / h).ceil() + 1.0;
        }
        let (mut fluid, mut walls) = (fluid, walls);
        let spacing = self.particles.spacing();
        let x_refined = spacing.refined_from_m().max(0.0);
        if x_refined < f.length_m {
            // A refined stretch: on top of the coarse count, its water (above the bed, from 200
            // samples) as if all of it were at the fine spacing.
            let hf = spacing.finest_m();
            fluid += self
                .water
                .iter()
                .map(|w| {
                    let (x0, x1) = (w.x_start_m.max(x_refined), w.x_end_m);
                    if x1 <= x0 {
                        return 0.0;
                    }
                    let dx = (x1 - x0) / 200.0;
                    let level = w.depth_m + w.surface_amplitude_m.abs();
                    let area: f64 = (0..200)
                        .map(|k| (level - f.bed_y_at(x0 + (k as f64 + 0.5) * dx)).max(0.0) * dx)
                        .sum();
                    area / (hf * hf) + (x1 - x0) / hf + 1.0
                })
                .sum::<f64>();
            walls += (f.length_m - x_refined + f.height_m) / hf * 1.5;
        }
        if let Some(width) = width_m {
            // The 3D tank: every line of nodes repeated across the width, and the two side
            // walls filled with wall nodes.
            let layers = (width / h).round().max(1.0) + 1.0;
            fluid *= layers;
            walls = walls * layers
                + 2.0 * ((f.length_m / h).round() + 1.0) * ((f.height_m / h).round() + 1.0);
        }
        SizeEstimate {
            fluid,
            walls,
            frames: (self.time.end_s / self.output.interval_s).ceil() + 1.0,
            min_steps: (self.time.end_s / self.time.dt_max_s).ceil(),
        }
    }

    /// Refuses a case whose estimated sizes exceed the limits, naming the field to change.
    pub(super) fn validate_size(&self) -> Result<(), (String, String)> {
        let e = self.size_estimate();
        let limit = max_nodes();
        if !within(e.nodes(), limit as f64) {
            // Name the field that makes the count: the width of a 3D tank whose 2D section
            // would fit, else the spacing when the water does, else the flume's longer side
            // (the walls are what a huge flume fills).
            let field = if self.flume.width_m.is_some()
                && within(self.estimate(None).nodes(), limit as f64)
            {
                "flume.width_m"
            } else if e.fluid >= e.walls {
                "particles.spacing_m"
            } else if self.flume.height_m > self.flume.length_m {
                "flume.height_m"
            } else {
                "flume.length_m"
            };
            return Err((
                field.to_owned(),
                format!(
                    "h = {} m in a {} × {}{} m flume would seed about {:.3e} nodes ({:.3e} \
                     fluid, {:.3e} wall); the limit is {limit} (raise it with --max-particles on \
                     a bigger machine)",
                    short(self.particles.spacing_m),
                    short(self.flume.length_m),
                    short(self.flume.height_m),
                    self.flume
                        .width_m
                        .map_or(String::new(), |w| format!(" × {}", short(w))),
                    e.nodes(),
                    e.fluid,
                    e.walls
                ),
            ));
        }
        if !within(e.frames, MAX_FRAMES) {
            return Err((
                "output.interval_s".to_owned(),
                format!(
                    "{} s to t = {} s is {:.3e} frames; the limit is {MAX_FRAMES:.0e}",
                    short(self.output.interval_s),
                    short(self.time.end_s),
                    e.frames
                ),
            ));
        }
        if !within(e.min_steps, MAX_STEPS) {
            return Err((
                "time.end_s".to_owned(),
                format!(
                    "{} s at Δt ≤ time.dt_max_s = {} s is at least {:.3e} steps; the limit is \
                     {MAX_STEPS:.0e}",
                    short(self.time.end_s),
                    short(self.time.dt_max_s),
                    e.min_steps
                ),
            ));
        }
        Ok(())
    }
}

/// `v ≤ limit`, false for NaN (an estimate that is not a number is refused too).
fn within(v: f64, limit: f64) -> bool {
    v <= limit
}

/// A number as a person writes it: plain in the usual range, in exponent form outside it (a
/// plain 1e300 would print three hundred digits).
fn short(v: f64) -> String {
    if v == 0.0 || (1e-4..1e9).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn case(extra: &[&str]) -> Result<Case, String> {
        let text = "[flume]\nlength_m = 1.0\nheight_m = 0.7\n[[water]]\nx_end_m = 1.0\n\
                    depth_m = 0.5\n[particles]\nspacing_m = 0.05\n";
        let overrides: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
        Case::from_toml_str(text, Path::new("t.toml"), "t", &overrides).map_err(|e| e.to_string())
    }

    #[test]
    fn the_estimate_bounds_what_is_seeded() {
        let c = case(&[]).unwrap();
        let e = c.size_estimate();
        let flume = crate::geometry::Flume::from_case(&c);
        let fluid = crate::geometry::seed_fluid(&c, &flume).len() as f64;
        let walls = flume.wall_nodes_with_tangents(&c.particles.spacing()).len() as f64;
        println!("estimate {e:?}; seeded {fluid} fluid, {walls} wall");
        assert!(e.fluid >= fluid && e.fluid <= 1.5 * fluid);
        assert!(e.walls >= walls && e.walls <= walls + 2.0);
    }

    #[test]
    fn absurd_sizes_are_refused_with_field_count_and_limit() {
        let e = case(&["particles.spacing_m=1e-300"]).unwrap_err();
        assert!(
            e.contains("particles.spacing_m") && e.contains("limit is 2000000"),
            "{e}"
        );
        let e = case(&["flume.height_m=7e5"]).unwrap_err();
        assert!(e.contains("flume.height_m") && e.contains("wall"), "{e}");
        let e = case(&["output.interval_s=1e-200"]).unwrap_err();
        assert!(
            e.contains("output.interval_s") && e.contains("frames"),
            "{e}"
        );
        let e = case(&["time.end_s=1e300"]).unwrap_err();
        assert!(
            e.contains("output.interval_s") && e.contains("1e300 s"),
            "{e}"
        );
        let e = case(&["time.end_s=1e12", "output.interval_s=1e7"]).unwrap_err();
        assert!(e.contains("time.end_s") && e.contains("steps"), "{e}");
    }
}
