//! Run-up: how high above still water the shoreline tip climbs, wave by wave.
//!
//! The shoreline tip is the edge of the swash, the most shoreward point where water stands on
//! the beach ([`shoreline_tip`](crate::diagnostics::surface::shoreline_tip)); its elevation
//! above the still level at each output frame makes a record R(t), and each wave's run-up is a
//! maximum of that record. A bore's crest shoreward of the still shoreline stands higher than
//! the tip ahead of it while it runs up, but it is not the edge of the water and does not
//! count.

/// The films whose edges are recorded beside the tip, m deep. A film's run-up is the height
/// above still water of the surface of the water lying on the bed at its edge, about the
/// bed's plus the film's depth: what a run-up wire that far above the bed reads. The tip
/// follows a swash tongue down to one particle's thickness, so it climbs further at each finer
/// spacing; the edge of a film a spacing or two deep need not (see `docs/sweep.md`). Where
/// the edge is a bore's front the surface there stands higher than bed + film, and a deeper
/// film can read higher than a shallower one.
pub const RUN_UP_FILMS_M: [f64; 3] = [0.005, 0.01, 0.02];

/// The film whose run-up `sweep.csv` reports beside the tip's (`run_up_2cm_film_m`), m: two
/// spacings of the 1:4 sweep's swash, the shallowest at which its surging and plunging
/// points' run-ups changed by less than 10 % at h/2.
pub const SWEEP_FILM_M: f64 = RUN_UP_FILMS_M[2];

/// The highest of the waves' run-ups, m (0 with none).
pub(super) fn highest_m(run_ups_m: &[f64]) -> f64 {
    run_ups_m.iter().copied().fold(0.0, f64::max)
}

/// Run-up at the edge of one film (`summary.json`, `breaking.run_up_films`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct FilmRunUp {
    /// The film's depth, m: the edge is where the water lying on the bed is at least this deep.
    pub film_m: f64,
    /// The highest of `run_ups_m` (0 with none), m above still water.
    pub run_up_m: f64,
    /// Each wave's: the highest elevation above still water of the surface of the water on
    /// the bed at the film's edge, m.
    pub run_ups_m: Vec<f64>,
}

/// The tip's elevation above still water at every frame after the gate: (t, R), s and m.
#[derive(Debug, Clone, Default)]
pub(super) struct SwashRecord {
    samples: Vec<(f64, f64)>,
}

impl SwashRecord {
    pub(super) fn push(&mut self, t_s: f64, elevation_m: f64) {
        self.samples.push((t_s, elevation_m));
    }

    /// Each wave's run-up, m, in time order, for waves `time_scale_s` apart (`single`: the
    /// record holds one wave, a solitary wave's, whose run-up is the record's maximum).
    ///
    /// In a periodic train a wave's run-up is a sample of R that is the highest within half a
    /// period either side of it (the first on a tie): the tip climbs once per period, and a
    /// window of one period centred on the climax holds no other wave's. Windows that run past
    /// either end of the record are left out: at the start the tip may still be falling from a
    /// ramp wave's run-up, at the end still climbing.
    pub(super) fn per_wave_m(&self, time_scale_s: f64, single: bool) -> Vec<f64> {
        let r = &self.samples;
        let (Some(first), Some(last)) = (r.first(), r.last()) else {
            return Vec::new();
        };
        if single {
            return vec![r.iter().map(|s| s.1).fold(f64::NEG_INFINITY, f64::max)];
        }
        let half = 0.5 * time_scale_s;
        let mut out = Vec::new();
        for (i, &(t, z)) in r.iter().enumerate() {
            if t - half < first.0 - 1e-9 || t + half > last.0 + 1e-9 {
                continue;
            }
            let highest = r
                .iter()
                .enumerate()
                .all(|(j, &(tj, zj))| (tj - t).abs() > half || zj < z || (zj == z && j >= i));
            if highest {
                out.push(z);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_run_up_per_period_and_none_from_a_cut_window() {
        // The tip climbs to 0.10, 0.12 and 0.11 m at t = 2.5, 4.5 and 6.5 s (T = 2 s), with a
        // smaller second bump 0.8 s after each climax; the record starts on a falling tip, and
        // its last climax (0.2 m at 8.5 s) lies within half a period of its end.
        let mut record = SwashRecord::default();
        let peaks = [
            (0.5, 0.09),
            (2.5, 0.10),
            (4.5, 0.12),
            (6.5, 0.11),
            (8.5, 0.2),
        ];
        for k in 0..=400 {
            let t = 1.0 + 0.02 * k as f64;
            let z = peaks
                .iter()
                .map(|(tp, zp)| {
                    zp * (-((t - tp) / 0.3).powi(2)).exp()
                        + 0.5 * zp * (-((t - tp - 0.8) / 0.1).powi(2)).exp()
                })
                .fold(f64::NEG_INFINITY, f64::max);
            record.push(t, z);
        }
        let waves = record.per_wave_m(2.0, false);
        println!("{waves:?}");
        assert_eq!(waves.len(), 3, "{waves:?}");
        for (got, want) in waves.iter().zip([0.10, 0.12, 0.11]) {
            assert!((got - want).abs() < 1e-3, "{got} vs {want}");
        }
        // A single wave: the record's highest.
        let single = record.per_wave_m(2.0, true);
        assert_eq!(single.len(), 1);
        assert!(single[0] > 0.12);
        assert!(SwashRecord::default().per_wave_m(2.0, false).is_empty());
    }
}
