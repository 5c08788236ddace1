//! A 3D flow seeded from a case whose `[flume]` has a `width_m`: the 2D case's flume and water
//! regions extruded across the width, between two side walls at z = 0 and z = width. With a
//! piston wavemaker the tank starts at the piston's face (`wavemaker.x_m`): the end wall x = lo
//! is the piston ([`super::Piston3`]), and the dry flume behind it is left out.
//!
//! The bed is the case's profile extruded across the width plus its bars
//! ([`Bed3`]); a flat one is the plane y = 0. Walls are lattices of nodes at about the particle
//! spacing h: the bed over the whole tank (its lattice through the bed's creases, the nodes
//! about h apart along it), the end walls and the side walls from the bed up to the flume's
//! height. Each node carries one bit per wall it lies on, in the order of [`box_planes`] (bit
//! 0 the bed). Fluid particles fill every water region on the 2D seeding's lattice (x and y as
//! `geometry::seed_fluid` spaces them, cut by the bed), repeated across the width at about h,
//! at least h/2 from every wall.

use super::{Flow3, Solver3, box_planes};
use crate::case::{Case, PressureSolver, WallCondition};
use crate::geometry::bed3d::Bed3;
use nalgebra::Vector3;

/// Why a case cannot be seeded on the 3D path: the field and what is wrong with it.
#[derive(Debug, thiserror::Error)]
#[error("{field}: {message}")]
pub struct Setup3Error {
    pub field: String,
    pub message: String,
}

/// The field that describes the bed of `f`: its bars, its beach or its polyline.
fn bed_field(f: &crate::case::Flume) -> &'static str {
    if !f.bars.is_empty() {
        "flume.bars"
    } else if f.beach.is_some() {
        "flume.beach"
    } else {
        "flume.bed_m"
    }
}

fn refuse(field: &str, message: &str) -> Setup3Error {
    Setup3Error {
        field: field.to_owned(),
        message: message.to_owned(),
    }
}

/// The 3D flow of `case` at rest (hydrostatic pressure), or why the 3D path cannot run it yet:
/// no width, a bed outside the tank or not flat under the piston's band, a flap or an absorbing
/// paddle, an absorber or one of the 2D solver's optional remedies. The case's sizes were
/// checked when it was loaded (`Case::validate` counts the 3D nodes).
pub fn from_case(case: &Case) -> Result<Flow3, Setup3Error> {
    let f = &case.flume;
    let Some(width) = f.width_m else {
        return Err(refuse(
            "flume.width_m",
            "the case has no width: it is a 2D case",
        ));
    };
    let bed = Bed3::from_flume(f);
    let mut piston_band_m = None;
    if let Some(w) = &case.wavemaker {
        if w.paddle != crate::waves::linear::PaddleKind::Piston {
            return Err(refuse(
                "wavemaker.paddle",
                "the 3D path has a piston across the tank, not a flap (yet)",
            ));
        }
        if w.absorb_long_waves || w.absorb_reflected_waves {
            return Err(refuse(
                if w.absorb_long_waves {
                    "wavemaker.absorb_long_waves"
                } else {
                    "wavemaker.absorb_reflected_waves"
                },
                "the 3D piston does not absorb yet (2D only): leave it off",
            ));
        }
        // The band of wall nodes spread with the face: ten times the larger excursion, at
        // least ten spacings, so that their spacing changes by a tenth at most.
        let reach = match crate::waves::paddle::PaddleMotion::from_case(case) {
            Some(Ok(m)) => {
                let (back, forward) = m.excursion_m();
                back.abs().max(forward.abs())
            }
            Some(Err(e)) => return Err(refuse("wavemaker", &e.to_string())),
            None => 0.0,
        };
        let h = case.particles.spacing_m;
        let band = (10.0 * reach).max(10.0 * h);
        // The band's nodes slide along x as the face moves: under them the bed must be flat.
        let band_end = w.x_m + band;
        let level = bed.height(w.x_m, 0.0);
        let flat_under_band = bed
            .x_breaks(w.x_m, band_end)
            .into_iter()
            .chain([w.x_m, band_end])
            .all(|x| {
                bed.z_breaks(0.0, width)
                    .into_iter()
                    .chain([0.0, width])
                    .all(|z| {
                        bed.height(x, z) == level && bed.normal(x, z).is_some_and(|n| n.y == 1.0)
                    })
            });
        if !flat_under_band {
            return Err(refuse(
                bed_field(f),
                &format!(
                    "the bed must be flat for {band:.3} m in front of the piston (x = {} to \
                     {band_end:.3} m): the wall nodes there move with the face",
                    w.x_m
                ),
            ));
        }
        if band > 0.5 * (f.length_m - w.x_m) {
            return Err(refuse(
                "flume.length_m",
                &format!(
                    "the tank in front of the piston ({:.3} m) is shorter than twice the band \
                     its wall nodes are spread over ({band:.3} m, ten strokes or ten spacings)",
                    f.length_m - w.x_m
                ),
            ));
        }
        piston_band_m = Some(band);
    }
    if case.absorber.is_some() {
        return Err(refuse("absorber", "the 3D path has no damping layer yet"));
    }
    if !case.output.probes_m.is_empty() {
        return Err(refuse(
            "output.probes_m",
            "the 3D path records elevation gauges (output.gauges_x_m) but no velocity probes yet",
        ));
    }
    // The 2D solver's optional remedies, off by default: asked for in a 3D case they would be
    // silently ignored, so they are refused.
    let s = &case.solver;
    let two_d_only = [
        ("solver.delta", s.delta > 0.0),
        ("solver.geometry_theta", s.geometry_theta.is_some()),
        ("solver.increment_weight", s.increment_weight != 1.0),
        // The 3D predictor's viscous term is explicit.
        ("solver.theta", s.theta != 0.0),
        ("solver.midpoint_move", s.midpoint_move),
        ("solver.area_correction", s.area_correction),
        ("solver.volume_recovery", s.volume_recovery),
    ];
    if let Some((field, _)) = two_d_only.iter().find(|(_, on)| *on) {
        return Err(refuse(
            field,
            "the 3D path does not have this yet (2D only): leave it at its default (off)",
        ));
    }
    let h = case.particles.spacing_m;
    if let Some(r) = s.insert_radius_h
        && super::nodes::insert_radius_3d(r, 1.0) >= s.alpha
    {
        return Err(refuse(
            "solver.insert_radius_h",
            &format!(
                "{r} h is {:.3} h in 3D (× √3/√2, see solver3d::nodes), not below solver.alpha = \
                 {}: tetrahedra would be dropped before they are split",
                super::nodes::insert_radius_3d(r, 1.0),
                s.alpha
            ),
        ));
    }
    if (width / h).round() < 2.0 {
        return Err(refuse(
            "flume.width_m",
            &format!(
                "{width} m is less than two particle spacings (h = {h} m): no layer of particles \
                 fits between the side walls"
            ),
        ));
    }
    // The tank starts at the piston's face, or at x = 0.
    let x_lo = case.wavemaker.as_ref().map_or(0.0, |w| w.x_m);
    // b is bilinear between its break lines, so its extremes are at their crossings.
    let x_probe: Vec<f64> = bed
        .x_breaks(x_lo, f.length_m)
        .into_iter()
        .chain([x_lo, f.length_m])
        .collect();
    let z_probe: Vec<f64> = bed
        .z_breaks(0.0, width)
        .into_iter()
        .chain([0.0, 0.5 * width, width])
        .collect();
    for &px in &x_probe {
        for &pz in &z_probe {
            let b = bed.height(px, pz);
            if !(0.0..f.height_m - h).contains(&b) {
                return Err(refuse(
                    bed_field(f),
                    &format!(
                        "the bed is {b:.3} m high at x = {px} m, z = {pz} m: it must lie in \
                         [0, flume.height_m − h) = [0, {:.3}) m",
                        f.height_m - h
                    ),
                ));
            }
        }
    }
    // The bed's lattice passes through its creases; along each piece the nodes are about h
    // apart along the bed (its steepest slope on the piece, across the tank or along it).
    let steepest = |along: usize, a: f64, b: f64, across: &[f64]| -> f64 {
        let mid = 0.5 * (a + b);
        across
            .iter()
            .map(|&c| {
                let (x, z) = if along == 0 { (mid, c) } else { (c, mid) };
                bed.slope(x, z, [1.0, 1.0])[if along == 0 { 0 } else { 1 }].abs()
            })
            .fold(0.0, f64::max)
    };
    let xs = crate::geometry::bed3d::lattice_through(
        x_lo,
        f.length_m,
        &bed.x_breaks(x_lo, f.length_m),
        |a, b| h / (1.0 + steepest(0, a, b, &z_probe).powi(2)).sqrt(),
    );
    let zs =
        crate::geometry::bed3d::lattice_through(0.0, width, &bed.z_breaks(0.0, width), |a, b| {
            h / (1.0 + steepest(2, a, b, &x_probe).powi(2)).sqrt()
        });
    let (nx, nz) = (xs.len() - 1, zs.len() - 1);
    // Each column of wall nodes runs from the bed up to the flume's height in about h steps.
    let rows = |base: f64| ((f.height_m - base) / h).round().max(1.0) as usize;
    let ny_max = (0..=nx)
        .flat_map(|i| (0..=nz).map(move |k| (i, k)))
        .map(|(i, k)| rows(bed.height(xs[i], zs[k])))
        .max()
        .unwrap_or(1);
    let side_mask = |i: usize, k: usize| -> u16 {
        ((i == 0) as u16) << 1
            | ((i == nx) as u16) << 2
            | ((k == 0) as u16) << 3
            | ((k == nz) as u16) << 4
    };
    let (mut x, mut walls) = (Vec::new(), Vec::new());
    for i in 0..=nx {
        for j in 0..=ny_max {
            for k in 0..=nz {
                let base = bed.height(xs[i], zs[k]);
                let ny = rows(base);
                let mask = (j == 0) as u16 | side_mask(i, k);
                if mask != 0 && j <= ny {
                    let dy = (f.height_m - base) / ny as f64;
                    x.push([xs[i], base + j as f64 * dy, zs[k]]);
                    walls.push(mask);
                }
            }
        }
    }
    let planes = box_planes([x_lo, 0.0, 0.0], [f.length_m, f.height_m, width]);
    let near_a_wall = |p: &[f64; 3]| {
        bed.distance(p) < 0.5 * h || planes.iter().skip(1).any(|q| q.distance(p) < 0.5 * h)
    };
    let nz_fluid = (width / h).round().max(1.0) as usize;
    let dz = width / nz_fluid as f64;
    let mut taken = std::collections::HashSet::new();
    for w in &case.water {
        let (nxw, dxw) = {
            let n = ((w.x_end_m - w.x_start_m) / h).round().max(1.0) as usize;
            (n, (w.x_end_m - w.x_start_m) / n as f64)
        };
        let nyw = (w.depth_m / h).round().max(1.0) as usize;
        for i in 0..=nxw {
            let px = w.x_start_m + i as f64 * dxw;
            let dyw = w.level_at(px) / nyw as f64;
            for j in 0..=nyw {
                for k in 1..nz_fluid {
                    // The 2D seeding's lattice, from y = 0 up to the level, cut by the bed.
                    let p = [px, j as f64 * dyw, k as f64 * dz];
                    if near_a_wall(&p) {
                        continue;
                    }
                    // Overlapping regions: one particle per half-spacing cell.
                    let key = (
                        (p[0] / (0.5 * h)).round() as i64,
                        (p[1] / (0.5 * h)).round() as i64,
                        k,
                    );
                    if taken.insert(key) {
                        x.push(p);
                        walls.push(0);
                    }
                }
            }
        }
    }
    let n = x.len();
    // The face is the plane x = lo, the second of `box_planes`.
    let piston = piston_band_m.map(|band| super::Piston3::new(1, x_lo, band, &x, &walls));
    let rho = case.fluid.density_kg_m3;
    let g = case.fluid.gravity_m_s2;
    // Hydrostatic under the level of the region above each node (the first frame's pressure),
    // and π = −∇p = (0, ρg, 0) on every node of the water and on the wall nodes less than h
    // above it (a contact point's tetrahedra), so that the FIC term starts balanced.
    let level = |q: &[f64; 3]| {
        case.water
            .iter()
            .filter(|w| w.spans(q[0], 0.5 * h))
            .map(|w| w.level_at(q[0].clamp(w.x_start_m, w.x_end_m)))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let p = x
        .iter()
        .map(|q| (rho * g * (level(q) - q[1])).max(0.0))
        .collect();
    let pi = x
        .iter()
        .map(|q| {
            if level(q) >= q[1] - h {
                Vector3::new(0.0, rho * g, 0.0)
            } else {
                Vector3::zeros()
            }
        })
        .collect();
    Ok(Flow3 {
        x,
        u: vec![Vector3::zeros(); n],
        walls,
        planes,
        bed: (!bed.is_flat()).then_some(bed),
        slip: f.walls == WallCondition::Slip,
        p,
        tau: case.solver.tau_formula(true),
        gamma: case.solver.gamma,
        pi,
        h_m: h,
        alpha_h_m: case.solver.alpha * h,
        wall_margin_m: case.solver.wall_margin_h * h,
        rho_kg_m3: rho,
        mu_pa_s: case.fluid.viscosity_pa_s,
        smagorinsky_cs: case.solver.smagorinsky_cs,
        gravity_m_s2: Vector3::new(0.0, -g, 0.0),
        solver: match case.solver.pressure_solver {
            // A 3D Cholesky factor stops paying above CHOLESKY_MAX_UNKNOWNS: by size.
            PressureSolver::Cholesky => Solver3::Auto,
            PressureSolver::Cg => Solver3::Cg,
        },
        weak_surface_m: case.solver.weak_surface_length_h.map(|l| l * h),
        in_mesh: vec![false; n],
        surface: Vec::new(),
        tetrahedra: Vec::new(),
        was_free: Vec::new(),
        mesher: Default::default(),
        piston,
        insert_radius_m: case
            .solver
            .insert_radius_h
            .map(|r| super::nodes::insert_radius_3d(r, h)),
        remove_distance_m: case.solver.remove_distance_h.map(|d| d * h),
        merge_distance_m: case.solver.merge_surface_distance_h.map(|d| d * h),
        surface_filter: case.solver.surface_filter,
        relax: case
            .solver
            .volume_relaxation_s
            .map(|t_r| super::relax::Relax3::new(t_r, h, 0.0, width)),
    })
}
