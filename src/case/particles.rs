//! `[particles]`: the resolution of the run.

use serde::{Deserialize, Serialize};

use super::{Flume, err, inside_flume, positive};

/// The particle lattice.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ParticleSettings {
    /// Particle spacing h of the initial lattice and of the wall nodes, m. Default 0.01.
    pub spacing_m: f64,
    /// A finer spacing shoreward of a line (the swash), optional: `[particles.refine]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub refine: Option<Refinement>,
}

/// `[particles.refine]`: the spacing falls linearly from h at `x_m − transition_m` to
/// `spacing_m` at `x_m` and stays there to the end of the flume. Every length the solver
/// measures in units of h (the α-shape's radius, insertion, removal, merging, the wall margin,
/// the weak surface's length) takes the local spacing; Δt takes the finest.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Refinement {
    /// Where the fine spacing is reached, m from the left wall.
    pub x_m: f64,
    /// The fine spacing, m (less than `particles.spacing_m`).
    pub spacing_m: f64,
    /// Length over which the spacing changes, m. Default: ten coarse spacings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transition_m: Option<f64>,
}

impl Default for ParticleSettings {
    fn default() -> Self {
        Self {
            spacing_m: 0.01,
            refine: None,
        }
    }
}

/// The particle spacing as a function of x, m: uniform, or refined shoreward of a line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spacing {
    coarse_m: f64,
    fine_m: f64,
    /// Where the fine spacing starts, and where the change starts (≤ `x_fine_m`).
    x_fine_m: f64,
    x_start_m: f64,
}

impl Spacing {
    pub fn uniform(h_m: f64) -> Spacing {
        Spacing {
            coarse_m: h_m,
            fine_m: h_m,
            x_fine_m: f64::INFINITY,
            x_start_m: f64::INFINITY,
        }
    }

    /// The spacing at abscissa `x_m`, m.
    #[inline]
    pub fn at(&self, x_m: f64) -> f64 {
        if x_m <= self.x_start_m {
            self.coarse_m
        } else if x_m >= self.x_fine_m {
            self.fine_m
        } else {
            let s = (x_m - self.x_start_m) / (self.x_fine_m - self.x_start_m);
            self.coarse_m + s * (self.fine_m - self.coarse_m)
        }
    }

    /// The largest spacing (the case's h), m.
    pub fn coarsest_m(&self) -> f64 {
        self.coarse_m
    }

    /// The smallest spacing, m.
    pub fn finest_m(&self) -> f64 {
        self.fine_m
    }

    /// Where the spacing starts to fall below h (infinite when uniform), m.
    pub fn refined_from_m(&self) -> f64 {
        self.x_start_m
    }
}

impl ParticleSettings {
    /// The spacing field of the case.
    pub fn spacing(&self) -> Spacing {
        match &self.refine {
            None => Spacing::uniform(self.spacing_m),
            Some(r) => {
                let transition = r.transition_m.unwrap_or(10.0 * self.spacing_m);
                Spacing {
                    coarse_m: self.spacing_m,
                    fine_m: r.spacing_m,
                    x_fine_m: r.x_m,
                    x_start_m: r.x_m - transition,
                }
            }
        }
    }

    /// h positive and at most a quarter of the flume's smaller side; a refinement finer than h,
    /// inside the flume, in 2D.
    pub(super) fn validate(&self, flume: &Flume) -> Result<(), (String, String)> {
        positive("particles.spacing_m", self.spacing_m)?;
        let h = self.spacing_m;
        if h > 0.25 * flume.length_m.min(flume.height_m) {
            return err(
                "particles.spacing_m",
                format!(
                    "{h} m is too coarse for a flume of {} × {} m",
                    flume.length_m, flume.height_m
                ),
            );
        }
        if let Some(r) = &self.refine {
            positive("particles.refine.spacing_m", r.spacing_m)?;
            if r.spacing_m >= h {
                return err(
                    "particles.refine.spacing_m",
                    format!(
                        "{} m is not finer than particles.spacing_m = {h} m",
                        r.spacing_m
                    ),
                );
            }
            if r.spacing_m < 0.25 * h {
                return err(
                    "particles.refine.spacing_m",
                    format!(
                        "{} m is finer than a quarter of particles.spacing_m = {h} m (the \
                         triangles of a sharper change are too distorted)",
                        r.spacing_m
                    ),
                );
            }
            inside_flume("particles.refine.x_m", r.x_m, flume.length_m)?;
            if let Some(t) = r.transition_m
                && !(t.is_finite() && t >= 2.0 * h)
            {
                return err(
                    "particles.refine.transition_m",
                    format!(
                        "must be at least two coarse spacings (2 h = {} m), got {t}",
                        2.0 * h
                    ),
                );
            }
            if flume.width_m.is_some() {
                return err(
                    "particles.refine",
                    "local refinement is 2D only so far (the case has flume.width_m)".to_owned(),
                );
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spacing_falls_linearly_over_the_transition() {
        let p = ParticleSettings {
            spacing_m: 0.02,
            refine: Some(Refinement {
                x_m: 6.0,
                spacing_m: 0.01,
                transition_m: Some(0.5),
            }),
        };
        let s = p.spacing();
        assert_eq!(s.at(0.0), 0.02);
        assert_eq!(s.at(5.5), 0.02);
        assert!((s.at(5.75) - 0.015).abs() < 1e-15);
        assert_eq!(s.at(6.0), 0.01);
        assert_eq!(s.at(8.0), 0.01);
        assert_eq!((s.coarsest_m(), s.finest_m()), (0.02, 0.01));
        let u = ParticleSettings::default().spacing();
        assert_eq!((u.at(-1.0), u.at(1e9)), (0.01, 0.01));
    }
}
