//! Perceptual colour mapping of scalar fields to sRGB.
//!
//! Rerun cannot colour-map `Points2D` itself, so particle colours are computed
//! here. The map is viridis (the matplotlib default by van der Walt, Smith and
//! Firing, released as CC0): it runs from dark purple through blue and green
//! to yellow, its lightness rises steadily, and it stays readable for the most
//! common forms of colour blindness and in greyscale print.

/// Viridis sampled at 33 evenly spaced points of `t` in [0, 1] (sRGB, 8 bit).
///
/// The knots were taken from the published 256-entry table. Piecewise-linear
/// interpolation between them stays within 2 units (out of 255) of the full
/// table for every `t`.
const VIRIDIS_KNOTS: [[u8; 3]; 33] = [
    [68, 1, 84],
    [71, 13, 96],
    [72, 24, 106],
    [72, 35, 116],
    [71, 45, 123],
    [69, 54, 129],
    [66, 64, 134],
    [63, 73, 137],
    [59, 82, 139],
    [55, 90, 141],
    [51, 99, 141],
    [47, 106, 142],
    [44, 114, 142],
    [41, 122, 142],
    [38, 129, 142],
    [35, 137, 142],
    [33, 144, 140],
    [31, 152, 139],
    [31, 159, 136],
    [33, 166, 133],
    [40, 174, 128],
    [49, 181, 123],
    [62, 188, 116],
    [76, 194, 108],
    [93, 201, 99],
    [110, 206, 88],
    [130, 211, 76],
    [150, 216, 63],
    [171, 220, 50],
    [192, 223, 36],
    [213, 226, 26],
    [234, 229, 26],
    [253, 231, 37],
];

/// Colour given to NaN inputs: a neutral mid grey that viridis never produces.
pub const NAN_COLOR: [u8; 3] = [128, 128, 128];

/// Viridis colour for `t` in [0, 1].
///
/// Values outside the interval are clamped to its ends (so +inf is yellow and
/// -inf dark purple); NaN gives [`NAN_COLOR`].
pub fn viridis(t: f64) -> [u8; 3] {
    if t.is_nan() {
        return NAN_COLOR;
    }
    let last = VIRIDIS_KNOTS.len() - 1;
    let x = t.clamp(0.0, 1.0) * last as f64;
    // `x` lies in [0, last]; the segment index is capped so that t = 1 uses
    // the final segment with weight 1 instead of reading past the table.
    let i = (x.floor() as usize).min(last - 1);
    let w = x - i as f64;
    let lo = VIRIDIS_KNOTS[i];
    let hi = VIRIDIS_KNOTS[i + 1];
    let mut out = [0u8; 3];
    for c in 0..3 {
        let v = f64::from(lo[c]) + w * (f64::from(hi[c]) - f64::from(lo[c]));
        out[c] = v.round().clamp(0.0, 255.0) as u8;
    }
    out
}

/// A linear mapping of a physical quantity onto the viridis colormap.
///
/// `min` is drawn dark purple and `max` yellow; values beyond the range take
/// the colour of the nearer end. If `min > max` the map is reversed. A
/// degenerate range (`min == max`, or a non-finite end) paints every finite
/// value with the middle colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorScale {
    /// Value drawn with the first colour (dark purple).
    pub min: f64,
    /// Value drawn with the last colour (yellow).
    pub max: f64,
}

impl ColorScale {
    /// Scale from `min` to `max`.
    pub fn new(min: f64, max: f64) -> Self {
        Self { min, max }
    }

    /// Scale from `-half_range` to `+half_range`, handy for signed velocities.
    pub fn symmetric(half_range: f64) -> Self {
        let h = half_range.abs();
        Self { min: -h, max: h }
    }

    /// Position of `v` along the scale: 0 at `min`, 1 at `max`, unclamped.
    /// NaN for NaN input; 0.5 when the range is degenerate.
    pub fn normalize(&self, v: f64) -> f64 {
        if v.is_nan() {
            return f64::NAN;
        }
        let span = self.max - self.min;
        if !span.is_finite() || span == 0.0 {
            return 0.5;
        }
        (v - self.min) / span
    }

    /// sRGB colour for the value `v`.
    pub fn color(&self, v: f64) -> [u8; 3] {
        viridis(self.normalize(v))
    }

    /// One-line human-readable statement of the mapping, e.g.
    /// `u1 [m/s]: viridis, -1.50 (dark purple) to 1.50 (yellow)`.
    pub fn describe(&self, quantity: &str, unit: &str) -> String {
        format!(
            "{quantity} [{unit}]: viridis, {} (dark purple) to {} (yellow); \
             values outside the range take the end colours, NaN is grey",
            format_value(self.min),
            format_value(self.max)
        )
    }
}

/// Two decimals for ordinary magnitudes, scientific notation for very small or
/// very large ones so that the stated range never reads as "0.00 to 0.00".
fn format_value(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (0.01..1.0e5).contains(&a) {
        format!("{v:.2}")
    } else {
        format!("{v:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative luminance (Rec. 709 weights) of an sRGB colour.
    fn luminance(c: [u8; 3]) -> f64 {
        let lin = |u: u8| {
            let s = f64::from(u) / 255.0;
            if s <= 0.04045 {
                s / 12.92
            } else {
                ((s + 0.055) / 1.055).powf(2.4)
            }
        };
        0.2126 * lin(c[0]) + 0.7152 * lin(c[1]) + 0.0722 * lin(c[2])
    }

    #[test]
    fn endpoints_match_the_published_table() {
        assert_eq!(viridis(0.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [253, 231, 37]);
        // The middle of viridis is a teal around (33, 145, 140).
        let mid = viridis(0.5);
        assert!((i32::from(mid[0]) - 33).abs() <= 2, "{mid:?}");
        assert!((i32::from(mid[1]) - 145).abs() <= 2, "{mid:?}");
        assert!((i32::from(mid[2]) - 140).abs() <= 2, "{mid:?}");
    }

    #[test]
    fn luminance_increases_monotonically() {
        let n = 1000;
        let mut prev = luminance(viridis(0.0));
        for k in 1..=n {
            let t = f64::from(k) / f64::from(n);
            let y = luminance(viridis(t));
            // Rounding to u8 can make neighbouring samples equal, never darker
            // by more than a rounding step.
            assert!(
                y >= prev - 1e-3,
                "luminance drops at t = {t}: {prev} -> {y}"
            );
            prev = prev.max(y);
        }
        // Strict increase at the knot spacing.
        for k in 0..VIRIDIS_KNOTS.len() - 1 {
            assert!(
                luminance(VIRIDIS_KNOTS[k + 1]) > luminance(VIRIDIS_KNOTS[k]),
                "knot {k}"
            );
        }
        assert!(luminance(viridis(1.0)) > 10.0 * luminance(viridis(0.0)));
    }

    #[test]
    fn out_of_range_values_clamp() {
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.5), viridis(1.0));
        assert_eq!(viridis(f64::INFINITY), viridis(1.0));
        assert_eq!(viridis(f64::NEG_INFINITY), viridis(0.0));
        let s = ColorScale::new(-1.5, 1.5);
        assert_eq!(s.color(-100.0), viridis(0.0));
        assert_eq!(s.color(100.0), viridis(1.0));
        assert_eq!(s.color(-1.5), viridis(0.0));
        assert_eq!(s.color(1.5), viridis(1.0));
        assert_eq!(s.color(0.0), viridis(0.5));
    }

    #[test]
    fn nan_is_grey() {
        assert_eq!(viridis(f64::NAN), NAN_COLOR);
        assert_eq!(ColorScale::new(0.0, 1.0).color(f64::NAN), NAN_COLOR);
        assert_eq!(ColorScale::new(0.0, 0.0).color(f64::NAN), NAN_COLOR);
    }

    #[test]
    fn reversed_and_degenerate_ranges() {
        let r = ColorScale::new(2.0, -2.0);
        assert_eq!(r.color(2.0), viridis(0.0));
        assert_eq!(r.color(-2.0), viridis(1.0));
        let d = ColorScale::new(1.0, 1.0);
        assert_eq!(d.color(-5.0), viridis(0.5));
        assert_eq!(d.color(5.0), viridis(0.5));
        let inf = ColorScale::new(0.0, f64::INFINITY);
        assert_eq!(inf.color(3.0), viridis(0.5));
        assert_eq!(ColorScale::symmetric(-2.0), ColorScale::new(-2.0, 2.0));
    }

    #[test]
    fn description_states_the_range() {
        let s = ColorScale::new(-1.5, 1.5);
        let d = s.describe("u1", "m/s");
        assert!(
            d.starts_with("u1 [m/s]: viridis, -1.50 (dark purple) to 1.50 (yellow)"),
            "{d}"
        );
        let tiny = ColorScale::new(0.0, 0.002).describe("p", "Pa");
        assert!(
            tiny.contains("0.00 (dark purple) to 2.000e-3 (yellow)"),
            "{tiny}"
        );
    }
}
