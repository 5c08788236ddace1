//! `[particles]`: the resolution of the run.

use serde::{Deserialize, Serialize};

use super::{Flume, err, positive};

/// The particle lattice.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ParticleSettings {
    /// Particle spacing h of the initial lattice and of the wall nodes, m. Default 0.01.
    pub spacing_m: f64,
}

impl Default for ParticleSettings {
    fn default() -> Self {
        Self { spacing_m: 0.01 }
    }
}

impl ParticleSettings {
    /// h positive and at most a quarter of the flume's smaller side.
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
        Ok(())
    }
}
