//! Stage `filter` (optional, `solver.surface_filter` = ε > 0): a fourth-difference filter of
//! the velocities of the free-surface fluid nodes, along the surface.
//!
//! With p = 0 imposed strongly, the surface nodes have no continuity equation, and a ripple of
//! one node up, the next down (wavelength 2h) grows out of round-off (README, *Surface
//! ripple*); it crowds the surface nodes, which the node stage then removes, and the water
//! drains. Walking along the free surface (boundary edges run with the water on their left,
//! so each surface node has one edge in and one out), each node i with two fluid surface
//! neighbours on each side gets
//!
//! u_i ← u_i − (ε/16) (u_{i−2} − 4 u_{i−1} + 6 u_i − 4 u_{i+1} + u_{i+2}).
//!
//! On a uniform chain a mode of wavenumber k loses ε (2 − 2 cos kh)²/16 per step: all of ε for
//! the 2h ripple, ε/4 at 4h, ε (kh)⁴/16 for a wave (2.5·10⁻⁴ ε per step for L = 0.5 m at
//! h = 2 cm). Nodes where the surface branches (more than one edge in or out), touches a wall
//! or ends within two nodes are left alone. The filter acts on the corrected velocity uⁿ⁺¹,
//! which the move then commits.

use super::Solver;
use super::surface::SurfaceChains;
use crate::particles::Particles;
use nalgebra::Vector2;

impl Solver {
    /// Applies the filter; returns how many nodes it changed.
    pub(super) fn filter_surface(&mut self, particles: &Particles) -> usize {
        let Some(eps) = self.params.settings.surface_filter else {
            return 0;
        };
        let chains = SurfaceChains::new(&self.mesh, particles);
        let u = &self.u_new;
        let mut change: Vec<(usize, Vector2<f64>)> = Vec::new();
        for i in 0..particles.len() as u32 {
            let Some((before, after)) = chains.window(i, 2).filter(|(b, _)| b.len() == 2) else {
                continue;
            };
            let [a, b, c, d, e] =
                [before[1], before[0], i, after[0], after[1]].map(|k| u[k as usize]);
            let fourth = a - 4.0 * b + 6.0 * c - 4.0 * d + e;
            change.push((i as usize, -eps / 16.0 * fourth));
        }
        for &(i, du) in &change {
            self.u_new[i] += du;
        }
        change.len()
    }
}

#[cfg(test)]
mod tests {
    use crate::case::Case;
    use crate::simulation::Simulation;
    use nalgebra::Vector2;

    /// The still tank's surface is one chain of fluid nodes h apart: a node-to-node ripple
    /// loses ε of itself, a wave of 0.5 m keeps all but ε (kh)⁴/16 of itself.
    #[test]
    fn the_filter_removes_the_ripple_and_keeps_the_wave() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/still_water.toml");
        let case = Case::load(&path, &["solver.surface_filter=0.5".to_string()]).unwrap();
        let h = case.particles.spacing_m;
        let mut sim = Simulation::new(&case).unwrap();
        let (p, solver) = (&sim.particles, &mut sim.solver);
        let surface: Vec<usize> = (0..p.len())
            .filter(|&i| p.is_fluid(i) && solver.mesh.free_surface[i])
            .collect();
        assert!(surface.len() > 40, "{} surface nodes", surface.len());
        let k = 2.0 * std::f64::consts::PI / 0.5;
        for (ripple, expected) in [(true, 0.5), (false, 1.0 - 0.5 * (k * h).powi(4) / 16.0)] {
            let shape = |x: f64| {
                if ripple {
                    // Nodes sit h apart: alternate by the nearest lattice index.
                    if ((x / h).round() as i64).rem_euclid(2) == 0 {
                        1.0
                    } else {
                        -1.0
                    }
                } else {
                    (k * x).sin()
                }
            };
            solver.u_new = vec![Vector2::zeros(); p.len()];
            for &i in &surface {
                solver.u_new[i].y = shape(p.position[i].x);
            }
            let changed = solver.filter_surface(p);
            // The two nodes at each end of the chain (next to the walls) are left alone.
            assert!(
                changed + 4 >= surface.len(),
                "{changed} of {}",
                surface.len()
            );
            let mut worst: f64 = 0.0;
            for &i in &surface {
                let x = p.position[i].x;
                if x < 3.0 * h || x > case.flume.length_m - 3.0 * h || shape(x).abs() < 0.5 {
                    continue;
                }
                worst = worst.max((solver.u_new[i].y / shape(x) - expected).abs());
            }
            println!("ripple {ripple}: worst |u/u0 − {expected:.6}| = {worst:.2e}");
            assert!(worst < if ripple { 1e-12 } else { 2e-4 }, "{worst}");
        }
    }
}
