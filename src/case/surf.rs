//! `[surf]`: surf-zone diagnostics, where the undertow is measured and from when.

use serde::{Deserialize, Serialize};

use super::{err, non_negative, off_if_zero};

/// Surf-zone diagnostics (`[surf]`): where the undertow is measured and from when.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SurfSettings {
    /// Flume x of the origin of the reference data's frame: reports give x − x_origin_m
    /// beside the flume x (Ting & Kirby's x = 0 is where the still water is 0.38 m deep).
    /// Default 0.
    pub x_origin_m: f64,
    /// Undertow stations, flume x in m: period-averaged u(z) from the bed to the crests.
    /// Default none.
    pub stations_x_m: Vec<f64>,
    /// Height of the bins of the undertow profiles, m. Default `None`: half the particle
    /// spacing (0 in a case file means the same).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile_dz_m: Option<f64>,
    /// Wave periods from t = 0 before averaging starts (the spin-up); the averages then take
    /// every whole period to the end of the run. Default 5.
    pub spin_up_periods: f64,
}

impl Default for SurfSettings {
    fn default() -> Self {
        Self {
            x_origin_m: 0.0,
            stations_x_m: Vec::new(),
            profile_dz_m: None,
            spin_up_periods: 5.0,
        }
    }
}

impl SurfSettings {
    /// Reads the 0 a case file writes for the bin height as `None` (half the spacing).
    pub(super) fn zero_means_off(&mut self) {
        off_if_zero(&mut self.profile_dz_m);
    }

    /// A finite origin, stations inside the flume (of length `flume_length_m`) and only with a
    /// wavemaker (`has_wavemaker`) to give the period, non-negative bins and spin-up.
    pub(super) fn validate(
        &self,
        flume_length_m: f64,
        has_wavemaker: bool,
    ) -> Result<(), (String, String)> {
        if !self.x_origin_m.is_finite() {
            return err("surf.x_origin_m", "must be finite".into());
        }
        if let Some(x) = self
            .stations_x_m
            .iter()
            .find(|x| !(x.is_finite() && **x > 0.0 && **x < flume_length_m))
        {
            return err(
                "surf.stations_x_m",
                format!("station at x = {x} m lies outside the flume (0, {flume_length_m}) m"),
            );
        }
        if let Some(dz) = self.profile_dz_m {
            non_negative("surf.profile_dz_m", dz)?;
        }
        non_negative("surf.spin_up_periods", self.spin_up_periods)?;
        if !self.stations_x_m.is_empty() && !has_wavemaker {
            return err(
                "surf.stations_x_m",
                "undertow stations average over wave periods: the case needs a [wavemaker]".into(),
            );
        }
        Ok(())
    }
}
