//! `[solver]`: the α-shape, the fractional step, stabilisation, the pressure solver, node
//! management and the optional corrections of the free surface and the water area.

use serde::{Deserialize, Serialize};

use super::{err, non_negative, off_if_zero, positive};

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

/// The solver's settings. The optional ones are off when `None`: a case file turns them off by
/// writing 0. Those that are on by default (`insert_radius_h`, `remove_distance_h`) write `null`
/// into summary.json when off, so that reading the summary back gives off, not the default;
/// those that are off by default are left out of it when off.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSettings {
    /// α-shape parameter: a triangle is kept when its circumradius is below α·h. Default 1.2.
    pub alpha: f64,
    /// Tighter α for triangles whose three nodes are all on the boundary (wall or free surface):
    /// they bridge concave stretches of the surface (see `mesh`). Used as min(α_b, α).
    /// Default 1.0.
    pub alpha_boundary: f64,
    /// Extended Delaunay Tessellation (thesis eq. 2.2): two neighbouring Delaunay triangles
    /// whose circumcentres are closer than δ times their mean circumradius are merged into one
    /// polygon element with MFEM shape functions (`mesh::edt`, `fem::polygon`). 0 keeps plain
    /// Delaunay triangles. Lies in [0, 1]; docs/alpha_delta.md measures 0.01–0.1. Default 0.
    pub delta: f64,
    /// Pressure splitting: 0 (first order) or 1 (incremental, second order). Default 1.
    pub gamma: f64,
    /// Weight β ≥ 1 of the weak surface's Robin term R in the incremental split's operator:
    /// (Δt/ρ L + L_τ + βR)(pⁿ⁺¹ − pⁿ) = −Dũ − (L_τ + R) pⁿ − Qπⁿ; β = 1 is the usual split.
    /// β does not enter the converged pressure; it sets how fast the surface's pressure
    /// reaches it. With β = 1 a pressure mode of the surface layer alternates from step to step
    /// (±2–5 kPa at 2–8 cm depth in Ting & Kirby's flume, growing into kicks of 10–30 m/s)
    /// wherever Δt D M⁻¹ Dᵀ exceeds (2/3)(2Δt/ρ L + L_τ + R), as the split's three-level
    /// recurrence gives (see `solver/pressure.rs`); β = 2 removes it (1.1 already nearly).
    /// Needs the weak surface (`weak_surface_length_h`). Default 1: without the mode the
    /// particles' move loses more water where no volume ledger gives it back (the 1:8 beach
    /// 2.9 → 4.2–4.3 % for every β from 1.1 to 2, the flap 0.500 → 0.563 %; docs/method.md,
    /// *The weighted surface*); Ting & Kirby's case files, which have the ledger, set 2. 2D only.
    pub increment_weight: f64,
    /// Viscous-term implicitness: 0 explicit, ½ Crank–Nicolson, 1 implicit. Default 0.
    pub theta: f64,
    /// Smagorinsky constant C_s (thesis eq. 1.20 uses 0.12); 0 turns the eddy viscosity off.
    /// Default 0.12.
    pub smagorinsky_cs: f64,
    /// Default (`None`): `inertial` in 2D, `none` in 3D ([`SolverSettings::tau_formula`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tau: Option<TauFormula>,
    /// Default `cholesky`.
    pub pressure_solver: PressureSolver,
    /// Relative residual at which CG stops. Default 1e-8.
    pub cg_tolerance: f64,
    /// Default 2000.
    pub cg_max_iterations: usize,
    /// How close (in units of h) a fluid particle may come to a solid wall before it is put back.
    /// Default 0.4.
    pub wall_margin_h: f64,
    /// A kept triangle whose circumradius exceeds this (in units of h) gets a new particle at its
    /// centroid; `None` (0 in a case file) turns insertion off. Keep it below α so triangles
    /// split before they drop. Default 0.9.
    pub insert_radius_h: Option<f64>,
    /// An interior particle closer than this (in units of h) to a neighbour is removed; `None`
    /// (0 in a case file) turns removal off. Default 0.35.
    pub remove_distance_h: Option<f64>,
    /// Two free-surface fluid particles closer than this (in units of h) are merged into one at
    /// their midpoint, with their mean velocity. Where a jet lands or a bore overtakes a crest,
    /// surface particles collide and make slivers that removal, which takes only interior
    /// particles, does not reach. Default off (`None`; 0 in a case file is off too).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub merge_surface_distance_h: Option<f64>,
    /// Put the water area lost since t = 0 back on the free surface every step (Kratos'
    /// PFEM-Fluid correction; see `solver/volume.rs`). Default off (false): it hides the loss.
    pub volume_recovery: bool,
    /// Ask the continuity equation for the divergence that keeps each triangle's area through
    /// the move x ← x + Δt u: ∇·u = −Δt det ∇u, not 0 (see `solver/pressure.rs`). Without it,
    /// the straight-line move shrinks every element whose flow strains it (det ∇u < 0, as in
    /// irrotational wave motion) by Δt² |det ∇u| A per step. Default off (false).
    pub area_correction: bool,
    /// Move each fluid particle by the implicit midpoint rule in the end-of-step velocity
    /// field, x ← x + Δt (I − Δt G/2)⁻¹ uⁿ⁺¹ (G the particle's area-weighted ∇uⁿ⁺¹), instead of
    /// x ← x + Δt uⁿ⁺¹. In a linear flow this is the exact midpoint map, which keeps every
    /// element's area when ∇·u = 0, where the straight-line move changes it by Δt² A det ∇u
    /// (see `solver/motion.rs`). Default off (false: the thesis's eq. 2.59): on the dam break
    /// the straight move's loss hides a gain of the α-shape at the spreading front, and the
    /// drift bar there is met only by the two cancelling (docs/validation/surface_mode.md).
    pub midpoint_move: bool,
    /// `None`: p = 0 strongly on free-surface fluid nodes. λ > 0: those nodes keep their
    /// continuity equation and p = 0 holds weakly, as the Robin condition
    /// ∂p/∂n + p/(λh) = 0 on the free-surface edges (see `solver/pressure.rs`). Default `None`
    /// (strong; 0 in a case file means strong too).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weak_surface_length_h: Option<f64>,
    /// Strength ε in [0, 1) of the surface filter: each step the velocity of a free-surface
    /// fluid node loses ε/16 of the fourth difference of the velocities along the surface
    /// (two neighbours each side). It removes ε of a node-to-node (2h) ripple per step and
    /// ε (k h)⁴/16 of a smooth wave of wavenumber k (see `solver/filter.rs`; in 3D the same
    /// filter on the surface's triangles, `solver3d/filter.rs`). Default off (`None`; 0 in a
    /// case file is off too).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface_filter: Option<f64>,
    /// Relaxation time T_r of the water area, s. The area the numerics lose (remeshing, motion)
    /// is booked per vertical strip of 20 h, and the nodes deep in the water of that strip (not
    /// on the mesh boundary, no wall neighbour) are asked for the divergence that gives it back
    /// over about T_r (see `solver/relax.rs`; in 3D per cell of 20 h along x and about 20 h
    /// across, `solver3d/relax.rs`). Default off (`None`; 0 in a case file is off too).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume_relaxation_s: Option<f64>,
    /// Implicitness θₓ in (0, 1] of the short-scale surface motion. After the first pass of the
    /// step, each free-surface fluid node is moved by θₓ Δt times the part of uⁿ⁺¹ that its
    /// 9-node neighbourhood along the surface does not share, and the element properties, the
    /// predictor, the pressure and the correction are computed again on that geometry (one
    /// extra pass, as Kratos PFEM and PFEM3D iterate on the moved mesh, but only for the
    /// short scales). The surface's restoring force then sees where the step takes a ripple,
    /// which removes the one-step lag that makes 3–8 h surface modes grow at Δt above about
    /// 2.5 ms at h = 2 cm; waves of 30 h and more are left as they were (a wave of wavenumber k
    /// is damped by θₓ (1 − ŝ(k)) ω² Δt/2 per second, ŝ the window's response; see
    /// `solver/motion.rs` and docs/validation/surface_mode.md). Default off (`None`; 0 in a
    /// case file is off too).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry_theta: Option<f64>,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            alpha: 1.2,
            alpha_boundary: 1.0,
            delta: 0.0,
            gamma: 1.0,
            increment_weight: 1.0,
            theta: 0.0,
            smagorinsky_cs: 0.12,
            tau: None,
            pressure_solver: PressureSolver::Cholesky,
            cg_tolerance: 1.0e-8,
            cg_max_iterations: 2000,
            wall_margin_h: 0.4,
            insert_radius_h: Some(0.9),
            remove_distance_h: Some(0.35),
            merge_surface_distance_h: None,
            volume_recovery: false,
            area_correction: false,
            midpoint_move: false,
            weak_surface_length_h: None,
            surface_filter: None,
            volume_relaxation_s: None,
            geometry_theta: None,
        }
    }
}

impl SolverSettings {
    /// The FIC formula a run uses: the case's `solver.tau`, else `inertial` in 2D and `none`
    /// in 3D. In 3D the FIC term lets the continuity rows of the water hold a divergence
    /// τ ∇·(∇p + π) wherever the pressure gradient departs from last step's projection, which
    /// it does in the layer under the free surface (whose nodes have no row), and there the
    /// water was lost: without it the narrow piston tank, the sloshing tank and the dam break
    /// lost a half to a third as much of their water (`docs/three_d.md`, *The FIC term in
    /// 3D*). The incremental split keeps its own stabilisation, (Δt/ρ)(L − D M⁻¹ G) of the
    /// pressure's increment.
    pub fn tau_formula(&self, three_d: bool) -> TauFormula {
        self.tau.unwrap_or(if three_d {
            TauFormula::None
        } else {
            TauFormula::Inertial
        })
    }

    /// Reads the 0 a case file writes for an optional setting as `None`.
    pub(super) fn zero_means_off(&mut self) {
        for v in [
            &mut self.insert_radius_h,
            &mut self.remove_distance_h,
            &mut self.merge_surface_distance_h,
            &mut self.weak_surface_length_h,
            &mut self.surface_filter,
            &mut self.volume_relaxation_s,
            &mut self.geometry_theta,
        ] {
            off_if_zero(v);
        }
    }

    /// Each setting in its range; insertion, when on, between 0.5 h and α h.
    pub(super) fn validate(&self) -> Result<(), (String, String)> {
        let s = self;
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
        if !(0.0..=1.0).contains(&s.delta) {
            return err(
                "solver.delta",
                format!(
                    "δ must lie in [0, 1] (0: plain Delaunay triangles; small values such as 0.01–0.1 merge nearly co-circular ones), got {}",
                    s.delta
                ),
            );
        }
        if s.gamma != 0.0 && s.gamma != 1.0 {
            return err("solver.gamma", format!("must be 0 or 1, got {}", s.gamma));
        }
        let b = s.increment_weight;
        if !(b.is_finite() && (1.0..=100.0).contains(&b)) {
            return err(
                "solver.increment_weight",
                format!("β must lie in [1, 100] (1: the usual split), got {b}"),
            );
        }
        if b != 1.0 && s.weak_surface_length_h.is_none() {
            return err(
                "solver.increment_weight",
                "weights the weak surface's Robin term: set solver.weak_surface_length_h too, \
                 or leave it at 1"
                    .into(),
            );
        }
        if !(0.0..=1.0).contains(&s.theta) {
            return err(
                "solver.theta",
                format!("must lie in [0, 1], got {}", s.theta),
            );
        }
        if let Some(t) = s.geometry_theta
            && !(t > 0.0 && t <= 1.0)
        {
            return err(
                "solver.geometry_theta",
                format!("must be 0 (off) or lie in (0, 1], got {t}"),
            );
        }
        non_negative("solver.smagorinsky_cs", s.smagorinsky_cs)?;
        positive("solver.cg_tolerance", s.cg_tolerance)?;
        if s.cg_max_iterations == 0 {
            return err("solver.cg_max_iterations", "must be at least 1".into());
        }
        if let Some(r) = s.insert_radius_h
            && !(r > 0.5 && r < s.alpha)
        {
            return err(
                "solver.insert_radius_h",
                format!(
                    "must be 0 (off) or lie in (0.5, α = {}), got {}",
                    s.alpha, r
                ),
            );
        }
        if let Some(d) = s.merge_surface_distance_h
            && !(0.0..0.5).contains(&d)
        {
            return err(
                "solver.merge_surface_distance_h",
                format!("must lie in [0, 0.5), got {d}"),
            );
        }
        if let Some(d) = s.remove_distance_h
            && !(0.0..0.9).contains(&d)
        {
            return err(
                "solver.remove_distance_h",
                format!("must lie in [0, 0.9), got {d}"),
            );
        }
        if !(0.0..0.5).contains(&s.wall_margin_h) {
            return err(
                "solver.wall_margin_h",
                format!("must lie in [0, 0.5), got {}", s.wall_margin_h),
            );
        }
        if let Some(l) = s.weak_surface_length_h {
            non_negative("solver.weak_surface_length_h", l)?;
        }
        if let Some(t) = s.volume_relaxation_s {
            non_negative("solver.volume_relaxation_s", t)?;
        }
        if let Some(e) = s.surface_filter
            && !(0.0..1.0).contains(&e)
        {
            return err(
                "solver.surface_filter",
                format!("must lie in [0, 1), got {e}"),
            );
        }
        Ok(())
    }
}
