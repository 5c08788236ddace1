//! Surf-zone observers: the free surface of the main body sampled along x, breaking onset and
//! breaker type, and the period-averaged flow at undertow stations.
//!
//! All of them read the simulation between steps; none changes it. Heights here are absolute
//! (m above the flume floor) unless a name says "above still water".

use crate::simulation::Simulation;
use crate::waves::breaker::{self, BreakerType};
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

/// What one breaker did, measured from the surface.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Breaker {
    /// Type decided from what follows the onset (see [`classify`]).
    pub observed: BreakerType,
    /// What triggered the onset: "kinematic" (crest particle faster than 0.85 c), "overturning"
    /// (the surface folds over a vertical line) or "steep_face" (front steeper than 60°).
    pub onset: &'static str,
    /// Crest position at onset, flume x, m.
    pub x_b_m: f64,
    /// Still-water depth under the crest at onset, m.
    pub h_b_m: f64,
    /// Crest height above the preceding trough at onset, m.
    pub height_b_m: f64,
    pub t_b_s: f64,
    /// Longest horizontal reach of an overturned part of the surface within half a period of
    /// the onset, m.
    pub overturn_reach_m: f64,
    /// How high the top of that longest fold stood above the onset's trough, m: a plunging jet
    /// is thrown from the crest, a collapsing front folds low on its face.
    pub overturn_top_m: f64,
    /// An enclosed air cavity appeared within half a period of the onset.
    pub cavity: bool,
    /// The front was steeper than 60° at some time within half a period of the onset.
    pub steep_face: bool,
    /// Where and when the front first folded over (a fold of 2 h or more by the followed
    /// crest) within half a period of the onset: the crest's flume x, m, its still depth, m,
    /// and the time, s. The same as the onset's when the onset was an overturning.
    pub fold_x_m: Option<f64>,
    pub fold_h_m: Option<f64>,
    pub fold_t_s: Option<f64>,
}

/// Surf-zone features of a breaker, to a type. Thresholds (method.md §6, with h_b / H_b
/// separating breaking offshore of the shoreline from breaking on it, and Galvin's (1968)
/// description of a collapsing breaker: the crest stays whole while the lower face steepens
/// and falls):
/// - a long fold is one that reaches 0.5 H_b or more (a plunging jet lands about a wave height
///   ahead of the crest; a spilling crest's roller is a fraction of it); it is thrown from the
///   crest when its top stands in the upper half of the wave (`top_m`, above the trough, at
///   least 0.5 H_b), and folds low on the face otherwise;
/// - offshore (h_b ≥ 0.5 H_b): plunging for a long fold from the crest, collapsing for a long
///   fold low on the face, spilling otherwise;
/// - at the shoreline (h_b < 0.5 H_b): plunging for a long fold from the crest that traps air,
///   collapsing otherwise (the front steepened or folded where the water ends).
pub fn classify(
    h_b_m: f64,
    height_b_m: f64,
    reach_m: f64,
    top_m: f64,
    cavity: bool,
) -> BreakerType {
    let long = reach_m >= 0.5 * height_b_m;
    let from_crest = top_m >= 0.5 * height_b_m;
    if h_b_m >= 0.5 * height_b_m {
        match (long, from_crest) {
            (true, true) => BreakerType::Plunging,
            (true, false) => BreakerType::Collapsing,
            (false, _) => BreakerType::Spilling,
        }
    } else if cavity && long && from_crest {
        BreakerType::Plunging
    } else {
        BreakerType::Collapsing
    }
}

/// The shortest fold that counts as a jet, and the horizontal span over which a face steeper
/// than 60° counts as a breaking face, m, for particle spacing `h_m` and wave height
/// `height_m`: 2h (one particle above the surface is not a jet) or 0.3 H, whichever is longer.
/// At 2 cm, 2h is the longer for waves up to 0.133 m (0.3 H = 3.75 cm for H = 0.125 m), so the
/// Ting & Kirby and collapsing cases keep the criteria of 2h (`plunging_slope025`, H = 0.30 m,
/// gets 9 cm); at finer spacings the criteria keep that physical size instead of shrinking
/// with h and seeing breaking in ever smaller folds and steps of the surface.
pub fn jet_length_m(h_m: f64, height_m: f64) -> f64 {
    (2.0 * h_m).max(0.3 * height_m)
}

/// Fixed quantities of a flume with a beach and a wavemaker.
#[derive(Debug, Clone)]
struct BeachSetup {
    g: f64,
    /// tan β of the beach.
    slope: f64,
    period_s: f64,
    height_m: f64,
    h: f64,
    /// Absolute still-water level over the beach, m.
    level_m: f64,
    /// Crests are searched between these x.
    x_min_m: f64,
    x_max_m: f64,
    /// Onsets before this time belong to the ramped first waves.
    gate_s: f64,
}

impl BeachSetup {
    /// The shortest fold that is a jet, and the span of a breaking face, m: `jet_length_m`.
    fn jet_m(&self) -> f64 {
        jet_length_m(self.h, self.height_m)
    }
}

/// The onset being watched.
#[derive(Debug, Clone, Copy)]
struct Watch {
    breaker: Breaker,
    until_s: f64,
    /// The breaking crest's x at the last frame, m: the breaker is followed, so that the folds
    /// and cavities of the bores shoreward of it are not taken for its own.
    crest_x_m: f64,
    /// The onset's trough, m above the floor.
    trough_m: f64,
}

/// Tells a new wave's breaking onset from the bores of the waves that broke before it.
///
/// In a periodic train several broken waves travel through the surf zone at once, and each
/// bore meets the onset criteria all the way to the shore. Breaking starts at the most seaward
/// breaking crest: each frame offers that crest, and it is a new onset when it lies more than
/// `jump_m` seaward of the last frame's (a bore only moves shoreward) and at least `min_gap_s`
/// after the last onset (a criterion that flickers off and on again is not a new wave). A
/// breaking crest last seen more than `min_gap_s / 2` ago is forgotten: on a steep beach each
/// wave has run up and gone before the next one breaks, at the same place.
#[derive(Debug, Clone, Copy, Default)]
pub struct OnsetTracker {
    /// (x, t) of the last frame's most seaward breaking crest.
    last: Option<(f64, f64)>,
    last_onset_s: Option<f64>,
}

impl OnsetTracker {
    /// Offers one frame's most seaward breaking crest (`None`: nothing breaks); true for a new
    /// onset.
    pub fn offer(&mut self, t_s: f64, x_m: Option<f64>, jump_m: f64, min_gap_s: f64) -> bool {
        let Some(x) = x_m else {
            return false;
        };
        let seaward = self
            .last
            .is_none_or(|(last, seen)| x < last - jump_m || t_s - seen > 0.5 * min_gap_s);
        let spaced = self.last_onset_s.is_none_or(|t0| t_s - t0 >= min_gap_s);
        self.last = Some((x, t_s));
        let new = seaward && spaced;
        if new {
            self.last_onset_s = Some(t_s);
        }
        new
    }
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

/// Watches every output frame for breaking; one per run.
#[derive(Debug, Clone)]
pub struct BreakingDetector {
    setup: Option<BeachSetup>,
    pub iribarren: f64,
    pub predicted: Option<BreakerType>,
    watch: Option<Watch>,
    tracker: OnsetTracker,
    /// Every breaker seen after the gate, in time order.
    pub breakers: Vec<Breaker>,
    /// Highest water above still level shoreward of the still shoreline, m.
    pub run_up_m: f64,
    shoreline_x_m: f64,
}

/// Breaking in `summary.json`.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BreakingSummary {
    pub iribarren: f64,
    pub predicted: &'static str,
    /// The Iribarren number at the breaking point, tan β / sqrt(H_b/L₀) with `H_b_m` below,
    /// and the type Battjes's (1974) breaker-point bands give it (spilling < 0.4 ≤ plunging
    /// < 2.0 ≤ `collapsing_or_surging`); null when nothing broke.
    pub iribarren_b: Option<f64>,
    pub battjes_b: Option<&'static str>,
    /// The most frequent type among the breakers the point is taken from (`basis`; the first
    /// of them on a tie), `surging` when no wave broke but the water ran up the beach, `none`
    /// otherwise.
    pub observed: &'static str,
    /// The breaking point (flume x) and its still depth: where each breaker's front first
    /// folded over ([`Breaker::fold_x_m`]; the onset's point for one that never folded), the
    /// visible start of breaking where experiments usually put the break point (a spilling
    /// crest drawing in air, a plunging face past vertical). With `basis` = "steady": the
    /// medians over the steady breakers (after `steady_from_s`, at least 0.75 H high); with
    /// "first": the first breaker's (no steady breaker); null when none broke.
    pub x_b_m: Option<f64>,
    /// `x_b_m − surf.x_origin_m`: the breaking point in the reference data's frame.
    pub x_b_data_frame_m: Option<f64>,
    pub h_b_m: Option<f64>,
    /// The same medians of the onsets (the crest at the first sign of breaking, see
    /// [`Breaker::onset`]), flume x and the data's frame, m.
    pub x_onset_m: Option<f64>,
    pub x_onset_data_frame_m: Option<f64>,
    /// The wave height (at the onset) and the time of the first breaker used.
    #[serde(rename = "H_b_m")]
    pub height_b_m: Option<f64>,
    pub t_b_s: Option<f64>,
    /// "steady", "first" or "none": what the point and the type above are taken from.
    pub basis: &'static str,
    /// The steady breakers are those from this time on (the surf averages' spin-up)...
    pub steady_from_s: f64,
    /// ...and this many of them were at least 0.75 H high.
    pub steady_breakers: usize,
    /// The first breaker of the run (often one of the ramped first waves).
    pub first: Option<Breaker>,
    /// Means over all breakers seen.
    pub x_b_mean_m: Option<f64>,
    #[serde(rename = "H_b_mean_m")]
    pub height_b_mean_m: Option<f64>,
    pub run_up_m: f64,
    pub breakers: Vec<Breaker>,
}

/// The most frequent type among `breakers` (the first one's on a tie).
fn most_frequent(breakers: &[&Breaker]) -> Option<BreakerType> {
    let mut best: Option<(usize, BreakerType)> = None;
    for b in breakers {
        let n = breakers.iter().filter(|o| o.observed == b.observed).count();
        if best.is_none_or(|(m, _)| n > m) {
            best = Some((n, b.observed));
        }
    }
    best.map(|b| b.1)
}

impl BreakingDetector {
    /// A detector for `sim`'s case: active with a beach and a wavemaker, idle otherwise.
    pub fn new(sim: &Simulation) -> Self {
        let case = &sim.case;
        let g = case.fluid.gravity_m_s2;
        let mut out = Self {
            setup: None,
            iribarren: f64::NAN,
            predicted: None,
            watch: None,
            tracker: OnsetTracker::default(),
            breakers: Vec::new(),
            run_up_m: 0.0,
            shoreline_x_m: f64::NAN,
        };
        let (Some(beach), Some(w)) = (&case.flume.beach, &case.wavemaker) else {
            return out;
        };
        out.iribarren = breaker::iribarren(beach.slope, w.height_m, w.period_s, g);
        out.predicted = Some(breaker::predicted_type(out.iribarren));
        let level = case.still_level_at(beach.toe_x_m).unwrap_or(0.0);
        let depth = case.paddle_depth_m().unwrap_or(level);
        out.shoreline_x_m = beach.toe_x_m + level / beach.slope;
        let wavelength = crate::waves::linear::wavelength(w.period_s, depth, g).unwrap_or(0.0);
        let celerity = wavelength / w.period_s;
        let h = case.particles.spacing_m;
        // The first full-height wave leaves the paddle after the ramp and reaches the toe
        // (toe − paddle)/c later; breakers before it are the ramp's.
        let travel = (beach.toe_x_m - w.x_m).max(0.0) / celerity.max(1e-9);
        out.setup = Some(BeachSetup {
            g,
            slope: beach.slope,
            period_s: w.period_s,
            height_m: w.height_m,
            h,
            level_m: level,
            x_min_m: (beach.toe_x_m - 0.25 * wavelength).max(w.x_m + 0.25 * wavelength),
            x_max_m: case.flume.length_m - 3.0 * h,
            gate_s: w.ramp_periods * w.period_s + travel,
        });
        out
    }

    /// The same detector for a wave that starts (ramps up) at `t0_s`, as when the lab changes
    /// the wave during a run: breakers count from `t0_s` plus the ramp and the travel time.
    pub fn starting_at(mut self, t0_s: f64) -> Self {
        if let Some(s) = self.setup.as_mut() {
            s.gate_s += t0_s;
        }
        self
    }

    pub fn active(&self) -> bool {
        self.setup.is_some()
    }

    /// Looks at one frame; returns the events to log (onset, classification).
    pub fn observe(&mut self, sim: &Simulation, profile: &SurfaceProfile) -> Vec<String> {
        let Some(s) = self.setup.clone() else {
            return Vec::new();
        };
        let t = sim.time_s;
        let mut events = Vec::new();
        // Run-up: the highest water shoreward of the still shoreline.
        let k0 = profile.index(self.shoreline_x_m);
        for k in k0..profile.crossings.len() {
            if let Some(y) = profile.top(k) {
                self.run_up_m = self.run_up_m.max(y - s.level_m);
            }
        }
        let k_min = profile.index(s.x_min_m);
        let k_max = profile.index(s.x_max_m);
        let span = |m: f64| ((m / profile.dx_m).round() as usize).max(1);
        let face_span = span(s.jet_m());

        // Overturned runs: contiguous samples with three or more crossings, kept when the
        // water on top of them moves shoreward on average. A breaker's jet is thrown ahead of
        // its crest; the roller of the backwash meeting the next wave folds seaward.
        // Each run: (start x, end x, its highest top), m.
        let mut runs: Vec<(f64, f64, f64)> = Vec::new();
        let mut start: Option<usize> = None;
        let (mut top_u1, mut top_y) = (0.0, f64::NEG_INFINITY);
        for k in k_min..=k_max + 1 {
            let folded = k <= k_max && profile.crossings[k].len() >= 3;
            match (folded, start) {
                (true, None) => {
                    start = Some(k);
                    (top_u1, top_y) = (profile.crossings[k][0].1, profile.crossings[k][0].0);
                }
                (true, Some(_)) => {
                    top_u1 += profile.crossings[k][0].1;
                    top_y = top_y.max(profile.crossings[k][0].0);
                }
                (false, Some(a)) => {
                    if top_u1 > 0.0 {
                        runs.push((profile.x_m(a), profile.x_m(k), top_y));
                    }
                    start = None;
                }
                (false, None) => {}
            }
        }
        let steep = |k: usize| -> bool {
            let (Some(a), Some(b)) = (profile.top(k), profile.top(k + face_span)) else {
                return false;
            };
            (a - b) / (face_span as f64 * profile.dx_m) > 3f64.sqrt()
        };
        let depth_at = |x: f64| s.level_m - sim.case.bed_y_at(x);

        // The breaker being watched: follow its crest for half a period and collect its
        // longest fold, an air cavity and a steep face near it (from H_b behind the crest to
        // 3 H_b ahead: a plunging jet lands about one to two wave heights ahead of it).
        if let Some(w) = &mut self.watch {
            let hb = w.breaker.height_b_m.max(2.0 * s.h);
            if let Some(x) = follow_crest(
                profile,
                w.crest_x_m,
                2.0 * s.h,
                s.level_m + 0.1 * s.height_m,
                k_min,
                k_max,
            ) {
                w.crest_x_m = x;
            }
            let (lo, hi) = (w.crest_x_m - hb, w.crest_x_m + 3.0 * hb);
            for (a, b, top) in &runs {
                if *b >= lo && *a <= hi {
                    if b - a > w.breaker.overturn_reach_m {
                        w.breaker.overturn_reach_m = b - a;
                        w.breaker.overturn_top_m = top - w.trough_m;
                    }
                    if b - a >= s.jet_m() && w.breaker.fold_x_m.is_none() {
                        w.breaker.fold_x_m = Some(w.crest_x_m);
                        w.breaker.fold_h_m = Some(depth_at(w.crest_x_m).max(0.0));
                        w.breaker.fold_t_s = Some(t);
                    }
                }
            }
            if profile.cavities.iter().any(|(c, _)| c.x >= lo && c.x <= hi) {
                w.breaker.cavity = true;
            }
            let (k_lo, k_hi) = (profile.index(lo).max(k_min), profile.index(hi).min(k_max));
            if (k_lo..k_hi.saturating_sub(face_span)).any(steep) {
                w.breaker.steep_face = true;
            }
            if t >= w.until_s {
                let mut b = w.breaker;
                b.observed = classify(
                    b.h_b_m,
                    b.height_b_m,
                    b.overturn_reach_m,
                    b.overturn_top_m,
                    b.cavity,
                );
                events.push(format!(
                    "breaker at t = {:.2} s classified {}: jet reach {:.3} m, its top {:.3} m above the trough, air cavity {}, front steeper than 60°: {}",
                    b.t_b_s,
                    b.observed.name(),
                    b.overturn_reach_m,
                    b.overturn_top_m,
                    if b.cavity { "yes" } else { "no" },
                    if b.steep_face { "yes" } else { "no" },
                ));
                self.breakers.push(b);
                self.watch = None;
            }
        }

        // The most seaward breaking crest of this frame: a local maximum of the top surface at
        // least H/4 above still water with a fold, a steep face or a fast crest by it.
        let mut onset: Option<(f64, &'static str, f64, f64)> = None;
        let mut k = k_min + 1;
        while k < k_max && onset.is_none() {
            let Some(y) = profile
                .crest(k)
                .filter(|y| y - s.level_m >= 0.25 * s.height_m)
            else {
                k += 1;
                continue;
            };
            let x = profile.x_m(k);
            let crest_above = y - s.level_m;
            let depth = depth_at(x);
            // The crest's own front: its folds up to 3 H ahead (where a jet lands), its face up
            // to 2 H ahead.
            let (reach_near, top_near) = runs
                .iter()
                .filter(|(a, b, _)| *b >= x - 2.0 * s.h && *a <= x + 3.0 * s.height_m)
                .map(|(a, b, top)| (b - a, *top))
                .fold(
                    (0.0, f64::NEG_INFINITY),
                    |m, r| if r.0 > m.0 { r } else { m },
                );
            let steep_near = (k..(k + span(2.0 * s.height_m)))
                .take_while(|&j| j + face_span <= k_max)
                .any(steep);
            if reach_near >= s.jet_m() {
                onset = Some((x, "overturning", reach_near, top_near));
            } else if steep_near {
                onset = Some((x, "steep_face", 0.0, 0.0));
            } else if depth >= 0.5 * s.height_m {
                // Kinematic: the fastest fluid particle of the crest against the crest's speed,
                // linear celerity at the local depth with the finite-amplitude factor.
                let c = crate::waves::linear::celerity(s.period_s, depth, s.g).unwrap_or(f64::NAN)
                    * (1.0 + crest_above / depth).sqrt();
                let p = &sim.particles;
                let u = (0..p.len())
                    .filter(|&i| p.is_fluid(i) && sim.solver.mesh.in_mesh[i])
                    .filter(|&i| {
                        let q = p.position[i];
                        (q.x - x).abs() <= 2.0 * s.h && q.y >= y - 2.0 * s.h
                    })
                    .map(|i| p.velocity[i].x)
                    .fold(f64::NEG_INFINITY, f64::max);
                if u >= 0.85 * c {
                    onset = Some((x, "kinematic", 0.0, 0.0));
                }
            }
            k += 1;
        }
        // A new wave's onset lies a quarter of its wavelength or more seaward of the last
        // frame's breaking crest.
        let jump = onset.map_or(0.0, |(x, _, _, _)| {
            0.25 * s.period_s * (s.g * (depth_at(x).max(s.h) + s.height_m)).sqrt()
        });
        let new = self
            .tracker
            .offer(t, onset.map(|o| o.0), jump, 0.5 * s.period_s);
        if !new || t < s.gate_s || self.watch.is_some() {
            return events;
        }
        let Some((x_b, trigger, reach_b, top_b)) = onset else {
            return events;
        };
        let depth = depth_at(x_b).max(0.0);
        let k_b = profile.index(x_b);
        let wavelength = s.period_s * (s.g * depth.max(s.h)).sqrt();
        let k_back = profile.index(x_b - 0.5 * wavelength).max(k_min);
        let crest = profile.top(k_b).unwrap_or(s.level_m);
        let trough = (k_back..=k_b)
            .filter_map(|k| profile.top(k))
            .fold(crest, f64::min);
        let breaker = Breaker {
            observed: BreakerType::Spilling,
            onset: trigger,
            x_b_m: x_b,
            h_b_m: depth,
            height_b_m: crest - trough,
            t_b_s: t,
            overturn_reach_m: if trigger == "overturning" {
                reach_b
            } else {
                0.0
            },
            overturn_top_m: if trigger == "overturning" {
                top_b - trough
            } else {
                0.0
            },
            cavity: false,
            steep_face: trigger == "steep_face",
            fold_x_m: (trigger == "overturning").then_some(x_b),
            fold_h_m: (trigger == "overturning").then_some(depth),
            fold_t_s: (trigger == "overturning").then_some(t),
        };
        events.push(format!(
            "breaking onset ({trigger}) at t = {t:.2} s, x = {x_b:.3} m, still depth {depth:.3} m, crest height {:.3} m",
            breaker.height_b_m
        ));
        self.watch = Some(Watch {
            breaker,
            until_s: t + 0.5 * s.period_s,
            crest_x_m: x_b,
            trough_m: trough,
        });
        events
    }

    /// The summary of the run (`None` without a beach and a wavemaker). `x_origin_m` shifts
    /// x_b into the reference data's frame.
    /// The run's breaking summary. A periodic wave train breaks at a steady point once the
    /// first waves have passed: the point is taken from the breakers after `steady_from_s`
    /// (the spin-up of the surf averages) that are at least 0.75 H high, which leaves out the
    /// ramp's low crests and the reforming bores shoreward of the break; without any, from the
    /// first breaker.
    pub fn summary(&self, x_origin_m: f64, steady_from_s: f64) -> Option<BreakingSummary> {
        let s = self.setup.as_ref()?;
        let steady: Vec<&Breaker> = self
            .breakers
            .iter()
            .filter(|b| b.t_b_s >= steady_from_s && b.height_b_m >= 0.75 * s.height_m)
            .collect();
        let first = self.breakers.first();
        let (basis, used): (&'static str, Vec<&Breaker>) = if !steady.is_empty() {
            ("steady", steady.clone())
        } else if let Some(b) = first {
            ("first", vec![b])
        } else {
            ("none", Vec::new())
        };
        let observed = match most_frequent(&used) {
            Some(t) => t.name(),
            None if self.run_up_m >= 0.25 * s.height_m => "surging",
            None => "none",
        };
        let pick = |f: fn(&Breaker) -> f64| {
            (!used.is_empty())
                .then(|| super::median(&used.iter().map(|b| f(b)).collect::<Vec<_>>()))
        };
        let mean = |f: fn(&Breaker) -> f64| {
            (!self.breakers.is_empty())
                .then(|| self.breakers.iter().map(f).sum::<f64>() / self.breakers.len() as f64)
        };
        let x_b = pick(|b| b.fold_x_m.unwrap_or(b.x_b_m));
        let x_onset = pick(|b| b.x_b_m);
        let height_b = pick(|b| b.height_b_m);
        let iribarren_b = height_b
            .filter(|h| *h > 0.0)
            .map(|h| breaker::iribarren(s.slope, h, s.period_s, s.g));
        Some(BreakingSummary {
            iribarren: self.iribarren,
            predicted: self.predicted.map_or("none", BreakerType::name),
            iribarren_b,
            battjes_b: iribarren_b.map(breaker::battjes_breaker_point_type),
            observed,
            x_b_m: x_b,
            x_b_data_frame_m: x_b.map(|x| x - x_origin_m),
            h_b_m: pick(|b| b.fold_h_m.unwrap_or(b.h_b_m)),
            x_onset_m: x_onset,
            x_onset_data_frame_m: x_onset.map(|x| x - x_origin_m),
            height_b_m: height_b,
            t_b_s: used.first().map(|b| b.t_b_s),
            basis,
            steady_from_s,
            steady_breakers: steady.len(),
            first: first.copied(),
            x_b_mean_m: mean(|b| b.x_b_m),
            height_b_mean_m: mean(|b| b.height_b_m),
            run_up_m: self.run_up_m,
            breakers: self.breakers.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_new_wave_breaks_seaward_of_the_bores_and_a_flicker_is_not_a_new_wave() {
        let mut tracker = OnsetTracker::default();
        let (jump, gap) = (0.5, 1.0);
        // The first breaking crest is an onset; the bore it becomes is not.
        assert!(tracker.offer(10.0, Some(6.0), jump, gap));
        for k in 1..25 {
            let t = 10.0 + 0.04 * k as f64;
            assert!(!tracker.offer(t, Some(6.0 + 1.3 * 0.04 * k as f64), jump, gap));
        }
        // Frames where nothing breaks change nothing.
        assert!(!tracker.offer(11.0, None, jump, gap));
        // The next wave breaks 2.6 m seaward of the bore, 2 s later: a new onset.
        assert!(tracker.offer(12.0, Some(6.05), jump, gap));
        // Its criterion flickers: the older bore is the most seaward for one frame, then the
        // same wave again, a little shoreward of its onset, within the gap: not a new onset.
        assert!(!tracker.offer(12.04, Some(8.7), jump, gap));
        assert!(!tracker.offer(12.08, Some(6.15), jump, gap));
        // A crest that moves back by less than the jump is the same wave, after the gap too.
        for k in 1..=35 {
            let t = 12.08 + 0.04 * k as f64;
            assert!(!tracker.offer(t, Some(6.15 + 0.02 * k as f64), jump, gap));
        }
        assert!(!tracker.offer(13.52, Some(6.6), jump, gap));
        // On a steep beach: nothing breaks for longer than half the gap, then the next wave
        // breaks where the last one did: a new onset.
        assert!(!tracker.offer(13.9, None, jump, gap));
        assert!(tracker.offer(14.1, Some(6.1), jump, gap));
    }

    #[test]
    fn the_jet_length_is_the_resolution_limit_or_a_fraction_of_the_wave() {
        // Ting & Kirby's cases at h = 2 cm keep 2h; at the thesis's 1.6 cm and at 1 cm the length
        // stays 0.3 H instead of following h down.
        assert_eq!(jet_length_m(0.02, 0.125), 0.04);
        assert_eq!(jet_length_m(0.02, 0.128), 0.04);
        assert!((jet_length_m(0.016, 0.125) - 0.0375).abs() < 1e-15);
        assert!((jet_length_m(0.01, 0.125) - 0.0375).abs() < 1e-15);
    }

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
}
