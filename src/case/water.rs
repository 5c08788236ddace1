//! `[[water]]`: the regions filled with water at the start.

use serde::{Deserialize, Serialize};

use super::{Flume, err};

/// A region filled with water at the start: between `x_start_m` and `x_end_m`, from the bed up to
/// the level `depth_m` above the flume floor.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WaterRegion {
    /// Left end of the region, m. Default 0.
    #[serde(default)]
    pub x_start_m: f64,
    /// Right end of the region, m. Required.
    pub x_end_m: f64,
    /// Still-water level above the flume floor (y = 0), m. Required.
    pub depth_m: f64,
    /// Amplitude of an initial standing-wave surface, η(x) = A cos(nπ(x − x_start)/width), m.
    /// Default 0 (a flat surface).
    #[serde(default)]
    pub surface_amplitude_m: f64,
    /// Mode n of that surface (1: one half wavelength over the region). Default 1.
    #[serde(default = "default_mode")]
    pub surface_mode: u32,
}

fn default_mode() -> u32 {
    1
}

impl WaterRegion {
    /// Initial surface level above the flume floor at `x_m`.
    pub fn level_at(&self, x_m: f64) -> f64 {
        let width = self.x_end_m - self.x_start_m;
        let phase =
            std::f64::consts::PI * self.surface_mode as f64 * (x_m - self.x_start_m) / width;
        self.depth_m + self.surface_amplitude_m * phase.cos()
    }

    /// Does the region span `x_m` (give or take `tolerance_m`)?
    pub fn spans(&self, x_m: f64, tolerance_m: f64) -> bool {
        x_m >= self.x_start_m - tolerance_m && x_m <= self.x_end_m + tolerance_m
    }

    /// Region `i` (named `water[i]` in messages): a positive depth and a surface below the walls,
    /// inside the flume and at least two spacings `h` wide.
    fn validate(&self, i: usize, flume: &Flume, h: f64) -> Result<(), (String, String)> {
        let f = |name: &str| format!("water[{i}].{name}");
        let w = self;
        if !w.depth_m.is_finite() || w.depth_m <= 0.0 {
            return err(
                &f("depth_m"),
                format!("depth must be positive, got {} m", w.depth_m),
            );
        }
        if !w.surface_amplitude_m.is_finite() || w.surface_amplitude_m.abs() >= 0.5 * w.depth_m {
            return err(
                &f("surface_amplitude_m"),
                format!(
                    "must be smaller than half the depth, got {} m",
                    w.surface_amplitude_m
                ),
            );
        }
        if w.surface_mode == 0 {
            return err(&f("surface_mode"), "must be at least 1".into());
        }
        if w.depth_m + w.surface_amplitude_m.abs() >= flume.height_m {
            return err(
                &f("depth_m"),
                format!(
                    "water level {} m is at or above the walls (flume.height_m = {} m): water outside the flume",
                    w.depth_m, flume.height_m
                ),
            );
        }
        if !(w.x_start_m.is_finite() && w.x_end_m.is_finite()) || w.x_end_m <= w.x_start_m {
            return err(
                &f("x_end_m"),
                format!("must exceed x_start_m = {} m", w.x_start_m),
            );
        }
        if w.x_start_m < 0.0 || w.x_end_m > flume.length_m {
            return err(
                &f("x_start_m"),
                format!(
                    "region [{}, {}] m lies outside the flume [0, {}] m: water outside the flume",
                    w.x_start_m, w.x_end_m, flume.length_m
                ),
            );
        }
        if w.x_end_m - w.x_start_m < 2.0 * h {
            return err(
                &f("x_end_m"),
                format!("region is narrower than two particle spacings ({h} m)"),
            );
        }
        Ok(())
    }
}

/// At least one region, each valid in a flume with particle spacing `h`.
pub(super) fn validate_regions(
    water: &[WaterRegion],
    flume: &Flume,
    h: f64,
) -> Result<(), (String, String)> {
    if water.is_empty() {
        return err("water", "at least one [[water]] region is needed".into());
    }
    for (i, w) in water.iter().enumerate() {
        w.validate(i, flume, h)?;
    }
    Ok(())
}
