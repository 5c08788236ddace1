use super::*;
use nalgebra::Vector2;

/// A flume made of synthetic surfaces: the case's bed, a clock, and the water of a crest
/// moving shoreward at `crest_u_fraction` of the crest's celerity as the kinematic criterion
/// reckons it (`None`: no water there, so no kinematic onset).
struct SyntheticFlume {
    case: Case,
    t_s: f64,
    crest_u_fraction: Option<f64>,
}

impl SyntheticFlume {
    fn new(case: Case, crest_u_fraction: Option<f64>) -> Self {
        Self {
            case,
            t_s: 0.0,
            crest_u_fraction,
        }
    }
}

impl FlumeState for SyntheticFlume {
    fn time_s(&self) -> f64 {
        self.t_s
    }
    fn bed_y_at(&self, x_m: f64) -> f64 {
        self.case.bed_y_at(x_m)
    }
    /// The fraction of c = c_linear(T, d) · sqrt(1 + η/d) at the local still depth d,
    /// η the height `y_m` above still water: the celerity `Frame::crest_is_fast` compares
    /// with.
    fn fastest_u_near(&self, x_m: f64, y_m: f64, _: f64) -> f64 {
        let (Some(fraction), Some(beach), Some(w)) = (
            self.crest_u_fraction,
            &self.case.flume.beach,
            &self.case.wavemaker,
        ) else {
            return f64::NEG_INFINITY;
        };
        let level_m = self.case.still_level_at(beach.toe_x_m).unwrap_or(0.0);
        let depth_m = level_m - self.bed_y_at(x_m);
        if depth_m <= 0.0 {
            return f64::NEG_INFINITY;
        }
        let g = self.case.fluid.gravity_m_s2;
        let c = crate::waves::linear::celerity(w.period_s, depth_m, g).unwrap()
            * (1.0 + (y_m - level_m) / depth_m).sqrt();
        fraction * c
    }
}

/// A surface sampled every `dx_m` from x = 0 to `length_m`: each sample's crossings (y, u1)
/// from `column(x)`, put highest first as `surface_profile` leaves them.
fn synthetic_profile(
    length_m: f64,
    dx_m: f64,
    column: impl Fn(f64) -> Vec<(f64, f64)>,
    cavities: Vec<(Vector2<f64>, f64)>,
) -> SurfaceProfile {
    let samples = (length_m / dx_m).round() as usize + 1;
    let crossings = (0..samples)
        .map(|k| {
            let mut c = column(k as f64 * dx_m);
            c.sort_by(|a, b| b.0.total_cmp(&a.0));
            c
        })
        .collect();
    SurfaceProfile {
        dx_m,
        crossings,
        cavities,
    }
}

/// `cases/solitary_beach.toml` (d = 0.3 m, H = 0.105 m, 1:15 from x = 2.7 m, still
/// shoreline at 7.2 m) seen through synthetic frames every 0.02 s from 2 s to 7 s:
/// - the solitary crest shoals at 1.5 m/s, growing from H to 0.12 m, smooth (its face
///   never steeper than 20°);
/// - from 4.00 to 4.04 s, at x = 5.70–5.76 m (still depth 0.10 m), a jet 0.1 m long is
///   thrown from the crest: three crossings under it, the water on top moving shoreward;
/// - after it, a smooth bore 0.10 m high runs on at 1.3 m/s and fades on the beach;
/// - the shoreline tip stands at 7.25 m until 4.5 s, climbs to 8.2 m (0.072 m above still
///   water, with a 5 mm film) by 5.6 s and falls back; the bore's crest passes x = 7.4 m
///   (shoreward of the still shoreline, 0.10 m above still water) behind the tip.
///
/// One breaker, plunging, at 5.70 m; one run-up, the tip's, not the bore's.
#[test]
fn a_solitary_wave_that_overturns_is_one_plunging_breaker_and_runs_up_to_its_tip() {
    let case = Case::load(std::path::Path::new("cases/solitary_beach.toml"), &[]).unwrap();
    let mut detector = BreakingDetector::for_case(&case);
    assert!(detector.active());
    let level = 0.3;
    let dx = 0.01;
    let length_m = case.flume.length_m;
    let sech2 = |z: f64| 1.0 / z.cosh().powi(2);
    let (t_b, x_b) = (4.0, 5.7);
    let mut flume = SyntheticFlume::new(case, None);
    let mut events = Vec::new();
    for n in 0..=250 {
        let t = 2.0 + 0.02 * n as f64;
        let x_tip = if t < 4.5 {
            7.25
        } else if t < 5.6 {
            7.25 + (8.2 - 7.25) * (t - 4.5) / 1.1
        } else {
            (8.2 - 0.7 * (t - 5.6)).max(7.5)
        };
        // The crest: shoaling, overturning, then a bore.
        let folding = (t_b - 1e-9..t_b + 0.05).contains(&t);
        let (x_c, amplitude) = if t < t_b - 1e-9 {
            let grown = 0.105 + 0.015 * ((t - 2.0) / (t_b - 2.0)).clamp(0.0, 1.0);
            (x_b - 1.5 * (t_b - t), grown)
        } else if folding {
            (x_b + 1.5 * (t - t_b), 0.12)
        } else {
            let x = x_b + 0.06 + 1.3 * (t - t_b - 0.06);
            (x, 0.10 * ((7.8 - x) / 0.4).clamp(0.0, 1.0))
        };
        let profile = synthetic_profile(
            length_m,
            dx,
            |x| {
                if x > x_tip + 1e-9 {
                    return Vec::new();
                }
                let film = flume.bed_y_at(x) + 0.005;
                let ahead = x - x_c;
                if folding && ahead > 1e-9 && ahead <= 0.1 + 1e-9 {
                    // Jet top falling from the crest, its underside 2 cm below, and the
                    // face under it.
                    let top = level + amplitude * (1.0 - 0.3 * ahead / 0.1);
                    let face = level + 0.3 * amplitude * (1.0 - ahead / 0.1);
                    return vec![(top, 1.0), (top - 0.02, 1.0), (face, 0.5)];
                }
                let eta = if folding && ahead > 0.1 {
                    0.3 * amplitude * sech2((ahead - 0.1) / 0.1)
                } else {
                    amplitude * sech2(ahead / 0.3)
                };
                vec![((level + eta).max(film), 0.5)]
            },
            Vec::new(),
        );
        flume.t_s = t;
        events.extend(detector.observe(&flume, &profile));
    }
    println!("{events:#?}");
    let b = &detector.breakers;
    assert_eq!(b.len(), 1, "{b:?}");
    assert_eq!(b[0].observed, BreakerType::Plunging, "{:?}", b[0]);
    assert_eq!(b[0].onset, "overturning");
    assert!((b[0].x_b_m - x_b).abs() <= dx + 1e-9, "{}", b[0].x_b_m);
    assert!((b[0].h_b_m - 0.1).abs() < 0.002, "{}", b[0].h_b_m);
    assert!(
        (b[0].height_b_m - 0.12).abs() < 0.005,
        "{}",
        b[0].height_b_m
    );
    let summary = detector.summary(0.0, 0.0).unwrap();
    assert_eq!(summary.observed, "plunging");
    assert_eq!(summary.predicted, "plunging");
    assert_eq!(summary.basis, "first");
    assert!((summary.slope_parameter.unwrap() - 0.1714).abs() < 1e-3);
    assert!((summary.time_scale_s - 2.233).abs() < 1e-3);
    assert!((summary.x_b_m.unwrap() - x_b).abs() <= dx + 1e-9);
    // The tip's highest, 1.1/15 m + 5 mm above still water at x = 8.2 m; the bore, 0.10 m
    // above still water shoreward of the still shoreline, does not count.
    let tip = (8.2 - 2.7) / 15.0 - level + 0.005;
    assert_eq!(summary.run_ups_m.len(), 1, "{:?}", summary.run_ups_m);
    assert!(
        (summary.run_up_m - tip).abs() < 0.002,
        "run-up {} m, the tip's highest {tip} m",
        summary.run_up_m
    );
    // The 5 mm film ahead of the bore is thinner than 1 and 2 cm: their edges stay at least
    // 1 cm lower, and above still water (the bore runs up the beach). The 2 cm film's edge is
    // the bore's steep front, whose surface stands higher than the 1 cm film's gentle edge.
    let film = |m: f64| {
        let f = summary.run_up_films.iter().find(|f| f.film_m == m).unwrap();
        assert_eq!(f.run_ups_m.len(), 1, "{f:?}");
        f.run_up_m
    };
    let (one, two) = (film(0.01), film(0.02));
    println!("run-up: tip {tip:.4} m, 1 cm film {one:.4} m, 2 cm film {two:.4} m");
    assert!(
        0.0 < one.min(two) && one.max(two) < tip - 0.01,
        "{one}, {two}, {tip}"
    );
}

/// The still level of `cases/collapsing_slope025.toml` (d = 0.7 m; a 1:4 beach from x =
/// 5.9 m, still shoreline at 8.7 m; H = 0.125 m, T = 2.2 s, ξ₀ = 1.94, predicted
/// collapsing), m above the floor. Every periodic test below runs on this one beach and
/// wave, so the type each finds comes from its surface alone, not from ξ₀.
const LEVEL_M: f64 = 0.7;
const SHORELINE_X_M: f64 = 8.7;
const SLOPE: f64 = 0.25;
const PERIOD_S: f64 = 2.2;
/// Every crest stands this high above a flat trough, m: the case's H.
const CREST_M: f64 = 0.125;
/// The trough stands this far below still water, m.
const TROUGH_BELOW_M: f64 = 0.03;
/// Crest n passes its breaking point at 7.6 + n T s (n = 0..3), after the gate (6.73 s:
/// two ramped periods and the travel to the toe), moving shoreward at 1.5 m/s.
const FIRST_CREST_S: f64 = 7.6;
const CREST_SPEED_M_S: f64 = 1.5;
/// What a crest does at its breaking point lasts from τ = 0 (its passing) to this, s; its
/// bore then fades out over 0.3 s.
const EVENT_S: f64 = 0.18;
/// The water film on the beach, m.
const FILM_M: f64 = 0.005;
const DX_M: f64 = 0.01;

/// One sample's crossings, (y, u1), m and m/s.
type Column = Vec<(f64, f64)>;

/// A periodic train of synthetic frames on the 1:4 beach, every 0.04 s (the case's output
/// interval) from 6.0 s to 16.32 s, sampled every 1 cm (h/2):
/// - crests 3.3 m apart, each a sech² crest `CREST_M` above a flat trough 3 cm below still
///   water (its back 0.25 m wide, its front `front_width_m`), pass `x_b_m` at 7.6 + n T;
/// - while the crest passing x_b is within `EVENT_S` of it, `front(τ, ahead)` gives, where
///   it returns a column, that column's crossings `ahead` m ahead of the crest, as (height
///   above the trough, u1); `cavity(τ)` an enclosed air cavity (ahead of the crest, height
///   above the trough, m);
/// - after it the crest runs on as a smooth bore that fades out over 0.3 s;
/// - the shoreline tip rests where the trough meets the beach, and from 0.3 s to 1.5 s
///   after crest n passes x_b climbs to `run_ups_m[n]` above still water (plus the film)
///   and falls back, as a half sine; the uprush over the beach is a lens up to 5 cm thick
///   whose middle stands up to 2.4 cm higher than the tip.
struct Train {
    x_b_m: f64,
    front_width_m: f64,
    front: fn(f64, f64) -> Option<Column>,
    cavity: fn(f64) -> Option<(f64, f64)>,
    run_ups_m: [f64; 4],
    crest_u_fraction: Option<f64>,
}

impl Train {
    /// The tip's elevation above still water at `t_s`, m (the film left out).
    fn tip_m(&self, t_s: f64) -> f64 {
        (-1..4)
            .map(|n: i32| {
                let tau = t_s - FIRST_CREST_S - n as f64 * PERIOD_S;
                let climb = (std::f64::consts::PI * (tau - 0.3) / 1.2).sin();
                if (0.3..1.5).contains(&tau) {
                    let top = self.run_ups_m[n.max(0) as usize];
                    -TROUGH_BELOW_M + (top + TROUGH_BELOW_M) * climb
                } else {
                    -TROUGH_BELOW_M
                }
            })
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Feeds the frames to a detector for `cases/collapsing_slope025.toml`; returns it and
    /// its events.
    fn run(&self) -> (BreakingDetector, Vec<String>) {
        let case = Case::load(std::path::Path::new("cases/collapsing_slope025.toml"), &[]).unwrap();
        let mut detector = BreakingDetector::for_case(&case);
        let gate_s = detector.setup.as_ref().unwrap().gate_s;
        assert!((6.0..FIRST_CREST_S).contains(&gate_s), "gate {gate_s} s");
        let length_m = case.flume.length_m;
        let mut flume = SyntheticFlume::new(case, self.crest_u_fraction);
        let trough_m = LEVEL_M - TROUGH_BELOW_M;
        let sech2 = |z: f64| 1.0 / z.cosh().powi(2);
        let mut events = Vec::new();
        for k in 0..=258 {
            let t = 6.0 + 0.04 * k as f64;
            let n = ((t - FIRST_CREST_S) / PERIOD_S).round();
            let tau = t - FIRST_CREST_S - n * PERIOD_S;
            let rise_m = self.tip_m(t);
            let x_tip = SHORELINE_X_M + rise_m / SLOPE;
            let event = (-1e-9..EVENT_S).contains(&tau);
            // The crests of waves n − 1, n and n + 1: (x, height above the trough).
            let crests: Vec<(f64, f64)> = (-1..=1)
                .map(|m| {
                    let tau_m = tau - m as f64 * PERIOD_S;
                    let fade = (1.0 - (tau_m - EVENT_S) / 0.3).clamp(0.0, 1.0);
                    let x = self.x_b_m + CREST_SPEED_M_S * tau_m;
                    (x, CREST_M * if tau_m < EVENT_S { 1.0 } else { fade })
                })
                .collect();
            let x_c = crests[1].0;
            let profile = synthetic_profile(
                length_m,
                DX_M,
                |x| {
                    if x > x_tip + 1e-9 {
                        return Vec::new();
                    }
                    if event
                        && x - x_c > 0.005
                        && let Some(c) = (self.front)(tau, x - x_c)
                    {
                        if c.len() > 1 {
                            return c.iter().map(|(y, u)| (trough_m + y, *u)).collect();
                        }
                        let y = (trough_m + c[0].0).max(flume.bed_y_at(x) + FILM_M);
                        return vec![(y, c[0].1)];
                    }
                    let eta = crests
                        .iter()
                        .map(|&(xc, height)| {
                            let ahead = x - xc;
                            let width = if ahead > 0.0 {
                                self.front_width_m
                            } else {
                                0.25
                            };
                            height * sech2(ahead / width)
                        })
                        .fold(0.0, f64::max);
                    let bed = flume.bed_y_at(x);
                    // Thinning to nothing one sample short of the tip, whose sample
                    // then stands the film over the bed.
                    let lens = if x_tip - DX_M > SHORELINE_X_M && x > SHORELINE_X_M {
                        let s = (x - SHORELINE_X_M) / (x_tip - DX_M - SHORELINE_X_M);
                        0.05 * (std::f64::consts::PI * s.min(1.0)).sin()
                    } else {
                        0.0
                    };
                    vec![((trough_m + eta).max(bed + FILM_M + lens), 0.5)]
                },
                (self.cavity)(tau)
                    .filter(|_| event)
                    .map(|(ahead, y)| (Vector2::new(x_c + ahead, trough_m + y), 0.002))
                    .into_iter()
                    .collect(),
            );
            flume.t_s = t;
            events.extend(detector.observe(&flume, &profile));
        }
        (detector, events)
    }
}

/// No cavity.
fn no_cavity(_: f64) -> Option<(f64, f64)> {
    None
}

/// The crest's four breakers, each of `kind` and no other, and the summary's type.
fn assert_four_breakers_of(detector: &BreakingDetector, kind: BreakerType) -> BreakingSummary {
    let b = &detector.breakers;
    assert_eq!(b.len(), 4, "{b:#?}");
    for breaker in b {
        assert_eq!(breaker.observed, kind, "{breaker:?}");
        assert!((breaker.height_b_m - CREST_M).abs() < 1e-3, "{breaker:?}");
    }
    let summary = detector.summary(0.0, 0.0).unwrap();
    assert_eq!(summary.observed, kind.name());
    assert_eq!(summary.basis, "steady");
    assert_eq!(summary.steady_breakers, 4);
    assert_eq!(summary.predicted, "collapsing");
    summary
}

/// Spilling: at x_b = 7.4 m (still depth 0.325 m), a roller 3 cm long sits on the crest
/// (three crossings, the water on top moving shoreward) and the front falls under it at
/// 68° (tan 2.5), 11 cm down to the trough. It exercises two thresholds:
/// - the steep face: 2.3–2.5 over the face span ℓ_j = 4 cm, 31–44 % over tan 60° = 1.73:
///   the onset is "steep_face";
/// - the long fold: the roller reaches 0.03 m, 0.24 H_b, half of 0.5 H_b (and under ℓ_j,
///   so it marks no fold point: x_b is the onset's crest). Its top is the crest's, so a
///   longer roller would have been a plunging jet: the reach alone makes it spilling.
#[test]
fn a_crest_with_a_short_roller_over_a_steep_front_is_spilling() {
    let train = Train {
        x_b_m: 7.4,
        front_width_m: 0.25,
        front: |tau, ahead| {
            (tau < EVENT_S).then(|| {
                if ahead <= 0.035 {
                    let top = CREST_M - 0.3 * ahead;
                    vec![(top, 1.0), (top - 0.01, 0.8), (0.9 * CREST_M - 0.02, 0.5)]
                } else {
                    vec![((0.9 * CREST_M - 2.5 * (ahead - 0.035)).max(0.0), 0.5)]
                }
            })
        },
        cavity: no_cavity,
        run_ups_m: [0.05; 4],
        crest_u_fraction: None,
    };
    let (detector, events) = train.run();
    println!("{events:#?}");
    let summary = assert_four_breakers_of(&detector, BreakerType::Spilling);
    for b in &detector.breakers {
        assert_eq!(b.onset, "steep_face", "{b:?}");
        assert!(b.steep_face);
        assert!((b.overturn_reach_m - 0.03).abs() < 1e-6, "{b:?}");
        assert_eq!(b.fold_x_m, None);
        assert!((b.x_b_m - 7.4).abs() <= DX_M + 1e-9, "{b:?}");
    }
    assert!((summary.x_b_m.unwrap() - 7.4).abs() <= DX_M + 1e-9);
}

/// Plunging: at x_b = 7.8 m (still depth 0.225 m) a jet is thrown from the crest, 0.12 m
/// long (its top falling from the crest's height to 0.7 H_b, its underside 2 cm below,
/// the front face under it), for three frames; then it lands 0.06 m ahead, closing an air
/// cavity (0.002 m², over 3 h²), for two. Thresholds:
/// - the fold is ≥ ℓ_j = 4 cm: the onset is "overturning", and the breaking point is the
///   crest where it first folded;
/// - the long fold: reach 0.12 m = 0.96 H_b, nearly twice 0.5 H_b;
/// - from the crest: its top 0.97 H_b above the trough, nearly twice 0.5 H_b.
#[test]
fn a_jet_thrown_from_the_crest_that_lands_ahead_is_plunging() {
    let train = Train {
        x_b_m: 7.8,
        front_width_m: 0.25,
        front: |tau, ahead| {
            let reach = 0.12;
            let jet = ahead <= reach + 0.005;
            Some(if tau < 0.1 && jet {
                let top = CREST_M * (1.0 - 0.3 * ahead / reach);
                let face = 0.3 * CREST_M * (1.0 - ahead / reach).max(0.0);
                vec![(top, 1.0), (top - 0.02, 1.0), (face, 0.5)]
            } else if jet {
                vec![(CREST_M * (1.0 - 0.7 * ahead / reach), 0.8)]
            } else {
                vec![(0.0, 0.5)]
            })
        },
        cavity: |tau| {
            (0.1..EVENT_S)
                .contains(&tau)
                .then_some((0.06, 0.15 * CREST_M))
        },
        run_ups_m: [0.05; 4],
        crest_u_fraction: None,
    };
    let (detector, events) = train.run();
    println!("{events:#?}");
    let summary = assert_four_breakers_of(&detector, BreakerType::Plunging);
    for b in &detector.breakers {
        assert_eq!(b.onset, "overturning", "{b:?}");
        assert!((b.overturn_reach_m - 0.12).abs() < 1e-6, "{b:?}");
        assert!(b.overturn_top_m > 0.95 * CREST_M, "{b:?}");
        assert!(b.cavity);
        assert!((b.fold_x_m.unwrap() - 7.8).abs() <= DX_M + 1e-9, "{b:?}");
    }
    assert!((summary.x_b_m.unwrap() - 7.8).abs() <= DX_M + 1e-9);
}

/// Collapsing: at x_b = 8.1 m (still depth 0.15 m, 1.2 H_b: offshore of the shoreline rule,
/// h_b ≥ 0.5 H_b, by a factor 2.4) the crest stays whole, its upper face a smooth 22°
/// slope down to 0.35 H_b above the trough 0.2 m ahead; below that the lower face folds
/// over: a lip 0.10 m long, its top falling from 0.35 to 0.245 H_b, its underside 1.5 cm
/// lower, the trough's water under it; no cavity. Thresholds:
/// - the fold is ≥ ℓ_j = 4 cm and within 3 H of the crest: the onset is "overturning" at the
///   crest;
/// - the long fold: reach 0.10 m = 0.8 H_b, 60 % over 0.5 H_b;
/// - low on the face: its top 0.34 H_b above the trough, 32 % under 0.5 H_b.
#[test]
fn a_whole_crest_whose_lower_face_folds_is_collapsing() {
    let train = Train {
        x_b_m: 8.1,
        front_width_m: 0.25,
        front: |_, ahead| {
            Some(if ahead <= 0.205 {
                vec![(CREST_M * (1.0 - 0.65 * ahead / 0.2), 0.5)]
            } else if ahead <= 0.305 {
                let top = 0.35 * CREST_M * (1.0 - 0.3 * (ahead - 0.2) / 0.1);
                vec![(top, 0.6), (top - 0.015, 0.3), (0.0, 0.2)]
            } else {
                vec![(0.0, 0.5)]
            })
        },
        cavity: no_cavity,
        run_ups_m: [0.05; 4],
        crest_u_fraction: None,
    };
    let (detector, events) = train.run();
    println!("{events:#?}");
    let summary = assert_four_breakers_of(&detector, BreakerType::Collapsing);
    for b in &detector.breakers {
        assert_eq!(b.onset, "overturning", "{b:?}");
        assert!((b.overturn_reach_m - 0.10).abs() < 1e-6, "{b:?}");
        assert!((b.overturn_top_m - 0.34 * CREST_M).abs() < 1e-3, "{b:?}");
        assert!(!b.cavity);
        assert!((b.h_b_m - 0.15).abs() < 1e-6, "{b:?}");
        assert!((b.fold_x_m.unwrap() - 8.1).abs() <= DX_M + 1e-9, "{b:?}");
    }
    assert!((summary.x_b_m.unwrap() - 8.1).abs() <= DX_M + 1e-9);
}

/// Collapsing as the issue describes it (23, item 4) without a fold: at x_b = 8.1 m the
/// crest stays whole (its upper face the smooth 22° slope of the collapsing test down to
/// 0.4 H_b above the trough), and its lower face steepens to 76° (tan 4) and falls, 5 cm
/// down to the trough, with no overturned part; the water of the crest moves at 0.7 c.
///
/// The older signs miss it: a face steeper than 60° counts over ℓ_j = 4 cm, a fall of
/// 6.9 cm (0.55 H_b) there, taller than the lower face; there is no fold; the crest is slow.
/// The whole crest's steep lower face is its own sign (`Frame::steep_lower_face_m`): the
/// upper face nowhere steeper than 60°, below half the height a run of samples at 76°
/// falling 5 cm (over max(2 h, H_b/4) = 4 cm). Each wave's onset is that face, and with no
/// long fold in 15 cm of water (h_b ≥ 0.5 H_b) the breaker is collapsing, not spilling.
#[test]
fn a_whole_crest_whose_lower_face_steepens_and_falls_without_folding_is_collapsing() {
    let train = Train {
        x_b_m: 8.1,
        front_width_m: 0.25,
        front: |_, ahead| {
            let face_top = 0.4 * CREST_M;
            let upper = (CREST_M - face_top) / (0.65 * CREST_M / 0.2);
            Some(if ahead <= upper {
                vec![(CREST_M * (1.0 - 0.65 * ahead / 0.2), 0.5)]
            } else {
                vec![((face_top - 4.0 * (ahead - upper)).max(0.0), 0.5)]
            })
        },
        cavity: no_cavity,
        run_ups_m: [0.05; 4],
        crest_u_fraction: Some(0.7),
    };
    let (detector, events) = train.run();
    println!("{events:#?}");
    let summary = assert_four_breakers_of(&detector, BreakerType::Collapsing);
    for b in &detector.breakers {
        assert_eq!(b.onset, "steep_lower_face", "{b:?}");
        assert_eq!(b.overturn_reach_m, 0.0, "{b:?}");
        // The 5 cm face, plus at most one sample of the upper face above its kink
        // (0.01 m at tan 22° = 0.0041 m) where the first steep step starts.
        assert!(
            b.lower_face_fall_m >= 0.05 - 1e-9 && b.lower_face_fall_m <= 0.0542,
            "{b:?}"
        );
        assert!((b.h_b_m - 0.15).abs() < 1e-6, "{b:?}");
    }
    println!(
        "steep lower face fall {:.4} m, observed {}",
        detector.breakers[0].lower_face_fall_m, summary.observed
    );
}

/// Surging: the same crests run up the beach without breaking, the shoreline tip climbing
/// 0.058–0.070 m above still water (1.9–2.2 times H/4 = 0.031 m) once a period and falling
/// back. The crests stand 0.095 m above still water (3 H/4, so the criteria are tried on
/// them) and stay on the unbroken side of each:
/// - the steep face: their front is a sech² 0.096 m wide, at most 45° (slope 1.0, 42 %
///   under tan 60°);
/// - the kinematic criterion: the water of the crest moves at 0.7 c, 18 % under 0.85 c;
/// - the fold: the surface crosses each vertical line once.
///
/// The uprush lens (5 cm thick, over the beach above the still shoreline) stands higher
/// than still water by more than H/4 too, but no water moves there at depth ≥ H/2, and it
/// is not steep.
fn surging_train() -> Train {
    Train {
        x_b_m: 8.1,
        front_width_m: 0.096,
        front: |_, _| None,
        cavity: no_cavity,
        run_ups_m: [0.058, 0.066, 0.062, 0.070],
        crest_u_fraction: Some(0.7),
    }
}

#[test]
fn a_wave_that_runs_up_the_beach_without_breaking_is_surging() {
    let (detector, events) = surging_train().run();
    println!("{events:#?}");
    assert!(events.is_empty(), "{events:#?}");
    assert!(detector.breakers.is_empty(), "{:#?}", detector.breakers);
    let summary = detector.summary(0.0, 0.0).unwrap();
    assert_eq!(summary.observed, "surging");
    assert_eq!(summary.predicted, "collapsing");
    assert_eq!(summary.basis, "none");
    assert_eq!(summary.x_b_m, None);
    assert!(summary.run_up_m >= 0.25 * CREST_M, "{}", summary.run_up_m);
}

/// An onset on a low feature of a surging wave (the face steepening over the backwash, in
/// the 1:4 sweep at ξ₀ = 2.72 crests of 0.004–0.044 m on a 0.10 m wave) does not type the
/// run: without a steady breaker the summary takes the first breaker at least 0.75 H high,
/// and with none it is a surging run. A breaker that high is taken.
#[test]
fn a_low_onset_on_a_surging_wave_is_not_the_wave_breaking() {
    let (mut detector, _) = surging_train().run();
    let height_m = detector.setup.as_ref().unwrap().height_m;
    let low = Breaker {
        observed: BreakerType::Plunging,
        onset: "steep_face",
        x_b_m: 7.9,
        h_b_m: 0.2,
        height_b_m: 0.2 * height_m,
        t_b_s: 7.0,
        overturn_reach_m: 0.03,
        overturn_top_m: 0.02,
        cavity: false,
        steep_face: true,
        lower_face_fall_m: 0.0,
        fold_x_m: None,
        fold_h_m: None,
        fold_t_s: None,
    };
    detector.breakers.push(low);
    let summary = detector.summary(0.0, 100.0).unwrap();
    assert_eq!(summary.basis, "none");
    assert_eq!(summary.observed, "surging");
    assert_eq!(summary.x_b_m, None);
    let whole = Breaker {
        observed: BreakerType::Collapsing,
        height_b_m: 0.8 * height_m,
        t_b_s: 9.0,
        ..low
    };
    detector.breakers.push(whole);
    let summary = detector.summary(0.0, 100.0).unwrap();
    assert_eq!(summary.basis, "first");
    assert_eq!(summary.observed, "collapsing");
    assert_eq!(summary.t_b_s, Some(9.0));
}

/// A surging run's run-ups are its shoreline tip's highest, one per period: four climbs
/// within the record (the fifth would be cut by its end), each the tip's 0.058–0.070 m plus
/// the film (within the 2.5 mm the tip's sample can stand below it), not the uprush
/// lens's, which stands up to 2.4 cm higher, nor the crests' 0.095 m.
#[test]
fn a_surging_run_up_is_the_tips_highest_once_a_period() {
    let train = surging_train();
    let (detector, _) = train.run();
    let summary = detector.summary(0.0, 0.0).unwrap();
    println!("{:?}", summary.run_ups_m);
    assert_eq!(summary.run_ups_m.len(), 4, "{:?}", summary.run_ups_m);
    for (got, tip) in summary.run_ups_m.iter().zip(train.run_ups_m) {
        let want = tip + FILM_M;
        assert!(
            *got <= want + 1e-9 && *got > want - 0.003,
            "run-up {got} m, the tip's highest {want} m"
        );
    }
    assert!((summary.run_up_m - (0.070 + FILM_M)).abs() < 0.003);
}

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
