//! `[flume]`: the walls and the bed (a polyline or a plane beach).

use serde::{Deserialize, Serialize};

use super::{err, inside_flume, positive};

/// The flume: a floor from x = 0 to `length_m`, vertical walls at both ends up to `height_m`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Flume {
    /// Length of the floor, wall to wall, m. Required.
    pub length_m: f64,
    /// Height of the end walls above the floor, m. Required.
    pub height_m: f64,
    /// Optional bed polyline `[[x, y], …]` in metres, x increasing from 0 to `length_m`.
    /// Default empty: a flat floor at y = 0.
    #[serde(default)]
    pub bed_m: Vec<[f64; 2]>,
    /// A plane beach instead of `bed_m`: flat floor up to `toe_x_m`, then rising at `slope`.
    /// Default none.
    #[serde(default)]
    pub beach: Option<Beach>,
    /// The condition on the solid walls. Default `no_slip`.
    #[serde(default)]
    pub walls: WallCondition,
    /// Width of the tank across the flume (z), m: a case with a width runs on the 3D path
    /// (`solver3d`), between two side walls at z = 0 and z = width. Default none: the 2D flume.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width_m: Option<f64>,
    /// Bars (or troughs) on the bed of a 3D tank, added to the bed's height where they lie
    /// (`[[flume.bars]]`). Default none. A 2D case refuses them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bars: Vec<Bar>,
}

/// A bar on the bed of a 3D tank: a raised (or, with a negative height, sunken) block whose
/// height above the bed is `height_m` times a trapezoid along x times a trapezoid across z, each
/// given by four abscissae: where it leaves the bed, reaches its crest, leaves the crest and is
/// back on the bed. Abscissae beyond the tank are allowed (a bar against a side wall has its
/// crest through the wall).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Bar {
    /// Along the flume: foot, crest start, crest end, foot, m. Required.
    pub x_m: [f64; 4],
    /// Across the tank: the same four, m. Required.
    pub z_m: [f64; 4],
    /// Height of the crest above the bed, m (negative: a trough). Required.
    pub height_m: f64,
}

/// The steepest flank a bar may have (rise over run), as for `flume.beach.slope`.
pub const BAR_MAX_SLOPE: f64 = 2.0;

impl Bar {
    /// The bar's height above the bed at (`x_m`, `z_m`), m.
    pub fn height_at(&self, x_m: f64, z_m: f64) -> f64 {
        self.height_m * trapezoid(&self.x_m, x_m) * trapezoid(&self.z_m, z_m)
    }

    /// The bar's slope (∂/∂x, ∂/∂z) at (`x_m`, `z_m`) on the side `side` (+1: from larger x
    /// and z, −1: from smaller), the one-sided derivatives where a flank meets the crest or
    /// the bed.
    pub fn slope_at(&self, x_m: f64, z_m: f64, side: [f64; 2]) -> [f64; 2] {
        let (tx, tz) = (trapezoid(&self.x_m, x_m), trapezoid(&self.z_m, z_m));
        [
            self.height_m * polyline_slope(&trapezoid_points(&self.x_m), x_m, side[0]) * tz,
            self.height_m * tx * polyline_slope(&trapezoid_points(&self.z_m), z_m, side[1]),
        ]
    }

    fn validate(&self, k: usize, length_m: f64) -> Result<(), (String, String)> {
        let field = |name: &str| format!("flume.bars[{k}].{name}");
        if !self.height_m.is_finite() || self.height_m == 0.0 {
            return err(
                &field("height_m"),
                format!("must be finite and not 0, got {}", self.height_m),
            );
        }
        for (name, a) in [("x_m", &self.x_m), ("z_m", &self.z_m)] {
            if a.iter().any(|v| !v.is_finite()) || !(a[0] < a[1] && a[1] <= a[2] && a[2] < a[3]) {
                return err(
                    &field(name),
                    format!("must be foot < crest start <= crest end < foot, got {a:?}"),
                );
            }
            let steepest = self.height_m.abs() / (a[1] - a[0]).min(a[3] - a[2]);
            if steepest > BAR_MAX_SLOPE {
                return err(
                    &field(name),
                    format!(
                        "its flanks rise {steepest:.2} m per m, steeper than {BAR_MAX_SLOPE}: \
                         widen them"
                    ),
                );
            }
        }
        if self.x_m[3] <= 0.0 || self.x_m[0] >= length_m {
            return err(
                &field("x_m"),
                format!("the bar lies outside the flume (0 to {length_m} m)"),
            );
        }
        Ok(())
    }
}

/// The trapezoid 0–1–1–0 over the four abscissae `a`, 0 beyond them.
fn trapezoid(a: &[f64; 4], t: f64) -> f64 {
    polyline_y(&trapezoid_points(a), t)
}

fn trapezoid_points(a: &[f64; 4]) -> [[f64; 2]; 4] {
    [[a[0], 0.0], [a[1], 1.0], [a[2], 1.0], [a[3], 0.0]]
}

/// A plane beach: the floor is flat (y = 0) up to the toe, then rises at `slope` (tan β) until
/// 90 % of the wall height, and is flat again up to the end wall.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Beach {
    /// x of the toe, m. Required.
    pub toe_x_m: f64,
    /// tan β, rise over run. Required.
    pub slope: f64,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum WallCondition {
    /// u = 0 at wall nodes.
    #[default]
    NoSlip,
    /// Only the velocity across the wall is zero: the water slides along it (corners stay fixed).
    Slip,
}

impl Flume {
    /// The bed polyline `[x, y]` from x = 0 to the end: `bed_m`, the beach, or a flat floor.
    pub fn bed_points(&self) -> Vec<[f64; 2]> {
        if let Some(b) = &self.beach {
            let top = 0.9 * self.height_m;
            let rise = b.slope * (self.length_m - b.toe_x_m);
            let mut bed = vec![[0.0, 0.0], [b.toe_x_m, 0.0]];
            if rise <= top {
                bed.push([self.length_m, rise]);
            } else {
                bed.push([b.toe_x_m + top / b.slope, top]);
                bed.push([self.length_m, top]);
            }
            bed
        } else if self.bed_m.is_empty() {
            vec![[0.0, 0.0], [self.length_m, 0.0]]
        } else {
            self.bed_m.clone()
        }
    }

    /// Bed height under `x_m`, linear between the bed points (0 for a flat floor).
    pub fn bed_y_at(&self, x_m: f64) -> f64 {
        polyline_y(&self.bed_points(), x_m)
    }

    /// The walls positive; a beach inside the flume and not beside `bed_m`; a bed polyline
    /// spanning the flume with x increasing and heights below the walls.
    pub(super) fn validate(&self) -> Result<(), (String, String)> {
        positive("flume.length_m", self.length_m)?;
        positive("flume.height_m", self.height_m)?;
        if let Some(w) = self.width_m {
            positive("flume.width_m", w)?;
        }
        if !self.bars.is_empty() && self.width_m.is_none() {
            return err(
                "flume.bars",
                "bars vary across the tank: they need a 3D case (flume.width_m)".into(),
            );
        }
        for (k, bar) in self.bars.iter().enumerate() {
            bar.validate(k, self.length_m)?;
        }
        if let Some(b) = &self.beach {
            if !self.bed_m.is_empty() {
                return err(
                    "flume.beach",
                    "give either flume.bed_m or flume.beach, not both".into(),
                );
            }
            inside_flume("flume.beach.toe_x_m", b.toe_x_m, self.length_m)?;
            if !(b.slope.is_finite() && b.slope > 0.0 && b.slope <= 2.0) {
                return err(
                    "flume.beach.slope",
                    format!("must lie in (0, 2] (tan β), got {}", b.slope),
                );
            }
        }
        let bed = &self.bed_m;
        if !bed.is_empty() {
            if bed.len() < 2 {
                return err("flume.bed_m", "needs at least two points".into());
            }
            if bed.iter().flatten().any(|v| !v.is_finite()) {
                return err("flume.bed_m", "has a non-finite coordinate".into());
            }
            if bed[0][0] != 0.0 || bed[bed.len() - 1][0] != self.length_m {
                return err(
                    "flume.bed_m",
                    format!(
                        "must run from x = 0 to x = flume.length_m = {}",
                        self.length_m
                    ),
                );
            }
            if bed.windows(2).any(|w| w[1][0] <= w[0][0]) {
                return err(
                    "flume.bed_m",
                    "x must increase strictly along the bed".into(),
                );
            }
            if bed.iter().any(|p| p[1] < 0.0 || p[1] >= self.height_m) {
                return err(
                    "flume.bed_m",
                    "bed heights must lie in [0, flume.height_m)".into(),
                );
            }
        }
        Ok(())
    }
}

/// y of a polyline `[x, y]` (x increasing, at least one point) at `x_m`, linear between the
/// points and constant beyond the ends: the bed height, here and in `geometry`.
pub fn polyline_y(points: &[[f64; 2]], x_m: f64) -> f64 {
    if x_m <= points[0][0] {
        return points[0][1];
    }
    for w in points.windows(2) {
        if x_m <= w[1][0] {
            let s = (x_m - w[0][0]) / (w[1][0] - w[0][0]);
            return w[0][1] + s * (w[1][1] - w[0][1]);
        }
    }
    points[points.len() - 1][1]
}

/// The slope of a polyline `[x, y]` (x increasing) at `x_m`, taken from the side `side` (+1:
/// the piece after `x_m`, −1: the piece before), 0 beyond the ends.
pub fn polyline_slope(points: &[[f64; 2]], x_m: f64, side: f64) -> f64 {
    for w in points.windows(2) {
        let inside = if side > 0.0 {
            x_m >= w[0][0] && x_m < w[1][0]
        } else {
            x_m > w[0][0] && x_m <= w[1][0]
        };
        if inside {
            return (w[1][1] - w[0][1]) / (w[1][0] - w[0][0]);
        }
    }
    0.0
}
