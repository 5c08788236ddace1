//! Observers that read the state after a step: integral quantities and simple probes.

use crate::simulation::Simulation;
use nalgebra::Vector2;

/// Integral and extreme values of the water at one instant.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct Integrals {
    pub t_s: f64,
    /// Area of the kept mesh, m² per metre of width.
    pub volume_m2: f64,
    /// Σ ½ m_i |u_i|² over fluid particles, with the lumped mass of the mesh, J per metre.
    pub kinetic_energy_j_per_m: f64,
    pub max_speed_m_s: f64,
    /// Largest x of a fluid particle in the main (largest) connected body of water.
    pub front_x_m: f64,
    /// Highest fluid particle of the main body within 1.5 h of the left wall (x = 0).
    pub left_wall_height_m: f64,
    pub fluid_particles: usize,
    pub isolated_particles: usize,
}

/// Measures [`Integrals`] from the last mesh of the simulation.
pub fn integrals(sim: &Simulation) -> Integrals {
    let p = &sim.particles;
    let mesh = &sim.solver.mesh;
    let n = p.len();
    let rho = sim.case.fluid.density_kg_m3;
    let mut mass = vec![0.0; n];
    for t in &mesh.triangles {
        let a = crate::fem::triangle_area(&p.position, t) / 3.0;
        for &i in t {
            mass[i as usize] += rho * a;
        }
    }
    let (label, count) = mesh.components(n);
    let mut size = vec![0usize; count];
    for i in 0..n {
        if p.is_fluid(i) && label[i] != u32::MAX {
            size[label[i] as usize] += 1;
        }
    }
    let main = size
        .iter()
        .enumerate()
        .max_by_key(|(_, s)| **s)
        .map(|(c, _)| c as u32);
    let h = sim.case.particles.spacing_m;
    let mut out = Integrals {
        t_s: sim.time_s,
        volume_m2: mesh.area(&p.position),
        front_x_m: f64::NAN,
        left_wall_height_m: f64::NAN,
        ..Default::default()
    };
    let mut front = f64::NEG_INFINITY;
    let mut wall_top = f64::NEG_INFINITY;
    for i in 0..n {
        if !p.is_fluid(i) {
            continue;
        }
        out.fluid_particles += 1;
        let u2 = p.velocity[i].norm_squared();
        out.kinetic_energy_j_per_m += 0.5 * mass[i] * u2;
        out.max_speed_m_s = out.max_speed_m_s.max(u2.sqrt());
        if !mesh.in_mesh[i] {
            out.isolated_particles += 1;
        }
        if Some(label[i]) == main {
            let x: Vector2<f64> = p.position[i];
            front = front.max(x.x);
            if x.x < 1.5 * h {
                wall_top = wall_top.max(x.y);
            }
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

/// Pressure at fluid particles near `y_m` in the band `x_range_m`, against the hydrostatic
/// ρ g (η − y) with η the highest fluid particle of the band: returns (mean relative error,
/// number of particles used).
pub fn hydrostatic_error(sim: &Simulation, y_m: f64, x_range_m: (f64, f64)) -> (f64, usize) {
    let p = &sim.particles;
    let h = sim.case.particles.spacing_m;
    let rho_g = sim.case.fluid.density_kg_m3 * sim.case.fluid.gravity_m_s2;
    let band = |i: usize| p.is_fluid(i) && (x_range_m.0..=x_range_m.1).contains(&p.position[i].x);
    let eta = (0..p.len())
        .filter(|&i| band(i) && sim.solver.mesh.in_mesh[i])
        .map(|i| p.position[i].y)
        .fold(f64::NEG_INFINITY, f64::max);
    let picked: Vec<usize> = (0..p.len())
        .filter(|&i| band(i) && (p.position[i].y - y_m).abs() <= 0.5 * h)
        .collect();
    let err = picked
        .iter()
        .map(|&i| {
            let expected = rho_g * (eta - p.position[i].y);
            (p.pressure[i] - expected).abs() / expected
        })
        .sum::<f64>()
        / picked.len().max(1) as f64;
    (err, picked.len())
}

/// Surface elevation η at `x_m`, m above the still-water level there: the highest crossing of
/// the vertical line x = x_m with a boundary edge of the kept mesh that is not a wall–wall edge
/// (so the free surface, overturned parts included; the highest one is taken). `None` when no
/// water stands at x_m.
pub fn surface_elevation(sim: &Simulation, x_m: f64) -> Option<f64> {
    let p = &sim.particles;
    let level = sim.case.still_level_at(x_m).unwrap_or(0.0);
    sim.solver
        .mesh
        .boundary_edges
        .iter()
        .filter(|[a, b]| p.is_fluid(*a as usize) || p.is_fluid(*b as usize))
        .filter_map(|[a, b]| {
            let (pa, pb) = (p.position[*a as usize], p.position[*b as usize]);
            let (lo, hi) = if pa.x <= pb.x { (pa, pb) } else { (pb, pa) };
            if x_m < lo.x || x_m > hi.x || hi.x == lo.x {
                return None;
            }
            Some(lo.y + (hi.y - lo.y) * (x_m - lo.x) / (hi.x - lo.x))
        })
        .reduce(f64::max)
        .map(|y| y - level)
}
