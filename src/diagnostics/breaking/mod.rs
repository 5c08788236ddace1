//! The breaker detector: breaking onset on a beach, each breaker followed for half the wave's
//! time scale and classified by what its front did, the run-up of the swash, and the run's
//! breaking summary.
//!
//! Everything that waits, spaces or measures in time uses one time scale: the period of a
//! periodic wave, or the effective period of a solitary wave
//! ([`crate::waves::solitary::effective_period_s`]), which has none.
//!
//! It reads the surface profile of each output frame ([`super::surface`]) and the simulation
//! (through [`FlumeState`]); it changes neither.

mod frame;
mod run_up;

use super::surface::{SurfaceProfile, film_edge, shoreline_tip, still_shoreline_x_m};
use crate::case::{Case, WaveTheory};
use crate::simulation::Simulation;
use crate::waves::breaker::{self, BreakerType};
use frame::{Frame, Onset};
pub use run_up::{FilmRunUp, SWEEP_FILM_M};
use run_up::{RUN_UP_FILMS_M, SwashRecord, highest_m};

/// What the detector reads of the simulation besides the surface profile: the time, the bed,
/// and how fast the water at a crest moves. [`Simulation`] is one; a test builds frames of its
/// own with another.
pub trait FlumeState {
    fn time_s(&self) -> f64;
    /// Height of the bed at `x_m`, m above the flume floor.
    fn bed_y_at(&self, x_m: f64) -> f64;
    /// The largest horizontal velocity of the meshed fluid within `radius_m` of `x_m` and no
    /// lower than `y_m − radius_m`, m/s (−∞ where there is none).
    fn fastest_u_near(&self, x_m: f64, y_m: f64, radius_m: f64) -> f64;
}

impl FlumeState for Simulation {
    fn time_s(&self) -> f64 {
        self.time_s
    }

    fn bed_y_at(&self, x_m: f64) -> f64 {
        self.case.bed_y_at(x_m)
    }

    fn fastest_u_near(&self, x_m: f64, y_m: f64, radius_m: f64) -> f64 {
        let p = &self.particles;
        (0..p.len())
            .filter(|&i| p.is_fluid(i) && self.solver.mesh.in_mesh[i])
            .filter(|&i| {
                let q = p.position[i];
                (q.x - x_m).abs() <= radius_m && q.y >= y_m - radius_m
            })
            .map(|i| p.velocity[i].x)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// What one breaker did, measured from the surface.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Breaker {
    /// Type decided from what follows the onset (see [`classify`]).
    pub observed: BreakerType,
    /// What triggered the onset: "kinematic" (crest particle faster than 0.85 c), "overturning"
    /// (the surface folds over a vertical line), "steep_face" (front steeper than 60° over
    /// ℓ_j) or "steep_lower_face" (a whole crest whose lower face is steeper than 60°, see
    /// `lower_face_fall_m`).
    pub onset: &'static str,
    /// Crest position at onset, flume x, m.
    pub x_b_m: f64,
    /// Still-water depth under the crest at onset, m.
    pub h_b_m: f64,
    /// Crest height above the preceding trough at onset (a solitary wave's: above still
    /// water), m.
    pub height_b_m: f64,
    pub t_b_s: f64,
    /// Longest horizontal reach of an overturned part of the surface within half a period (the
    /// wave's time scale, see the module) of the onset, m.
    pub overturn_reach_m: f64,
    /// How high the top of that longest fold stood above the onset's trough, m: a plunging jet
    /// is thrown from the crest, a collapsing front folds low on its face.
    pub overturn_top_m: f64,
    /// An enclosed air cavity appeared within half a period of the onset.
    pub cavity: bool,
    /// The front was steeper than 60° at some time within half a period of the onset.
    pub steep_face: bool,
    /// The longest fall of a lower face steeper than 60° under a whole crest within half a
    /// period of the onset (Galvin's collapsing front: the upper face nowhere steeper than
    /// 60°, the steep run below half the height above the trough and falling at least
    /// max(2 h, H_b/4)), m; 0 when the front never did that.
    pub lower_face_fall_m: f64,
    /// Where and when the front first folded over (a fold of 2 h or more by the followed
    /// crest) within half a period of the onset: the crest's flume x, m, its still depth, m,
    /// and the time, s. The same as the onset's when the onset was an overturning.
    pub fold_x_m: Option<f64>,
    pub fold_h_m: Option<f64>,
    pub fold_t_s: Option<f64>,
}

/// What [`classify`] reads of a breaker (the fields of [`Breaker`] it comes from in brackets).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BreakerFeatures {
    /// Still depth under the crest at the onset, m (`h_b_m`).
    pub h_b_m: f64,
    /// Crest height above the trough at the onset, m (`height_b_m`).
    pub height_b_m: f64,
    /// Longest fold of the front, m (`overturn_reach_m`).
    pub reach_m: f64,
    /// How high the fold's top stood above the trough, m (`overturn_top_m`).
    pub top_m: f64,
    /// The fold closed over air (`cavity`).
    pub cavity: bool,
    /// The lower face of the whole crest steepened and fell (`lower_face_fall_m` > 0).
    pub steep_lower_face: bool,
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
///   fold low on the face, collapsing without a long fold when the lower face of the whole
///   crest steepened past 60° (`steep_lower_face`, see [`Breaker::lower_face_fall_m`]),
///   spilling otherwise;
/// - at the shoreline (h_b < 0.5 H_b): plunging for a long fold from the crest that traps air,
///   collapsing otherwise (the front steepened or folded where the water ends).
pub fn classify(f: &BreakerFeatures) -> BreakerType {
    let long = f.reach_m >= 0.5 * f.height_b_m;
    let from_crest = f.top_m >= 0.5 * f.height_b_m;
    if f.h_b_m >= 0.5 * f.height_b_m {
        match (long, from_crest, f.steep_lower_face) {
            (true, true, _) => BreakerType::Plunging,
            (true, false, _) | (false, _, true) => BreakerType::Collapsing,
            (false, _, false) => BreakerType::Spilling,
        }
    } else if f.cavity && long && from_crest {
        BreakerType::Plunging
    } else {
        BreakerType::Collapsing
    }
}

/// The height, in units of the wave's H, of a crest whose breaking is the wave breaking: the
/// summary's breakers are at least this high (see [`BreakingDetector::summary`]).
pub const WAVE_BREAKER_H: f64 = 0.75;

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
    /// Beach toe, flume x, m: the swash tip is looked for shoreward of it.
    toe_x_m: f64,
    /// The wave's time scale: its period, or a solitary wave's effective period (see the
    /// module). The watch lasts half of it, onsets are at least half of it apart.
    time_scale_s: f64,
    /// One solitary wave: every breaker and the whole swash belong to it.
    single_wave: bool,
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

/// Watches every output frame for breaking; one per run.
#[derive(Debug, Clone)]
pub struct BreakingDetector {
    setup: Option<BeachSetup>,
    pub iribarren: f64,
    pub predicted: Option<BreakerType>,
    watch: Option<Watch>,
    tracker: OnsetTracker,
    /// Grilli et al.'s (1997) slope parameter S₀ of a solitary wave (`None` for a periodic
    /// one), which `predicted` comes from in its case.
    pub slope_parameter: Option<f64>,
    /// Every breaker seen after the gate, in time order.
    pub breakers: Vec<Breaker>,
    /// The shoreline tip's elevation above still water at each frame after the gate.
    swash: SwashRecord,
    /// The same for the edge of each of [`RUN_UP_FILMS_M`].
    films: Vec<SwashRecord>,
}

/// Breaking in `summary.json`.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BreakingSummary {
    /// tan β / sqrt(H/L₀), L₀ = g T²/2π, with T the wave's time scale (a solitary wave's
    /// effective period).
    pub iribarren: f64,
    /// The time scale, s: the period, or a solitary wave's effective period.
    pub time_scale_s: f64,
    /// A solitary wave's slope parameter S₀ = 1.521 tan β / sqrt(H/d) (Grilli et al. 1997);
    /// null for a periodic wave.
    pub slope_parameter: Option<f64>,
    /// The type the thesis's table gives `iribarren`, or for a solitary wave the type Grilli
    /// et al.'s bands give `slope_parameter`.
    pub predicted: &'static str,
    /// The Iribarren number at the breaking point, tan β / sqrt(H_b/L₀) with `H_b_m` below,
    /// and the type Battjes's (1974) breaker-point bands give it (spilling < 0.4 ≤ plunging
    /// < 2.0 ≤ `collapsing_or_surging`); null when nothing broke, and the type null for a
    /// solitary wave (the bands are a periodic wave's).
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
    /// The highest of `run_ups_m` (0 when no wave's run-up was recorded), m.
    pub run_up_m: f64,
    /// Each wave's run-up after the gate: the highest elevation above still water its
    /// shoreline tip (the edge of the swash) reached, m; one value for a solitary wave.
    pub run_ups_m: Vec<f64>,
    /// The run-up read at the edge of films of fixed depths instead of the tip.
    pub run_up_films: Vec<FilmRunUp>,
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
        Self::for_case(&sim.case)
    }

    /// A detector for `case`: active with a beach and a wavemaker, idle otherwise.
    ///
    /// A periodic wave's time scale is its period; its length the linear wavelength at the
    /// paddle; the first full-height wave leaves the paddle after the ramp and reaches the toe
    /// (toe − paddle)/c later, and breakers before that (the gate) are the ramp's. A solitary
    /// wave's time scale is its effective period T_eff, its length the effective length
    /// c·T_eff with c = sqrt(g (d + H)); it is the only wave, so there is no gate, and its type
    /// is predicted from Grilli et al.'s slope parameter, which needs no period (the Iribarren
    /// number with T_eff is reported beside it, but its bands were drawn for periodic waves).
    pub fn for_case(case: &Case) -> Self {
        let g = case.fluid.gravity_m_s2;
        let mut out = Self {
            setup: None,
            iribarren: f64::NAN,
            predicted: None,
            watch: None,
            tracker: OnsetTracker::default(),
            slope_parameter: None,
            breakers: Vec::new(),
            swash: SwashRecord::default(),
            films: vec![SwashRecord::default(); RUN_UP_FILMS_M.len()],
        };
        let (Some(beach), Some(w)) = (&case.flume.beach, &case.wavemaker) else {
            return out;
        };
        let level = case.still_level_at(beach.toe_x_m).unwrap_or(0.0);
        let depth = case.paddle_depth_m().unwrap_or(level);
        let single_wave = w.theory == WaveTheory::Solitary;
        let (time_scale, wavelength, gate) = if single_wave {
            let t_eff = crate::waves::solitary::effective_period_s(w.height_m, depth, g);
            let celerity = (g * (depth + w.height_m)).sqrt();
            (t_eff, celerity * t_eff, 0.0)
        } else {
            let wavelength = crate::waves::linear::wavelength(w.period_s, depth, g).unwrap_or(0.0);
            let celerity = wavelength / w.period_s;
            let travel = (beach.toe_x_m - w.x_m).max(0.0) / celerity.max(1e-9);
            (w.period_s, wavelength, w.ramp_periods * w.period_s + travel)
        };
        out.iribarren = breaker::iribarren(beach.slope, w.height_m, time_scale, g);
        if single_wave {
            let s0 = breaker::solitary_slope_parameter(beach.slope, w.height_m, depth);
            out.slope_parameter = Some(s0);
            out.predicted = Some(breaker::solitary_predicted_type(s0));
        } else {
            out.predicted = Some(breaker::predicted_type(out.iribarren));
        }
        let h = case.particles.spacing_m;
        out.setup = Some(BeachSetup {
            g,
            slope: beach.slope,
            toe_x_m: beach.toe_x_m.min(still_shoreline_x_m(case)),
            time_scale_s: time_scale,
            single_wave,
            height_m: w.height_m,
            h,
            level_m: level,
            x_min_m: (beach.toe_x_m - 0.25 * wavelength).max(w.x_m + 0.25 * wavelength),
            x_max_m: case.flume.length_m - 3.0 * h,
            gate_s: gate,
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
    ///
    /// In order: the shoreline tip; the breaker being watched, followed and, once its half
    /// period is over, classified; then this frame's most seaward breaking crest, which starts
    /// a new watch when it is a new wave's onset, after the ramped first waves, with no
    /// breaker being watched.
    pub fn observe(&mut self, sim: &dyn FlumeState, profile: &SurfaceProfile) -> Vec<String> {
        let Some(s) = self.setup.clone() else {
            return Vec::new();
        };
        let mut events = Vec::new();
        self.record_tip(&s, sim, profile);
        let frame = Frame::new(sim, profile, &s);
        events.extend(self.follow_watched(&frame));
        let onset = frame.most_seaward_onset();
        let new = self.offer_onset(&frame, onset.as_ref());
        if !new || frame.t < s.gate_s || self.watch.is_some() {
            return events;
        }
        let Some(onset) = onset else {
            return events;
        };
        events.push(self.start_watch(&frame, &onset));
        events
    }

    /// The shoreline tip's elevation above still water (see [`shoreline_tip`]), and the
    /// films' edges' ([`film_edge`]), after the gate: the ramp's waves run up too, but their
    /// run-up is not the wave's.
    fn record_tip(&mut self, s: &BeachSetup, sim: &dyn FlumeState, profile: &SurfaceProfile) {
        let t_s = sim.time_s();
        if t_s < s.gate_s {
            return;
        }
        let k_toe = profile.index(s.toe_x_m);
        if let Some((_, y)) = shoreline_tip(profile, k_toe) {
            self.swash.push(t_s, y - s.level_m);
        }
        for (record, film) in self.films.iter_mut().zip(RUN_UP_FILMS_M) {
            if let Some((_, y)) = film_edge(profile, k_toe, film, |x| sim.bed_y_at(x)) {
                record.push(t_s, y - s.level_m);
            }
        }
    }

    /// The breaker being watched: follows its crest and collects what its front does near
    /// it; once its half period is over, classifies it, keeps it and ends the watch. Returns
    /// the classification's event.
    fn follow_watched(&mut self, f: &Frame) -> Option<String> {
        let w = self.watch.as_mut()?;
        w.follow(f);
        if f.t < w.until_s {
            return None;
        }
        let b = w.classified();
        self.breakers.push(b);
        self.watch = None;
        Some(classified_event(&b))
    }

    /// Offers this frame's most seaward breaking crest to the onset tracker: true for a new
    /// wave's onset. A new wave's onset lies a quarter of its wavelength or more seaward of
    /// the last frame's breaking crest.
    fn offer_onset(&mut self, f: &Frame, onset: Option<&Onset>) -> bool {
        let s = f.s;
        let jump = onset.map_or(0.0, |o| {
            0.25 * s.time_scale_s * (s.g * (f.depth_at(o.x_m).max(s.h) + s.height_m)).sqrt()
        });
        self.tracker
            .offer(f.t, onset.map(|o| o.x_m), jump, 0.5 * s.time_scale_s)
    }

    /// Starts watching the breaker of a new onset: its still depth, and its height over the
    /// lowest top within half a wavelength behind it. Returns the onset's event.
    fn start_watch(&mut self, f: &Frame, onset: &Onset) -> String {
        let (s, t) = (f.s, f.t);
        let (x_b, trigger) = (onset.x_m, onset.trigger);
        let depth = f.depth_at(x_b).max(0.0);
        let (crest, trough) = f.crest_and_trough(x_b, depth);
        let overturning = trigger == "overturning";
        let breaker = Breaker {
            observed: BreakerType::Spilling,
            onset: trigger,
            x_b_m: x_b,
            h_b_m: depth,
            height_b_m: crest - trough,
            t_b_s: t,
            overturn_reach_m: if overturning { onset.reach_m } else { 0.0 },
            overturn_top_m: if overturning {
                onset.top_m - trough
            } else {
                0.0
            },
            cavity: false,
            steep_face: trigger == "steep_face",
            lower_face_fall_m: f.steep_lower_face_m(f.profile_index(x_b), trough, crest - trough),
            fold_x_m: overturning.then_some(x_b),
            fold_h_m: overturning.then_some(depth),
            fold_t_s: overturning.then_some(t),
        };
        let event = format!(
            "breaking onset ({trigger}) at t = {t:.2} s, x = {x_b:.3} m, still depth {depth:.3} m, crest height {:.3} m",
            breaker.height_b_m
        );
        self.watch = Some(Watch {
            breaker,
            until_s: t + 0.5 * s.time_scale_s,
            crest_x_m: x_b,
            trough_m: trough,
        });
        event
    }

    /// The summary of the run (`None` without a beach and a wavemaker). `x_origin_m` shifts
    /// x_b into the reference data's frame.
    /// The run's breaking summary. A periodic wave train breaks at a steady point once the
    /// first waves have passed: the point is taken from the breakers after `steady_from_s`
    /// (the spin-up of the surf averages) that are at least 0.75 H high, which leaves out the
    /// ramp's low crests and the reforming bores shoreward of the break; without any, from the
    /// first breaker at least 0.75 H high. An onset on a lower crest is not the wave breaking:
    /// where waves surge up a steep beach, the incoming face steepens over the backwash in
    /// features of 0.05–0.3 H, and the first of those must not type the run. A solitary wave is one wave: its point is its first breaker's
    /// (`basis` "first"; what breaks after it are its bore re-forming and its backwash).
    pub fn summary(&self, x_origin_m: f64, steady_from_s: f64) -> Option<BreakingSummary> {
        let s = self.setup.as_ref()?;
        let steady: Vec<&Breaker> = self
            .breakers
            .iter()
            .filter(|_| !s.single_wave)
            .filter(|b| b.t_b_s >= steady_from_s && b.height_b_m >= WAVE_BREAKER_H * s.height_m)
            .collect();
        let run_ups = self.swash.per_wave_m(s.time_scale_s, s.single_wave);
        let run_up = highest_m(&run_ups);
        let first = self.breakers.first();
        let first_wave = self
            .breakers
            .iter()
            .find(|b| b.height_b_m >= WAVE_BREAKER_H * s.height_m);
        let (basis, used): (&'static str, Vec<&Breaker>) = if !steady.is_empty() {
            ("steady", steady.clone())
        } else if let Some(b) = first_wave {
            ("first", vec![b])
        } else {
            ("none", Vec::new())
        };
        let observed = match most_frequent(&used) {
            Some(t) => t.name(),
            None if run_up >= 0.25 * s.height_m => "surging",
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
            .map(|h| breaker::iribarren(s.slope, h, s.time_scale_s, s.g));
        Some(BreakingSummary {
            iribarren: self.iribarren,
            time_scale_s: s.time_scale_s,
            slope_parameter: self.slope_parameter,
            predicted: self.predicted.map_or("none", BreakerType::name),
            iribarren_b,
            battjes_b: iribarren_b
                .filter(|_| !s.single_wave)
                .map(breaker::battjes_breaker_point_type),
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
            run_up_m: run_up,
            run_ups_m: run_ups,
            run_up_films: self
                .films
                .iter()
                .zip(RUN_UP_FILMS_M)
                .map(|(record, film_m)| {
                    let run_ups_m = record.per_wave_m(s.time_scale_s, s.single_wave);
                    FilmRunUp {
                        film_m,
                        run_up_m: highest_m(&run_ups_m),
                        run_ups_m,
                    }
                })
                .collect(),
            breakers: self.breakers.clone(),
        })
    }
}

/// The event of a classified breaker.
fn classified_event(b: &Breaker) -> String {
    format!(
        "breaker at t = {:.2} s classified {}: jet reach {:.3} m, its top {:.3} m above the trough, air cavity {}, front steeper than 60°: {}, steep lower face under a whole crest: {:.3} m",
        b.t_b_s,
        b.observed.name(),
        b.overturn_reach_m,
        b.overturn_top_m,
        if b.cavity { "yes" } else { "no" },
        if b.steep_face { "yes" } else { "no" },
        b.lower_face_fall_m,
    )
}

#[cfg(test)]
mod tests;
