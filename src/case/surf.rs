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
    /// In a 3D case, where each station stands across the tank, m (one z per x of
    /// `stations_x_m`). Default none; a 2D case refuses it.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stations_z_m: Vec<f64>,
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
            stations_z_m: Vec::new(),
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
    /// wavemaker (`has_wavemaker`) to give the period, non-negative bins and spin-up; in a 3D
    /// tank (`width_m`) one z inside it per station, in 2D none.
    pub(super) fn validate(
        &self,
        flume_length_m: f64,
        width_m: Option<f64>,
        has_wavemaker: bool,
    ) -> Result<(), (String, String)> {
        match width_m {
            None if !self.stations_z_m.is_empty() => {
                return err(
                    "surf.stations_z_m",
                    "stations across the tank need a 3D case (flume.width_m)".into(),
                );
            }
            Some(width) => {
                if self.stations_z_m.len() != self.stations_x_m.len() {
                    return err(
                        "surf.stations_z_m",
                        format!(
                            "a 3D case gives one z per station: {} for {} stations",
                            self.stations_z_m.len(),
                            self.stations_x_m.len()
                        ),
                    );
                }
                if let Some(z) = self
                    .stations_z_m
                    .iter()
                    .find(|z| !(z.is_finite() && **z > 0.0 && **z < width))
                {
                    return err(
                        "surf.stations_z_m",
                        format!("station at z = {z} m lies outside the tank (0, {width}) m"),
                    );
                }
            }
            None => {}
        }
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
