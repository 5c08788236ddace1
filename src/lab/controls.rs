//! What the panel controls, and what follows from it: the settings a user turns, the case they
//! make (checked exactly like a case file), and the derived read-outs (L₀, kh, H/L, I_r, the
//! predicted breaker, the paddle stroke). No egui here, so it is testable on its own.

use crate::case::{Case, CaseError, WaveTheory};
use crate::waves::breaker::{self, BreakerType};
use crate::waves::linear::{self, PaddleKind};
use crate::waves::paddle::PaddleMotion;
use std::path::{Path, PathBuf};

/// A case file offered in the preset list.
#[derive(Debug, Clone)]
pub struct Preset {
    pub name: String,
    pub path: PathBuf,
    pub text: String,
}

/// The case files in `dir`, 2D flumes and 3D tanks (`flume.width_m`), sorted by name
/// (unreadable files are skipped).
pub fn presets_in(dir: &Path) -> Vec<Preset> {
    let mut out: Vec<Preset> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .filter_map(|path| {
            let text = std::fs::read_to_string(&path).ok()?;
            let name = path.file_stem()?.to_string_lossy().into_owned();
            Some(Preset { name, path, text })
        })
        .collect();
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

/// The settings the panel turns. `None` fields do not apply to the current preset (no
/// wavemaker, no beach).
#[derive(Debug, Clone, PartialEq)]
pub struct Controls {
    pub height_m: Option<f64>,
    /// The preset's paddle height over its H (its calibration, `wavemaker.paddle_height_m`;
    /// 1 without one): a new H drives the paddle for H times this.
    pub paddle_ratio: f64,
    pub period_s: Option<f64>,
    pub paddle: Option<PaddleKind>,
    pub theory: Option<WaveTheory>,
    pub slope: Option<f64>,
    pub alpha: f64,
    /// δ of the EDT merge (0: plain Delaunay triangles).
    pub delta: f64,
    pub spacing_m: f64,
    /// Width of a 3D tank across the flume, m (`flume.width_m`; `None` on a 2D flume).
    pub width_m: Option<f64>,
}

impl Controls {
    /// The settings as the case has them.
    pub fn from_case(case: &Case) -> Controls {
        let w = case.wavemaker.as_ref();
        Controls {
            height_m: w.map(|w| w.height_m),
            paddle_ratio: w.map_or(1.0, |w| w.paddle_height() / w.height_m),
            period_s: w.map(|w| w.period_s),
            paddle: w.map(|w| w.paddle),
            theory: w.map(|w| w.theory),
            slope: case.flume.beach.as_ref().map(|b| b.slope),
            alpha: case.solver.alpha,
            delta: case.solver.delta,
            spacing_m: case.particles.spacing_m,
            width_m: case.flume.width_m,
        }
    }

    /// Puts these settings into `case` (a parsed preset), field by field; the fields that do
    /// not apply to the preset (`None`) are left alone.
    pub fn apply(&self, case: &mut Case) {
        case.solver.alpha = self.alpha;
        case.solver.delta = self.delta;
        case.particles.spacing_m = self.spacing_m;
        if let Some(w) = case.wavemaker.as_mut() {
            if let Some(h) = self.height_m {
                w.height_m = h;
                if self.paddle_ratio != 1.0 {
                    w.paddle_height_m = Some(h * self.paddle_ratio);
                }
            }
            if let Some(t) = self.period_s {
                w.period_s = t;
            }
            if let Some(p) = self.paddle {
                w.paddle = p;
            }
            if let Some(t) = self.theory {
                w.theory = t;
            }
        }
        if let (Some(b), Some(slope)) = (case.flume.beach.as_mut(), self.slope) {
            b.slope = slope;
        }
        if case.flume.width_m.is_some() {
            case.flume.width_m = self.width_m;
        }
    }

    /// The case these settings make from `preset`, validated like a file: an error names the
    /// field and the reason (a wave too steep, a stroke the flume has no room for, …).
    pub fn case(&self, preset: &Preset) -> Result<Case, CaseError> {
        let mut case = Case::from_toml_str(&preset.text, &preset.path, &preset.name, &[])?;
        self.apply(&mut case);
        case.check(&preset.path)?;
        Ok(case)
    }

    /// Does going from `self` to `other` need a new flume (new geometry or particles)? Any
    /// change to a 3D tank does (the 3D path has no retune).
    pub fn needs_rebuild(&self, other: &Controls) -> bool {
        self.width_m.is_some()
            || other.width_m.is_some()
            || self.slope != other.slope
            || self.spacing_m != other.spacing_m
            || self.paddle != other.paddle
            || self.theory != other.theory
    }
}

/// Values derived from a case, for the read-outs.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Derived {
    /// Deep-water wavelength gT²/2π, m.
    pub l0_m: Option<f64>,
    /// Depth at the paddle, m.
    pub depth_m: Option<f64>,
    /// Linear wavelength at the paddle depth, m.
    pub wavelength_m: Option<f64>,
    pub kh: Option<f64>,
    pub steepness: Option<f64>,
    pub iribarren: Option<f64>,
    pub predicted: Option<BreakerType>,
    /// Paddle stroke at the still-water level, m.
    pub stroke_m: Option<f64>,
    /// Why the wave cannot be made, when it cannot.
    pub refusal: Option<String>,
}

impl Derived {
    /// Read-outs for the settings on `preset`: from the validated case, or, when validation
    /// refuses it, from the raw settings with the reason.
    pub fn compute(controls: &Controls, preset: &Preset) -> Derived {
        let candidate = controls.case(preset);
        let mut d = Derived::default();
        let base = match &candidate {
            Ok(c) => c.clone(),
            Err(e) => {
                d.refusal = Some(refusal_text(e));
                match Case::from_toml_str(&preset.text, &preset.path, &preset.name, &[]) {
                    Ok(c) => c,
                    Err(_) => return d,
                }
            }
        };
        let g = base.fluid.gravity_m_s2;
        let (Some(h), Some(t)) = (controls.height_m, controls.period_s) else {
            return d;
        };
        if controls.theory != Some(WaveTheory::Solitary) && t > 0.0 {
            d.l0_m = Some(breaker::deep_water_wavelength_m(t, g));
        }
        d.depth_m = base.paddle_depth_m();
        if let (Some(depth), Some(_)) = (d.depth_m, d.l0_m)
            && let Ok(k) = linear::wavenumber(t, depth, g)
        {
            d.kh = Some(k * depth);
            d.wavelength_m = Some(std::f64::consts::TAU / k);
            d.steepness = Some(h / (std::f64::consts::TAU / k));
        }
        if let (Some(slope), Some(_)) = (controls.slope, d.l0_m)
            && h > 0.0
        {
            let ir = breaker::iribarren(slope, h, t, g);
            d.iribarren = Some(ir);
            d.predicted = Some(breaker::predicted_type(ir));
        }
        if let Ok(c) = &candidate
            && let Some(Ok(m)) = PaddleMotion::from_case(c)
        {
            d.stroke_m = Some(m.stroke_m());
        }
        d
    }
}

/// The reason in a case error, without the file name.
fn refusal_text(e: &CaseError) -> String {
    match e {
        CaseError::Field { field, message, .. } => format!("{field}: {message}"),
        CaseError::Override {
            assignment,
            message,
            ..
        } => format!("{assignment}: {message}"),
        other => other.to_string(),
    }
}
