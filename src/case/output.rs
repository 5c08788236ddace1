//! `[output]`: what is recorded and how often.

use serde::{Deserialize, Serialize};

use super::{Flume, err, positive};

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSettings {
    /// Simulated time between recorded frames and CSV rows, s. Default 0.02.
    pub interval_s: f64,
    /// Log the triangle edges to the .rrd as well. Default off (false).
    pub mesh: bool,
    /// Colour range `[min, max]` for u1, m/s. Default `None`: ±sqrt(g·d) of the deepest water
    /// region (an empty list in a case file means the same).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub u1_range_m_s: Option<Vec<f64>>,
    /// Surface-elevation gauges: x positions, m. Recorded to gauges.csv at every output.
    /// Default none.
    pub gauges_x_m: Vec<f64>,
    /// Velocity probes: `[x, y]` positions, m (y above the flume floor). Recorded to gauges.csv
    /// as `u_<x>_<y>` and `w_<x>_<y>`; empty when the probe is dry. Default none.
    pub probes_m: Vec<[f64; 2]>,
    /// 3D cases only: planes z = const across the tank, m from the side wall z = 0; the
    /// particles within h/2 of each are recorded to the .rrd as a 2D view (x, y) coloured by
    /// u1. Default none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub planes_z_m: Vec<f64>,
}

impl Default for OutputSettings {
    fn default() -> Self {
        Self {
            interval_s: 0.02,
            mesh: false,
            u1_range_m_s: None,
            gauges_x_m: Vec::new(),
            probes_m: Vec::new(),
            planes_z_m: Vec::new(),
        }
    }
}

impl OutputSettings {
    /// Reads the empty colour range a case file may write as `None`.
    pub(super) fn zero_means_off(&mut self) {
        if self.u1_range_m_s.as_ref().is_some_and(Vec::is_empty) {
            self.u1_range_m_s = None;
        }
    }

    /// A positive interval, gauges and probes inside `flume`, planes inside a 3D tank's width (and
    /// none in 2D), a colour range [min, max] with
    /// min < max.
    pub(super) fn validate(&self, flume: &Flume) -> Result<(), (String, String)> {
        positive("output.interval_s", self.interval_s)?;
        if let Some(x) = self
            .gauges_x_m
            .iter()
            .find(|x| !(x.is_finite() && **x >= 0.0 && **x <= flume.length_m))
        {
            return err(
                "output.gauges_x_m",
                format!(
                    "gauge at x = {x} m lies outside the flume [0, {}] m",
                    flume.length_m
                ),
            );
        }
        if let Some(p) = self.probes_m.iter().find(|p| {
            !(p.iter().all(|v| v.is_finite())
                && (0.0..=flume.length_m).contains(&p[0])
                && (0.0..=flume.height_m).contains(&p[1]))
        }) {
            return err(
                "output.probes_m",
                format!("probe at {p:?} m lies outside the flume"),
            );
        }
        match flume.width_m {
            None if !self.planes_z_m.is_empty() => {
                return err(
                    "output.planes_z_m",
                    "planes z = const need a 3D case (flume.width_m)".into(),
                );
            }
            Some(w) => {
                if let Some(z) = self
                    .planes_z_m
                    .iter()
                    .find(|z| !(z.is_finite() && **z >= 0.0 && **z <= w))
                {
                    return err(
                        "output.planes_z_m",
                        format!("plane z = {z} m lies outside the tank's width [0, {w}] m"),
                    );
                }
            }
            None => {}
        }
        match self.u1_range_m_s.as_deref() {
            None => {}
            Some([lo, hi]) if lo.is_finite() && hi.is_finite() && lo < hi => {}
            Some(_) => {
                return err(
                    "output.u1_range_m_s",
                    "must be [min, max] with min < max".into(),
                );
            }
        }
        Ok(())
    }
}
