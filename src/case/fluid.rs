//! `[fluid]`: the fluid's properties and gravity.

use serde::{Deserialize, Serialize};

use super::{err, positive};

/// The fluid, water by default.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Fluid {
    /// Density ρ, kg/m³. Default 1000.
    pub density_kg_m3: f64,
    /// Dynamic (molecular) viscosity μ, Pa·s. Default 1.0e-3.
    pub viscosity_pa_s: f64,
    /// Gravitational acceleration g, m/s², pointing down (−y). Default 9.81.
    pub gravity_m_s2: f64,
}

impl Default for Fluid {
    fn default() -> Self {
        Self {
            density_kg_m3: 1000.0,
            viscosity_pa_s: 1.0e-3,
            gravity_m_s2: 9.81,
        }
    }
}

impl Fluid {
    /// ρ and g positive, μ ≥ 0.
    pub(super) fn validate(&self) -> Result<(), (String, String)> {
        positive("fluid.density_kg_m3", self.density_kg_m3)?;
        positive("fluid.gravity_m_s2", self.gravity_m_s2)?;
        if !(self.viscosity_pa_s.is_finite() && self.viscosity_pa_s >= 0.0) {
            return err(
                "fluid.viscosity_pa_s",
                format!("must be ≥ 0, got {}", self.viscosity_pa_s),
            );
        }
        Ok(())
    }
}
