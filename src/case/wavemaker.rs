//! `[wavemaker]` (the paddle at the left end) and `[absorber]` (the damping layer at the right
//! end). The paddle's motion is designed from these settings in `crate::wavemaker`
//! (`PaddleMotion::from_case`); the schema only names the wave.

use serde::{Deserialize, Serialize};

use super::{Flume, err, positive};
use crate::waves::linear::PaddleKind;
use crate::waves::{WaveError, absorption};

/// Which theory drives the paddle.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum WaveTheory {
    /// Sinusoidal motion with the Biesel transfer function (thesis eqs. 2.32–2.40).
    Linear,
    /// Goring-type piston for a first-order cnoidal wave (thesis eqs. 2.41–2.54); piston only.
    Cnoidal,
    /// Goring's piston for one solitary wave; piston only, `period_s` unused.
    Solitary,
}

/// The wavemaker: a moving wall of the mesh standing at `x_m` at rest.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WavemakerSettings {
    /// How the paddle moves: `piston` or `flap`. Required.
    pub paddle: PaddleKind,
    /// Which theory drives it. Required.
    pub theory: WaveTheory,
    /// Target wave height H, m: the Iribarren number and the surf observers use it. Required.
    pub height_m: f64,
    /// The height the paddle's theory is driven for, when it is not `height_m`: a calibration.
    /// In a closed flume the beach's reflection, re-reflected by the paddle, changes the
    /// incident height, so the Ting & Kirby cases drive the paddle for the height that gives
    /// their measured H at the offshore gauge. Default: `height_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paddle_height_m: Option<f64>,
    /// Wave period T, s (linear and cnoidal; a solitary wave has none). Default 0, which only
    /// the solitary wave accepts.
    #[serde(default)]
    pub period_s: f64,
    /// Length of the half-cosine start-up ramp, in periods. Default 2.
    #[serde(default = "default_ramp_periods")]
    pub ramp_periods: f64,
    /// Rest position of the paddle face (for a flap, of its hinge on the bed), m. The water
    /// starts in front of it; the flume behind it stays dry. It must leave room for the backward
    /// stroke. Required.
    pub x_m: f64,
    /// A piston absorbs the long waves that reach it (the seiche and set-down a beach sends
    /// back; see `wavemaker.rs`), as a long flume or an absorbing lab paddle would. Default off
    /// (false).
    #[serde(default)]
    pub absorb_long_waves: bool,
    /// The paddle absorbs the wave the beach reflects, at its own period: two gauges in front
    /// of it split the last period's first harmonic into the wave going out and the wave coming
    /// back, and the paddle adds the motion that radiates the opposite of the second
    /// (`waves::absorption`), as an absorbing lab paddle does. Without it a closed flume builds
    /// a standing wave between the paddle and a reflective beach. Needs a period, flat bed in
    /// front of the paddle for the gauges and room behind it for twice the backward stroke.
    /// Default off (false).
    #[serde(default)]
    pub absorb_reflected_waves: bool,
}

impl WavemakerSettings {
    /// The height the paddle is driven for (`paddle_height_m`, else `height_m`), m.
    pub fn paddle_height(&self) -> f64 {
        self.paddle_height_m.unwrap_or(self.height_m)
    }

    /// The paddle in the first half of `flume`, a theory its paddle can run, a period where the
    /// theory needs one, water deeper than two spacings `h` in front of it (`depth_m`, the
    /// still-water depth there), a wave its theory can make, and room behind it for the
    /// backward stroke. `excursion` designs the motion and returns its range [min, max] of
    /// X(t) at the still-water level, m; it is called last, once everything else holds.
    pub(super) fn validate(
        &self,
        flume: &Flume,
        h: f64,
        gravity_m_s2: f64,
        depth_m: Option<f64>,
        excursion: impl FnOnce() -> Result<(f64, f64), WaveError>,
    ) -> Result<(), (String, String)> {
        let w = self;
        if !(w.x_m.is_finite() && w.x_m > 0.0 && w.x_m < 0.5 * flume.length_m) {
            return err(
                "wavemaker.x_m",
                format!(
                    "the paddle must stand in the first half of the flume, got x = {} m",
                    w.x_m
                ),
            );
        }
        if w.theory != WaveTheory::Linear && w.paddle != PaddleKind::Piston {
            return err(
                "wavemaker.paddle",
                format!("{:?} theory drives a piston, not a flap", w.theory).to_lowercase(),
            );
        }
        if w.absorb_long_waves && w.paddle != PaddleKind::Piston {
            return err(
                "wavemaker.absorb_long_waves",
                "long-wave absorption is made for a piston, not a flap".to_owned(),
            );
        }
        if w.absorb_long_waves && w.theory == WaveTheory::Solitary {
            return err(
                "wavemaker.absorb_long_waves",
                "a solitary wave has no period to average over".to_owned(),
            );
        }
        if w.absorb_reflected_waves && w.theory == WaveTheory::Solitary {
            return err(
                "wavemaker.absorb_reflected_waves",
                "a solitary wave has no period to absorb at".to_owned(),
            );
        }
        if let Some(v) = w.paddle_height_m
            && !(v.is_finite() && v > 0.0)
        {
            return err(
                "wavemaker.paddle_height_m",
                format!("must be a positive number, got {v}"),
            );
        }
        if w.theory != WaveTheory::Solitary && !(w.period_s.is_finite() && w.period_s > 0.0) {
            return err(
                "wavemaker.period_s",
                format!("must be a positive number, got {}", w.period_s),
            );
        }
        // The motion is designed (and its excursion sampled) over the whole ramp.
        if !(0.0..=MAX_RAMP_PERIODS).contains(&w.ramp_periods) {
            return err(
                "wavemaker.ramp_periods",
                format!(
                    "must lie in [0, {MAX_RAMP_PERIODS}] periods, got {}",
                    w.ramp_periods
                ),
            );
        }
        let Some(depth) = depth_m.filter(|d| *d > 2.0 * h) else {
            return err(
                "wavemaker.x_m",
                format!(
                    "no water (deeper than 2 h) stands just in front of the paddle at x = {} m",
                    w.x_m
                ),
            );
        };
        if w.absorb_reflected_waves {
            let flat = absorption::flat_length_m(w.x_m, flume.length_m, |x| flume.bed_y_at(x));
            if let Err(e) = absorption::gauge_offsets_m(w.period_s, depth, gravity_m_s2, flat) {
                return err("wavemaker.absorb_reflected_waves", e);
            }
        }
        let (back, _) = match excursion() {
            Ok(range) => range,
            Err(e) => {
                return err(
                    if w.paddle_height_m.is_some() {
                        "wavemaker.paddle_height_m"
                    } else {
                        "wavemaker.height_m"
                    },
                    format!("the wave cannot be made: {e}"),
                );
            }
        };
        // The top of a flap moves (top height / depth) times as far as its still-water point.
        let reach = match w.paddle {
            PaddleKind::Piston => 1.0,
            PaddleKind::Flap => (flume.height_m - flume.bed_y_at(w.x_m)) / depth,
        };
        // Absorbing may add a motion as large as the paddle's own (a wave reflected whole).
        let back = if w.absorb_reflected_waves {
            2.0 * back
        } else {
            back
        };
        if w.x_m + reach * back < 2.0 * h {
            let with = if w.absorb_reflected_waves {
                " (twice its backward stroke, with the absorbing motion)"
            } else {
                ""
            };
            return err(
                "wavemaker.x_m",
                format!(
                    "the paddle swings back {:.3} m{with} and would hit the left wall: put it at x ≥ {:.3} m",
                    -reach * back,
                    -reach * back + 2.0 * h
                ),
            );
        }
        Ok(())
    }
}

/// The longest start-up ramp, in periods: longer than any run, and short enough to sample.
pub const MAX_RAMP_PERIODS: f64 = 100.0;

fn default_ramp_periods() -> f64 {
    2.0
}

/// A damping layer from `flume.length_m − length_m` to the end wall: every step, fluid velocities
/// there are multiplied by max(0, 1 − Δt·β·f²), f the fraction of the way into the layer
/// (DualSPHysics' passive damping). It should be at least one wavelength long.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Absorber {
    /// Length of the layer, m. Required.
    pub length_m: f64,
    /// β, 1/s. Default 10.
    #[serde(default = "default_absorber_strength")]
    pub strength_per_s: f64,
}

fn default_absorber_strength() -> f64 {
    10.0
}

impl Absorber {
    /// A layer shorter than the flume (of length `flume_length_m`), a positive β.
    pub(super) fn validate(&self, flume_length_m: f64) -> Result<(), (String, String)> {
        let a = self;
        if !(a.length_m.is_finite() && a.length_m > 0.0 && a.length_m < flume_length_m) {
            return err(
                "absorber.length_m",
                format!(
                    "must lie in (0, flume.length_m = {}) m, got {}",
                    flume_length_m, a.length_m
                ),
            );
        }
        positive("absorber.strength_per_s", a.strength_per_s)
    }
}

#[cfg(test)]
mod tests {
    use super::super::Case;
    use std::path::Path;

    #[test]
    fn long_wave_absorption_is_for_a_piston_with_a_period() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
        let c = Case::load(&dir.join("ting_kirby_plunging.toml"), &[]).unwrap();
        assert!(c.wavemaker.as_ref().unwrap().absorb_long_waves);
        let on = ["wavemaker.absorb_long_waves=true".to_owned()];
        let e = Case::load(&dir.join("flap_deep_water.toml"), &on).unwrap_err();
        assert!(
            e.to_string().contains("wavemaker.absorb_long_waves") && e.to_string().contains("flap"),
            "{e}"
        );
        let e = Case::load(&dir.join("solitary.toml"), &on).unwrap_err();
        assert!(e.to_string().contains("wavemaker.absorb_long_waves"), "{e}");
    }

    #[test]
    fn reflected_wave_absorption_needs_a_period_gauge_room_and_stroke_room() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
        let base = dir.join("breaker_map_slope025.toml");
        let c = Case::load(&base, &["wavemaker.period_s=4.0".to_owned()]).unwrap();
        assert!(c.wavemaker.as_ref().unwrap().absorb_reflected_waves);
        let on = ["wavemaker.absorb_reflected_waves=true".to_owned()];
        let e = Case::load(&dir.join("solitary.toml"), &on).unwrap_err();
        assert!(e.to_string().contains("absorb_reflected_waves"), "{e}");
        // The slope 1.5 m from the paddle: no room for the gauges of a 4 s wave.
        let short = [
            "flume.beach.toe_x_m=2.5".to_owned(),
            "wavemaker.period_s=4.0".to_owned(),
        ];
        let e = Case::load(&base, &short).unwrap_err().to_string();
        println!("{e}");
        assert!(
            e.contains("absorb_reflected_waves") && e.contains("1.50 m long"),
            "{e}"
        );
        // The hinge 0.5 m from the left wall: room for the flap's own backward stroke at 3 s
        // (0.31 m at its top), not for twice it.
        let near = [
            "wavemaker.x_m=0.5".to_owned(),
            "water.0.x_start_m=0.5".to_owned(),
            "wavemaker.period_s=3.0".to_owned(),
        ];
        let e = Case::load(&base, &near).unwrap_err().to_string();
        println!("{e}");
        assert!(e.contains("wavemaker.x_m") && e.contains("twice"), "{e}");
        let mut rigid = near.to_vec();
        rigid.push("wavemaker.absorb_reflected_waves=false".to_owned());
        Case::load(&base, &rigid).unwrap();
    }
}
