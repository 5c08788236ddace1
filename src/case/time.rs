//! `[time]`: the end of the run and the Δt policy with its bounds.

use serde::{Deserialize, Serialize};

use super::{err, non_negative, off_if_zero, positive};

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum DtPolicy {
    /// Δt = CFL·h/|u|max, between `dt_min_s` and `dt_max_s`.
    #[default]
    Cfl,
    /// Δt = `dt_max_s` every step.
    Fixed,
}

/// The clock. `surface_wave_courant` is on by default; off (`None`, 0 in a case file) it is
/// written as `null` into summary.json, so that reading the summary back gives off.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct TimeSettings {
    /// Simulated time at which the run ends, s. Default 1.
    pub end_s: f64,
    /// Default `cfl`.
    pub dt_policy: DtPolicy,
    /// Courant number for the CFL policy: a particle moves at most this fraction of h per step.
    /// Default 0.25.
    pub cfl: f64,
    /// Largest step, and the step of the fixed policy, s. Default 2e-3.
    pub dt_max_s: f64,
    /// Smallest step the CFL policy may take before the run is declared stuck, s. Default 1e-6.
    pub dt_min_s: f64,
    /// Bound C on ω Δt for the shortest free-surface wave the particles carry (k = π/h,
    /// ω = sqrt(g k)), i.e. Δt ≤ C / sqrt(π g / h). The free surface of the projection step
    /// grows a 2h-wavelength ripple when Δt exceeds about 0.126/ω (measured in still water:
    /// 3.2 ms at h = 2 cm, 2.3 ms at h = 1 cm), which then drains volume. Both policies obey
    /// it: the CFL policy as one more bound, the fixed one by splitting its Δt into equal
    /// substeps. `None` (0 in a case file) turns the bound off. Default 0.1.
    pub surface_wave_courant: Option<f64>,
}

impl TimeSettings {
    /// The surface-wave bound on Δt in s for particle spacing `h_m` and gravity `g_m_s2`
    /// (infinite when the bound is off).
    pub fn surface_wave_dt_s(&self, h_m: f64, g_m_s2: f64) -> f64 {
        match self.surface_wave_courant {
            Some(c) => c / (std::f64::consts::PI * g_m_s2 / h_m).sqrt(),
            None => f64::INFINITY,
        }
    }

    /// Reads the 0 a case file writes for the surface-wave bound as off.
    pub(super) fn zero_means_off(&mut self) {
        off_if_zero(&mut self.surface_wave_courant);
    }

    /// Positive times with dt_min ≤ dt_max, a CFL number in (0, 1], a bound C ≥ 0.
    pub(super) fn validate(&self) -> Result<(), (String, String)> {
        let t = self;
        positive("time.end_s", t.end_s)?;
        positive("time.dt_max_s", t.dt_max_s)?;
        positive("time.dt_min_s", t.dt_min_s)?;
        if t.dt_min_s > t.dt_max_s {
            return err("time.dt_min_s", "must not exceed time.dt_max_s".into());
        }
        if !(t.cfl > 0.0 && t.cfl <= 1.0) {
            return err("time.cfl", format!("must lie in (0, 1], got {}", t.cfl));
        }
        if let Some(c) = t.surface_wave_courant {
            non_negative("time.surface_wave_courant", c)?;
        }
        Ok(())
    }
}

impl Default for TimeSettings {
    fn default() -> Self {
        Self {
            end_s: 1.0,
            dt_policy: DtPolicy::Cfl,
            cfl: 0.25,
            dt_max_s: 2.0e-3,
            dt_min_s: 1.0e-6,
            surface_wave_courant: Some(0.1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{MINIMAL, parse};

    #[test]
    fn surface_wave_bound_on_dt() {
        let c = parse(MINIMAL, &[]).unwrap();
        // 0.1 / sqrt(π g / h) at h = 2 cm: 2.548 ms.
        let dt = c.time.surface_wave_dt_s(0.02, 9.81);
        assert!((dt - 0.1 / (std::f64::consts::PI * 9.81 / 0.02).sqrt()).abs() < 1e-15);
        assert!((dt - 2.548e-3).abs() < 1e-6, "{dt}");
        let off = parse(MINIMAL, &["time.surface_wave_courant=0"]).unwrap();
        assert_eq!(off.time.surface_wave_dt_s(0.02, 9.81), f64::INFINITY);
        let e = parse(MINIMAL, &["time.surface_wave_courant=-1"]).unwrap_err();
        assert!(e.to_string().contains("surface_wave_courant"), "{e}");
        let e = parse(MINIMAL, &["solver.weak_surface_length_h=-0.3"]).unwrap_err();
        assert!(e.to_string().contains("weak_surface_length_h"), "{e}");
        let e = parse(MINIMAL, &["solver.merge_surface_distance_h=0.6"]).unwrap_err();
        assert!(e.to_string().contains("merge_surface_distance_h"), "{e}");
    }
}
