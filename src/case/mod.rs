//! Cases: one TOML file per run, parsed with serde.
//!
//! Every table has defaults, so a case says only what differs, and every table denies unknown
//! fields, so a typo is an error that names the field instead of a silent default. A case can be
//! changed from the command line with `--set dotted.path=value` overrides, applied to the parsed
//! TOML before it is turned into a [`Case`], so they are checked exactly like the file itself.
//!
//! Lengths are in metres with y up and y = 0 at the flume floor; times in seconds; SI throughout.

mod overrides;

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub use overrides::apply_override;

use crate::waves::linear::PaddleKind;
use crate::waves::paddle::PaddleMotion;

/// Everything that can go wrong while reading a case. Each variant names the file and, where
/// there is one, the field.
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    #[error("{file}: cannot read the case file: {source}")]
    Io {
        file: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{file}: the case file is empty; a case needs at least a [flume] and one [[water]] region"
    )]
    Empty { file: PathBuf },
    #[error("{file}: not valid TOML: {message}")]
    Syntax { file: PathBuf, message: String },
    #[error("{file}: field `{field}`: {message}")]
    Field {
        file: PathBuf,
        field: String,
        message: String,
    },
    #[error("{file}: --set {assignment}: {message}")]
    Override {
        file: PathBuf,
        assignment: String,
        message: String,
    },
}

/// A whole run description.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Case {
    /// Name of the run; defaults to the file stem.
    #[serde(default)]
    pub name: String,
    /// Free text shown in the summary.
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub fluid: Fluid,
    pub flume: Flume,
    /// Initial water regions; at least one.
    #[serde(default)]
    pub water: Vec<WaterRegion>,
    #[serde(default)]
    pub particles: ParticleSettings,
    #[serde(default)]
    pub solver: SolverSettings,
    #[serde(default)]
    pub time: TimeSettings,
    #[serde(default)]
    pub output: OutputSettings,
    /// A paddle that makes waves at the left end of the flume.
    #[serde(default)]
    pub wavemaker: Option<WavemakerSettings>,
    /// A passive damping layer at the right end, for flumes without a beach.
    #[serde(default)]
    pub absorber: Option<Absorber>,
    /// Surf-zone diagnostics: undertow stations, spin-up, the reference frame of the data.
    #[serde(default)]
    pub surf: SurfSettings,
}

/// Surf-zone diagnostics (`[surf]`): where the undertow is measured and from when.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SurfSettings {
    /// Flume x of the origin of the reference data's frame: reports give x − x_origin_m
    /// beside the flume x (Ting & Kirby's x = 0 is where the still water is 0.38 m deep).
    pub x_origin_m: f64,
    /// Undertow stations, flume x in m: period-averaged u(z) from the bed to the crests.
    pub stations_x_m: Vec<f64>,
    /// Height of the bins of the undertow profiles, m; 0 means half the particle spacing.
    pub profile_dz_m: f64,
    /// Wave periods from t = 0 before averaging starts (the spin-up); the averages then take
    /// every whole period to the end of the run.
    pub spin_up_periods: f64,
}

impl Default for SurfSettings {
    fn default() -> Self {
        Self {
            x_origin_m: 0.0,
            stations_x_m: Vec::new(),
            profile_dz_m: 0.0,
            spin_up_periods: 5.0,
        }
    }
}

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
    /// How the paddle moves: `piston` or `flap`.
    pub paddle: PaddleKind,
    pub theory: WaveTheory,
    /// Target wave height H: the Iribarren number and the surf observers use it.
    pub height_m: f64,
    /// The height the paddle's theory is driven for, when it is not `height_m`: a calibration.
    /// In a closed flume the beach's reflection, re-reflected by the paddle, changes the
    /// incident height, so the Ting & Kirby cases drive the paddle for the height that gives
    /// their measured H at the offshore gauge. Default: `height_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paddle_height_m: Option<f64>,
    /// Wave period T (linear and cnoidal).
    #[serde(default)]
    pub period_s: f64,
    /// Length of the half-cosine start-up ramp, in periods.
    #[serde(default = "default_ramp_periods")]
    pub ramp_periods: f64,
    /// Rest position of the paddle face (for a flap, of its hinge on the bed). The water starts
    /// in front of it; the flume behind it stays dry. It must leave room for the backward stroke.
    pub x_m: f64,
    /// A piston absorbs the long waves that reach it (the seiche and set-down a beach sends
    /// back; see `wavemaker.rs`), as a long flume or an absorbing lab paddle would. Default off.
    #[serde(default)]
    pub absorb_long_waves: bool,
}

impl WavemakerSettings {
    /// The height the paddle is driven for (`paddle_height_m`, else `height_m`), m.
    pub fn paddle_height(&self) -> f64 {
        self.paddle_height_m.unwrap_or(self.height_m)
    }
}

fn default_ramp_periods() -> f64 {
    2.0
}

/// A damping layer from `flume.length_m − length_m` to the end wall: every step, fluid velocities
/// there are multiplied by max(0, 1 − Δt·β·f²), f the fraction of the way into the layer
/// (DualSPHysics' passive damping). It should be at least one wavelength long.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Absorber {
    pub length_m: f64,
    /// β, 1/s.
    #[serde(default = "default_absorber_strength")]
    pub strength_per_s: f64,
}

fn default_absorber_strength() -> f64 {
    10.0
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct Fluid {
    pub density_kg_m3: f64,
    /// Dynamic (molecular) viscosity μ.
    pub viscosity_pa_s: f64,
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

/// The flume: a floor from x = 0 to `length_m`, vertical walls at both ends up to `height_m`.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Flume {
    pub length_m: f64,
    /// Height of the end walls above the floor.
    pub height_m: f64,
    /// Optional bed polyline `[[x, y], …]` in metres, x increasing from 0 to `length_m`.
    /// Empty means a flat floor at y = 0.
    #[serde(default)]
    pub bed_m: Vec<[f64; 2]>,
    /// A plane beach instead of `bed_m`: flat floor up to `toe_x_m`, then rising at `slope`.
    #[serde(default)]
    pub beach: Option<Beach>,
    #[serde(default)]
    pub walls: WallCondition,
}

/// A plane beach: the floor is flat (y = 0) up to the toe, then rises at `slope` (tan β) until
/// 90 % of the wall height, and is flat again up to the end wall.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Beach {
    pub toe_x_m: f64,
    /// tan β, rise over run.
    pub slope: f64,
}

impl Flume {
    /// The bed polyline `[x, y]` from x = 0 to the end: `bed_m`, the beach, or a flat floor.
    pub fn bed_points(&self) -> Vec<[f64; 2]> {
        if let Some(b) = &self.beach {
            let top = 0.9 * self.height_m;
            let rise = b.slope * (self.length_m - b.toe_x_m);
            let mut bed = vec![[0.0, 0.0], [b.toe_x_m, 0.0]];
            if rise <= top {
                bed.push([self.length_m, rise]);
            } else {
                bed.push([b.toe_x_m + top / b.slope, top]);
                bed.push([self.length_m, top]);
            }
            bed
        } else if self.bed_m.is_empty() {
            vec![[0.0, 0.0], [self.length_m, 0.0]]
        } else {
            self.bed_m.clone()
        }
    }
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum WallCondition {
    /// u = 0 at wall nodes.
    #[default]
    NoSlip,
    /// Only the velocity across the wall is zero: the water slides along it (corners stay fixed).
    Slip,
}

/// A region filled with water at the start: between `x_start_m` and `x_end_m`, from the bed up to
/// the level `depth_m` above the flume floor.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WaterRegion {
    #[serde(default)]
    pub x_start_m: f64,
    pub x_end_m: f64,
    /// Still-water level above the flume floor (y = 0).
    pub depth_m: f64,
    /// Amplitude of an initial standing-wave surface, η(x) = A cos(nπ(x − x_start)/width).
    #[serde(default)]
    pub surface_amplitude_m: f64,
    /// Mode n of that surface (1: one half wavelength over the region).
    #[serde(default = "default_mode")]
    pub surface_mode: u32,
}

fn default_mode() -> u32 {
    1
}

impl WaterRegion {
    /// Initial surface level above the flume floor at `x_m`.
    pub fn level_at(&self, x_m: f64) -> f64 {
        let width = self.x_end_m - self.x_start_m;
        let phase =
            std::f64::consts::PI * self.surface_mode as f64 * (x_m - self.x_start_m) / width;
        self.depth_m + self.surface_amplitude_m * phase.cos()
    }

    /// Does the region span `x_m` (give or take `tolerance_m`)?
    pub fn spans(&self, x_m: f64, tolerance_m: f64) -> bool {
        x_m >= self.x_start_m - tolerance_m && x_m <= self.x_end_m + tolerance_m
    }
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct ParticleSettings {
    /// Particle spacing h of the initial lattice and of the wall nodes.
    pub spacing_m: f64,
}

impl Default for ParticleSettings {
    fn default() -> Self {
        Self { spacing_m: 0.01 }
    }
}

/// Which formula gives the FIC/PSPG stabilisation parameter τ (see `fem::tau`).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum TauFormula {
    /// τ = (8μ_e/(3h²) + 2ρ/Δt)⁻¹ — viscous and inertial limits (method.md §1 recommendation).
    #[default]
    Inertial,
    /// τ = (ρ|ū|/h + ρ/Δt + 8μ/h²)⁻¹ with μ capped at 0.1 (Kratos FIC element).
    Kratos,
    /// τ = 3h²/(8μ), thesis eq. 2.66 as printed: far too large for water; kept for comparison.
    Thesis,
    /// No stabilisation term.
    None,
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum PressureSolver {
    /// Preconditioned conjugate gradients (faer, Jacobi), warm-started from the last pressure.
    Cg,
    /// Sparse Cholesky (faer, nested-dissection ordering, supernodal), factorised anew each
    /// step: about 5× faster than Jacobi-CG at 5 400 unknowns (4.0–4.4 against 21 ms per step
    /// on the dam break, where CG needs about 300 iterations).
    #[default]
    Cholesky,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSettings {
    /// α-shape parameter: a triangle is kept when its circumradius is below α·h.
    pub alpha: f64,
    /// Tighter α for triangles whose three nodes are all on the boundary (wall or free surface):
    /// they bridge concave stretches of the surface (see `mesh`). Used as min(α_b, α).
    pub alpha_boundary: f64,
    /// Pressure splitting: 0 (first order) or 1 (incremental, second order).
    pub gamma: f64,
    /// Viscous-term implicitness: 0 explicit, ½ Crank–Nicolson, 1 implicit.
    pub theta: f64,
    /// Smagorinsky constant C_s (thesis eq. 1.20 uses 0.12); 0 turns the eddy viscosity off.
    pub smagorinsky_cs: f64,
    pub tau: TauFormula,
    pub pressure_solver: PressureSolver,
    /// Relative residual at which CG stops.
    pub cg_tolerance: f64,
    pub cg_max_iterations: usize,
    /// How close (in units of h) a fluid particle may come to a solid wall before it is put back.
    pub wall_margin_h: f64,
    /// A kept triangle whose circumradius exceeds this (in units of h) gets a new particle at its
    /// centroid; 0 turns insertion off. Keep it below α so triangles split before they drop.
    pub insert_radius_h: f64,
    /// An interior particle closer than this (in units of h) to a neighbour is removed; 0 turns
    /// removal off.
    pub remove_distance_h: f64,
    /// Two free-surface fluid particles closer than this (in units of h) are merged into one at
    /// their midpoint, with their mean velocity; 0 (the default) turns it off. Where a jet lands
    /// or a bore overtakes a crest, surface particles collide and make slivers that removal,
    /// which takes only interior particles, does not reach.
    pub merge_surface_distance_h: f64,
    /// Put the water area lost since t = 0 back on the free surface every step (Kratos'
    /// PFEM-Fluid correction; see `solver/volume.rs`). Off by default: it hides the loss.
    pub volume_recovery: bool,
    /// Ask the continuity equation for the divergence that keeps each triangle's area through
    /// the move x ← x + Δt u: ∇·u = −Δt det ∇u, not 0 (see `solver/pressure.rs`). Without it,
    /// the straight-line move shrinks every element whose flow strains it (det ∇u < 0, as in
    /// irrotational wave motion) by Δt² |det ∇u| A per step.
    pub area_correction: bool,
    /// 0: p = 0 strongly on free-surface fluid nodes (the default). λ > 0: those nodes keep
    /// their continuity equation and p = 0 holds weakly, as the Robin condition
    /// ∂p/∂n + p/(λh) = 0 on the free-surface edges (see `solver/pressure.rs`).
    pub weak_surface_length_h: f64,
    /// Strength ε in [0, 1) of the surface filter: each step the velocity of a free-surface
    /// fluid node loses ε/16 of the fourth difference of the velocities along the surface
    /// (two neighbours each side). It removes ε of a node-to-node (2h) ripple per step and
    /// ε (k h)⁴/16 of a smooth wave of wavenumber k (see `solver/filter.rs`); 0 turns it off.
    pub surface_filter: f64,
    /// Relaxation time T_r of the water area, s; 0 (the default) turns it off. The area the
    /// numerics lose (remeshing, motion) is booked per vertical strip of 20 h, and the nodes
    /// deep in the water of that strip (not on the mesh boundary, no wall neighbour) are asked
    /// for the divergence that gives it back over about T_r (see `solver/relax.rs`).
    pub volume_relaxation_s: f64,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            alpha: 1.2,
            alpha_boundary: 1.0,
            gamma: 1.0,
            theta: 0.0,
            smagorinsky_cs: 0.12,
            tau: TauFormula::Inertial,
            pressure_solver: PressureSolver::Cholesky,
            cg_tolerance: 1.0e-8,
            cg_max_iterations: 2000,
            wall_margin_h: 0.4,
            insert_radius_h: 0.9,
            remove_distance_h: 0.35,
            merge_surface_distance_h: 0.0,
            volume_recovery: false,
            area_correction: false,
            weak_surface_length_h: 0.0,
            surface_filter: 0.0,
            volume_relaxation_s: 0.0,
        }
    }
}

#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, Default)]
#[serde(rename_all = "snake_case")]
pub enum DtPolicy {
    /// Δt = CFL·h/|u|max, between `dt_min_s` and `dt_max_s`.
    #[default]
    Cfl,
    /// Δt = `dt_max_s` every step.
    Fixed,
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct TimeSettings {
    pub end_s: f64,
    pub dt_policy: DtPolicy,
    /// Courant number for the CFL policy: a particle moves at most this fraction of h per step.
    pub cfl: f64,
    /// Largest step, and the step of the fixed policy.
    pub dt_max_s: f64,
    /// Smallest step the CFL policy may take before the run is declared stuck.
    pub dt_min_s: f64,
    /// Bound on ω Δt for the shortest free-surface wave the particles carry (k = π/h,
    /// ω = sqrt(g k)), i.e. Δt ≤ C / sqrt(π g / h). The free surface of the projection step
    /// grows a 2h-wavelength ripple when Δt exceeds about 0.126/ω (measured in still water:
    /// 3.2 ms at h = 2 cm, 2.3 ms at h = 1 cm), which then drains volume. Both policies obey
    /// it: the CFL policy as one more bound, the fixed one by splitting its Δt into equal
    /// substeps. 0 turns the bound off.
    pub surface_wave_courant: f64,
}

impl TimeSettings {
    /// The surface-wave bound on Δt in s for particle spacing `h_m` and gravity `g_m_s2`
    /// (infinite when the bound is off).
    pub fn surface_wave_dt_s(&self, h_m: f64, g_m_s2: f64) -> f64 {
        if self.surface_wave_courant > 0.0 {
            self.surface_wave_courant / (std::f64::consts::PI * g_m_s2 / h_m).sqrt()
        } else {
            f64::INFINITY
        }
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
            surface_wave_courant: 0.1,
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSettings {
    /// Simulated time between recorded frames and CSV rows.
    pub interval_s: f64,
    /// Log the triangle edges to the .rrd as well.
    pub mesh: bool,
    /// Colour range for u1; empty means ±sqrt(g·d) of the deepest water region.
    pub u1_range_m_s: Vec<f64>,
    /// Surface-elevation gauges: x positions, m. Recorded to gauges.csv at every output.
    pub gauges_x_m: Vec<f64>,
    /// Velocity probes: `[x, y]` positions, m (y above the flume floor). Recorded to gauges.csv
    /// as `u_<x>_<y>` and `w_<x>_<y>`; empty when the probe is dry.
    pub probes_m: Vec<[f64; 2]>,
}

impl Default for OutputSettings {
    fn default() -> Self {
        Self {
            interval_s: 0.02,
            mesh: false,
            u1_range_m_s: Vec::new(),
            gauges_x_m: Vec::new(),
            probes_m: Vec::new(),
        }
    }
}

impl Case {
    /// Reads, overrides and validates a case file.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Case, CaseError> {
        let text = std::fs::read_to_string(path).map_err(|source| CaseError::Io {
            file: path.to_owned(),
            source,
        })?;
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "case".to_owned());
        Case::from_toml_str(&text, path, &stem, overrides)
    }

    /// Parses a case from TOML text; `file` is only used in messages.
    pub fn from_toml_str(
        text: &str,
        file: &Path,
        default_name: &str,
        overrides: &[String],
    ) -> Result<Case, CaseError> {
        if text.trim().is_empty() {
            return Err(CaseError::Empty {
                file: file.to_owned(),
            });
        }
        let mut table: toml::Table = toml::from_str(text).map_err(|e| CaseError::Syntax {
            file: file.to_owned(),
            message: e.message().to_owned() + &line_hint(text, e.span()),
        })?;
        for assignment in overrides {
            apply_override(&mut table, assignment).map_err(|message| CaseError::Override {
                file: file.to_owned(),
                assignment: assignment.clone(),
                message,
            })?;
        }
        let mut case: Case =
            serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
                CaseError::Field {
                    file: file.to_owned(),
                    field: e.path().to_string(),
                    message: e.inner().message().to_owned(),
                }
            })?;
        if case.name.is_empty() {
            case.name = default_name.to_owned();
        }
        case.validate()
            .map_err(|(field, message)| CaseError::Field {
                file: file.to_owned(),
                field,
                message,
            })?;
        Ok(case)
    }

    /// The still-water level at `x_m`: the depth of the deepest region spanning it.
    pub fn still_level_at(&self, x_m: f64) -> Option<f64> {
        self.water
            .iter()
            .filter(|w| w.spans(x_m, 0.0))
            .map(|w| w.depth_m)
            .reduce(f64::max)
    }

    /// The deepest still-water depth over all regions, measured from the bed under the region.
    pub fn max_depth_m(&self) -> f64 {
        self.water.iter().map(|w| w.depth_m).fold(0.0, f64::max)
    }

    /// Bed height under `x_m`, linear between the `flume.bed_m` points (0 for a flat floor).
    pub fn bed_y_at(&self, x_m: f64) -> f64 {
        polyline_y(&self.flume.bed_points(), x_m)
    }

    /// Still-water depth in front of the paddle (level above the bed at its rest position), m.
    pub fn paddle_depth_m(&self) -> Option<f64> {
        let w = self.wavemaker.as_ref()?;
        let x = w.x_m + self.particles.spacing_m;
        Some(self.still_level_at(x)? - self.bed_y_at(w.x_m))
    }

    /// Colour range for u1.
    pub fn u1_range(&self) -> (f64, f64) {
        match self.output.u1_range_m_s.as_slice() {
            [lo, hi] => (*lo, *hi),
            _ => {
                let c = (self.fluid.gravity_m_s2 * self.max_depth_m()).sqrt();
                (-c, c)
            }
        }
    }

    /// Checks the values serde cannot: signs, ranges and geometric consistency.
    /// Returns the dotted field path and the reason.
    fn validate(&self) -> Result<(), (String, String)> {
        let err = |field: &str, message: String| Err((field.to_owned(), message));
        let positive = |field: &str, v: f64| -> Result<(), (String, String)> {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err((
                    field.to_owned(),
                    format!("must be a positive number, got {v}"),
                ))
            }
        };
        let non_negative = |field: &str, v: f64| -> Result<(), (String, String)> {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err((field.to_owned(), format!("must be finite and ≥ 0, got {v}")))
            }
        };
        positive("fluid.density_kg_m3", self.fluid.density_kg_m3)?;
        positive("fluid.gravity_m_s2", self.fluid.gravity_m_s2)?;
        if !(self.fluid.viscosity_pa_s.is_finite() && self.fluid.viscosity_pa_s >= 0.0) {
            return err(
                "fluid.viscosity_pa_s",
                format!("must be ≥ 0, got {}", self.fluid.viscosity_pa_s),
            );
        }
        positive("flume.length_m", self.flume.length_m)?;
        positive("flume.height_m", self.flume.height_m)?;
        positive("particles.spacing_m", self.particles.spacing_m)?;
        let h = self.particles.spacing_m;
        if h > 0.25 * self.flume.length_m.min(self.flume.height_m) {
            return err(
                "particles.spacing_m",
                format!(
                    "{h} m is too coarse for a flume of {} × {} m",
                    self.flume.length_m, self.flume.height_m
                ),
            );
        }
        if let Some(b) = &self.flume.beach {
            if !self.flume.bed_m.is_empty() {
                return err(
                    "flume.beach",
                    "give either flume.bed_m or flume.beach, not both".into(),
                );
            }
            if !(b.toe_x_m.is_finite() && b.toe_x_m > 0.0 && b.toe_x_m < self.flume.length_m) {
                return err(
                    "flume.beach.toe_x_m",
                    format!(
                        "must lie inside the flume (0, {}) m, got {}",
                        self.flume.length_m, b.toe_x_m
                    ),
                );
            }
            if !(b.slope.is_finite() && b.slope > 0.0 && b.slope <= 2.0) {
                return err(
                    "flume.beach.slope",
                    format!("must lie in (0, 2] (tan β), got {}", b.slope),
                );
            }
        }
        let bed = &self.flume.bed_m;
        if !bed.is_empty() {
            if bed.len() < 2 {
                return err("flume.bed_m", "needs at least two points".into());
            }
            if bed.iter().flatten().any(|v| !v.is_finite()) {
                return err("flume.bed_m", "has a non-finite coordinate".into());
            }
            if bed[0][0] != 0.0 || bed[bed.len() - 1][0] != self.flume.length_m {
                return err(
                    "flume.bed_m",
                    format!(
                        "must run from x = 0 to x = flume.length_m = {}",
                        self.flume.length_m
                    ),
                );
            }
            if bed.windows(2).any(|w| w[1][0] <= w[0][0]) {
                return err(
                    "flume.bed_m",
                    "x must increase strictly along the bed".into(),
                );
            }
            if bed
                .iter()
                .any(|p| p[1] < 0.0 || p[1] >= self.flume.height_m)
            {
                return err(
                    "flume.bed_m",
                    "bed heights must lie in [0, flume.height_m)".into(),
                );
            }
        }
        if self.water.is_empty() {
            return err("water", "at least one [[water]] region is needed".into());
        }
        for (i, w) in self.water.iter().enumerate() {
            let f = |name: &str| format!("water[{i}].{name}");
            if !w.depth_m.is_finite() || w.depth_m <= 0.0 {
                return err(
                    &f("depth_m"),
                    format!("depth must be positive, got {} m", w.depth_m),
                );
            }
            if !w.surface_amplitude_m.is_finite() || w.surface_amplitude_m.abs() >= 0.5 * w.depth_m
            {
                return err(
                    &f("surface_amplitude_m"),
                    format!(
                        "must be smaller than half the depth, got {} m",
                        w.surface_amplitude_m
                    ),
                );
            }
            if w.surface_mode == 0 {
                return err(&f("surface_mode"), "must be at least 1".into());
            }
            if w.depth_m + w.surface_amplitude_m.abs() >= self.flume.height_m {
                return err(
                    &f("depth_m"),
                    format!(
                        "water level {} m is at or above the walls (flume.height_m = {} m): water outside the flume",
                        w.depth_m, self.flume.height_m
                    ),
                );
            }
            if !(w.x_start_m.is_finite() && w.x_end_m.is_finite()) || w.x_end_m <= w.x_start_m {
                return err(
                    &f("x_end_m"),
                    format!("must exceed x_start_m = {} m", w.x_start_m),
                );
            }
            if w.x_start_m < 0.0 || w.x_end_m > self.flume.length_m {
                return err(
                    &f("x_start_m"),
                    format!(
                        "region [{}, {}] m lies outside the flume [0, {}] m: water outside the flume",
                        w.x_start_m, w.x_end_m, self.flume.length_m
                    ),
                );
            }
            if w.x_end_m - w.x_start_m < 2.0 * h {
                return err(
                    &f("x_end_m"),
                    format!("region is narrower than two particle spacings ({h} m)"),
                );
            }
        }
        let s = &self.solver;
        if !(s.alpha.is_finite() && s.alpha > 1.0) {
            return err(
                "solver.alpha",
                format!(
                    "α must be greater than 1 (1.2–1.4 is usual), got {}",
                    s.alpha
                ),
            );
        }
        if !(s.alpha_boundary.is_finite() && s.alpha_boundary >= 0.75) {
            return err(
                "solver.alpha_boundary",
                format!(
                    "must be at least 0.75 (a flat surface's right triangles have R = 0.71 h), got {}",
                    s.alpha_boundary
                ),
            );
        }
        if s.gamma != 0.0 && s.gamma != 1.0 {
            return err("solver.gamma", format!("must be 0 or 1, got {}", s.gamma));
        }
        if !(0.0..=1.0).contains(&s.theta) {
            return err(
                "solver.theta",
                format!("must lie in [0, 1], got {}", s.theta),
            );
        }
        non_negative("solver.smagorinsky_cs", s.smagorinsky_cs)?;
        positive("solver.cg_tolerance", s.cg_tolerance)?;
        if s.cg_max_iterations == 0 {
            return err("solver.cg_max_iterations", "must be at least 1".into());
        }
        if s.insert_radius_h != 0.0 && !(s.insert_radius_h > 0.5 && s.insert_radius_h < s.alpha) {
            return err(
                "solver.insert_radius_h",
                format!(
                    "must be 0 (off) or lie in (0.5, α = {}), got {}",
                    s.alpha, s.insert_radius_h
                ),
            );
        }
        if !(0.0..0.5).contains(&s.merge_surface_distance_h) {
            return err(
                "solver.merge_surface_distance_h",
                format!("must lie in [0, 0.5), got {}", s.merge_surface_distance_h),
            );
        }
        if !(0.0..0.9).contains(&s.remove_distance_h) {
            return err(
                "solver.remove_distance_h",
                format!("must lie in [0, 0.9), got {}", s.remove_distance_h),
            );
        }
        if !(0.0..0.5).contains(&s.wall_margin_h) {
            return err(
                "solver.wall_margin_h",
                format!("must lie in [0, 0.5), got {}", s.wall_margin_h),
            );
        }
        let t = &self.time;
        positive("time.end_s", t.end_s)?;
        positive("time.dt_max_s", t.dt_max_s)?;
        positive("time.dt_min_s", t.dt_min_s)?;
        if t.dt_min_s > t.dt_max_s {
            return err("time.dt_min_s", "must not exceed time.dt_max_s".into());
        }
        if !(t.cfl > 0.0 && t.cfl <= 1.0) {
            return err("time.cfl", format!("must lie in (0, 1], got {}", t.cfl));
        }
        non_negative("solver.weak_surface_length_h", s.weak_surface_length_h)?;
        non_negative("solver.volume_relaxation_s", s.volume_relaxation_s)?;
        if !(0.0..1.0).contains(&s.surface_filter) {
            return err(
                "solver.surface_filter",
                format!("must lie in [0, 1), got {}", s.surface_filter),
            );
        }
        non_negative("time.surface_wave_courant", t.surface_wave_courant)?;
        positive("output.interval_s", self.output.interval_s)?;
        if let Some(x) = self
            .output
            .gauges_x_m
            .iter()
            .find(|x| !(x.is_finite() && **x >= 0.0 && **x <= self.flume.length_m))
        {
            return err(
                "output.gauges_x_m",
                format!(
                    "gauge at x = {x} m lies outside the flume [0, {}] m",
                    self.flume.length_m
                ),
            );
        }
        if let Some(p) = self.output.probes_m.iter().find(|p| {
            !(p.iter().all(|v| v.is_finite())
                && (0.0..=self.flume.length_m).contains(&p[0])
                && (0.0..=self.flume.height_m).contains(&p[1]))
        }) {
            return err(
                "output.probes_m",
                format!("probe at {p:?} m lies outside the flume"),
            );
        }
        if let Some(a) = &self.absorber {
            if !(a.length_m.is_finite() && a.length_m > 0.0 && a.length_m < self.flume.length_m) {
                return err(
                    "absorber.length_m",
                    format!(
                        "must lie in (0, flume.length_m = {}) m, got {}",
                        self.flume.length_m, a.length_m
                    ),
                );
            }
            positive("absorber.strength_per_s", a.strength_per_s)?;
        }
        if let Some(w) = &self.wavemaker {
            self.validate_wavemaker(w)?;
        }
        let surf = &self.surf;
        if !surf.x_origin_m.is_finite() {
            return err("surf.x_origin_m", "must be finite".into());
        }
        if let Some(x) = surf
            .stations_x_m
            .iter()
            .find(|x| !(x.is_finite() && **x > 0.0 && **x < self.flume.length_m))
        {
            return err(
                "surf.stations_x_m",
                format!(
                    "station at x = {x} m lies outside the flume (0, {}) m",
                    self.flume.length_m
                ),
            );
        }
        non_negative("surf.profile_dz_m", surf.profile_dz_m)?;
        non_negative("surf.spin_up_periods", surf.spin_up_periods)?;
        if !surf.stations_x_m.is_empty() && self.wavemaker.is_none() {
            return err(
                "surf.stations_x_m",
                "undertow stations average over wave periods: the case needs a [wavemaker]".into(),
            );
        }
        match self.output.u1_range_m_s.as_slice() {
            [] => {}
            [lo, hi] if lo.is_finite() && hi.is_finite() && lo < hi => {}
            _ => {
                return err(
                    "output.u1_range_m_s",
                    "must be [min, max] with min < max".into(),
                );
            }
        }
        Ok(())
    }
}

impl Case {
    fn validate_wavemaker(&self, w: &WavemakerSettings) -> Result<(), (String, String)> {
        let err = |field: &str, message: String| Err((field.to_owned(), message));
        let h = self.particles.spacing_m;
        if !(w.x_m.is_finite() && w.x_m > 0.0 && w.x_m < 0.5 * self.flume.length_m) {
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
        let Some(depth) = self.paddle_depth_m().filter(|d| *d > 2.0 * h) else {
            return err(
                "wavemaker.x_m",
                format!(
                    "no water (deeper than 2 h) stands just in front of the paddle at x = {} m",
                    w.x_m
                ),
            );
        };
        // The motion is designed from the theory in `crate::wavemaker`.
        let motion = match PaddleMotion::from_case(self) {
            Some(Ok(m)) => m,
            Some(Err(e)) => {
                return err(
                    if w.paddle_height_m.is_some() {
                        "wavemaker.paddle_height_m"
                    } else {
                        "wavemaker.height_m"
                    },
                    format!("the wave cannot be made: {e}"),
                );
            }
            None => unreachable!("a wavemaker is present"),
        };
        // The top of a flap moves (top height / depth) times as far as its still-water point.
        let reach = match w.paddle {
            PaddleKind::Piston => 1.0,
            PaddleKind::Flap => (self.flume.height_m - self.bed_y_at(w.x_m)) / depth,
        };
        let (back, _) = motion.excursion_m();
        if w.x_m + reach * back < 2.0 * h {
            return err(
                "wavemaker.x_m",
                format!(
                    "the paddle swings back {:.3} m and would hit the left wall: put it at x ≥ {:.3} m",
                    -reach * back,
                    -reach * back + 2.0 * h
                ),
            );
        }
        Ok(())
    }
}

/// y of a polyline `[x, y]` (x increasing, at least one point) at `x_m`, linear between the
/// points and constant beyond the ends: the bed height, here and in `geometry`.
pub fn polyline_y(points: &[[f64; 2]], x_m: f64) -> f64 {
    if x_m <= points[0][0] {
        return points[0][1];
    }
    for w in points.windows(2) {
        if x_m <= w[1][0] {
            let s = (x_m - w[0][0]) / (w[1][0] - w[0][0]);
            return w[0][1] + s * (w[1][1] - w[0][1]);
        }
    }
    points[points.len() - 1][1]
}

/// " (line L)" for a byte span of `text`, or nothing.
fn line_hint(text: &str, span: Option<std::ops::Range<usize>>) -> String {
    match span {
        Some(r) => {
            let line = text[..r.start.min(text.len())].matches('\n').count() + 1;
            format!(" (line {line})")
        }
        None => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str =
        "[flume]\nlength_m = 1.0\nheight_m = 0.8\n[[water]]\nx_end_m = 1.0\ndepth_m = 0.5\n";

    fn parse(text: &str, overrides: &[&str]) -> Result<Case, CaseError> {
        let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        Case::from_toml_str(text, Path::new("test.toml"), "test", &o)
    }

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
    fn minimal_case_takes_defaults() {
        let c = parse(MINIMAL, &[]).unwrap();
        assert_eq!(c.name, "test");
        assert_eq!(c.solver.alpha, 1.2);
        assert_eq!(c.fluid.density_kg_m3, 1000.0);
    }

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

    #[test]
    fn unknown_field_is_named() {
        let e = parse(&format!("{MINIMAL}[solver]\nalpah = 1.3\n"), &[]).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("alpah") && msg.contains("test.toml"), "{msg}");
    }

    #[test]
    fn override_by_dotted_path() {
        let c = parse(
            MINIMAL,
            &[
                "solver.alpha=1.3",
                "time.dt_policy=fixed",
                "output.mesh=true",
            ],
        )
        .unwrap();
        assert_eq!(c.solver.alpha, 1.3);
        assert_eq!(c.time.dt_policy, DtPolicy::Fixed);
        assert!(c.output.mesh);
        let c = parse(MINIMAL, &["water.0.depth_m=0.4"]).unwrap();
        assert_eq!(c.water[0].depth_m, 0.4);
    }

    #[test]
    fn bad_values_are_refused_with_the_field() {
        for (o, field) in [
            ("solver.alpha=1.0", "solver.alpha"),
            ("water.0.depth_m=-0.5", "water[0].depth_m"),
            ("water.0.x_end_m=2.0", "water[0].x_start_m"),
            ("particles.spacing_m=0", "particles.spacing_m"),
            ("solver.gamma=0.5", "solver.gamma"),
        ] {
            let msg = parse(MINIMAL, &[o]).unwrap_err().to_string();
            assert!(msg.contains(field), "{o}: {msg}");
        }
        assert!(
            parse(MINIMAL, &["solver.nope=1"])
                .unwrap_err()
                .to_string()
                .contains("nope")
        );
    }

    #[test]
    fn empty_and_non_toml_are_errors() {
        assert!(matches!(parse("  \n", &[]), Err(CaseError::Empty { .. })));
        assert!(matches!(
            parse("this is not toml", &[]),
            Err(CaseError::Syntax { .. })
        ));
    }
}
