//! One output frame as the breaker detector sees it: the overturned runs of the surface, its
//! steep faces, its most seaward breaking crest, and the watched breaker followed through it.

use super::{BeachSetup, Breaker, BreakerFeatures, FlumeState, Watch, classify};
use crate::diagnostics::surface::{SurfaceProfile, follow_crest};

impl Watch {
    /// Follows the breaking crest to this frame and collects near it (from H_b behind the
    /// crest to 3 H_b ahead: a plunging jet lands about one to two wave heights ahead of it)
    /// its longest fold, an air cavity and a steep face.
    pub(super) fn follow(&mut self, f: &Frame) {
        let s = f.s;
        let hb = self.breaker.height_b_m.max(2.0 * s.h);
        if let Some(x) = follow_crest(
            f.profile,
            self.crest_x_m,
            2.0 * s.h,
            s.level_m + 0.1 * s.height_m,
            f.k_min,
            f.k_max,
        ) {
            self.crest_x_m = x;
        }
        let (lo, hi) = (self.crest_x_m - hb, self.crest_x_m + 3.0 * hb);
        self.collect_folds(f, lo, hi);
        if f.profile
            .cavities
            .iter()
            .any(|(c, _)| c.x >= lo && c.x <= hi)
        {
            self.breaker.cavity = true;
        }
        let (k_lo, k_hi) = (
            f.profile.index(lo).max(f.k_min),
            f.profile.index(hi).min(f.k_max),
        );
        if (k_lo..k_hi.saturating_sub(f.face_span)).any(|k| f.steep(k)) {
            self.breaker.steep_face = true;
        }
        let k_c = f.profile.index(self.crest_x_m);
        let fall = f.steep_lower_face_m(k_c, self.trough_m, hb);
        if fall > self.breaker.lower_face_fall_m {
            self.breaker.lower_face_fall_m = fall;
        }
    }

    /// The overturned runs of the frame between `lo` and `hi`: the longest (and its top above
    /// the onset's trough), and the first that is a jet (where and when the front folded).
    fn collect_folds(&mut self, f: &Frame, lo: f64, hi: f64) {
        let s = f.s;
        for (a, b, top) in &f.runs {
            if *b >= lo && *a <= hi {
                if b - a > self.breaker.overturn_reach_m {
                    self.breaker.overturn_reach_m = b - a;
                    self.breaker.overturn_top_m = top - self.trough_m;
                }
                if b - a >= s.jet_m() && self.breaker.fold_x_m.is_none() {
                    self.breaker.fold_x_m = Some(self.crest_x_m);
                    self.breaker.fold_h_m = Some(f.depth_at(self.crest_x_m).max(0.0));
                    self.breaker.fold_t_s = Some(f.t);
                }
            }
        }
    }

    /// The watched breaker with its type decided from what it did (see [`classify`]).
    pub(super) fn classified(&self) -> Breaker {
        let mut b = self.breaker;
        b.observed = classify(&BreakerFeatures {
            h_b_m: b.h_b_m,
            height_b_m: b.height_b_m,
            reach_m: b.overturn_reach_m,
            top_m: b.overturn_top_m,
            cavity: b.cavity,
            steep_lower_face: b.lower_face_fall_m > 0.0,
        });
        b
    }
}

/// A frame's most seaward breaking crest.
#[derive(Debug, Clone, Copy)]
pub(super) struct Onset {
    /// The crest's x, m.
    pub(super) x_m: f64,
    /// "overturning", "steep_face", "steep_lower_face" or "kinematic" (see
    /// [`Breaker::onset`]).
    pub(super) trigger: &'static str,
    /// For an overturning: the longest fold of the crest's front, and how high its top
    /// stands above the floor, m (0 otherwise).
    pub(super) reach_m: f64,
    pub(super) top_m: f64,
}

/// One output frame as the detector sees it.
pub(super) struct Frame<'a> {
    state: &'a dyn FlumeState,
    profile: &'a SurfaceProfile,
    /// The beach and the wave the detector watches.
    pub(super) s: &'a BeachSetup,
    /// The frame's time, s.
    pub(super) t: f64,
    /// Crests are searched between these samples.
    k_min: usize,
    k_max: usize,
    /// The samples over which a face steeper than 60° is a breaking face.
    face_span: usize,
    /// The overturned runs of the surface: (start x, end x, highest top), m.
    runs: Vec<(f64, f64, f64)>,
}

impl<'a> Frame<'a> {
    pub(super) fn new(
        state: &'a dyn FlumeState,
        profile: &'a SurfaceProfile,
        s: &'a BeachSetup,
    ) -> Self {
        let k_min = profile.index(s.x_min_m);
        let k_max = profile.index(s.x_max_m);
        let mut frame = Frame {
            state,
            profile,
            s,
            t: state.time_s(),
            k_min,
            k_max,
            face_span: 1,
            runs: overturned_runs(profile, k_min, k_max),
        };
        frame.face_span = frame.span(s.jet_m());
        frame
    }

    /// The profile's sample nearest to `x_m`.
    pub(super) fn profile_index(&self, x_m: f64) -> usize {
        self.profile.index(x_m)
    }

    /// A length in samples (at least one).
    fn span(&self, m: f64) -> usize {
        ((m / self.profile.dx_m).round() as usize).max(1)
    }

    /// Whether the top falls faster than 60° over the `face_span` samples from `k`.
    fn steep(&self, k: usize) -> bool {
        let profile = self.profile;
        let (Some(a), Some(b)) = (profile.top(k), profile.top(k + self.face_span)) else {
            return false;
        };
        (a - b) / (self.face_span as f64 * profile.dx_m) > 3f64.sqrt()
    }

    /// Galvin's (1968) collapsing front, seen on the crest at sample `k` of a wave `height_m`
    /// high over its trough at `trough_m` (m above the floor): the crest stays whole while the
    /// lower face steepens. Walking down the front from the crest (up to 2 H ahead, until the
    /// top rises again or the water ends): the upper face, down to half the height above the
    /// trough, is nowhere steeper than 60° from one sample to the next, and the lower face
    /// below it has a run of samples steeper than 60° that falls at least max(2 h, H/4) (two
    /// particle spacings: a single edge of the surface is not a face). Returns that run's
    /// fall, m, or 0 when the front is not such a face.
    ///
    /// A face steep from the crest down (a spilling crest's roller, a bore) is not a whole
    /// crest; a face steep over ℓ_j anywhere is also the steep-face onset, and either way its
    /// type comes from what follows ([`classify`]).
    pub(super) fn steep_lower_face_m(&self, k: usize, trough_m: f64, height_m: f64) -> f64 {
        let (s, profile) = (self.s, self.profile);
        let mid_m = trough_m + 0.5 * height_m;
        let tan60 = 3f64.sqrt();
        let end = (k + self.span(2.0 * s.height_m)).min(self.k_max);
        let mut run_top: Option<f64> = None;
        let mut fall_m: f64 = 0.0;
        for j in k..end {
            let (Some(a), Some(b)) = (profile.top(j), profile.top(j + 1)) else {
                break;
            };
            if b > a {
                break;
            }
            let steep = (a - b) / profile.dx_m > tan60;
            if a > mid_m {
                if steep {
                    return 0.0;
                }
                continue;
            }
            if steep {
                let top = *run_top.get_or_insert(a);
                fall_m = fall_m.max(top - b);
            } else {
                run_top = None;
            }
        }
        if fall_m >= (2.0 * s.h).max(0.25 * height_m) {
            fall_m
        } else {
            0.0
        }
    }

    /// Whether the crest at sample `k` (flume `x`, over `depth` m of still water) has a steep
    /// lower face under a whole crest, with its height over the trough behind it.
    fn whole_crest_with_steep_lower_face(&self, k: usize, x: f64, depth: f64) -> bool {
        let (crest, trough) = self.crest_and_trough(x, depth.max(0.0));
        self.steep_lower_face_m(k, trough, crest - trough) > 0.0
    }

    /// Still-water depth at `x`, m (negative where the bed stands above the still level).
    pub(super) fn depth_at(&self, x: f64) -> f64 {
        self.s.level_m - self.state.bed_y_at(x)
    }

    /// The most seaward breaking crest of this frame: a local maximum of the top surface at
    /// least H/4 above still water with a fold, a steep face or a fast crest by it.
    pub(super) fn most_seaward_onset(&self) -> Option<Onset> {
        let s = self.s;
        ((self.k_min + 1)..self.k_max).find_map(|k| {
            let y = self
                .profile
                .crest(k)
                .filter(|y| y - s.level_m >= 0.25 * s.height_m)?;
            self.onset_at(k, y)
        })
    }

    /// Whether the crest at sample `k`, `y` m high, is breaking, and by which sign.
    fn onset_at(&self, k: usize, y: f64) -> Option<Onset> {
        let s = self.s;
        let x = self.profile.x_m(k);
        let depth = self.depth_at(x);
        // The crest's own front: its folds up to 3 H ahead (where a jet lands), its face up
        // to 2 H ahead.
        let (reach_near, top_near) = self
            .runs
            .iter()
            .filter(|(a, b, _)| *b >= x - 2.0 * s.h && *a <= x + 3.0 * s.height_m)
            .map(|(a, b, top)| (b - a, *top))
            .fold(
                (0.0, f64::NEG_INFINITY),
                |m, r| if r.0 > m.0 { r } else { m },
            );
        let steep_near = (k..(k + self.span(2.0 * s.height_m)))
            .take_while(|&j| j + self.face_span <= self.k_max)
            .any(|j| self.steep(j));
        let onset = |trigger, reach_m, top_m| Onset {
            x_m: x,
            trigger,
            reach_m,
            top_m,
        };
        if reach_near >= s.jet_m() {
            Some(onset("overturning", reach_near, top_near))
        } else if steep_near {
            Some(onset("steep_face", 0.0, 0.0))
        } else if self.whole_crest_with_steep_lower_face(k, x, depth) {
            Some(onset("steep_lower_face", 0.0, 0.0))
        } else if depth >= 0.5 * s.height_m && self.crest_is_fast(x, y, depth) {
            Some(onset("kinematic", 0.0, 0.0))
        } else {
            None
        }
    }

    /// Kinematic: the fastest fluid particle of the crest at (`x`, `y`) against the crest's
    /// speed, linear celerity at the local `depth` for the wave's time scale with the
    /// finite-amplitude factor (for a solitary wave, whose T_eff is long, nearly sqrt(g (d +
    /// η))); fast when it reaches 0.85 of it.
    fn crest_is_fast(&self, x: f64, y: f64, depth: f64) -> bool {
        let s = self.s;
        let crest_above = y - s.level_m;
        let c = crate::waves::linear::celerity(s.time_scale_s, depth, s.g).unwrap_or(f64::NAN)
            * (1.0 + crest_above / depth).sqrt();
        self.state.fastest_u_near(x, y, 2.0 * s.h) >= 0.85 * c
    }

    /// The top at the onset crest `x_b` (still level where none) and the lowest top from half
    /// a wavelength (at the crest's still `depth`) behind it to the crest, m.
    ///
    /// A solitary wave has no trough: its height is its crest's elevation above still water,
    /// as Grilli et al. (1997) measure H_b, and its trough here is the still level. (Half its
    /// effective length behind a shoaled crest the surface still stands a quarter of the crest
    /// high: the lowest top there would cut H_b by as much.)
    pub(super) fn crest_and_trough(&self, x_b: f64, depth: f64) -> (f64, f64) {
        let (s, profile) = (self.s, self.profile);
        let k_b = profile.index(x_b);
        let crest = profile.top(k_b).unwrap_or(s.level_m);
        if s.single_wave {
            return (crest, s.level_m);
        }
        let wavelength = s.time_scale_s * (s.g * depth.max(s.h)).sqrt();
        let k_back = profile.index(x_b - 0.5 * wavelength).max(self.k_min);
        let trough = (k_back..=k_b)
            .filter_map(|k| profile.top(k))
            .fold(crest, f64::min);
        (crest, trough)
    }
}

/// Overturned runs between samples `k_min` and `k_max`: contiguous samples with three or
/// more crossings, kept when the water on top of them moves shoreward on average. A breaker's
/// jet is thrown ahead of its crest; the roller of the backwash meeting the next wave folds
/// seaward. Each run: (start x, end x, its highest top), m.
fn overturned_runs(profile: &SurfaceProfile, k_min: usize, k_max: usize) -> Vec<(f64, f64, f64)> {
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
    runs
}
