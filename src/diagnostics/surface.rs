//! The free surface of the main body of water, sampled along x: every crossing of a vertical
//! line with the surface (overturned parts and enclosed air cavities included), the crests on
//! it and the crest a breaker is followed to, the shoreline tip of the swash, and where the
//! still water meets the bed.
//!
//! All of it reads the simulation between steps; none changes it. Heights here are absolute
//! (m above the flume floor) unless a name says "above still water".

use crate::case::Case;
use crate::simulation::Simulation;
use nalgebra::Vector2;

/// The free surface of the main body of water at one instant, sampled every `dx_m` from x = 0.
///
/// Each sample holds the crossings of the vertical line with the outer boundary of the main
/// body, wall–wall edges left out (the bed and the walls are not free surface) and the edges of
/// enclosed air cavities left out (they are reported in `cavities`). One crossing is an ordinary
/// surface; three or more mean the surface folds over the line: an overturning face or jet.
#[derive(Debug, Clone, Default)]
pub struct SurfaceProfile {
    pub dx_m: f64,
    /// Per sample: (y, u1) at each crossing, highest first; y in m, u1 in m/s.
    pub crossings: Vec<Vec<(f64, f64)>>,
    /// Enclosed air cavities of the main body larger than 3 h²: (centroid, area in m²).
    pub cavities: Vec<(Vector2<f64>, f64)>,
}

impl SurfaceProfile {
    pub fn x_m(&self, k: usize) -> f64 {
        k as f64 * self.dx_m
    }

    /// Height of the highest crossing at sample `k` (`None` where no water stands).
    pub fn top(&self, k: usize) -> Option<f64> {
        self.crossings[k].first().map(|c| c.0)
    }

    /// Height of the top at sample `k` when it is a crest: at least its left neighbour's and
    /// above its right one's (`None` otherwise, at the ends, or where no water stands).
    pub fn crest(&self, k: usize) -> Option<f64> {
        let top = |j: usize| self.crossings.get(j)?.first().map(|c| c.0);
        let (y, left, right) = (top(k)?, top(k.checked_sub(1)?)?, top(k + 1)?);
        (y >= left && y > right).then_some(y)
    }

    /// The sample nearest to `x_m`.
    pub fn index(&self, x_m: f64) -> usize {
        ((x_m / self.dx_m).round().max(0.0) as usize).min(self.crossings.len().saturating_sub(1))
    }
}

/// Samples the free surface of the main body of `sim` every `dx_m`.
pub fn surface_profile(sim: &Simulation, dx_m: f64) -> SurfaceProfile {
    let p = &sim.particles;
    let mesh = &sim.solver.mesh;
    let h = sim.case.particles.spacing_m;
    let samples = (sim.case.flume.length_m / dx_m).floor() as usize + 1;
    let mut out = SurfaceProfile {
        dx_m,
        crossings: vec![Vec::new(); samples],
        cavities: Vec::new(),
    };
    let (label, main) = mesh.main_body(p);
    let Some(main) = main else {
        return out;
    };
    // Boundary loops of the main body: boundary edges joined through shared nodes. Edges run
    // with the water on their left, so a loop's Σ (x_a y_b − x_b y_a)/2 is its enclosed area,
    // positive for the outer boundary and negative around a hole.
    let edges: Vec<[usize; 2]> = mesh
        .boundary_edges
        .iter()
        .map(|e| [e[0] as usize, e[1] as usize])
        .filter(|e| label[e[0]] == main && label[e[1]] == main)
        .collect();
    let mut parent: Vec<usize> = (0..edges.len()).collect();
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let mut first_edge_at = std::collections::HashMap::with_capacity(2 * edges.len());
    for (k, e) in edges.iter().enumerate() {
        for v in e {
            if let Some(&other) = first_edge_at.get(v) {
                let (a, b) = (find(&mut parent, k), find(&mut parent, other));
                parent[a] = b;
            } else {
                first_edge_at.insert(*v, k);
            }
        }
    }
    let mut area = vec![0.0; edges.len()];
    let mut centroid = vec![Vector2::zeros(); edges.len()];
    let mut all_fluid = vec![true; edges.len()];
    for (k, e) in edges.iter().enumerate() {
        let r = find(&mut parent, k);
        let (a, b) = (p.position[e[0]], p.position[e[1]]);
        let cross = a.x * b.y - b.x * a.y;
        area[r] += 0.5 * cross;
        centroid[r] += (a + b) * cross / 6.0;
        all_fluid[r] &= p.is_fluid(e[0]) && p.is_fluid(e[1]);
    }
    let mut is_hole = vec![false; edges.len()];
    for k in 0..edges.len() {
        if parent[k] == k && area[k] < 0.0 {
            is_hole[k] = true;
            if all_fluid[k] && -area[k] > 3.0 * h * h {
                out.cavities.push((centroid[k] / area[k], -area[k]));
            }
        }
    }
    for (k, e) in edges.iter().enumerate() {
        if is_hole[find(&mut parent, k)] || (!p.is_fluid(e[0]) && !p.is_fluid(e[1])) {
            continue;
        }
        let (a, b) = (p.position[e[0]], p.position[e[1]]);
        let (ua, ub) = (p.velocity[e[0]].x, p.velocity[e[1]].x);
        let (lo, hi) = if a.x <= b.x { (a.x, b.x) } else { (b.x, a.x) };
        if hi == lo {
            continue;
        }
        // Samples with lo ≤ x < hi: a line through a node is crossed once, not twice.
        let first = (lo / dx_m).ceil().max(0.0) as usize;
        let mut s = first;
        while s < samples && (s as f64) * dx_m < hi {
            let x = s as f64 * dx_m;
            let f = (x - a.x) / (b.x - a.x);
            out.crossings[s].push((a.y + f * (b.y - a.y), ua + f * (ub - ua)));
            s += 1;
        }
    }
    for c in &mut out.crossings {
        c.sort_by(|a, b| b.0.total_cmp(&a.0));
    }
    out
}

/// The crest followed from `from_x_m`: the first local maximum of the top surface at or
/// shoreward of `from_x_m − back_m` that stands at least `min_y` high, between samples `k_min`
/// and `k_max`.
pub fn follow_crest(
    profile: &SurfaceProfile,
    from_x_m: f64,
    back_m: f64,
    min_y: f64,
    k_min: usize,
    k_max: usize,
) -> Option<f64> {
    let k0 = profile.index(from_x_m - back_m).max(k_min + 1);
    (k0..k_max).find_map(|k| {
        profile
            .crest(k)
            .filter(|y| *y >= min_y)
            .map(|_| profile.x_m(k))
    })
}

/// The shoreline tip: the most shoreward sample at or beyond `k_from` where water stands, as
/// (x, height of its top), m; `None` when no water stands there.
///
/// The main body is one connected piece of water, so the samples it covers are contiguous and
/// the last of them is the edge of the swash. There the top is the water's edge meeting the
/// bed: the boundary edge from the last fluid particle down to the bed node ahead of it, crossed
/// within one sample of that node, so the height stands above the bed by less than the film's
/// thickness at the last particle (at most about half a particle spacing for samples h/2
/// apart). Where the still water stands against the far wall, the tip is the water at the wall.
/// A plunging jet flying over the dry beach ahead of the swash is part of the main body too,
/// and until it lands the tip is its top; [`film_edge`] leaves it out.
pub fn shoreline_tip(profile: &SurfaceProfile, k_from: usize) -> Option<(f64, f64)> {
    (k_from..profile.crossings.len())
        .rev()
        .find_map(|k| profile.top(k).map(|y| (profile.x_m(k), y)))
}

/// The edge of a film at least `film_m` thick: the most shoreward sample at or beyond `k_from`
/// where the water lying on the bed (`bed_y_at`, m above the floor) is at least `film_m` deep,
/// as (x, height of that water's surface), m; `None` when it is nowhere that deep there.
///
/// The crossings alternate between entering and leaving the water from the top down, and with
/// an odd number of them the last one is the surface of the water that meets the bed; that
/// layer's depth is what counts. A jet or a splash above it (an even number of crossings over a
/// dry bed, or the upper pairs over a wet one) is not run-up and is left out. This is what a
/// run-up wire a height `film_m` above the bed reads; unlike [`shoreline_tip`] it does not
/// follow a film thinner than `film_m`, whose tip, one particle thick, climbs further at each
/// finer spacing.
pub fn film_edge(
    profile: &SurfaceProfile,
    k_from: usize,
    film_m: f64,
    bed_y_at: impl Fn(f64) -> f64,
) -> Option<(f64, f64)> {
    (k_from..profile.crossings.len()).rev().find_map(|k| {
        let c = &profile.crossings[k];
        if c.len().is_multiple_of(2) {
            return None;
        }
        let surface = c[c.len() - 1].0;
        let x = profile.x_m(k);
        (surface - bed_y_at(x) >= film_m).then_some((x, surface))
    })
}

/// The still shoreline, flume x, m: where the still water surface meets the bed as it rises
/// shoreward, or the far wall (`flume.length_m`) where the bed never rises out of the water.
///
/// - A plane beach (`flume.beach`): toe + level / tan β, with the still level over the toe,
///   while that level lies below the top of the beach's face (the face stops at 90 % of the
///   wall height, or at the far wall).
/// - A polyline bed (`flume.bed_m`, or the flat floor): the first x, walking shoreward from the
///   paddle's water (x_m + h, where the paddle depth is taken; without a wavemaker, the start
///   of the first water region), at which the bed reaches the still level there, linear
///   between the bed's points.
///
/// The level is 0 where no water stands at its reference point.
pub fn still_shoreline_x_m(case: &Case) -> f64 {
    let length = case.flume.length_m;
    if let Some(b) = &case.flume.beach {
        let level = case.still_level_at(b.toe_x_m).unwrap_or(0.0);
        let face_top = (0.9 * case.flume.height_m).min(b.slope * (length - b.toe_x_m));
        return if level <= face_top {
            b.toe_x_m + level / b.slope
        } else {
            length
        };
    }
    let x0 = match &case.wavemaker {
        Some(w) => w.x_m + case.particles.spacing_m,
        None => case.water.first().map_or(0.0, |w| w.x_start_m),
    };
    let level = case.still_level_at(x0).unwrap_or(0.0);
    let (mut xa, mut ya) = (x0, case.bed_y_at(x0));
    if ya >= level {
        return x0;
    }
    for [xb, yb] in case.flume.bed_points().into_iter().filter(|p| p[0] > x0) {
        if yb >= level {
            return xa + (level - ya) / (yb - ya) * (xb - xa);
        }
        (xa, ya) = (xb, yb);
    }
    length
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_followed_crest_is_the_next_one_shoreward() {
        // Two crests 0.02 m high, at x = 1.0 and 3.0 m, on a level of 0.
        let dx = 0.01;
        let crossings = (0..=400)
            .map(|k| {
                let x = k as f64 * dx;
                let y = 0.02 * (-((x - 1.0) / 0.2).powi(2)).exp()
                    + 0.02 * (-((x - 3.0) / 0.2).powi(2)).exp();
                vec![(y, 0.0)]
            })
            .collect();
        let profile = SurfaceProfile {
            dx_m: dx,
            crossings,
            cavities: Vec::new(),
        };
        let crest = |from: f64| follow_crest(&profile, from, 0.04, 0.01, 0, 400);
        // From just shoreward of a crest, it is found within the allowed step back.
        assert!((crest(1.02).unwrap() - 1.0).abs() < 1e-9);
        // From further shoreward, the next crest is taken.
        assert!((crest(1.2).unwrap() - 3.0).abs() < 1e-9);
        // Nothing high enough shoreward of the last crest.
        assert_eq!(crest(3.3), None);
    }

    #[test]
    fn the_shoreline_tip_is_the_edge_of_the_water_not_a_higher_bore() {
        // Level 0.3 m on a 1:15 beach from x = 2.7 m (still shoreline 7.2 m): a bore 0.09 m
        // above still water at x = 7.4 m, and a film 5 mm deep up to x = 7.6 m.
        let dx = 0.01;
        let bed = |x: f64| ((x - 2.7) / 15.0).max(0.0);
        let crossings = (0..=1000)
            .map(|k| {
                let x = k as f64 * dx;
                if x > 7.6 + 1e-9 {
                    return Vec::new();
                }
                let bore = 0.3 + 0.09 * (-((x - 7.4) / 0.1).powi(2)).exp();
                vec![(bore.max(bed(x) + 0.005), 0.5)]
            })
            .collect();
        let profile = SurfaceProfile {
            dx_m: dx,
            crossings,
            cavities: Vec::new(),
        };
        let (x, y) = shoreline_tip(&profile, profile.index(2.7)).unwrap();
        assert!((x - 7.6).abs() < 1e-9, "{x}");
        assert!((y - (bed(7.6) + 0.005)).abs() < 1e-9, "{y}");
        assert!(
            y - 0.3 < 0.04,
            "the tip stands {} m above still water",
            y - 0.3
        );
        assert_eq!(shoreline_tip(&profile, profile.index(7.7)), None);
    }

    #[test]
    fn the_film_edge_reads_the_water_on_the_bed_and_not_a_jet_above_it() {
        // A 1:4 beach from x = 1 m (bed 0.25 (x − 1)), still level 0.5 m: water 0.5 m deep
        // up to x = 2 m, then a film thinning linearly from 0.04 m at x = 2 m to nothing at
        // x = 2.4 m; over x = 2.25–2.35 m a jet 2 mm thick stands 0.2 m above the film, and
        // over the dry bed at x = 2.45–2.5 m a jet 3 cm thick stands 0.1 m above the bed.
        let bed = |x: f64| (0.25 * (x - 1.0)).max(0.0);
        let film = |x: f64| bed(x) + 0.04 * (2.4 - x) / 0.4;
        let dx = 0.005;
        let crossings = (0..=600)
            .map(|k| {
                let x = k as f64 * dx;
                if x < 2.0 {
                    return vec![(0.5_f64.max(bed(x) + 0.04), 0.0)];
                }
                if (2.45..2.5).contains(&x) {
                    return vec![(bed(x) + 0.13, 0.0), (bed(x) + 0.1, 0.0)];
                }
                if x >= 2.4 {
                    return Vec::new();
                }
                let mut c = vec![(film(x), 0.0)];
                if (2.25..2.35).contains(&x) {
                    c.insert(0, (film(x) + 0.202, 0.0));
                    c.insert(1, (film(x) + 0.2, 0.0));
                }
                c
            })
            .collect();
        let profile = SurfaceProfile {
            dx_m: dx,
            crossings,
            cavities: Vec::new(),
        };
        let edge = |depth: f64| film_edge(&profile, profile.index(1.0), depth, bed).unwrap();
        // The film is 0.02 m deep at x = 2.2 m and 0.01 m at 2.3 m; neither jet counts, the
        // one over the film (its top 0.2 m up) nor the one over the dry bed (3 cm thick)...
        for (depth, at) in [(0.02, 2.2), (0.01, 2.3)] {
            let (x, y) = edge(depth);
            assert!(
                (x - at).abs() <= dx + 1e-9,
                "edge of the {depth} m film at {x}"
            );
            assert!((y - film(x)).abs() < 1e-9, "{y}");
        }
        // ...while the tip follows the last water, the dry bed's jet.
        let (tip, _) = shoreline_tip(&profile, profile.index(1.0)).unwrap();
        assert!(tip > 2.49, "{tip}");
        // The film is nowhere 0.1 m deep; the water is nowhere 1 m deep.
        let (x, _) = edge(0.1);
        assert!((x - (2.0 - dx)).abs() < 1e-9, "{x}");
        assert_eq!(film_edge(&profile, profile.index(1.0), 1.0, bed), None);
    }

    /// The shoreline of every case in cases/: on a plane beach toe + level / tan β (the
    /// shorelines the cases' comments give), on a bed polyline that rises above the level
    /// where it does, elsewhere the far wall.
    #[test]
    fn the_still_shoreline_of_every_case() {
        let mut seen = 0;
        for entry in std::fs::read_dir("cases").unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_none_or(|e| e != "toml") {
                continue;
            }
            let case = Case::load(&path, &[]).unwrap();
            let x = still_shoreline_x_m(&case);
            println!("{}: still shoreline x = {x} m", case.name);
            let bed = &case.flume.bed_m;
            let expected = match &case.flume.beach {
                Some(b) => b.toe_x_m + case.still_level_at(b.toe_x_m).unwrap() / b.slope,
                // A bed polyline (the 3D tanks'): where its last rise reaches the level.
                None if bed.len() > 1 && bed[bed.len() - 1][1] > case.water[0].depth_m => {
                    let level = case.water[0].depth_m;
                    let w = bed.windows(2).find(|w| w[1][1] >= level).unwrap();
                    w[0][0] + (level - w[0][1]) * (w[1][0] - w[0][0]) / (w[1][1] - w[0][1])
                }
                None => case.flume.length_m,
            };
            assert!(
                (x - expected).abs() < 1e-12,
                "{}: {x} {expected}",
                case.name
            );
            seen += 1;
        }
        assert!(seen >= 13, "{seen} cases");
        let beach = Case::load(std::path::Path::new("cases/teaching_beach.toml"), &[]).unwrap();
        assert!((still_shoreline_x_m(&beach) - 7.0).abs() < 1e-12);
    }

    /// A beach given as a polyline meets the water where the plane beach does; a beach whose
    /// face stops below the still level, and a bed that never reaches it, leave the water
    /// against the far wall.
    #[test]
    fn the_still_shoreline_of_a_polyline_bed_and_a_drowned_beach() {
        let load = |overrides: &[&str]| {
            let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
            Case::load(std::path::Path::new("cases/teaching_beach.toml"), &o).unwrap()
        };
        // Toe at 3 m, 1:10, level 0.4 m: the shoreline at 7 m either way.
        let mut polyline = load(&[]);
        polyline.flume.bed_m = polyline.flume.bed_points();
        polyline.flume.beach = None;
        assert!((still_shoreline_x_m(&polyline) - 7.0).abs() < 1e-12);
        // A shoal that rises to 0.3 m and falls again does not reach the level.
        polyline.flume.bed_m = vec![[0.0, 0.0], [4.0, 0.3], [6.0, 0.0], [8.0, 0.0]];
        assert_eq!(still_shoreline_x_m(&polyline), 8.0);
        // 1:20 from 3 m rises 0.25 m by the end wall: the water stands against it.
        let gentle = load(&["flume.beach.slope=0.05"]);
        assert_eq!(still_shoreline_x_m(&gentle), 8.0);
    }
}
