//! Stages `assemble` and `pressure_solve`: the stabilised pressure Poisson equation
//! (thesis eq. 2.74 with the τ of method.md §1):
//!
//! (Δt/ρ L + L_τ) pⁿ⁺¹ = −D ũ + γ (Δt/ρ) L pⁿ − Q πⁿ (with β = 1, below),
//!
//! with, per element, L_ij = A b_i·b_j, L_τ,ij = τ_e A b_i·b_j, (D ũ)_i = (A/3) ∇·ũ and
//! (Q π)_i = τ_e A b_i·π̄; with `volume_relaxation_s`, D ũ becomes D ũ − M s, s the
//! divergence asked of the deep nodes by `relax.rs`. With `area_correction`, ∇·ũ in D ũ
//! becomes ∇·ũ + Δt det ∇ũ: the move x ← x + Δt u maps a triangle of area A to one of area
//! A (1 + Δt ∇·u + Δt² det ∇u), so asking for ∇·u = −Δt det ∇u keeps it, where ∇·u = 0 would
//! lose Δt² |det ∇u| A per step wherever the flow strains the element (det ∇u = −(∂ₓu)² −
//! ∂_y u ∂ₓw < 0 for irrotational flow, so the loss is one-signed and grows with time). The
//! correction leaves out the triangles with a wall node.
//!
//! Since L_τ p + Q π = Σ τ_e A b_i·(∇p + π̄) and π ≈ −∇p, the stabilisation vanishes where
//! the pressure gradient is smooth (hydrostatic water included). p = 0 is imposed strongly on
//! free-surface nodes and isolated nodes; the other wall nodes are unknowns. A wall node on the
//! free surface is a contact point: the water line meets the wall somewhere between it and the
//! next wall node, so it gets the hydrostatic pressure ρ g (ȳ − y) of the fluid surface nodes
//! next to it (ȳ their mean height), not 0. With 0 there, the kept triangle at the wall would
//! hold a pressure that falls to 0 at a node up to h below or above the water line, and its
//! gradient would push the water away from or into the wall: the still tank at h = 4 cm, whose
//! water line lies 5.6 mm below a wall node, moved at 0.05 m/s within 0.5 s; now it holds
//! 1e-14 m/s. The edge from that wall node to the water line is on the free surface but not at
//! p = 0, so the pressure force of `predict.rs` and `correct.rs` leaves out its traction.
//! With `weak_surface_length_h` λ/h(x) > 0, free-surface fluid nodes stay unknowns with their own
//! continuity row and p = 0 holds weakly through the Robin term
//! (Δt/ρ + τ_e) ℓ/(2λ) on the diagonal of both nodes of each free-surface edge of length ℓ.
//! Strong p = 0 leaves the surface layer without a continuity equation, and there a 2h ripple
//! grows out of round-off (README, *Surface ripple*); the weak form damps it. The matrix is
//! symmetric positive definite and assembled straight into CSR from the mesh.
//!
//! The incremental split (γ = 1) with the weak surface weights the surface's share of the
//! increment's operator by β (`solver.increment_weight`): with R the Robin term and
//! S = (Δt/ρ)L + (β − 1)R, (S + L_τ + R) pⁿ⁺¹ = −D ũ + S pⁿ − Q πⁿ, which converges to the
//! same pressure for every β. The velocity ũ carries Δt M⁻¹Dᵀpⁿ, so with W = Δt D M⁻¹ Dᵀ,
//! T = L_τ + R and the last step's divergence left in uⁿ, the pressure of a fixed mesh obeys
//! the three-level recurrence (S + T) pⁿ⁺¹ = (2S + T − 2W) pⁿ + (W − S) pⁿ⁻¹ + forcing. A mode
//! with the Rayleigh quotients w, s, t has a root μ = −1, a pressure that alternates from step
//! to step, when 3w = 4s + 2t; with β = 1 that is w = (2/3)(2a + t). In Ting & Kirby's flume,
//! at the nodes where the pressure alternated (±2–5 kPa at 2–8 cm depth, growing into
//! 10–30 m/s kicks on broken crests), the increment's w/(2a + t) measured 0.69–0.71. The modes
//! are those of the surface layer, where a nearly uniform pressure over a few surface nodes
//! pushes them (w up to 23 a) while its gradient is small; R holds them, and the (β − 1)R of S
//! moves the onset to 3w = 4a + 2t + (4β − 2)r. A weight on the Laplacian instead (βL in S)
//! leaves some of them even at β = 3 and slows the pressure everywhere: the dam break's
//! volume drift passed its bar (docs/validation/ting_kirby.md).
//!
//! The pattern and the Dirichlet set are known as soon as the α-shape is: `prepare_pressure`
//! builds the pattern and, for the Cholesky solver, starts the symbolic analysis (the
//! nested-dissection ordering of `ordering.rs` and faer's supernodal structure) on a second
//! thread, which works while this one computes the element properties, the predictor and the
//! matrix values.

use super::element_set::{ElementSet, PolygonOperators, polygon_boundary};
use super::{Solver, StepError, pieces};
use crate::case::PressureSolver;
use crate::mesh::edt::MAX_POLYGON_NODES;
use crate::particles::Particles;
use crate::second_core::Pending;
use faer::sparse::linalg::cholesky::SymbolicCholesky;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use nalgebra::Vector2;
use std::sync::Arc;

const NONE: u32 = u32::MAX;

/// The pressure system of one step in compressed sparse rows (symmetric, so also CSC).
#[derive(Debug, Default, Clone)]
pub struct PressureSystem {
    /// Node → row, or `u32::MAX` for nodes with prescribed pressure.
    pub row_of_node: Vec<u32>,
    pub node_of_row: Vec<u32>,
    pub row_ptr: Vec<usize>,
    pub col: Vec<usize>,
    pub val: Vec<f64>,
    pub rhs: Vec<f64>,
    /// Solution, warm-started from the previous pressure.
    pub x: Vec<f64>,
    /// Position of the node of each row (for the fill-reducing ordering).
    pub position: Vec<[f64; 2]>,
    /// The symbolic Cholesky analysis of this step's pattern, once known.
    symbolic: Option<Arc<SymbolicCholesky<usize>>>,
    /// The values of the Cholesky factor (reused from step to step).
    factor: Vec<f64>,
    /// Per element e of n nodes, the index in `val` of its entry (a, b) at
    /// `slot_start[e] + n a + b` (local node numbers), `u32::MAX` where a or b has a
    /// prescribed pressure.
    slots: Vec<u32>,
    slot_start: Vec<usize>,
    /// Scratch of `build_pattern`: the last row that listed each column and the place of that
    /// column in it.
    last_row_of: Vec<u32>,
    slot_of: Vec<u32>,
}

/// The symbolic analysis running on the second core.
pub(super) type SymbolicJob = Pending<Result<SymbolicCholesky<usize>, String>>;

/// Symbolic Cholesky analysis of a symmetric pattern (full CSR = CSC) whose rows are nodes at
/// `position`: nested-dissection ordering, supernodal structure.
fn analyse(
    position: &[[f64; 2]],
    row_ptr: &[usize],
    col: &[usize],
) -> Result<SymbolicCholesky<usize>, String> {
    super::ordering::symbolic_cholesky(position, row_ptr, col)
}

impl PressureSystem {
    pub fn unknowns(&self) -> usize {
        self.node_of_row.len()
    }

    /// The pattern of the node graph of the elements restricted to unknown nodes: each row
    /// takes the distinct unknowns of the elements around its node (a marker per column, no
    /// sort of duplicates) and sorts them.
    fn build_pattern(&mut self, elements: &ElementSet) {
        let n = self.unknowns();
        let row_of_node = &self.row_of_node;
        // `last_row_of[c]` marks column c as listed in row r; `slot_of[c]` is then its place.
        let (last_row_of, slot_of) = (&mut self.last_row_of, &mut self.slot_of);
        last_row_of.clear();
        last_row_of.resize(n, NONE);
        slot_of.resize(n, 0);
        let (slots, slot_start) = (&mut self.slots, &mut self.slot_start);
        slot_start.clear();
        slot_start.push(0);
        for e in 0..elements.len() {
            let k = elements.nodes(e).len();
            slot_start.push(slot_start[e] + k * k);
        }
        slots.clear();
        slots.resize(slot_start[elements.len()], NONE);
        self.row_ptr.clear();
        self.row_ptr.push(0);
        self.col.clear();
        for r in 0..n {
            let row_start = self.col.len();
            let node = self.node_of_row[r];
            let row_elements = elements.around(node as usize);
            for &e in row_elements {
                for &b in elements.nodes(e as usize) {
                    let rb = row_of_node[b as usize];
                    if rb != NONE && last_row_of[rb as usize] != r as u32 {
                        last_row_of[rb as usize] = r as u32;
                        self.col.push(rb as usize);
                    }
                }
            }
            self.col[row_start..].sort_unstable();
            for (s, &c) in self.col[row_start..].iter().enumerate() {
                slot_of[c] = (row_start + s) as u32;
            }
            for &e in row_elements {
                let t = elements.nodes(e as usize);
                let a = t.iter().position(|&i| i == node);
                let a = a.expect("an element around a node has it as a vertex");
                let base = slot_start[e as usize] + t.len() * a;
                for (b, &j) in t.iter().enumerate() {
                    let rb = row_of_node[j as usize];
                    if rb != NONE {
                        slots[base + b] = slot_of[rb as usize];
                    }
                }
            }
            self.row_ptr.push(self.col.len());
        }
        self.val.clear();
        self.val.resize(self.col.len(), 0.0);
    }

    #[inline]
    fn add(&mut self, row: usize, col: usize, v: f64) {
        let cols = &self.col[self.row_ptr[row]..self.row_ptr[row + 1]];
        let k = cols
            .iter()
            .position(|&c| c == col)
            .expect("entry in pattern");
        self.val[self.row_ptr[row] + k] += v;
    }

    /// y = A x.
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        for (i, yi) in y.iter_mut().enumerate() {
            let (s, e) = (self.row_ptr[i], self.row_ptr[i + 1]);
            *yi = self.col[s..e]
                .iter()
                .zip(&self.val[s..e])
                .map(|(&c, v)| v * x[c])
                .sum();
        }
    }

    fn matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        let n = self.unknowns();
        let symbolic = SymbolicSparseColMatRef::new_checked(n, n, &self.row_ptr, None, &self.col);
        SparseColMatRef::new(symbolic, &self.val)
    }

    /// Solves the system in place into `x` with the chosen method; returns iterations (0 for a
    /// direct solve).
    pub fn solve(
        &mut self,
        method: PressureSolver,
        rel_tolerance: f64,
        max_iterations: usize,
    ) -> Result<usize, String> {
        let n = self.unknowns();
        if n == 0 {
            return Ok(0);
        }
        match method {
            PressureSolver::Cholesky => {
                let symbolic = match &self.symbolic {
                    Some(s) => s.clone(),
                    None => Arc::new(analyse(&self.position, &self.row_ptr, &self.col)?),
                };
                let mut factor = std::mem::take(&mut self.factor);
                let mut b = faer::Mat::<f64>::from_fn(n, 1, |i, _| self.rhs[i]);
                super::ordering::factor_and_solve(
                    &symbolic,
                    self.matrix(),
                    &mut factor,
                    b.as_mut(),
                )?;
                for i in 0..n {
                    self.x[i] = b[(i, 0)];
                }
                self.factor = factor;
                Ok(0)
            }
            PressureSolver::Cg => {
                use faer::dyn_stack::{MemBuffer, MemStack};
                use faer::matrix_free::conjugate_gradient::{
                    CgParams, conjugate_gradient, conjugate_gradient_scratch,
                };
                let a = self.matrix();
                let mut dinv = faer::diag::Diag::<f64>::zeros(n);
                for i in 0..n {
                    let (s, e) = (self.row_ptr[i], self.row_ptr[i + 1]);
                    let d = (s..e)
                        .find(|&k| self.col[k] == i)
                        .map_or(0.0, |k| self.val[k]);
                    dinv[i] = if d > 0.0 { 1.0 / d } else { 1.0 };
                }
                let precond = dinv.as_ref();
                let par = faer::Par::Seq;
                let mut mem = MemBuffer::new(conjugate_gradient_scratch(precond, a, 1, par));
                let mut x = faer::Mat::<f64>::from_fn(n, 1, |i, _| self.x[i]);
                let b = faer::Mat::<f64>::from_fn(n, 1, |i, _| self.rhs[i]);
                let params = CgParams {
                    rel_tolerance,
                    max_iters: max_iterations,
                    ..Default::default()
                };
                let info = conjugate_gradient(
                    x.as_mut(),
                    precond,
                    a,
                    b.as_ref(),
                    params,
                    |_| {},
                    par,
                    MemStack::new(&mut mem),
                )
                .map_err(|e| format!("conjugate gradients did not converge: {e:?}"))?;
                for i in 0..n {
                    self.x[i] = x[(i, 0)];
                }
                Ok(info.iter_count)
            }
        }
    }
}

impl Solver {
    /// The Dirichlet set, the numbering of the unknowns and the matrix pattern; for Cholesky,
    /// starts the symbolic analysis on a second thread.
    pub(super) fn prepare_pressure(&mut self, particles: &Particles) {
        let n = particles.len();
        // Dirichlet p = 0: free-surface nodes held strongly and nodes in no kept triangle.
        let mut dirichlet = std::mem::take(&mut self.dirichlet);
        dirichlet.clear();
        dirichlet
            .extend((0..n).map(|i| self.surface_pinned(particles, i) || !self.mesh.in_mesh[i]));
        pieces::pin_pieces(&self.mesh, particles, &mut dirichlet);
        self.dirichlet = dirichlet;
        self.contact_pressure(particles);
        self.cells.set_topology(&self.mesh, n);

        let sys = &mut self.pressure;
        sys.row_of_node.clear();
        sys.row_of_node.resize(n, NONE);
        sys.node_of_row.clear();
        sys.position.clear();
        for i in 0..n {
            if !self.dirichlet[i] {
                sys.row_of_node[i] = sys.node_of_row.len() as u32;
                sys.node_of_row.push(i as u32);
                let x = particles.position[i];
                sys.position.push([x.x, x.y]);
            }
        }
        sys.build_pattern(&self.cells);
        sys.symbolic = None;
        self.symbolic_job = None;
        let m = sys.unknowns();
        // With one core only (the lab leaves the other to the window) the solve analyses
        // the pattern itself.
        if self.params.settings.pressure_solver == PressureSolver::Cholesky
            && m > 0
            && let Some(core) = &self.second_core
        {
            let (position, row_ptr, col) =
                (sys.position.clone(), sys.row_ptr.clone(), sys.col.clone());
            self.symbolic_job = Some(core.run(move || analyse(&position, &row_ptr, &col)));
        }
    }

    /// Matrix values and right-hand side for this Δt (the pattern is `prepare_pressure`'s).
    pub(super) fn assemble_pressure(&mut self, particles: &Particles, dt: f64) {
        let rho = self.params.density_kg_m3;
        let gamma = self.params.settings.gamma;
        let area_dt = if self.params.settings.area_correction {
            dt
        } else {
            0.0
        };
        let sys = &mut self.pressure;
        let m = sys.unknowns();
        sys.val.iter_mut().for_each(|v| *v = 0.0);
        sys.rhs.clear();
        sys.rhs.resize(m, 0.0);
        sys.x.clear();
        sys.x.extend(
            sys.node_of_row
                .iter()
                .map(|&i| particles.pressure[i as usize]),
        );

        let p_fixed = &self.p_fixed;
        let target = &self.divergence_target;
        let (p_old, pi_old, u_t) = (
            &self.p_old,
            &particles.pressure_gradient_projection,
            &self.u_tilde,
        );
        for e in 0..self.cells.len() {
            let tau = self.tau_e[e];
            let slots = &sys.slots[sys.slot_start[e]..sys.slot_start[e + 1]];
            if let Some(ops) = self.cells.polygon_operators(e) {
                let fields = PolygonFields {
                    particles,
                    p_old,
                    p_fixed,
                    u_t,
                    target,
                    dt,
                    rho,
                    gamma,
                    tau,
                    area_correction: self.params.settings.area_correction,
                };
                ops.specialised(
                    #[inline(always)]
                    |ops| assemble_polygon(sys, e, ops, &self.cells, &fields),
                );
                continue;
            }
            for cell in self.cells.cells(e) {
                let c = (dt / rho + tau) * cell.area;
                let grad_u = cell.velocity_gradient(|i| u_t[i]);
                // Moving the nodes by Δt u changes the area by Δt A ∇·u + Δt² A det ∇u; with
                // the correction, the equation asks for the divergence that cancels both.
                // Not where a wall node is a vertex: there ũ jumps from the fluid's velocity to
                // the wall's, and its det ∇ũ is no measure of the straining (at the flap's water
                // line the correction drove the run to 48 m/s by 13.3 s at Δt = 9.1 ms).
                let fluid_only = cell.nodes.iter().all(|&i| particles.is_fluid(i as usize));
                let div_u = grad_u.trace()
                    + if fluid_only {
                        area_dt * grad_u.determinant()
                    } else {
                        0.0
                    };
                let grad_p = cell.gradient(|i| p_old[i]);
                let pi_mean = cell.mean_vector(|i| pi_old[i]);
                let flux = gamma * (dt / rho) * grad_p - tau * pi_mean;
                let k = cell.nodes.len();
                for a in 0..k {
                    let ia = cell.node(a);
                    let ra = sys.row_of_node[ia];
                    if ra == NONE {
                        continue;
                    }
                    let ra = ra as usize;
                    sys.rhs[ra] += cell.integral(a, 1.0) * (target[ia] - div_u)
                        + cell.area * cell.grad[a].dot(&flux);
                    for b in 0..k {
                        let kab = c * cell.grad[a].dot(&cell.grad[b]);
                        let slot = slots[k * a + b];
                        add_entry(&mut sys.rhs[ra], &mut sys.val, slot, kab, || {
                            p_fixed[cell.node(b)]
                        });
                    }
                }
            }
        }
        self.add_weak_surface(particles, dt);
    }

    /// The pressure of the Dirichlet nodes: 0, but a wall node pinned as a contact point gets
    /// the hydrostatic ρ g (ȳ − y) of the mean height ȳ of the fluid nodes it shares a
    /// free-surface edge with (negative when it stands above the water line).
    fn contact_pressure(&mut self, particles: &Particles) {
        let n = particles.len();
        self.p_fixed.clear();
        self.p_fixed.resize(n, 0.0);
        let mut sum = vec![(0.0, 0usize); n];
        for [a, b] in self.contact_edges(particles) {
            let (w, f) = if particles.is_fluid(a) {
                (b, a)
            } else {
                (a, b)
            };
            if self.dirichlet[w] {
                sum[w].0 += particles.position[f].y;
                sum[w].1 += 1;
            }
        }
        let g = -self.params.gravity_m_s2.y;
        let rho = self.params.density_kg_m3;
        for (i, &(s, k)) in sum.iter().enumerate() {
            if k > 0 {
                self.p_fixed[i] = rho * g * (s / k as f64 - particles.position[i].y);
            }
        }
    }

    /// Whether node `i` gets its pressure imposed as a free-surface node: always with the
    /// strong condition; with the weak one, wall contact points and the fluid surface nodes of
    /// thin water (no interior fluid node in any kept triangle around them: a jet, a film, a
    /// drop touching down), where a Robin row has no interior pressure to lean on and the
    /// breaking crest of Ting & Kirby's wave blew up (47 m/s at 11.3 s); the other fluid
    /// surface nodes keep their row.
    fn surface_pinned(&self, particles: &Particles, i: usize) -> bool {
        if !self.mesh.free_surface[i] {
            return false;
        }
        if !(self.params.settings.weak_surface_length_h.is_some() && particles.is_fluid(i)) {
            return true;
        }
        let interior =
            |j: u32| particles.is_fluid(j as usize) && !self.mesh.free_surface[j as usize];
        !self
            .mesh
            .triangles_around(i)
            .iter()
            .any(|&t| self.mesh.triangles[t as usize].iter().any(|&j| interior(j)))
    }

    /// The weak free-surface condition: on each free-surface edge of length ℓ, the Robin term
    /// (Δt/ρ + τ_e) ∫ N_i p / λ, lumped (ℓ/2 per node), so that the boundary flux of the
    /// Poisson operator meets ∂p/∂n + p/λ = 0.
    fn add_weak_surface(&mut self, particles: &Particles, dt: f64) {
        let Some(length_h) = self.params.settings.weak_surface_length_h else {
            return;
        };
        let spacing = self.params.spacing;
        let rho = self.params.density_kg_m3;
        // (β − 1)R on both sides of the incremental split's equation; none in the first-order
        // one (γ = 0), where (β − 1)R pⁿ would not cancel.
        let settings = &self.params.settings;
        let lag = settings.gamma * (settings.increment_weight - 1.0);
        let mesh = &self.mesh;
        let sys = &mut self.pressure;
        let p_old = &self.p_old;
        for (&[a, b], &k) in mesh.boundary_edges.iter().zip(&mesh.boundary_edge_triangle) {
            let (a, b) = (a as usize, b as usize);
            let surface = mesh.free_surface[a] && mesh.free_surface[b];
            if !surface || !(particles.is_fluid(a) || particles.is_fluid(b)) {
                continue;
            }
            let len = (particles.position[a] - particles.position[b]).norm();
            let mid_x = 0.5 * (particles.position[a].x + particles.position[b].x);
            // λ in units of the spacing where the edge is.
            let lambda = length_h * spacing.at(mid_x);
            let tau = self.tau_e[self.cells.element_of_triangle(k as usize)];
            let w = (dt / rho + tau) * len / (2.0 * lambda);
            for i in [a, b] {
                let r = sys.row_of_node[i];
                if r != NONE {
                    sys.add(r as usize, r as usize, (1.0 + lag) * w);
                    sys.rhs[r as usize] += lag * w * p_old[i];
                }
            }
        }
    }

    pub(super) fn solve_pressure(&mut self, particles: &Particles) -> Result<usize, StepError> {
        if let Some(job) = self.symbolic_job.take() {
            let symbolic = job
                .wait()
                .map_err(|_| StepError::Pressure("the symbolic analysis thread panicked".into()))?
                .map_err(StepError::Pressure)?;
            self.pressure.symbolic = Some(Arc::new(symbolic));
        }
        let p = &self.params;
        let iterations = self
            .pressure
            .solve(
                p.settings.pressure_solver,
                p.settings.cg_tolerance,
                p.settings.cg_max_iterations,
            )
            .map_err(StepError::Pressure)?;
        self.p_new.clear();
        self.p_new.extend_from_slice(&self.p_fixed);
        for (r, &i) in self.pressure.node_of_row.iter().enumerate() {
            let v = self.pressure.x[r];
            if !v.is_finite() {
                let x = particles.position[i as usize];
                return Err(StepError::NonFinite {
                    quantity: "pressure",
                    node: i as usize,
                    x: x.x,
                    y: x.y,
                });
            }
            self.p_new[i as usize] = v;
        }
        Ok(iterations)
    }
}

/// Adds matrix entry (row, column) = `value` at its `slot` in the values, or, when the column's
/// pressure is prescribed (`NONE`), moves it to the row's right-hand side times that pressure.
#[inline]
fn add_entry(rhs: &mut f64, val: &mut [f64], slot: u32, value: f64, fixed: impl Fn() -> f64) {
    match slot {
        NONE => *rhs -= value * fixed(),
        slot => val[slot as usize] += value,
    }
}

/// What the rows of a polygon element read.
struct PolygonFields<'a> {
    particles: &'a Particles,
    p_old: &'a [f64],
    p_fixed: &'a [f64],
    u_t: &'a [Vector2<f64>],
    target: &'a [f64],
    dt: f64,
    rho: f64,
    gamma: f64,
    tau: f64,
    area_correction: bool,
}

/// The rows of polygon element `e`, from its operators (see `element_set.rs`): the matrix
/// (Δt/ρ + τ) L, and on the right −∫ N_a ∇·ũ = −∮ N_a ũ·n + ∫ ∇N_a·ũ, the divergence target
/// W_a s_a, the flux γ (Δt/ρ) L pⁿ − τ ∫ ∇N_a·π, and with `area_correction` the strong
/// −∫ N_a Δt det ∇ũ of each cell.
#[inline(always)]
fn assemble_polygon(
    sys: &mut PressureSystem,
    e: usize,
    ops: &PolygonOperators,
    cells: &ElementSet,
    f: &PolygonFields,
) {
    let pi_old = &f.particles.pressure_gradient_projection;
    let n = ops.len();
    let fluid_only = ops.nodes.iter().all(|&i| f.particles.is_fluid(i as usize));
    let mut det_part = [0.0; MAX_POLYGON_NODES];
    if f.area_correction && fluid_only {
        for cell in cells.cells(e) {
            let det = f.dt * cell.velocity_gradient(|i| f.u_t[i]).determinant();
            for (a, d) in det_part.iter_mut().enumerate().take(n) {
                *d += cell.integral(a, det);
            }
        }
    }
    let c = f.dt / f.rho + f.tau;
    let slot_start = sys.slot_start[e];
    for a in 0..n {
        let ia = ops.node(a);
        let ra = sys.row_of_node[ia];
        if ra == NONE {
            continue;
        }
        let ra = ra as usize;
        sys.rhs[ra] += ops.node_w[a] * f.target[ia] - det_part[a]
            + ops.divergence_row(a, |i| f.u_t[i])
            + f.gamma * (f.dt / f.rho) * ops.lap_row(a, |i| f.p_old[i])
            - f.tau * ops.divergence_row(a, |i| pi_old[i]);
        for b in 0..n {
            let kab = c * ops.lap[a * n + b];
            let slot = sys.slots[slot_start + n * a + b];
            add_entry(&mut sys.rhs[ra], &mut sys.val, slot, kab, || {
                f.p_fixed[ops.node(b)]
            });
        }
    }
    for (a, b, nu) in polygon_boundary(ops.nodes, &f.particles.position) {
        let (ia, ib) = (ops.node(a), ops.node(b));
        let (ua, ub) = (nu.dot(&f.u_t[ia]), nu.dot(&f.u_t[ib]));
        for (i, flux) in [(ia, ua / 3.0 + ub / 6.0), (ib, ua / 6.0 + ub / 3.0)] {
            let r = sys.row_of_node[i];
            if r != NONE {
                sys.rhs[r as usize] -= flux;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn pattern_of_two_triangles() {
        let mut sys = PressureSystem {
            row_of_node: vec![0, 1, 2, NONE],
            node_of_row: vec![0, 1, 2],
            ..Default::default()
        };
        let mesh = Mesh::from_triangles(4, vec![[0, 1, 2], [1, 3, 2]]);
        let x = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]].map(|[a, b]| Vector2::new(a, b));
        sys.build_pattern(&ElementSet::from_mesh(&mesh, &x));
        assert_eq!(sys.row_ptr, vec![0, 3, 6, 9]);
        assert_eq!(sys.col, vec![0, 1, 2, 0, 1, 2, 0, 1, 2]);
    }
}
