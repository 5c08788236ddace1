//! The 3D form of the 2D solver's volume relaxation (`solver.volume_relaxation_s` = T_r > 0,
//! `solver/relax.rs`): the water volume that the numerics lose (or make) is given back where it
//! was lost, through the continuity equation.
//!
//! The tank is cut into cells: strips along x of `STRIP_H`·h, and across them bands in z of
//! about the same width (the tank's width divided into equal bands, one in a narrow tank). A
//! ledger holds, per cell, the volume the numerics have changed there since t = 0, E_c:
//! - remeshing: the new mesh's volume in the cell minus the last mesh's at the same positions
//!   (after the node stage). The tetrahedra are cut exactly at the strip lines, so two
//!   tetrahedralisations of the same water give the same strip volumes; across the bands a
//!   tetrahedron counts whole in the band of its centroid, so a tetrahedron that changes band
//!   between two meshes moves its volume from one band's balance to the next (a swap between
//!   neighbours that the relaxation evens out, never a change of the total).
//! - motion: each kept tetrahedron's volume after the move minus before, charged to the cell of
//!   its centroid after the move.
//!
//! A tetrahedron the step treats as flat (`FLAT_QUALITY`, zero volume in its elements) counts
//! zero in both, until a remesh finds it no longer flat, as in the run's own volume
//! (`Step3`), so that the ledger's sum is the change of that volume.
//!
//! The nodes deep in the water of cell c (fluid nodes of the kept mesh, not on the free surface
//! and in no kept tetrahedron with a wall node) are asked for the uniform divergence
//!
//! ∇·u = −E_c / (V_c T_r),  capped at ±0.25/T_r (`solver/relax.rs`'s cap),
//!
//! V_c their lumped volume; the payment is itself a change of the motion, so the ledger closes.
//! In each band, from the shore out, a cell with less than `MIN_DEEP_H3`·h³ of deep water (the
//! swash, a jet) hands its balance to the next cell offshore, and one whose balance is more than
//! the cap hands on the excess, as in 2D. It is a correction for a numerical loss, not physics.

use crate::fem::tet::P1Tet;
use crate::mesh3d::{AlphaShape, Tetrahedralisation};
use crate::solver::relax::{add_into, strip_rates};
use nalgebra::Vector3;

/// Strip width along x, and the bands' target width across, in units of h (as in 2D).
const STRIP_H: f64 = 20.0;
/// Least deep volume a cell needs to pay its own balance, in units of h³.
const MIN_DEEP_H3: f64 = 10.0;

/// The per-cell volume balance and what it needs between the stages of a step.
#[derive(Debug, Clone)]
pub struct Relax3 {
    /// T_r, s.
    pub time_s: f64,
    strip_m: f64,
    /// The bands across: the first one's lower edge and their width, m, and how many.
    z0_m: f64,
    band_m: f64,
    bands: usize,
    /// E_c, m³, cell c = strip × bands + band.
    pub error_m3: Vec<f64>,
    /// The cell volumes of the last mesh after its move (`None` before the first step).
    moved: Option<Vec<f64>>,
    /// The kept tetrahedra's volumes before the move, in the order of `AlphaShape::kept` (0 for a
    /// flat one).
    before_move: Vec<f64>,
    h_m: f64,
}

fn tet_volume(p: &[Vector3<f64>; 4]) -> f64 {
    (p[1] - p[0])
        .dot(&(p[2] - p[0]).cross(&(p[3] - p[0])))
        .abs()
        / 6.0
}

/// Volume of the part of the tetrahedron `p` with x < `c`, m³: the region is a convex
/// polyhedron whose corners are the corners left of the plane and the edges' crossings.
pub fn volume_left_of(p: &[Vector3<f64>; 4], c: f64) -> f64 {
    let left: Vec<usize> = (0..4).filter(|&k| p[k].x < c).collect();
    let whole = tet_volume(p);
    let cut = |a: usize, b: usize| p[a] + (c - p[a].x) / (p[b].x - p[a].x) * (p[b] - p[a]);
    match left.len() {
        0 => 0.0,
        4 => whole,
        1 => {
            // A corner tetrahedron at the left corner a.
            let a = left[0];
            let f: f64 = (0..4)
                .filter(|&j| j != a)
                .map(|j| (c - p[a].x) / (p[j].x - p[a].x))
                .product();
            whole * f
        }
        3 => {
            // The whole less the corner tetrahedron at the right corner b.
            let b = (0..4).find(|k| !left.contains(k)).unwrap_or(0);
            let f: f64 = (0..4)
                .filter(|&j| j != b)
                .map(|j| (p[b].x - c) / (p[b].x - p[j].x))
                .product();
            whole * (1.0 - f)
        }
        _ => {
            // Corners a, b left, c, d right: the cone from a over the faces that do not hold
            // a (the cut quadrilateral ac–ad–bd–bc, split on ac–bd, and the triangle b–bc–bd
            // of the face bcd).
            let (a, b) = (left[0], left[1]);
            let right: Vec<usize> = (0..4).filter(|k| !left.contains(k)).collect();
            let (r, s) = (right[0], right[1]);
            let (ar, as_, br, bs) = (cut(a, r), cut(a, s), cut(b, r), cut(b, s));
            tet_volume(&[p[a], ar, as_, bs])
                + tet_volume(&[p[a], ar, bs, br])
                + tet_volume(&[p[a], p[b], br, bs])
        }
    }
}

impl Relax3 {
    /// The relaxation with time `time_s` for spacing `h_m` in a tank spanning z from `z0_m` to
    /// `z0_m + width_m`.
    pub fn new(time_s: f64, h_m: f64, z0_m: f64, width_m: f64) -> Self {
        let strip_m = STRIP_H * h_m;
        let bands = ((width_m / strip_m).round() as usize).max(1);
        Relax3 {
            time_s,
            strip_m,
            z0_m,
            band_m: width_m / bands as f64,
            bands,
            error_m3: Vec::new(),
            moved: None,
            before_move: Vec::new(),
            h_m,
        }
    }

    fn strip_of(&self, x: f64) -> usize {
        (x / self.strip_m).floor().max(0.0) as usize
    }

    fn band_of(&self, z: f64) -> usize {
        (((z - self.z0_m) / self.band_m).floor().max(0.0) as usize).min(self.bands - 1)
    }

    /// The cell of the point (x, z).
    fn cell_of(&self, x: f64, z: f64) -> usize {
        self.strip_of(x) * self.bands + self.band_of(z)
    }

    /// The kept tetrahedra's volume per cell (see the module comment).
    fn cell_volumes(&self, x: &[[f64; 3]], tets: impl Iterator<Item = [u32; 4]>) -> Vec<f64> {
        let mut out = Vec::new();
        for t in tets {
            let p = t.map(|i| Vector3::from(x[i as usize]));
            let band = self.band_of(p.iter().map(|v| v.z).sum::<f64>() / 4.0);
            let lo = p.iter().map(|v| v.x).fold(f64::INFINITY, f64::min);
            let hi = p.iter().map(|v| v.x).fold(f64::NEG_INFINITY, f64::max);
            let (first, last) = (self.strip_of(lo), self.strip_of(hi));
            let whole = tet_volume(&p);
            let mut left = 0.0;
            for b in first..last {
                let upto = volume_left_of(&p, (b + 1) as f64 * self.strip_m);
                add_into(&mut out, b * self.bands + band, upto - left);
                left = upto;
            }
            add_into(&mut out, last * self.bands + band, whole - left);
        }
        out
    }

    /// After the α-shape: books the remeshing change and returns the divergence asked of each
    /// node, 1/s (0 but at the deep nodes). `elements` are the kept tetrahedra's.
    pub fn targets(
        &mut self,
        x: &[[f64; 3]],
        walls: &[u16],
        mesh: &Tetrahedralisation,
        shape: &AlphaShape,
        elements: &[P1Tet],
    ) -> Vec<f64> {
        let n = x.len();
        self.before_move.clear();
        self.before_move.extend(elements.iter().map(|e| e.volume));
        let now = self.cell_volumes(x, self.solid(mesh, shape));
        if let Some(moved) = self.moved.take() {
            for (c, v) in now.iter().enumerate() {
                add_into(&mut self.error_m3, c, *v);
            }
            for (c, v) in moved.iter().enumerate() {
                add_into(&mut self.error_m3, c, -*v);
            }
        }
        let mut deep: Vec<bool> = (0..n)
            .map(|i| walls[i] == 0 && shape.in_mesh[i] && !shape.free_surface[i])
            .collect();
        let mut share = vec![0.0; n];
        for (&k, &volume) in shape.kept.iter().zip(&self.before_move) {
            let t = mesh.tets[k as usize];
            let walled = t.iter().any(|&i| walls[i as usize] != 0);
            for &i in &t {
                share[i as usize] += volume / 4.0;
                if walled {
                    deep[i as usize] = false;
                }
            }
        }
        let cells = self.error_m3.len();
        let mut deep_m3 = vec![0.0; cells];
        for i in (0..n).filter(|&i| deep[i]) {
            let c = self.cell_of(x[i][0], x[i][2]);
            if c < cells {
                deep_m3[c] += share[i];
            }
        }
        let rate = self.cell_rates(&deep_m3);
        (0..n)
            .map(|i| {
                let c = self.cell_of(x[i][0], x[i][2]);
                if deep[i] && c < cells { rate[c] } else { 0.0 }
            })
            .collect()
    }

    /// The divergence asked of each cell's deep water (1/s), given its deep volume: each band's
    /// cells in turn as `solver/relax.rs`'s strips, from the shore out.
    fn cell_rates(&self, deep_m3: &[f64]) -> Vec<f64> {
        let min_deep = MIN_DEEP_H3 * self.h_m.powi(3);
        let cells = self.error_m3.len();
        let mut rate = vec![0.0; cells];
        for band in 0..self.bands {
            let band_cells: Vec<usize> = (band..cells).step_by(self.bands).collect();
            let error: Vec<f64> = band_cells.iter().map(|&c| self.error_m3[c]).collect();
            let deep: Vec<f64> = band_cells.iter().map(|&c| deep_m3[c]).collect();
            for (&c, r) in band_cells
                .iter()
                .zip(strip_rates(&error, &deep, min_deep, self.time_s))
            {
                rate[c] = r;
            }
        }
        rate
    }

    /// The kept tetrahedra that are not flat (nonzero volume before the move).
    fn solid<'a>(
        &'a self,
        mesh: &'a Tetrahedralisation,
        shape: &'a AlphaShape,
    ) -> impl Iterator<Item = [u32; 4]> + 'a {
        (shape.kept.iter().zip(&self.before_move))
            .filter(|(_, v)| **v > 0.0)
            .map(|(&t, _)| mesh.tets[t as usize])
    }

    /// After the move: books each kept tetrahedron's volume change and keeps the cell volumes
    /// for the next remesh.
    pub fn after_move(&mut self, x: &[[f64; 3]], mesh: &Tetrahedralisation, shape: &AlphaShape) {
        for (&t, before) in shape.kept.iter().zip(&self.before_move) {
            if *before == 0.0 {
                continue;
            }
            let p = mesh.tets[t as usize].map(|i| Vector3::from(x[i as usize]));
            let centroid = p.iter().sum::<Vector3<f64>>() / 4.0;
            let c = self.cell_of(centroid.x, centroid.z);
            add_into(&mut self.error_m3, c, tet_volume(&p) - before);
        }
        self.moved = Some(self.cell_volumes(x, self.solid(mesh, shape)));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The volume of a linear function's sublevel set in a simplex with distinct values x_i
    /// (the cubic B-spline form): V Σ_{x_i < c} (c − x_i)³ / Π_{j ≠ i} (x_j − x_i).
    fn sublevel(p: &[Vector3<f64>; 4], c: f64) -> f64 {
        let v = tet_volume(p);
        (0..4)
            .filter(|&i| p[i].x < c)
            .map(|i| {
                let d: f64 = (0..4)
                    .filter(|&j| j != i)
                    .map(|j| p[j].x - p[i].x)
                    .product();
                v * (c - p[i].x).powi(3) / d
            })
            .sum()
    }

    #[test]
    fn a_tetrahedron_cut_by_a_plane_keeps_its_volume() {
        let p = [
            Vector3::new(0.03, 0.0, 0.01),
            Vector3::new(0.41, 0.1, -0.05),
            Vector3::new(0.17, 0.3, 0.2),
            Vector3::new(0.26, -0.1, 0.12),
        ];
        let whole = tet_volume(&p);
        // Every count of corners left of the plane: 0, 1, 2, 3, 4.
        for c in [0.0, 0.1, 0.2, 0.3, 0.5] {
            let left = volume_left_of(&p, c);
            assert!((left - sublevel(&p, c)).abs() < 1e-15, "{c}: {left}");
            let mirror = p.map(|v| Vector3::new(-v.x, v.y, v.z));
            let right = volume_left_of(&mirror, -c);
            assert!(
                (left + right - whole).abs() < 1e-15,
                "{c}: {left} + {right}"
            );
        }
        // The unit corner tetrahedron cut halfway: the tip beyond the plane is an eighth.
        let q = [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 1.0, 0.0),
            Vector3::new(0.0, 0.0, 1.0),
        ];
        assert!((volume_left_of(&q, 0.5) - (1.0 - 0.125) / 6.0).abs() < 1e-15);
        assert_eq!(volume_left_of(&q, 0.0), 0.0);
    }

    #[test]
    fn cells_cut_along_x_and_whole_across() {
        // h = 0.01: strips of 0.2 m; a 0.5 m wide tank has 3 bands of 1/6 m.
        let relax = Relax3::new(0.25, 0.01, 0.0, 0.5);
        assert_eq!(relax.bands, 3);
        let x = [
            [0.1, 0.0, 0.0],
            [0.5, 0.0, 0.1],
            [0.2, 0.3, 0.05],
            [0.3, 0.1, 0.3],
        ];
        let cells = relax.cell_volumes(&x, [[0u32, 1, 2, 3]].into_iter());
        let p = x.map(Vector3::from);
        let whole = tet_volume(&p);
        // Centroid z 0.1125: band 0; strips 0, 1, 2.
        assert_eq!(cells.len(), 7);
        assert!((cells.iter().sum::<f64>() - whole).abs() < 1e-15);
        let (s0, s1) = (volume_left_of(&p, 0.2), volume_left_of(&p, 0.4));
        for (c, want) in [(0, s0), (3, s1 - s0), (6, whole - s1)] {
            assert!(
                (cells[c] - want).abs() < 1e-15 && want > 0.0,
                "{c}: {cells:?}"
            );
        }
        assert!(
            cells
                .iter()
                .enumerate()
                .all(|(c, v)| c % 3 == 0 || *v == 0.0)
        );
    }

    /// `cases/tank3d_still.toml` (0.3 × 0.14 × 0.2 m of water, h = 2 cm) with T_r = `t_r`.
    fn still_tank_relaxing(t_r: f64) -> crate::solver3d::Flow3 {
        let set = vec![format!("solver.volume_relaxation_s={t_r}")];
        let path = std::path::Path::new("cases/tank3d_still.toml");
        let case = crate::case::Case::load(path, &set).unwrap();
        crate::solver3d::setup::from_case(&case).unwrap()
    }

    #[test]
    fn the_ledger_books_every_change_and_still_water_stays_still() {
        let mut flow = still_tank_relaxing(0.05);
        let first = flow.step(2.5e-3).unwrap();
        let mut worst: f64 = 0.0;
        for _ in 0..40 {
            let s = flow.step(2.5e-3).unwrap();
            // After the move: the ledger holds the water the numerics changed since the first
            // mesh (which books nothing), here round-off.
            let ledger: f64 = flow.relax.as_ref().unwrap().error_m3.iter().sum();
            worst = worst.max((s.moved_volume_m3 - first.volume_m3 - ledger).abs());
        }
        let speed = flow.max_fluid_speed();
        println!("still tank relaxing: ledger closes to {worst:.1e} m³, speed {speed:.1e} m/s");
        assert!(worst < 1e-15 && speed < 1e-12, "{worst:e} {speed:e}");
    }

    #[test]
    fn a_volume_deficit_is_paid_back_over_the_relaxation_time() {
        // A deficit of 2e-5 m³ (0.24 % of the water) put in the ledger; T_r = 0.05 s, Δt =
        // 2.5 ms: each step pays Δt/T_r of what is left, 1 − 0.95¹⁰⁰ = 0.9941 of it in 100.
        let (t_r, dt) = (0.05, 2.5e-3);
        let mut flow = still_tank_relaxing(t_r);
        let before = flow.step(dt).unwrap().moved_volume_m3;
        let deficit = 2e-5;
        for e in flow.relax.as_mut().unwrap().error_m3.iter_mut() {
            *e = 0.0;
        }
        flow.relax.as_mut().unwrap().error_m3[0] = -deficit;
        let mut after = before;
        for _ in 0..100 {
            after = flow.step(dt).unwrap().moved_volume_m3;
        }
        let left: f64 = flow.relax.as_ref().unwrap().error_m3.iter().sum();
        let paid = (after - before) / deficit;
        let expected = 1.0 - (1.0 - dt / t_r).powi(100);
        println!(
            "deficit {deficit:e} m³: paid {paid:.4} of it (geometric {expected:.4}), {:.2e} of it \
             left in the ledger, speed {:.1e} m/s",
            left / deficit,
            flow.max_fluid_speed()
        );
        assert!((paid - expected).abs() < 0.02, "paid {paid}");
        assert!((left / deficit + 1.0 - paid).abs() < 1e-9, "{left:e}");
    }

    #[test]
    fn a_band_pays_its_shore_debt_offshore_and_not_in_the_next_band() {
        let mut relax = Relax3::new(0.5, 0.01, 0.0, 0.4);
        assert_eq!(relax.bands, 2);
        // Strip 2 of band 1 (cell 5) lost 1e-5 m³ and has no deep water; strips 0–1 of both
        // bands have 2e-5 m³ each, so can pay 0.5e-5 per T_r.
        relax.error_m3 = vec![0.0, 0.0, 0.0, 0.0, 0.0, -1e-5];
        let deep = [2e-5, 2e-5, 2e-5, 2e-5, 0.0, 0.0];
        let rate = relax.cell_rates(&deep);
        let paid: Vec<f64> = rate.iter().zip(&deep).map(|(r, d)| r * d * 0.5).collect();
        let close = |a: f64, b: f64| (a - b).abs() < 1e-18;
        assert!(close(paid[3], 0.5e-5) && close(paid[1], 0.5e-5), "{paid:?}");
        assert!(
            paid[0] == 0.0 && paid[2] == 0.0 && paid[4] == 0.0,
            "{paid:?}"
        );
    }
}
