//! The flume: its solid outline, the wall nodes along it, the initial fluid lattice, and the
//! guard that keeps fluid particles inside.
//!
//! The outline runs from the top of the left wall down to the bed, along the bed (a polyline,
//! flat by default) and up the right wall. Walking along it, the fluid is on the left, so the
//! left normal n = (−dy, dx)/|d| of each segment points into the water.

pub mod bed3d;

use crate::case::{Case, Spacing};
use nalgebra::Vector2;

/// One straight piece of the solid boundary, with its unit normal into the fluid.
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    pub a: Vector2<f64>,
    pub b: Vector2<f64>,
    pub normal: Vector2<f64>,
}

/// The flume's solid boundary.
#[derive(Debug, Clone)]
pub struct Flume {
    pub length_m: f64,
    pub height_m: f64,
    /// Outline vertices: left wall top, left wall foot, bed points…, right wall foot, right wall top.
    pub outline: Vec<Vector2<f64>>,
    pub segments: Vec<Segment>,
    /// Bed polyline from x = 0 to x = length (at least two points).
    pub bed: Vec<[f64; 2]>,
    /// The paddle face at the end of the current step, when there is a wavemaker (for the guard).
    pub paddle: Option<PaddleFace>,
    /// The paddle face at the start of the current step (for the mesh: nothing behind it is water).
    pub paddle_now: Option<PaddleFace>,
}

/// The straight face of a paddle, from its foot to its top, with the velocities of both ends
/// (a rigid piston or flap: the velocity varies linearly along the face). The water is on the
/// side of `normal`; the face extends without limit up and down for the guard.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaddleFace {
    pub foot: Vector2<f64>,
    pub top: Vector2<f64>,
    pub foot_velocity: Vector2<f64>,
    pub top_velocity: Vector2<f64>,
}

impl PaddleFace {
    /// Unit normal into the water (towards +x for an upright face).
    pub fn normal(&self) -> Vector2<f64> {
        let d = (self.top - self.foot).normalize();
        Vector2::new(d.y, -d.x)
    }

    /// Signed distance of `p` from the face line, positive on the water side.
    pub fn distance(&self, p: Vector2<f64>) -> f64 {
        (p - self.foot).dot(&self.normal())
    }

    /// Velocity of the face at the height of `p`.
    pub fn velocity_at(&self, p: Vector2<f64>) -> Vector2<f64> {
        let d = self.top - self.foot;
        let s = (p - self.foot).dot(&d) / d.norm_squared();
        self.foot_velocity + s * (self.top_velocity - self.foot_velocity)
    }
}

impl Flume {
    pub fn from_case(case: &Case) -> Flume {
        let f = &case.flume;
        let bed = f.bed_points();
        let mut outline = vec![Vector2::new(0.0, f.height_m)];
        outline.extend(bed.iter().map(|p| Vector2::new(p[0], p[1])));
        outline.push(Vector2::new(f.length_m, f.height_m));
        let segments = outline
            .windows(2)
            .filter(|w| (w[1] - w[0]).norm() > 0.0)
            .map(|w| {
                let d = (w[1] - w[0]).normalize();
                Segment {
                    a: w[0],
                    b: w[1],
                    normal: Vector2::new(-d.y, d.x),
                }
            })
            .collect();
        Flume {
            length_m: f.length_m,
            height_m: f.height_m,
            outline,
            segments,
            bed,
            paddle: None,
            paddle_now: None,
        }
    }

    /// Bed height y_b(x), linear between the bed points, clamped at the ends.
    pub fn bed_y(&self, x: f64) -> f64 {
        crate::case::polyline_y(&self.bed, x)
    }

    /// Smallest distance from `p` to the solid outline.
    pub fn distance_to_solid(&self, p: Vector2<f64>) -> f64 {
        self.segments
            .iter()
            .map(|s| {
                let d = s.b - s.a;
                let t = ((p - s.a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
                (p - (s.a + t * d)).norm()
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Wall nodes along the whole outline at about the local spacing h(x), corners included
    /// once, each with the unit tangent of the segment it stands on; the tangent is zero at the
    /// ends of the outline and at corners, where two segments meet at an angle (a node there
    /// cannot slide).
    pub fn wall_nodes_with_tangents(&self, spacing: &Spacing) -> Vec<(Vector2<f64>, Vector2<f64>)> {
        let mut nodes = vec![(self.outline[0], Vector2::zeros())];
        for w in self.outline.windows(2) {
            let len = (w[1] - w[0]).norm();
            if len == 0.0 {
                continue;
            }
            let tangent = (w[1] - w[0]) / len;
            let fractions = graded_fractions(len, spacing, |s| w[0].x + s * (w[1].x - w[0].x));
            // The segment's start node is the previous segment's end: keep its tangent only if
            // both segments are in line.
            if let Some(last) = nodes.last_mut()
                && last.1 != Vector2::zeros()
                && (last.1 - tangent).norm() > 1e-9
            {
                last.1 = Vector2::zeros();
            }
            for &s in &fractions[1..] {
                nodes.push((w[0] + (w[1] - w[0]) * s, tangent));
            }
        }
        // The two ends of the outline (the wall tops) and every corner are fixed.
        let last = nodes.len() - 1;
        nodes[last].1 = Vector2::zeros();
        nodes
    }

    /// Puts a fluid particle that came closer than `margin` to the solid (or went through it)
    /// back at distance `margin` along the wall normal, and removes the velocity component into
    /// the wall. Returns true when the particle was moved.
    pub fn guard(&self, p: &mut Vector2<f64>, v: &mut Vector2<f64>, margin: f64) -> bool {
        let mut moved = false;
        // The walls are vertical and extend upward without limit for this purpose.
        let x_lo = margin;
        let x_hi = self.length_m - margin;
        if p.x < x_lo {
            p.x = x_lo;
            v.x = v.x.max(0.0);
            moved = true;
        } else if p.x > x_hi {
            p.x = x_hi;
            v.x = v.x.min(0.0);
            moved = true;
        }
        if let Some(face) = &self.paddle {
            let dist = face.distance(*p);
            if dist < margin {
                let n = face.normal();
                *p += (margin - dist) * n;
                let vn_wall = face.velocity_at(*p).dot(&n);
                let vn = v.dot(&n);
                if vn < vn_wall {
                    *v += (vn_wall - vn) * n;
                }
                moved = true;
            }
        }
        for s in &self.segments {
            let d = s.b - s.a;
            let t = (*p - s.a).dot(&d) / d.norm_squared();
            if !(0.0..=1.0).contains(&t) {
                continue;
            }
            let dist = (*p - s.a).dot(&s.normal);
            if dist < margin {
                *p += (margin - dist) * s.normal;
                let vn = v.dot(&s.normal);
                if vn < 0.0 {
                    *v -= vn * s.normal;
                }
                moved = true;
            }
        }
        moved
    }
}

/// Where along a segment of length `len` nodes stand (as fractions of it, 0 and 1 included) so
/// that their spacing follows h(x(s)): equal steps of ∫ ds / h, rounded to a whole number of
/// them. Where h is uniform along the segment, exactly k/n with n = round(len/h).
fn graded_fractions(len: f64, spacing: &Spacing, x_at: impl Fn(f64) -> f64) -> Vec<f64> {
    let (x0, x1) = (x_at(0.0), x_at(1.0));
    if x0.max(x1) <= spacing.refined_from_m() {
        let n = (len / spacing.coarsest_m()).round().max(1.0) as usize;
        return (0..=n).map(|k| k as f64 / n as f64).collect();
    }
    // ∫ ds / h sampled at a quarter of the finest spacing, then inverted.
    let samples = ((4.0 * len / spacing.finest_m()).ceil() as usize).max(1);
    let mut tau = Vec::with_capacity(samples + 1);
    tau.push(0.0);
    for k in 0..samples {
        let s_mid = (k as f64 + 0.5) / samples as f64;
        let ds = len / samples as f64;
        tau.push(tau[k] + ds / spacing.at(x_at(s_mid)));
    }
    let n = tau[samples].round().max(1.0) as usize;
    let mut fractions = Vec::with_capacity(n + 1);
    let mut k = 0;
    for j in 0..=n {
        let target = tau[samples] * j as f64 / n as f64;
        while k + 1 < samples && tau[k + 1] < target {
            k += 1;
        }
        let w = ((target - tau[k]) / (tau[k + 1] - tau[k])).clamp(0.0, 1.0);
        fractions.push(((k as f64 + w) / samples as f64).clamp(0.0, 1.0));
    }
    fractions[0] = 0.0;
    fractions[n] = 1.0;
    fractions
}

/// Fluid particles on a lattice inside the water regions: for each region the column spacing
/// follows h(x) with whole numbers of cells across its width, and each column is divided
/// evenly up to the local initial surface (flat, or a standing-wave shape) in cells of about
/// h(x); points closer than h/2 to the solid (where wall nodes stand), to the paddle or behind
/// it, or to an already seeded particle are skipped.
pub fn seed_fluid(case: &Case, flume: &Flume) -> Vec<Vector2<f64>> {
    let spacing = case.particles.spacing();
    let paddle_x = case.wavemaker.as_ref().map_or(f64::NEG_INFINITY, |w| w.x_m);
    let mut points: Vec<Vector2<f64>> = Vec::new();
    let mut grid = SpatialHash::new(spacing.coarsest_m());
    for w in &case.water {
        let width = w.x_end_m - w.x_start_m;
        let columns = graded_fractions(width, &spacing, |s| w.x_start_m + s * width);
        let nx = columns.len() - 1;
        for (i, s) in columns.into_iter().enumerate() {
            // Uniform: the lattice's abscissae as x₀ + i dx (the tests' figures are these).
            let x = if w.x_end_m <= spacing.refined_from_m() {
                w.x_start_m + i as f64 * (width / nx as f64)
            } else {
                w.x_start_m + s * width
            };
            let h = spacing.at(x);
            let ny = (w.depth_m / h).round().max(1.0) as usize;
            let dy = w.level_at(x) / ny as f64;
            for j in 0..=ny {
                let y = j as f64 * dy;
                let p = Vector2::new(x, y);
                if y < flume.bed_y(x)
                    || flume.distance_to_solid(p) < 0.5 * h
                    || x < paddle_x + 0.5 * h
                {
                    continue;
                }
                if grid.any_within(&points, p, 0.5 * h) {
                    continue;
                }
                grid.insert(points.len(), p);
                points.push(p);
            }
        }
    }
    points
}

/// A bucket grid for "is there a point within r" queries during seeding.
struct SpatialHash {
    cell: f64,
    buckets: std::collections::HashMap<(i64, i64), Vec<usize>>,
}

impl SpatialHash {
    fn new(cell: f64) -> Self {
        Self {
            cell,
            buckets: Default::default(),
        }
    }
    fn key(&self, p: Vector2<f64>) -> (i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
        )
    }
    fn insert(&mut self, i: usize, p: Vector2<f64>) {
        self.buckets.entry(self.key(p)).or_default().push(i);
    }
    fn any_within(&self, points: &[Vector2<f64>], p: Vector2<f64>, r: f64) -> bool {
        let (kx, ky) = self.key(p);
        (-1..=1).any(|dx| {
            (-1..=1).any(|dy| {
                self.buckets
                    .get(&(kx + dx, ky + dy))
                    .is_some_and(|b| b.iter().any(|&i| (points[i] - p).norm() < r))
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tank() -> Case {
        let text = "[flume]\nlength_m = 1.0\nheight_m = 0.8\n[[water]]\nx_end_m = 1.0\ndepth_m = 0.5\n[particles]\nspacing_m = 0.05\n";
        Case::from_toml_str(text, std::path::Path::new("t.toml"), "t", &[]).unwrap()
    }

    #[test]
    fn outline_normals_point_into_the_water() {
        let f = Flume::from_case(&tank());
        let inside = Vector2::new(0.5, 0.3);
        for s in &f.segments {
            assert!((inside - s.a).dot(&s.normal) > 0.0);
        }
    }

    #[test]
    fn seeding_fills_the_region_and_stays_off_the_walls() {
        let case = tank();
        let f = Flume::from_case(&case);
        let fluid = seed_fluid(&case, &f);
        // 21 × 11 lattice minus the bottom row and the two wall columns.
        assert_eq!(fluid.len(), 19 * 10);
        assert!(fluid.iter().all(|p| f.distance_to_solid(*p) >= 0.049));
        let walls = f.wall_nodes_with_tangents(&Spacing::uniform(0.05));
        assert_eq!(walls.len(), 16 + 20 + 16 + 1);
    }

    /// `[particles.refine]`: 5 cm to x = 0.4 m, 2.5 cm from x = 0.6 m, graded between.
    #[test]
    fn a_refined_stretch_is_seeded_and_walled_at_the_local_spacing() {
        let mut case = tank();
        case.particles.refine = Some(crate::case::Refinement {
            x_m: 0.6,
            spacing_m: 0.025,
            transition_m: Some(0.2),
        });
        let spacing = case.particles.spacing();
        let f = Flume::from_case(&case);
        let walls = f.wall_nodes_with_tangents(&spacing);
        let mut bed: Vec<f64> = walls
            .iter()
            .filter(|(p, _)| p.y == 0.0)
            .map(|(p, _)| p.x)
            .collect();
        bed.sort_by(f64::total_cmp);
        assert_eq!((bed[0], bed[bed.len() - 1]), (0.0, 1.0), "the corners stay");
        for w in bed.windows(2) {
            let (mid, gap) = (0.5 * (w[0] + w[1]), w[1] - w[0]);
            let h = spacing.at(mid);
            assert!(
                (gap / h - 1.0).abs() < 0.1,
                "bed gap {gap} at x = {mid}, h(x) = {h}"
            );
        }
        let fluid = seed_fluid(&case, &f);
        let nearest = |p: &Vector2<f64>| {
            fluid
                .iter()
                .filter(|q| *q != p)
                .map(|q| (q - p).norm())
                .fold(f64::INFINITY, f64::min)
        };
        for p in &fluid {
            let d = nearest(p);
            if p.x < 0.35 {
                assert!((d / 0.05 - 1.0).abs() < 0.05, "coarse: {d} at {p:?}");
            } else if p.x > 0.65 {
                assert!((d / 0.025 - 1.0).abs() < 0.05, "fine: {d} at {p:?}");
            } else {
                assert!(d > 0.02 && d < 0.055, "graded: {d} at {p:?}");
            }
        }
        // Uniform where not refined: the same nodes as without the refinement.
        let uniform = Flume::from_case(&tank()).wall_nodes_with_tangents(&Spacing::uniform(0.05));
        assert_eq!(walls[..16], uniform[..16], "the left wall is untouched");
    }

    #[test]
    fn wall_tangents_follow_the_segments_and_corners_are_fixed() {
        let f = Flume::from_case(&tank());
        let nodes = f.wall_nodes_with_tangents(&Spacing::uniform(0.05));
        for (p, t) in &nodes {
            let corner = (p.x == 0.0 || p.x == 1.0) && (p.y == 0.0 || p.y == 0.8);
            if corner {
                assert_eq!(*t, Vector2::zeros(), "{p:?}");
            } else if p.y == 0.0 {
                assert_eq!(*t, Vector2::new(1.0, 0.0), "{p:?}");
            } else {
                assert!(
                    (t.x).abs() < 1e-12 && (t.y.abs() - 1.0).abs() < 1e-12,
                    "{p:?} {t:?}"
                );
            }
        }
    }

    #[test]
    fn guard_puts_a_particle_back_and_stops_it() {
        let f = Flume::from_case(&tank());
        let mut p = Vector2::new(0.5, -0.01);
        let mut v = Vector2::new(0.1, -1.0);
        assert!(f.guard(&mut p, &mut v, 0.01));
        assert!((p.y - 0.01).abs() < 1e-12 && v.y == 0.0 && v.x == 0.1);
        let mut p = Vector2::new(-0.2, 0.001);
        let mut v = Vector2::new(-1.0, -1.0);
        f.guard(&mut p, &mut v, 0.01);
        assert!(p.x >= 0.01 - 1e-12 && p.y >= 0.01 - 1e-12, "{p:?}");
    }
}
