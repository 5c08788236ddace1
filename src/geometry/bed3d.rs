//! The bed of a 3D tank (issue 26): the 2D case's bed profile (`flume.bed_m` or
//! `flume.beach`) extruded across the width, plus the case's bars, as a height field
//! y = b(x, z). The profile is piecewise linear in x and each bar is its height times a
//! trapezoid in x times one in z, so b is bilinear on each cell of the grid of their break
//! lines: its slope is constant along the grid's lines and jumps across some of them, where the
//! bed has a crease (the toe of a beach, the edges of a bar's crest).

use crate::case::{Bar, Flume, polyline_slope, polyline_y};
use nalgebra::Vector3;

/// The bed of a 3D tank as a height field.
#[derive(Debug, Clone, PartialEq)]
pub struct Bed3 {
    /// The profile `[x, y]` along the flume, m (as `case::Flume::bed_points`).
    pub profile: Vec<[f64; 2]>,
    /// The bars added to it.
    pub bars: Vec<Bar>,
}

/// Slopes that differ by less than this (m per m) are one slope: a node there is not on a
/// crease.
const SAME_SLOPE: f64 = 1e-9;

/// A node this close to a crease (m) is on it: the slopes are compared this far to each side,
/// so a lattice that meets a crease up to round-off finds it.
const ON_A_CREASE_M: f64 = 1e-9;

impl Bed3 {
    /// The bed of the case's flume.
    pub fn from_flume(f: &Flume) -> Self {
        Bed3 {
            profile: f.bed_points(),
            bars: f.bars.clone(),
        }
    }

    /// A flat bed at y = 0 from x = 0 to `length_m`.
    pub fn flat(length_m: f64) -> Self {
        Bed3 {
            profile: vec![[0.0, 0.0], [length_m, 0.0]],
            bars: Vec::new(),
        }
    }

    /// Is the bed the plane y = 0?
    pub fn is_flat(&self) -> bool {
        self.bars.is_empty() && self.profile.iter().all(|p| p[1] == 0.0)
    }

    /// The bed's height at (`x_m`, `z_m`), m.
    pub fn height(&self, x_m: f64, z_m: f64) -> f64 {
        polyline_y(&self.profile, x_m)
            + self.bars.iter().map(|b| b.height_at(x_m, z_m)).sum::<f64>()
    }

    /// The slope (∂b/∂x, ∂b/∂z) at (`x_m`, `z_m`) from the side `side` (see
    /// [`Bar::slope_at`]).
    pub fn slope(&self, x_m: f64, z_m: f64, side: [f64; 2]) -> [f64; 2] {
        let mut s = [polyline_slope(&self.profile, x_m, side[0]), 0.0];
        for b in &self.bars {
            let d = b.slope_at(x_m, z_m, side);
            s[0] += d[0];
            s[1] += d[1];
        }
        s
    }

    /// The unit normal into the water at (`x_m`, `z_m`), or `None` on a crease (the slopes
    /// from the four sides differ): a wall node there has no plane to slide along, and is held
    /// as the 2D flume's corner nodes are.
    pub fn normal(&self, x_m: f64, z_m: f64) -> Option<Vector3<f64>> {
        let e = ON_A_CREASE_M;
        let s = self.slope(x_m + e, z_m + e, [1.0, 1.0]);
        for side in [[-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]] {
            let t = self.slope(x_m + side[0] * e, z_m + side[1] * e, side);
            if (t[0] - s[0]).abs() > SAME_SLOPE || (t[1] - s[1]).abs() > SAME_SLOPE {
                return None;
            }
        }
        Some(Vector3::new(-s[0], 1.0, -s[1]).normalize())
    }

    /// How far `x` lies above the bed, measured along the normal of the bed's plane under it
    /// (the vertical height over √(1 + |∇b|²)), m; negative below the bed.
    pub fn distance(&self, x: &[f64; 3]) -> f64 {
        let s = self.slope(x[0], x[2], [1.0, 1.0]);
        (x[1] - self.height(x[0], x[2])) / (1.0 + s[0] * s[0] + s[1] * s[1]).sqrt()
    }

    /// Puts a point less than `margin_m` above the bed (along the normal, see
    /// [`Self::distance`]) back to `margin_m` above it, straight up, and removes the part of its
    /// velocity `u` into the bed. Returns whether it was moved.
    pub fn guard(&self, x: &mut [f64; 3], u: &mut Vector3<f64>, margin_m: f64) -> bool {
        let s = self.slope(x[0], x[2], [1.0, 1.0]);
        let stretch = (1.0 + s[0] * s[0] + s[1] * s[1]).sqrt();
        let b = self.height(x[0], x[2]);
        if (x[1] - b) / stretch >= margin_m {
            return false;
        }
        x[1] = b + margin_m * stretch;
        let n = Vector3::new(-s[0], 1.0, -s[1]) / stretch;
        let into = u.dot(&n);
        if into < 0.0 {
            *u -= into * n;
        }
        true
    }

    /// The abscissae along x where the bed's slope may change (the profile's points and the
    /// bars' x), sorted, within (`lo`, `hi`).
    pub fn x_breaks(&self, lo: f64, hi: f64) -> Vec<f64> {
        let all = self
            .profile
            .iter()
            .map(|p| p[0])
            .chain(self.bars.iter().flat_map(|b| b.x_m));
        sorted_within(all, lo, hi)
    }

    /// The bars' abscissae across the tank within (`lo`, `hi`), sorted.
    pub fn z_breaks(&self, lo: f64, hi: f64) -> Vec<f64> {
        sorted_within(self.bars.iter().flat_map(|b| b.z_m), lo, hi)
    }
}

fn sorted_within(values: impl Iterator<Item = f64>, lo: f64, hi: f64) -> Vec<f64> {
    let mut v: Vec<f64> = values.filter(|&t| t > lo && t < hi).collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

/// Points from `lo` to `hi` (both included) through every break in `breaks` (sorted, inside),
/// each piece between breaks cut into equal steps no longer than `step_of(a, b)` (the spacing
/// wanted on that piece, m), at least one.
pub fn lattice_through(
    lo: f64,
    hi: f64,
    breaks: &[f64],
    step_of: impl Fn(f64, f64) -> f64,
) -> Vec<f64> {
    let mut ends = vec![lo];
    ends.extend_from_slice(breaks);
    ends.push(hi);
    let mut out = vec![lo];
    for w in ends.windows(2) {
        let (a, b) = (w[0], w[1]);
        let n = ((b - a) / step_of(a, b)).round().max(1.0) as usize;
        let d = (b - a) / n as f64;
        out.extend((1..=n).map(|i| a + i as f64 * d));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn barred() -> Bed3 {
        Bed3 {
            profile: vec![[0.0, 0.0], [2.0, 0.0], [6.0, 0.4]],
            bars: vec![Bar {
                x_m: [3.0, 3.5, 4.0, 4.5],
                z_m: [-1.0, -0.5, 1.0, 1.5],
                height_m: 0.1,
            }],
        }
    }

    #[test]
    fn the_bed_is_the_profile_plus_its_bars_with_creases_at_their_edges() {
        let bed = barred();
        // Flat, on the slope beside the bar, on the bar's crest, in its z flank.
        assert_eq!(bed.height(1.0, 0.5), 0.0);
        assert!((bed.height(3.75, 2.0) - 0.175).abs() < 1e-15);
        assert!((bed.height(3.75, 0.5) - 0.275).abs() < 1e-15);
        assert!((bed.height(3.75, 1.25) - 0.225).abs() < 1e-15);
        // The slope's normal off the creases; none on the toe, on the crest's edges or where a
        // flank meets the bed, but the bar's x edges are no crease where the bar is not.
        let n = bed.normal(5.0, 0.5).unwrap();
        assert!((n - Vector3::new(-0.1, 1.0, 0.0).normalize()).norm() < 1e-15);
        let n = bed.normal(3.75, 1.25).unwrap();
        assert!((n - Vector3::new(-0.1, 1.0, 0.2).normalize()).norm() < 1e-15);
        for (x, z) in [(2.0, 0.5), (3.5, 0.5), (4.0, 0.2), (3.75, 1.0), (3.75, 1.5)] {
            assert_eq!(bed.normal(x, z), None, "({x}, {z})");
        }
        assert!(bed.normal(3.5, 2.0).is_some());
        // Distance along the normal on the slope; the guard puts a point back above the bed
        // and keeps only the velocity along it.
        let d = bed.distance(&[5.0, 0.4, 2.0]);
        assert!((d - 0.1 / 1.01f64.sqrt()).abs() < 1e-15);
        let (mut x, mut u) = ([5.0, 0.29, 2.0], Vector3::new(0.0, -1.0, 0.0));
        assert!(bed.guard(&mut x, &mut u, 0.01));
        assert!((bed.distance(&x) - 0.01).abs() < 1e-15);
        assert!(u.dot(&bed.normal(5.0, 2.0).unwrap()).abs() < 1e-15);
        assert!(!bed.guard(&mut [5.0, 0.4, 2.0], &mut u, 0.01));
    }

    #[test]
    fn a_lattice_passes_through_the_breaks() {
        let l = lattice_through(0.0, 1.0, &[0.3], |_, _| 0.1);
        assert_eq!(l.len(), 11);
        assert!((l[3] - 0.3).abs() < 1e-15 && l[0] == 0.0 && (l[10] - 1.0).abs() < 1e-15);
        // Without breaks, the uniform lattice of the flat tank.
        let l = lattice_through(0.3, 4.5, &[], |_, _| 0.025);
        assert_eq!(l.len(), 169);
        assert_eq!(l[5], 0.3 + 5.0 * (4.2 / 168.0));
    }
}
