//! Cases: one TOML file per run, parsed with serde.
//!
//! Every table has defaults, so a case says only what differs, and every table denies unknown
//! fields, so a typo is an error that names the field instead of a silent default. A case can be
//! changed from the command line with `--set dotted.path=value` overrides, applied to the parsed
//! TOML before it is turned into a [`Case`], so they are checked exactly like the file itself.
//!
//! One file per table: `fluid`, `flume` (with the bed), `water`, `particles`, `solver`, `time`,
//! `output`, `wavemaker` (with `[absorber]`) and `surf`. Each holds the table's fields, their
//! defaults (stated in each field's doc comment) and the checks serde cannot make; this file
//! holds the whole [`Case`], its loading and the helpers that read several tables at once.
//!
//! A setting that can be switched off is an `Option`: `None` is off. TOML has no null, so a case
//! file (or a `--set`) turns such a setting off by writing 0 (an empty list for
//! `output.u1_range_m_s`), which is read as `None` before the case is checked.
//!
//! Lengths are in metres with y up and y = 0 at the flume floor; times in seconds; SI throughout.

mod fluid;
mod flume;
mod output;
mod overrides;
mod particles;
mod size;
mod solver;
mod surf;
mod time;
mod water;
mod wavemaker;

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

pub use fluid::Fluid;
pub use flume::{BAR_MAX_SLOPE, Bar, Beach, Flume, WallCondition, polyline_slope, polyline_y};
pub use output::OutputSettings;
pub use overrides::apply_override;
pub use particles::{ParticleSettings, Refinement, Spacing};
pub use size::{DEFAULT_MAX_NODES, SizeEstimate, max_nodes, set_max_nodes};
pub use solver::{PressureSolver, SolverSettings, TauFormula};
pub use surf::SurfSettings;
pub use time::{DtPolicy, TimeSettings};
pub use water::WaterRegion;
pub use wavemaker::{Absorber, WaveTheory, WavemakerSettings};

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
    /// Name of the run. Default: the file stem.
    #[serde(default)]
    pub name: String,
    /// Free text shown in the summary. Default empty.
    #[serde(default)]
    pub description: String,
    /// Default: water (see [`Fluid`]).
    #[serde(default)]
    pub fluid: Fluid,
    /// The flume's walls and bed. Required.
    pub flume: Flume,
    /// Initial water regions; at least one (the default, none, is refused).
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
    /// A paddle that makes waves at the left end of the flume. Default none.
    #[serde(default)]
    pub wavemaker: Option<WavemakerSettings>,
    /// A passive damping layer at the right end, for flumes without a beach. Default none.
    #[serde(default)]
    pub absorber: Option<Absorber>,
    /// Surf-zone diagnostics: undertow stations, spin-up, the reference frame of the data.
    #[serde(default)]
    pub surf: SurfSettings,
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
        case.zero_means_off();
        case.validate()
            .map_err(|(field, message)| CaseError::Field {
                file: file.to_owned(),
                field,
                message,
            })?;
        Ok(case)
    }

    /// Validates a case changed in code (the lab's controls) exactly as a file is validated;
    /// `file` is only used in messages.
    pub fn check(&self, file: &Path) -> Result<(), CaseError> {
        self.validate()
            .map_err(|(field, message)| CaseError::Field {
                file: file.to_owned(),
                field,
                message,
            })
    }

    /// The case a run wrote to its summary.json (`parameters`), as it was: not validated
    /// again. Summaries written before a setting became an `Option` hold 0 where it was off;
    /// that 0 is read as off here too.
    pub fn from_summary(parameters: serde_json::Value) -> Result<Case, serde_json::Error> {
        let mut case: Case = serde_json::from_value(parameters)?;
        case.zero_means_off();
        Ok(case)
    }

    /// Reads the 0 (or empty list) a case file writes for an optional setting as `None`.
    fn zero_means_off(&mut self) {
        self.solver.zero_means_off();
        self.time.zero_means_off();
        self.output.zero_means_off();
        self.surf.zero_means_off();
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
        self.flume.bed_y_at(x_m)
    }

    /// Still-water depth in front of the paddle (level above the bed at its rest position), m.
    pub fn paddle_depth_m(&self) -> Option<f64> {
        let w = self.wavemaker.as_ref()?;
        let x = w.x_m + self.particles.spacing_m;
        Some(self.still_level_at(x)? - self.bed_y_at(w.x_m))
    }

    /// Colour range for u1: `output.u1_range_m_s`, else ±sqrt(g·d) of the deepest region.
    pub fn u1_range(&self) -> (f64, f64) {
        match self.output.u1_range_m_s.as_deref() {
            Some([lo, hi]) => (*lo, *hi),
            _ => {
                let c = (self.fluid.gravity_m_s2 * self.max_depth_m()).sqrt();
                (-c, c)
            }
        }
    }

    /// Checks the values serde cannot: signs, ranges and geometric consistency, table by table
    /// (each table's checks are beside its fields). Returns the dotted field path and the reason.
    fn validate(&self) -> Result<(), (String, String)> {
        self.fluid.validate()?;
        self.flume.validate()?;
        self.particles.validate(&self.flume)?;
        let h = self.particles.spacing_m;
        water::validate_regions(&self.water, &self.flume, h)?;
        self.solver.validate()?;
        self.time.validate()?;
        self.output.validate(&self.flume)?;
        if let Some(a) = &self.absorber {
            a.validate(self.flume.length_m)?;
        }
        if let Some(w) = &self.wavemaker {
            // The wave must be one the paddle can make, and its stroke must fit in the flume:
            // both need the motion designed from the theory (in `crate::wavemaker`).
            w.validate(
                &self.flume,
                h,
                self.fluid.gravity_m_s2,
                self.paddle_depth_m(),
                || {
                    PaddleMotion::from_case(self)
                        .expect("a wavemaker is present")
                        .map(|m| m.excursion_m())
                },
            )?;
        }
        self.surf.validate(
            self.flume.length_m,
            self.flume.width_m,
            self.wavemaker.is_some(),
        )?;
        self.validate_size()
    }
}

/// A refusal of `field` with `message`.
fn err(field: &str, message: String) -> Result<(), (String, String)> {
    Err((field.to_owned(), message))
}

/// Refuses `v` unless it is finite and > 0.
fn positive(field: &str, v: f64) -> Result<(), (String, String)> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        err(field, format!("must be a positive number, got {v}"))
    }
}

/// Refuses an abscissa `x_m` unless it lies strictly inside a flume `length_m` long.
fn inside_flume(field: &str, x_m: f64, length_m: f64) -> Result<(), (String, String)> {
    if x_m.is_finite() && x_m > 0.0 && x_m < length_m {
        Ok(())
    } else {
        err(
            field,
            format!("must lie inside the flume (0, {length_m}) m, got {x_m}"),
        )
    }
}

/// Refuses `v` unless it is finite and ≥ 0.
fn non_negative(field: &str, v: f64) -> Result<(), (String, String)> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        err(field, format!("must be finite and ≥ 0, got {v}"))
    }
}

/// An optional setting written as 0 (the case file's "off") becomes `None`.
fn off_if_zero(v: &mut Option<f64>) {
    if *v == Some(0.0) {
        *v = None;
    }
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

    pub(super) const MINIMAL: &str =
        "[flume]\nlength_m = 1.0\nheight_m = 0.8\n[[water]]\nx_end_m = 1.0\ndepth_m = 0.5\n";

    pub(super) fn parse(text: &str, overrides: &[&str]) -> Result<Case, CaseError> {
        let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
        Case::from_toml_str(text, Path::new("test.toml"), "test", &o)
    }

    #[test]
    fn minimal_case_takes_defaults() {
        let c = parse(MINIMAL, &[]).unwrap();
        assert_eq!(c.name, "test");
        assert_eq!(c.solver.alpha, 1.2);
        assert_eq!(c.fluid.density_kg_m3, 1000.0);
    }

    #[test]
    fn the_fic_term_defaults_to_inertial_in_2d_and_none_in_3d() {
        use super::solver::TauFormula;
        let c = parse(MINIMAL, &[]).unwrap();
        assert_eq!(c.solver.tau, None);
        assert_eq!(c.solver.tau_formula(false), TauFormula::Inertial);
        assert_eq!(c.solver.tau_formula(true), TauFormula::None);
        // A case's own setting holds in either.
        let c = parse(MINIMAL, &["solver.tau=kratos"]).unwrap();
        assert_eq!(c.solver.tau_formula(false), TauFormula::Kratos);
        assert_eq!(c.solver.tau_formula(true), TauFormula::Kratos);
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
            ("solver.increment_weight=0.5", "solver.increment_weight"),
            // It weights the weak surface's Robin term, which the minimal case has not.
            ("solver.increment_weight=2", "solver.increment_weight"),
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

    /// Every optional setting written as 0 (or, for the colour range, an empty list).
    const ALL_OFF: &str = "[solver]\ninsert_radius_h = 0.0\nremove_distance_h = 0\n\
        merge_surface_distance_h = 0.0\nweak_surface_length_h = 0.0\nsurface_filter = 0.0\n\
        volume_relaxation_s = 0.0\ngeometry_theta = 0.0\n[time]\nsurface_wave_courant = 0.0\n\
        [output]\nu1_range_m_s = []\n[surf]\nprofile_dz_m = 0.0\n";

    fn assert_all_off(c: &Case) {
        let s = &c.solver;
        assert_eq!(
            [
                s.insert_radius_h,
                s.remove_distance_h,
                s.merge_surface_distance_h,
                s.weak_surface_length_h,
                s.surface_filter,
                s.volume_relaxation_s,
                s.geometry_theta,
                c.time.surface_wave_courant,
                c.surf.profile_dz_m,
            ],
            [None; 9]
        );
        assert_eq!(c.output.u1_range_m_s, None);
    }

    #[test]
    fn zero_in_a_case_file_or_an_override_means_off() {
        let d = parse(MINIMAL, &[]).unwrap();
        assert_eq!(d.solver.insert_radius_h, Some(0.9));
        assert_eq!(d.solver.remove_distance_h, Some(0.35));
        assert_eq!(d.time.surface_wave_courant, Some(0.1));
        assert_eq!(d.solver.surface_filter, None);
        assert_eq!(d.surf.profile_dz_m, None);
        assert_all_off(&parse(&format!("{MINIMAL}{ALL_OFF}"), &[]).unwrap());
        let sets = [
            "solver.insert_radius_h=0",
            "solver.remove_distance_h=0",
            "solver.merge_surface_distance_h=0",
            "solver.weak_surface_length_h=0.0",
            "solver.surface_filter=0",
            "solver.volume_relaxation_s=0",
            "solver.geometry_theta=0",
            "time.surface_wave_courant=0",
            "output.u1_range_m_s=[]",
            "surf.profile_dz_m=0",
        ];
        assert_all_off(&parse(MINIMAL, &sets).unwrap());
        let on = parse(
            MINIMAL,
            &["solver.surface_filter=0.2", "output.u1_range_m_s=[-1, 1]"],
        )
        .unwrap();
        assert_eq!(on.solver.surface_filter, Some(0.2));
        assert_eq!(on.u1_range(), (-1.0, 1.0));
        for (o, field) in [
            ("output.u1_range_m_s=[1]", "output.u1_range_m_s"),
            ("solver.insert_radius_h=0.4", "solver.insert_radius_h"),
            ("solver.remove_distance_h=-0.1", "solver.remove_distance_h"),
            ("solver.surface_filter=1", "solver.surface_filter"),
            (
                "solver.volume_relaxation_s=-1",
                "solver.volume_relaxation_s",
            ),
            ("surf.profile_dz_m=-0.01", "surf.profile_dz_m"),
            ("solver.geometry_theta=1.5", "solver.geometry_theta"),
            ("solver.geometry_theta=-0.5", "solver.geometry_theta"),
        ] {
            let msg = parse(MINIMAL, &[o]).unwrap_err().to_string();
            assert!(msg.contains(field), "{o}: {msg}");
        }
    }

    #[test]
    fn the_summary_reads_back_as_the_case() {
        let c = parse(&format!("{MINIMAL}{ALL_OFF}"), &[]).unwrap();
        let json = serde_json::to_value(&c).unwrap();
        // Off where the default is on: null, so it does not read back as the default.
        assert!(json["time"]["surface_wave_courant"].is_null());
        assert!(json["solver"].get("insert_radius_h").is_some());
        // Off where the default is off: left out.
        assert!(json["solver"].get("surface_filter").is_none());
        assert!(json["output"].get("u1_range_m_s").is_none());
        assert_eq!(Case::from_summary(json).unwrap(), c);
        let d = parse(MINIMAL, &[]).unwrap();
        assert_eq!(
            Case::from_summary(serde_json::to_value(&d).unwrap()).unwrap(),
            d
        );
        // A summary written while these were plain numbers holds 0 (and []) where they were off.
        let mut old = serde_json::to_value(&d).unwrap();
        for (table, key) in [
            ("solver", "insert_radius_h"),
            ("solver", "remove_distance_h"),
            ("solver", "merge_surface_distance_h"),
            ("solver", "weak_surface_length_h"),
            ("solver", "surface_filter"),
            ("solver", "volume_relaxation_s"),
            ("solver", "geometry_theta"),
            ("time", "surface_wave_courant"),
            ("surf", "profile_dz_m"),
        ] {
            old[table][key] = 0.0.into();
        }
        old["output"]["u1_range_m_s"] = serde_json::json!([]);
        assert_all_off(&Case::from_summary(old).unwrap());
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
