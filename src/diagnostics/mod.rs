//! Observers that read the state after a step: integral quantities and simple probes.

pub mod breaking;
pub mod surface;
pub mod surface_u1;
pub mod undertow;
pub mod undertow3d;

use crate::simulation::{AreaBudget, Simulation};
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
    /// Where the volume went since t = 0.
    pub area_budget: AreaBudget,
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
    let (label, main) = mesh.main_body(p);
    let h = sim.case.particles.spacing_m;
    let mut out = Integrals {
        t_s: sim.time_s,
        volume_m2: mesh.area(&p.position),
        front_x_m: f64::NAN,
        left_wall_height_m: f64::NAN,
        area_budget: sim.area_budget,
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
        // 0.75 h, not 0.5 h: on a lattice whose rows lie h/2 from y_m, round-off in the
        // positions would decide which rows count.
        .filter(|&i| band(i) && (p.position[i].y - y_m).abs() <= 0.75 * h)
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
    surface_crossings(sim, x_m).first().copied()
}

/// Every crossing of the vertical line x = `x_m` with the free surface (boundary edges of the
/// kept mesh that are not wall–wall edges), m above the still-water level there, highest first.
/// More than one crossing means an overturned face, a jet or a drop above the gauge.
pub fn surface_crossings(sim: &Simulation, x_m: f64) -> Vec<f64> {
    let level = sim.case.still_level_at(x_m).unwrap_or(0.0);
    let mut out: Vec<f64> = sim
        .surface_heights_at(x_m)
        .into_iter()
        .map(|y| y - level)
        .collect();
    out.sort_by(|a, b| b.total_cmp(a));
    out.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    out
}

/// Velocity at `point` (x, y in m), interpolated linearly in the kept triangle that contains it;
/// `None` when the point is dry (outside every kept triangle).
pub fn velocity_at(sim: &Simulation, point: Vector2<f64>) -> Option<Vector2<f64>> {
    let p = &sim.particles;
    sim.solver.mesh.triangles.iter().find_map(|t| {
        let [a, b, c] = t.map(|i| p.position[i as usize]);
        let det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if det == 0.0 {
            return None;
        }
        let l1 = ((point.x - a.x) * (c.y - a.y) - (c.x - a.x) * (point.y - a.y)) / det;
        let l2 = ((b.x - a.x) * (point.y - a.y) - (point.x - a.x) * (b.y - a.y)) / det;
        let l0 = 1.0 - l1 - l2;
        let eps = -1e-12;
        (l0 >= eps && l1 >= eps && l2 >= eps).then(|| {
            let [ua, ub, uc] = t.map(|i| p.velocity[i as usize]);
            l0 * ua + l1 * ub + l2 * uc
        })
    })
}

/// Median of a sample (NaN for none).
pub fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mut v = values.to_vec();
    v.sort_by(|a, b| a.total_cmp(b));
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// Zero-up-crossing statistics of a surface-elevation record.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct WaveStats {
    /// Mean crest-to-trough height of the waves used, m.
    pub mean_height_m: f64,
    /// Mean zero-up-crossing period, s.
    pub mean_period_s: f64,
    /// Mean water level over the waves used, m above still water.
    pub mean_level_m: f64,
    /// Number of whole waves used.
    pub waves: usize,
}

/// Statistics over the last `last_waves` whole waves of the record (`t_s`, `eta_m`; dry
/// samples are `None` and skipped), counted between up-crossings of the record's mean level
/// over `t ≥ from_s`. `None` when there is not one whole wave.
pub fn wave_stats(
    t_s: &[f64],
    eta_m: &[Option<f64>],
    from_s: f64,
    last_waves: usize,
) -> Option<WaveStats> {
    let wet: Vec<(f64, f64)> = t_s
        .iter()
        .zip(eta_m)
        .filter(|(t, _)| **t >= from_s)
        .filter_map(|(t, e)| e.map(|e| (*t, e)))
        .collect();
    if wet.len() < 3 {
        return None;
    }
    let mean = wet.iter().map(|w| w.1).sum::<f64>() / wet.len() as f64;
    // Up-crossing times, interpolated between samples.
    let ups: Vec<(usize, f64)> = wet
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0].1 < mean && w[1].1 >= mean)
        .map(|(k, w)| {
            let s = (mean - w[0].1) / (w[1].1 - w[0].1);
            (k + 1, w[0].0 + s * (w[1].0 - w[0].0))
        })
        .collect();
    if ups.len() < 2 {
        return None;
    }
    let first = ups.len().saturating_sub(last_waves + 1);
    let used = &ups[first..];
    let (mut h, mut level, mut n) = (0.0, 0.0, 0usize);
    for w in used.windows(2) {
        let seg = &wet[w[0].0..w[1].0];
        let hi = seg.iter().map(|s| s.1).fold(f64::NEG_INFINITY, f64::max);
        let lo = seg.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
        h += hi - lo;
        level += seg.iter().map(|s| s.1).sum::<f64>() / seg.len() as f64;
        n += 1;
    }
    Some(WaveStats {
        mean_height_m: h / n as f64,
        mean_period_s: (used[used.len() - 1].1 - used[0].1) / n as f64,
        mean_level_m: level / n as f64,
        waves: n,
    })
}

/// Mean over `periods` whole periods from `from_s` of the range of η within each period
/// (highest minus lowest wet sample), m. Unlike the zero-up-crossing height, a long cnoidal
/// wave's secondary oscillations in its trough do not count as waves of their own. `None` when
/// a period has no wet sample.
pub fn period_height_m(
    t_s: &[f64],
    eta_m: &[Option<f64>],
    from_s: f64,
    period_s: f64,
    periods: usize,
) -> Option<f64> {
    if periods == 0 {
        return None;
    }
    let mut sum = 0.0;
    for n in 0..periods {
        let (a, b) = (
            from_s + n as f64 * period_s - 1e-9,
            from_s + (n + 1) as f64 * period_s - 1e-9,
        );
        let (lo, hi) = t_s
            .iter()
            .zip(eta_m)
            .filter(|(t, _)| **t >= a && **t < b)
            .filter_map(|(_, e)| *e)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), e| {
                (lo.min(e), hi.max(e))
            });
        if lo > hi {
            return None;
        }
        sum += hi - lo;
    }
    Some(sum / periods as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn period_height_ignores_the_secondary_crests_of_a_long_wave() {
        // A peaked 0.1 m crest every 5 s (at 2.5 s into each period) over a flat trough, with
        // a ±0.02 m ripple at 1 s: the ripple crosses the mean level in the trough, so the
        // zero-up-crossing count finds five waves per period; the range per period is the
        // crest plus the ripple's trough, 0.12 m, and up to the ripple's crest more (0.14 m).
        let t: Vec<f64> = (0..4000).map(|i| i as f64 * 0.005).collect();
        let eta: Vec<Option<f64>> = t
            .iter()
            .map(|t| {
                let phase = t % 5.0;
                Some(
                    0.1 * (-((phase - 2.5) / 0.4).powi(2)).exp()
                        + 0.02 * (std::f64::consts::TAU * t).sin(),
                )
            })
            .collect();
        let h = period_height_m(&t, &eta, 0.0, 5.0, 4).unwrap();
        let zero_up = wave_stats(&t, &eta, 0.0, 4).unwrap().mean_height_m;
        println!("per-period height {h:.4} m, zero-up-crossing {zero_up:.4} m");
        assert!((0.12..=0.14).contains(&h), "{h}");
        assert!(zero_up < 0.08, "{zero_up}");
        assert_eq!(period_height_m(&t, &vec![None; t.len()], 0.0, 5.0, 4), None);
    }

    #[test]
    fn wave_stats_of_a_sine() {
        let t: Vec<f64> = (0..4000).map(|i| i as f64 * 0.005).collect();
        let eta: Vec<Option<f64>> = t
            .iter()
            .map(|t| Some(0.01 + 0.03 * (std::f64::consts::TAU * t / 0.91).sin()))
            .collect();
        let s = wave_stats(&t, &eta, 2.0, 5).unwrap();
        println!("{s:?}");
        assert_eq!(s.waves, 5);
        assert!((s.mean_height_m - 0.06).abs() < 1e-4);
        assert!((s.mean_period_s - 0.91).abs() < 1e-4);
        assert!((s.mean_level_m - 0.01).abs() < 1e-3);
    }
}
