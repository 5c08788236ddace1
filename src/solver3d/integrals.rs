//! The frame's figures of a 3D flow: the fastest fluid node, the free surface's heights on a
//! vertical line, and [`Integrals3`].

use super::Flow3;

/// What a frame of a 3D run reports (the 3D counterpart of `diagnostics::Integrals`).
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Integrals3 {
    pub fluid_particles: usize,
    /// Fluid particles in no kept tetrahedron.
    pub isolated_particles: usize,
    pub max_speed_m_s: f64,
    pub kinetic_energy_j: f64,
    /// Largest x of a fluid particle in the mesh, m.
    pub front_x_m: f64,
    /// Highest fluid particle in the mesh within 1.5 h of the wall x = 0, m.
    pub left_wall_height_m: f64,
}

impl Flow3 {
    /// The largest speed of a fluid node, m/s.
    pub fn max_fluid_speed(&self) -> f64 {
        (0..self.x.len())
            .filter(|&i| self.walls[i] == 0)
            .map(|i| self.u[i].norm())
            .fold(0.0, f64::max)
    }

    /// Every crossing of the vertical line through (`x_m`, ·, `z_m`) with the last step's free
    /// surface (its triangles, walls excluded), heights in m, highest first; empty where the
    /// line meets no water. A crossing on an edge or a node shared by several triangles is
    /// counted once; more than one crossing means an overturned face, a jet or a drop above.
    pub fn surface_heights_at(&self, x_m: f64, z_m: f64) -> Vec<f64> {
        let mut out = Vec::new();
        for f in &self.surface {
            let [a, b, c] = f.map(|i| self.x[i as usize]);
            // Barycentric coordinates of (x, z) in the triangle's projection on the bed.
            let det = (b[0] - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (b[2] - a[2]);
            if det == 0.0 {
                continue; // a vertical triangle: its edges belong to its neighbours
            }
            let l1 = ((x_m - a[0]) * (c[2] - a[2]) - (c[0] - a[0]) * (z_m - a[2])) / det;
            let l2 = ((b[0] - a[0]) * (z_m - a[2]) - (x_m - a[0]) * (b[2] - a[2])) / det;
            let l0 = 1.0 - l1 - l2;
            let eps = -1e-12;
            if l0 >= eps && l1 >= eps && l2 >= eps {
                out.push(l0 * a[1] + l1 * b[1] + l2 * c[1]);
            }
        }
        out.sort_by(|p, q| q.total_cmp(p));
        out.dedup_by(|p, q| (*p - *q).abs() < 1e-9 * self.h_m);
        out
    }

    /// The frame's figures (see [`Integrals3`]); the mesh flags are the last step's.
    pub fn integrals(&self) -> Integrals3 {
        let mut out = Integrals3 {
            front_x_m: f64::NAN,
            left_wall_height_m: f64::NAN,
            ..Default::default()
        };
        let (mut front, mut wall_top) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        let x0 = self
            .planes
            .iter()
            .find(|p| p.axis == 0 && p.inward > 0.0)
            .map_or(0.0, |p| p.at_m);
        for i in 0..self.x.len() {
            if self.walls[i] != 0 {
                continue;
            }
            out.fluid_particles += 1;
            let speed = self.u[i].norm();
            out.max_speed_m_s = out.max_speed_m_s.max(speed);
            // Each particle carries the volume h³.
            out.kinetic_energy_j += 0.5 * self.rho_kg_m3 * self.h_m.powi(3) * speed * speed;
            if !self.in_mesh.get(i).copied().unwrap_or(false) {
                out.isolated_particles += 1;
                continue;
            }
            front = front.max(self.x[i][0]);
            if self.x[i][0] - x0 < 1.5 * self.h_m {
                wall_top = wall_top.max(self.x[i][1]);
            }
        }
        if front.is_finite() {
            out.front_x_m = front;
        }
        if wall_top.is_finite() {
            out.left_wall_height_m = wall_top;
        }
        out
    }
}
