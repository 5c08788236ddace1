//! A piston wavemaker across the 3D tank (issue 26): the tank's wall x = lo is a rigid face
//! spanning the width and the height, moved along x as the driver prescribes
//! ([`super::Flow3::drive_piston`]); the solver knows its path only one step ahead and nothing
//! of the wave theory behind it.
//!
//! In a step from t to t + Δt the face moves from where it stands to the target with the
//! velocity U = (target − x)/Δt. That velocity enters three places:
//! - the pressure equation, as the flux the face pushes into the water: u·n = U·n on the face
//!   at the end of the step, the boundary term −(ρ/Δt) ∮ φᵢ U·n_out dA of the weak form
//!   (lumped, A/3 per node of each face whose three nodes lie on the face);
//! - the face's own nodes: their velocity along x is U (slip or no-slip);
//! - the walls' guard: a fluid node is kept a margin in front of the face's new position, its
//!   velocity along x at least U.
//!
//! Nothing stands behind the face. So that the face never passes over a node of the bed or of
//! the side walls (the 2D paddle stands half a spacing above the bed for that reason, which in
//! 3D would leave a gap under its foot whose faces look like free surface), the wall nodes in a
//! band in front of the face are spread with it: a node at rest at x₀ = x_rest + s B (0 ≤ s ≤ 1,
//! B the band's length) stands at X + s (x_rest + B − X) when the face is at X. The bed and the
//! side walls are planes, so moving their nodes along them changes no boundary; the spacing in
//! the band changes by the stroke over B.

use super::Flow3;

/// The moving wall x = lo of a 3D tank.
#[derive(Debug, Clone, PartialEq)]
pub struct Piston3 {
    /// The face's plane in [`Flow3::planes`] (axis 0, the water on its +x side).
    pub plane: usize,
    /// The face's x at rest, m.
    pub rest_m: f64,
    /// Length of the band of wall nodes in front of the face that are spread with it, m.
    pub band_m: f64,
    /// The wall nodes of the band, with their x at rest, m (the face's own nodes at s = 0).
    band: Vec<(u32, f64)>,
    /// Where the face is to be at the end of the next step, m.
    target_m: f64,
}

impl Piston3 {
    /// The piston on `plane` (standing at `rest_m`) of a tank whose nodes are `x` and wall
    /// masks `walls`: every wall node within `band_m` in front of the face joins the band.
    pub fn new(plane: usize, rest_m: f64, band_m: f64, x: &[[f64; 3]], walls: &[u16]) -> Self {
        let reach = rest_m + band_m * (1.0 + 1e-12);
        let band = (0..x.len())
            .filter(|&i| walls[i] != 0 && x[i][0] <= reach)
            .map(|i| (i as u32, x[i][0]))
            .collect();
        Piston3 {
            plane,
            rest_m,
            band_m,
            band,
            target_m: rest_m,
        }
    }

    /// Follows a renumbering of the nodes (`new_index[old]`; the band's wall nodes are never
    /// removed).
    pub(super) fn renumber(&mut self, new_index: &[u32]) {
        for (i, _) in &mut self.band {
            *i = new_index[*i as usize];
        }
    }

    /// x of a band node that stands at `x0_m` at rest, when the face is at `face_m`.
    pub fn spread(&self, x0_m: f64, face_m: f64) -> f64 {
        let s = ((x0_m - self.rest_m) / self.band_m).clamp(0.0, 1.0);
        face_m + s * (self.rest_m + self.band_m - face_m)
    }
}

impl Flow3 {
    /// Sets where the piston's face is to stand at the end of the next step, m (x of the face).
    /// Without a piston it does nothing. The face moves there at a constant velocity during the
    /// step; a target never set leaves it where it is.
    pub fn drive_piston(&mut self, target_m: f64) {
        if let Some(p) = self.piston.as_mut() {
            p.target_m = target_m;
        }
    }

    /// The speed of the moving walls in the last (or current) step, m/s (0 without one).
    pub fn wall_speed(&self) -> f64 {
        self.planes
            .iter()
            .map(|p| p.velocity_m_s.abs())
            .fold(0.0, f64::max)
    }

    /// At the start of a step of `dt_s`: the piston's velocity for the step.
    pub(super) fn start_piston(&mut self, dt_s: f64) {
        if let Some(p) = &self.piston {
            let plane = &mut self.planes[p.plane];
            plane.velocity_m_s = (p.target_m - plane.at_m) / dt_s;
        }
    }

    /// Before the move: the face's plane at the end of the step (for the walls' guard).
    pub(super) fn advance_piston_plane(&mut self) {
        if let Some(p) = &self.piston {
            self.planes[p.plane].at_m = p.target_m;
        }
    }

    /// After the move: the band's wall nodes spread in front of the face's new position.
    pub(super) fn place_piston_band(&mut self) {
        if let Some(p) = &self.piston {
            let face = self.planes[p.plane].at_m;
            for &(i, x0) in &p.band {
                self.x[i as usize][0] = p.spread(x0, face);
            }
        }
    }

    /// Per node, the volume per second the moving walls push into the water, m³/s: U·n_in A/3
    /// from every face of a kept tetrahedron whose three nodes lie on a moving plane (none
    /// without one).
    pub(super) fn wall_inflow(
        &self,
        mesh: &crate::mesh3d::Tetrahedralisation,
        shape: &crate::mesh3d::AlphaShape,
    ) -> Option<Vec<f64>> {
        let moving: u16 = self
            .planes
            .iter()
            .enumerate()
            .filter(|(_, p)| p.velocity_m_s != 0.0)
            .fold(0, |m, (b, _)| m | 1 << b);
        if moving == 0 {
            return None;
        }
        let mut q = vec![0.0; self.x.len()];
        for &t in &shape.kept {
            let v = mesh.tets[t as usize];
            for skip in 0..4 {
                let f = [1, 2, 3].map(|k| v[(skip + k) % 4]);
                let shared = f.iter().fold(u16::MAX, |m, &i| m & self.walls[i as usize]) & moving;
                if shared == 0 {
                    continue;
                }
                let [a, b, c] = [0, 1, 2].map(|k| nalgebra::Vector3::from(self.x[f[k] as usize]));
                let area = 0.5 * (b - a).cross(&(c - a)).norm();
                for (bit, plane) in self.planes.iter().enumerate() {
                    if shared & (1 << bit) != 0 {
                        let flux = plane.inward * plane.velocity_m_s * area / 3.0;
                        for &i in &f {
                            q[i as usize] += flux;
                        }
                    }
                }
            }
        }
        Some(q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver3d::still_tank;
    use nalgebra::Vector3;

    #[test]
    fn the_band_follows_the_face_and_keeps_its_far_end() {
        let x = vec![
            [1.0, 0.0, 0.0],
            [1.1, 0.0, 0.0],
            [1.2, 0.0, 0.0],
            [1.3, 0.0, 0.0],
        ];
        let p = Piston3::new(1, 1.0, 0.2, &x, &[2, 1, 1, 1]);
        // The nodes at 1.0, 1.1 and 1.2 are in the band; 1.3 is not.
        assert_eq!(p.band.len(), 3);
        for (x0, face, want) in [(1.0, 1.05, 1.05), (1.2, 1.05, 1.2), (1.1, 1.05, 1.125)] {
            assert!((p.spread(x0, face) - want).abs() < 1e-15, "{x0} {face}");
        }
    }

    /// One step of a piston moving at U into a tank of water at rest without gravity: the face
    /// sweeps U Δt A (A its wetted area) out of the tank, and the water it pushes should rise
    /// by as much. Without the face's flux in the pressure equation the water would not move
    /// and the whole U Δt A would be lost. Measured today on this coarse tank (six layers):
    /// 38 % of it is lost in the step (slip and no-slip), of which 8 % is the flux booked on
    /// the water line's nodes, where p = 0 is strong and there is no continuity row; the rest
    /// is the lumped pressure gradient's, which moves the first layer of water at 0.4–0.6 U.
    /// The bar guards what holds: the water takes more than half of the swept volume and moves
    /// with the face. (docs/three_d.md, "The piston".)
    #[test]
    fn one_step_of_a_piston_moves_the_water_it_sweeps() {
        let h = 0.02;
        let (nx, ny, nz) = (12, 7, 6);
        for slip in [true, false] {
            let mut flow = still_tank(nx, ny, nz, h, 0.0);
            flow.gravity_m_s2 = Vector3::zeros();
            flow.slip = slip;
            flow.piston = Some(Piston3::new(1, 0.0, 4.0 * h, &flow.x, &flow.walls));
            let v0 = flow.mesh_now().unwrap();
            let (u, dt) = (0.01, 1.0e-3);
            flow.drive_piston(u * dt);
            let s = flow.step(dt).unwrap();
            let swept = u * dt * ((ny - 1) as f64 * h) * ((nz - 1) as f64 * h);
            let change = s.moved_volume_m3 - s.volume_m3;
            let mean_u: f64 = {
                let first: Vec<usize> = (0..flow.x.len())
                    .filter(|&i| flow.walls[i] == 0 && flow.x[i][0] < 1.5 * h)
                    .collect();
                first.iter().map(|&i| flow.u[i][0]).sum::<f64>() / first.len() as f64
            };
            println!(
                "slip {slip}: volume before {v0:.6e} m³, swept {swept:.3e} m³, change in the \
                 step {change:+.3e} m³ ({:+.2} % of the swept volume); mean u of the first \
                 fluid layer {mean_u:.5} m/s (face {u} m/s)",
                100.0 * change / swept
            );
            assert!((s.volume_m3 - v0).abs() < 1e-12 * v0);
            assert!(
                change < 0.0 && change.abs() < 0.45 * swept,
                "{change} of {swept}"
            );
            assert!(mean_u > 0.3 * u && mean_u < u, "{mean_u}");
            assert!((flow.planes[1].at_m - u * dt).abs() < 1e-15);
        }
    }
}
