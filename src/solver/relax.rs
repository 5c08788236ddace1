//! Stage `relax` (optional, `solver.volume_relaxation_s` = T_r > 0): the water area that the
//! numerics lose (or make) is given back where it was lost, through the continuity equation.
//!
//! The flume is cut into vertical strips `STRIP_H`·h wide. A ledger holds, per strip, the
//! area the numerics have changed there since t = 0, E_b:
//! - remeshing: the new mesh's area in the strip minus the last mesh's at the same positions
//!   (after the node stage), both cut exactly at the strip lines, so that two triangulations
//!   of the same water give the same strip areas and only what the α-shape (and node
//!   insertion, removal and merging) adds or drops is counted;
//! - motion: each triangle's area after the move minus before, charged to the strip of its
//!   centroid (the flow is incompressible, so every such change is an error; whole triangles
//!   crossing a strip line are water moving, and are not charged).
//!
//! The nodes deep in the water of strip b (fluid nodes of the kept mesh off its boundary and
//! with no wall neighbour) are then asked for the uniform divergence
//!
//! ∇·u = −E_b / (A_b T_r),  capped at ±`MAX_RATE`/T_r,
//!
//! A_b their lumped area, which pays E_b back over about T_r; the payment is itself a motion
//! change, so the ledger closes. Going from the shore out, a strip with less than
//! `MIN_DEEP_H2`·h² of deep water (the swash, a thin jet) hands its balance to the next strip
//! offshore for that step, and one whose balance is more than the cap hands on the excess, so
//! the swash's debt is paid by the first strips offshore of it that have the water to pay.
//!
//! Why: at broken crests the α-shape drops triangles whose particles stay, and the surface
//! layer shrinks as it moves; the solver then keeps the smaller area and the water is gone for
//! good (README, *Surf zone*). Ting & Kirby's spilling flume lost 13 % by 34 s, most of it in
//! the surf zone. A global version (one balance for the flume, paid by all deep nodes, like
//! Kratos' correction `volume.rs` but through continuity) held the volume to 0.3 % but put
//! the surf zone's water back offshore, which drove a mean onshore flow of the size of the
//! waves' own mass flux and reversed the undertow. A per-particle version (each particle
//! carrying its area, its deep neighbourhood asked to keep it) lost more than no correction:
//! the areas of particles that move into the surface layer are not seen there.

use super::Solver;
use crate::mesh::Mesh;
use crate::particles::Particles;
use nalgebra::Vector2;

/// Strip width in units of h.
const STRIP_H: f64 = 20.0;
/// Largest |E_b| / A_b the divergence acts on.
const MAX_RATE: f64 = 0.25;
/// Least deep area a strip needs to pay its own balance, in units of h².
const MIN_DEEP_H2: f64 = 10.0;

/// The per-strip area balance (see the module comment).
#[derive(Debug, Clone, Default)]
pub(crate) struct AreaLedger {
    strip_m: f64,
    /// E_b, m².
    pub error_m2: Vec<f64>,
    /// The strip areas of the last mesh after its move (of the initial mesh before the first
    /// step; `None` until then).
    moved: Option<Vec<f64>>,
    /// The triangle areas before the move (taken after the α-shape; the nodes do not move
    /// in between).
    before_move: Vec<f64>,
}

/// Area of the part of a triangle with x < c.
fn area_left_of(p: [Vector2<f64>; 3], c: f64) -> f64 {
    // Clip the triangle by the half-plane x < c (Sutherland–Hodgman) and take the area.
    let mut poly: [Vector2<f64>; 4] = [Vector2::zeros(); 4];
    let mut n = 0;
    for k in 0..3 {
        let (a, b) = (p[k], p[(k + 1) % 3]);
        let (ina, inb) = (a.x < c, b.x < c);
        if ina {
            poly[n] = a;
            n += 1;
        }
        if ina != inb {
            let f = (c - a.x) / (b.x - a.x);
            poly[n] = a + f * (b - a);
            n += 1;
        }
    }
    let mut twice = 0.0;
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        twice += a.x * b.y - b.x * a.y;
    }
    0.5 * twice
}

fn strip_of(x: f64, strip_m: f64) -> usize {
    (x / strip_m).floor().max(0.0) as usize
}

/// The mesh's area in each strip, triangles cut exactly at the strip lines.
pub(crate) fn strip_areas(mesh: &Mesh, position: &[Vector2<f64>], strip_m: f64) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for t in &mesh.triangles {
        let p = t.map(|i| position[i as usize]);
        let lo = p.iter().map(|v| v.x).fold(f64::INFINITY, f64::min);
        let hi = p.iter().map(|v| v.x).fold(f64::NEG_INFINITY, f64::max);
        let (first, last) = (strip_of(lo, strip_m), strip_of(hi, strip_m));
        if out.len() <= last {
            out.resize(last + 1, 0.0);
        }
        let total = crate::fem::triangle_area(position, t);
        if first == last {
            out[first] += total;
            continue;
        }
        let mut left = 0.0;
        for (b, slot) in out.iter_mut().enumerate().take(last).skip(first) {
            let upto = area_left_of(p, (b + 1) as f64 * strip_m);
            *slot += upto - left;
            left = upto;
        }
        out[last] += total - left;
    }
    out
}

/// The divergence, 1/s, asked of the deep water of each strip, given the strips' balances
/// and deep areas (m²). From the shore out, a strip pays what its deep water can (at most
/// `MAX_RATE` of its area per T_r) and passes the rest on; one with less than `min_deep_m2`
/// of deep water passes it all. What is left past the last strip is paid later. (In 3D the
/// same per band of cells, with volumes: `solver3d/relax.rs`.)
pub(crate) fn strip_rates(
    error_m2: &[f64],
    deep_m2: &[f64],
    min_deep_m2: f64,
    t_r: f64,
) -> Vec<f64> {
    let mut rate = vec![0.0; error_m2.len()];
    let mut carry = 0.0;
    for b in (0..error_m2.len()).rev() {
        carry += error_m2[b];
        if deep_m2[b] >= min_deep_m2 {
            let most = MAX_RATE * deep_m2[b];
            let paid = carry.clamp(-most, most);
            rate[b] = -paid / (deep_m2[b] * t_r);
            carry -= paid;
        }
    }
    rate
}

/// Adds `v` to `into[b]`, growing `into` with zeros as needed.
pub(crate) fn add_into(into: &mut Vec<f64>, b: usize, v: f64) {
    if into.len() <= b {
        into.resize(b + 1, 0.0);
    }
    into[b] += v;
}

impl Solver {
    /// The ledger's balance per strip (strip b spans [b, b + 1)·`strip_m`), m²; empty unless
    /// `volume_relaxation_s` > 0. Its sum is the mesh area minus the initial one.
    pub fn area_ledger_m2(&self) -> &[f64] {
        &self.ledger.error_m2
    }

    /// The width of the ledger's strips, m (0 until the first step).
    pub fn area_ledger_strip_m(&self) -> f64 {
        self.ledger.strip_m
    }

    /// The ledger's balance over the strips whose centre lies at or right of `x_m`, m²: what
    /// the numerics changed of the water area there since t = 0, net of what the relaxation
    /// paid back. 0 unless `volume_relaxation_s` > 0, and before the first step.
    pub fn area_ledger_right_of_m2(&self, x_m: f64) -> f64 {
        let strip_m = self.ledger.strip_m;
        if strip_m > 0.0 {
            self.ledger
                .error_m2
                .iter()
                .enumerate()
                .filter(|(b, _)| (*b as f64 + 0.5) * strip_m >= x_m)
                .map(|(_, e)| e)
                .sum()
        } else {
            0.0
        }
    }

    /// The kept mesh's area right of the vertical line x = `x_m`, with the nodes at
    /// `position`: every triangle's area less its part left of the line, m².
    pub fn mesh_area_right_of_m2(&self, position: &[Vector2<f64>], x_m: f64) -> f64 {
        self.mesh
            .triangles
            .iter()
            .map(|t| {
                let q = t.map(|i| position[i as usize]);
                crate::fem::triangle_area(position, t) - area_left_of(q, x_m)
            })
            .sum()
    }

    /// Before the first step's node stage: the strip areas of the initial mesh.
    pub(super) fn relax_start(&mut self, particles: &Particles) {
        if self.params.settings.volume_relaxation_s.is_none() || self.ledger.moved.is_some() {
            return;
        }
        self.ledger.strip_m = STRIP_H * self.params.spacing_m;
        self.ledger.moved = Some(strip_areas(
            &self.mesh,
            &particles.position,
            self.ledger.strip_m,
        ));
    }

    /// After the α-shape: books the remeshing change and fills `divergence_target`.
    pub(super) fn relax_targets(&mut self, particles: &Particles) {
        let n = particles.len();
        self.divergence_target.clear();
        self.divergence_target.resize(n, 0.0);
        let Some(t_r) = self.params.settings.volume_relaxation_s else {
            return;
        };
        let h = self.params.spacing_m;
        let ledger = &mut self.ledger;
        let strip_m = ledger.strip_m;
        let mesh = &self.mesh;
        let x = &particles.position;
        let now = strip_areas(mesh, x, strip_m);
        if let Some(moved) = &ledger.moved {
            for (b, a) in now.iter().enumerate() {
                add_into(&mut ledger.error_m2, b, *a);
            }
            for (b, a) in moved.iter().enumerate() {
                add_into(&mut ledger.error_m2, b, -*a);
            }
        }

        let mut deep: Vec<bool> = (0..n)
            .map(|i| particles.is_fluid(i) && mesh.in_mesh[i])
            .collect();
        for &[a, b] in &mesh.boundary_edges {
            deep[a as usize] = false;
            deep[b as usize] = false;
        }
        let mut share = vec![0.0; n];
        // The positions stay as they are until the move: these are also the areas the move's
        // change is measured from.
        ledger.before_move.clear();
        for t in &mesh.triangles {
            let area = crate::fem::triangle_area(x, t);
            ledger.before_move.push(area);
            let walled = t.iter().any(|&i| !particles.is_fluid(i as usize));
            for &i in t {
                share[i as usize] += area / 3.0;
                if walled {
                    deep[i as usize] = false;
                }
            }
        }
        let strips = ledger.error_m2.len();
        let mut deep_m2 = vec![0.0; strips];
        for i in (0..n).filter(|&i| deep[i]) {
            let b = strip_of(x[i].x, strip_m);
            if b < strips {
                deep_m2[b] += share[i];
            }
        }
        let rate = strip_rates(&ledger.error_m2, &deep_m2, MIN_DEEP_H2 * h * h, t_r);
        for i in (0..n).filter(|&i| deep[i]) {
            let b = strip_of(x[i].x, strip_m);
            if b < strips {
                self.divergence_target[i] = rate[b];
            }
        }
    }

    /// After the move: books each triangle's area change and keeps the strip areas for the
    /// next remesh.
    pub(super) fn relax_after_move(&mut self, particles: &Particles) {
        if self.params.settings.volume_relaxation_s.is_none() {
            return;
        }
        let x = &particles.position;
        let ledger = &mut self.ledger;
        for (t, before) in self.mesh.triangles.iter().zip(&ledger.before_move) {
            let after = crate::fem::triangle_area(x, t);
            // Its centroid after the move: a triangle moves a fraction of h per step.
            let centroid_x = t.iter().map(|&i| x[i as usize].x).sum::<f64>() / 3.0;
            add_into(
                &mut ledger.error_m2,
                strip_of(centroid_x, ledger.strip_m),
                after - before,
            );
        }
        ledger.moved = Some(strip_areas(&self.mesh, x, ledger.strip_m));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_cut_into_strips_keeps_its_area() {
        let p = [
            Vector2::new(0.05, 0.0),
            Vector2::new(0.37, 0.1),
            Vector2::new(0.12, 0.3),
        ];
        let total = 0.5 * (p[1] - p[0]).perp(&(p[2] - p[0]));
        let mut mesh = Mesh::default();
        mesh.triangles.push([0, 1, 2]);
        let strips = strip_areas(&mesh, &p, 0.1);
        assert_eq!(strips.len(), 4);
        assert!((strips.iter().sum::<f64>() - total).abs() < 1e-15);
        assert!(strips.iter().all(|a| *a > 0.0), "{strips:?}");
        // The part left of x = 0.1 by hand: the triangle's x < 0.1 corner.
        assert!((area_left_of(p, 0.1) - strips[0]).abs() < 1e-15);
        assert!((area_left_of(p, 1.0) - total).abs() < 1e-15);
        assert_eq!(area_left_of(p, 0.0), 0.0);
    }

    #[test]
    fn the_swash_debt_is_paid_by_the_strips_offshore_of_it() {
        // Strip 3 (the swash) has lost 0.01 m² and no deep water; each of strips 0–2 has
        // 0.02 m² of deep water, so can pay 0.25 × 0.02 = 0.005 m² per T_r; strip 1 has
        // gained 0.001 m².
        let t_r = 0.5;
        let error = [0.0, 0.001, 0.0, -0.01];
        let deep = [0.02, 0.02, 0.02, 0.0];
        let rate = strip_rates(&error, &deep, 0.004, t_r);
        let paid: Vec<f64> = rate.iter().zip(&deep).map(|(r, d)| r * d * t_r).collect();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        assert_eq!(rate[3], 0.0);
        assert!(close(paid[2], 0.005), "{paid:?}");
        assert!(close(paid[1], 0.004), "{paid:?}");
        assert!(close(paid[0], 0.0), "{paid:?}");
        // A balance within every cap is paid where it is.
        let rate = strip_rates(&[0.002, -0.001], &[0.02, 0.02], 0.004, t_r);
        assert!(close(rate[0] * 0.02 * t_r, -0.002) && close(rate[1] * 0.02 * t_r, 0.001));
    }
}
