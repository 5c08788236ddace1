//! The 3D fractional step (issue 26): the pressure Poisson equation of one step on the
//! α-shape's tetrahedra, the end-of-step velocity, and [`Flow3`], the time step around them
//! (remesh, explicit Smagorinsky predictor, pressure, correction, slip or no-slip walls, move
//! with the walls' guard, node insertion and removal); [`setup::from_case`] seeds it from a
//! case with a `flume.width_m`. Axes: x along the flume, y up, z across it. A piston across
//! the tank is in `piston`, node management in `nodes`, the pressure equation and the
//! correction in `pressure`.

mod filter;
mod ic0;
mod integrals;
pub mod nodes;
mod pieces;
pub mod piston;
pub mod pressure;
pub mod relax;
pub mod setup;
mod walls;

pub use integrals::Integrals3;
pub use nodes::{INSERT_RADIUS_3D_OVER_2D, NodeChanges3};
pub use piston::Piston3;

pub use pressure::{
    CHOLESKY_LIMIT_UNKNOWNS, CHOLESKY_MAX_UNKNOWNS, FLAT_QUALITY, Fic, NESTED_DISSECTION_UNKNOWNS,
    PressureError, Solver3, WeakSurface, correct, elements, nodal_gradient, pressure, projection,
};

use crate::case::TauFormula;
use crate::fem::tet::P1Tet;
use crate::geometry::bed3d::Bed3;
use crate::mesh3d::{AlphaShape, Tetrahedralisation, Tetrahedraliser};
use nalgebra::Vector3;

/// A plane wall of a box-shaped tank: the solid lies on the side of `at_m` away from `inward`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallPlane {
    /// 0 (x), 1 (y) or 2 (z).
    pub axis: usize,
    /// Where the plane cuts its axis, m.
    pub at_m: f64,
    /// +1 when the water is on the side of larger coordinates, −1 otherwise.
    pub inward: f64,
    /// Velocity of the plane along its axis in the current step, m/s (0 for a fixed wall;
    /// a piston's face moves).
    pub velocity_m_s: f64,
}

impl WallPlane {
    /// Signed distance of `x` from the plane, positive on the water's side, m.
    pub fn distance(&self, x: &[f64; 3]) -> f64 {
        self.inward * (x[self.axis] - self.at_m)
    }
}

/// The box of planes of a tank from `lo` to `hi` (m), in the order of the wall bits of
/// `mesh3d::lattice_tank` and [`setup::from_case`]: bed (y = lo), x = lo, x = hi, z = lo,
/// z = hi.
pub fn box_planes(lo: [f64; 3], hi: [f64; 3]) -> Vec<WallPlane> {
    let plane = |axis: usize, at_m: f64, inward: f64| WallPlane {
        axis,
        at_m,
        inward,
        velocity_m_s: 0.0,
    };
    vec![
        plane(1, lo[1], 1.0),
        plane(0, lo[0], 1.0),
        plane(0, hi[0], -1.0),
        plane(2, lo[2], 1.0),
        plane(2, hi[2], -1.0),
    ]
}

/// The state of a 3D flow of particles and everything its step needs.
#[derive(Debug, Clone)]
pub struct Flow3 {
    /// Node positions, m (x along the flume, y up, z across).
    pub x: Vec<[f64; 3]>,
    /// Node velocities, m/s (on a wall node: along the wall when the walls slip, else zero).
    pub u: Vec<Vector3<f64>>,
    /// Per node, one bit per wall plane it lies on (bit b ↔ `planes[b]`; 0: fluid).
    pub walls: Vec<u16>,
    /// The planes the wall bits refer to; fluid nodes are kept on their water side.
    pub planes: Vec<WallPlane>,
    /// A bed that is not flat: the wall bit 0 is then this height field, not `planes[0]`
    /// (`None`: the bed is the plane `planes[0]`).
    pub bed: Option<Bed3>,
    /// Slip walls (the velocity across a wall removed) or no-slip (u = 0 on wall nodes).
    pub slip: bool,
    /// The last step's pressure, Pa.
    pub p: Vec<f64>,
    /// The FIC stabilisation's τ formula (`solver.tau`; `TauFormula::None`: none).
    pub tau: TauFormula,
    /// The split (`solver.gamma`): 1 incremental (the predictor carries −(Δt/ρ) ∇pⁿ and the
    /// projection the increment), 0 plain.
    pub gamma: f64,
    /// The last step's projection of −∇p per node (`pressure::projection`), Pa/m.
    pub pi: Vec<Vector3<f64>>,
    /// Particle spacing h, m.
    pub h_m: f64,
    /// α h, m.
    pub alpha_h_m: f64,
    /// A fluid node closer than this to a wall plane is put back at it, m.
    pub wall_margin_m: f64,
    pub rho_kg_m3: f64,
    pub mu_pa_s: f64,
    pub smagorinsky_cs: f64,
    pub gravity_m_s2: Vector3<f64>,
    pub solver: Solver3,
    /// λ of the weak free surface ([`WeakSurface`]), m; `None`: p = 0 strongly on the free
    /// surface.
    pub weak_surface_m: Option<f64>,
    /// Whether each node was in a kept tetrahedron at the last step (all false before it).
    pub in_mesh: Vec<bool>,
    /// The last step's free-surface triangles (outward), node indices.
    pub surface: Vec<[u32; 3]>,
    /// The kept tetrahedra of the last step, on the moved nodes (for diagnostics that cut the
    /// water; those of a node removed after the move are dropped).
    pub tetrahedra: Vec<[u32; 4]>,
    /// Per node: on the last step's free surface (empty before the first mesh), for the
    /// α-shape's contact-line rule.
    pub was_free: Vec<bool>,
    /// The tetrahedralisation's working memory, kept from step to step.
    pub mesher: Tetrahedraliser,
    /// The piston wavemaker, when the tank has one (its face is one of `planes`).
    pub piston: Option<Piston3>,
    /// A kept tetrahedron wider than this (circumradius, m) gets a node at its centroid
    /// (`nodes`); `None`: no insertion.
    pub insert_radius_m: Option<f64>,
    /// An interior fluid node closer than this to a neighbour is removed (`nodes`), m; `None`:
    /// no removal.
    pub remove_distance_m: Option<f64>,
    /// Two free-surface fluid nodes closer than this along a kept edge become one (`nodes`),
    /// m; `None`: no merging.
    pub merge_distance_m: Option<f64>,
    /// ε of the surface velocities' fourth-difference filter (`filter`); `None`: off.
    pub surface_filter: Option<f64>,
    /// The volume relaxation's ledger (`relax`, `solver.volume_relaxation_s`); `None`: off.
    pub relax: Option<relax::Relax3>,
}

/// The stages of [`Flow3::step`], in order.
pub const STAGES_3D: [&str; 8] = [
    "tetrahedralise",
    "alpha_shape",
    "elements",
    "predict",
    "pressure",
    "correct",
    "move",
    "nodes",
];

/// What one step of [`Flow3`] measured.
#[derive(Debug, Clone, Copy)]
pub struct Step3 {
    /// Volume of the kept tetrahedra at the start of the step, m³.
    pub volume_m3: f64,
    pub tetrahedra: usize,
    pub slivers_kept: usize,
    /// The pressure solver's iterations (0 for Cholesky).
    pub iterations: usize,
    /// Fluid nodes the walls' guard put back this step.
    pub guarded: usize,
    /// Volume of the same tetrahedra after the move (guard included), m³: the move changed
    /// the water by `moved_volume_m3 − volume_m3`, the next remesh by its `volume_m3` less
    /// this.
    pub moved_volume_m3: f64,
    /// Fluid nodes the `nodes` stage inserted and removed after the move.
    pub nodes: NodeChanges3,
    /// Wall time of each stage of [`STAGES_3D`], ms.
    pub stage_ms: [f64; 8],
}

impl Flow3 {
    /// One step of Δt: tetrahedralise, α-shape, elements, predict, pressure, correct, move,
    /// nodes (the stages of [`STAGES_3D`]).
    pub fn step(&mut self, dt_s: f64) -> Result<Step3, PressureError> {
        if let Some(i) = (0..self.x.len()).find(|&i| {
            !(self.x[i].iter().all(|c| c.is_finite()) && self.u[i].iter().all(|c| c.is_finite()))
        }) {
            return Err(PressureError::Diverged(format!(
                "node {i} is at {:?} with velocity {:?}",
                self.x[i], self.u[i]
            )));
        }
        let mut stage_ms = [0.0; 8];
        let mut clock = std::time::Instant::now();
        let mut lap = |k: usize| {
            stage_ms[k] = clock.elapsed().as_secs_f64() * 1e3;
            clock = std::time::Instant::now();
        };
        self.start_piston(dt_s);
        let mut mesher = std::mem::take(&mut self.mesher);
        let remeshed = self.remesh(&mut mesher, &mut lap);
        self.mesher = mesher;
        let (mesh, mut shape, elements) = remeshed?;
        if self.slip {
            self.slip_walls_take_the_water_velocity(&mesh, &shape);
        }
        let inflow = self.wall_inflow(&mesh, &shape);
        let fixed = self.contact_pressure(&shape);
        // The incremental split's pⁿ on this step's boundary: the nodes whose pressure is
        // imposed now (the free surface with strong p = 0, its contact points) take that value,
        // so that a node changing role adds no kink to the increment's equation.
        // (Started at 0, the contact points of the still case tank with its water line between
        // two rows of wall nodes moved it at 0.02 m/s within 2 s.)
        if self.gamma != 0.0 && self.weak_surface_m.is_none() {
            for i in (0..self.x.len()).filter(|&i| shape.in_mesh[i] && shape.free_surface[i]) {
                self.p[i] = fixed.as_ref().map_or(0.0, |f| f[i]);
            }
        }
        let volume_m3 = elements.iter().map(|e| e.volume).sum();
        let target = (self.relax.as_mut())
            .map(|r| r.targets(&self.x, &self.walls, &mesh, &shape, &elements));
        // Every node of the mesh, walls included, predicts from the momentum equation; the
        // wall's u·n = 0 enters through the pressure's natural boundary condition, and the
        // wall's constraint is applied to the corrected velocity.
        let (u_star, tau_e) = self.predict(&mesh, &shape, &elements, dt_s);
        lap(3);
        let fic = (self.tau != TauFormula::None).then_some(Fic {
            tau_e: &tau_e,
            pi: &self.pi,
        });
        let (p, iterations) = pressure(
            &self.x,
            &mesh,
            &shape,
            &elements,
            &u_star,
            self.rho_kg_m3,
            dt_s,
            self.solver,
            self.weak_surface_m.map(|length_m| WeakSurface {
                points: &self.x,
                length_m,
            }),
            inflow.as_deref(),
            fixed.as_deref(),
            fic,
            (self.gamma != 0.0).then_some(&self.p[..]),
            target.as_deref(),
        )?;
        // What the correction applies: the increment with the incremental split.
        let increment: Vec<f64> = p
            .iter()
            .zip(&self.p)
            .map(|(new, old)| new - self.gamma * old)
            .collect();
        self.p = p;
        if self.tau != TauFormula::None {
            self.pi = projection(&mesh, &shape, &elements, &tau_e, &self.p);
        }
        lap(4);
        let strong = self.weak_surface_m.is_none();
        let grad = nodal_gradient(&mesh, &shape, &elements, &increment, strong);
        self.u = correct(&u_star, &grad, self.rho_kg_m3, dt_s);
        if let Some(eps) = self.surface_filter {
            filter::filter_surface(&mut self.u, &shape.surface, &self.walls, eps);
        }
        lap(5);
        self.advance_piston_plane();
        let guarded = self.move_nodes(dt_s, &shape.in_mesh);
        self.place_piston_band();
        if let Some(r) = &mut self.relax {
            r.after_move(&self.x, &mesh, &shape);
        }
        // The same tetrahedra on the moved nodes: what the move changed (the next remesh
        // changes the rest).
        let moved_volume_m3 = shape
            .kept
            .iter()
            .zip(&elements)
            .filter(|(_, e)| e.volume > 0.0)
            .map(|(&t, _)| {
                let v = mesh.tets[t as usize].map(|i| Vector3::from(self.x[i as usize]));
                (v[1] - v[0])
                    .dot(&(v[2] - v[0]).cross(&(v[3] - v[0])))
                    .abs()
                    / 6.0
            })
            .sum();
        self.in_mesh = std::mem::take(&mut shape.in_mesh);
        self.was_free = std::mem::take(&mut shape.free_surface);
        self.surface = std::mem::take(&mut shape.surface);
        self.tetrahedra = shape.kept.iter().map(|&t| mesh.tets[t as usize]).collect();
        lap(6);
        let nodes = self.manage_nodes(&mesh, &shape);
        lap(7);
        Ok(Step3 {
            volume_m3,
            tetrahedra: shape.kept.len(),
            slivers_kept: shape.slivers_kept,
            iterations,
            guarded,
            moved_volume_m3,
            nodes,
            stage_ms,
        })
    }

    /// The first three stages: the tetrahedralisation, the α-shape and the elements of the
    /// current positions, `lap(k)` called at the end of stage k. Only the wall nodes near the
    /// water take part (see `near_water`); the mesh and the α-shape are built on them and the
    /// fluid, then numbered as the whole cloud.
    fn remesh(
        &self,
        mesher: &mut Tetrahedraliser,
        lap: &mut impl FnMut(usize),
    ) -> Result<(Tetrahedralisation, AlphaShape, Vec<P1Tet>), PressureError> {
        use crate::mesh3d::{ContactLine, InSolid, alpha_shape_with};
        let active = self.near_water();
        let sub_x: Vec<[f64; 3]> = active.iter().map(|&i| self.x[i as usize]).collect();
        let sub_walls: Vec<u16> = active.iter().map(|&i| self.walls[i as usize]).collect();
        let mut mesh = mesher.tetrahedralise(&sub_x);
        lap(0);
        // Under a bed that is not flat, all-wall tetrahedra across a downward bend lie in the
        // bed: their centroid is more than round-off below it.
        let depth_m = 1e-6 * self.h_m;
        let in_the_bed = self
            .bed
            .as_ref()
            .map(|bed| move |c: &[f64; 3]| bed.distance(c) < -depth_m);
        let solid: Option<InSolid> = in_the_bed.as_ref().map(|f| f as _);
        // The contact-line rule needs the previous free surface; the first mesh takes it from
        // an α-shape without the rule.
        let sub_free: Vec<bool> = if self.was_free.len() == self.x.len() {
            active.iter().map(|&i| self.was_free[i as usize]).collect()
        } else {
            alpha_shape_with(&sub_x, &sub_walls, &mesh, self.alpha_h_m, None, solid).free_surface
        };
        let contact = ContactLine {
            was_free: &sub_free,
            up_axis: 1,
        };
        let mut shape = alpha_shape_with(
            &sub_x,
            &sub_walls,
            &mesh,
            self.alpha_h_m,
            Some(contact),
            solid,
        );
        renumber(&mut mesh, &mut shape, &active, self.x.len());
        lap(1);
        let elements = elements(&self.x, &mesh, &shape)?;
        lap(2);
        Ok((mesh, shape, elements))
    }

    /// Meshes the current positions without stepping (the first frame of a run): sets
    /// `in_mesh` and `surface` and returns the kept volume, m³.
    pub fn mesh_now(&mut self) -> Result<f64, PressureError> {
        let mut mesher = std::mem::take(&mut self.mesher);
        let remeshed = self.remesh(&mut mesher, &mut |_| {});
        self.mesher = mesher;
        let (mesh, shape, elements) = remeshed?;
        self.in_mesh = shape.in_mesh;
        self.was_free = shape.free_surface;
        self.surface = shape.surface;
        self.tetrahedra = shape.kept.iter().map(|&t| mesh.tets[t as usize]).collect();
        Ok(elements.iter().map(|e| e.volume).sum())
    }

    /// The pressure imposed on the free surface's nodes with strong p = 0 (`None` with the weak
    /// surface, whose nodes all keep their row): 0, but a wall node on the free surface is a
    /// contact point — the water line crosses the wall somewhere between it and the fluid
    /// nodes of its surface triangles — and gets the hydrostatic ρ g (ȳ − y) of their mean
    /// height ȳ (negative above the water line), as in 2D. With 0 there, a water line that
    /// does not lie on a row of wall nodes holds a pressure that falls to 0 up to h below or
    /// above it, whose gradient pushes the water from or into the wall: the case tank with
    /// 6.5 h of water moved at 0.13 m/s by 0.2 s and lost 40 % of its water in 1 s.
    fn contact_pressure(&self, shape: &AlphaShape) -> Option<Vec<f64>> {
        if self.weak_surface_m.is_some() {
            return None;
        }
        let n = self.x.len();
        let mut sum = vec![(0.0, 0usize); n];
        for f in &shape.surface {
            for &w in f {
                if self.walls[w as usize] == 0 {
                    continue;
                }
                for &i in f {
                    if self.walls[i as usize] == 0 {
                        sum[w as usize].0 += self.x[i as usize][1];
                        sum[w as usize].1 += 1;
                    }
                }
            }
        }
        let g = -self.gravity_m_s2.y;
        Some(
            (0..n)
                .map(|i| match sum[i] {
                    (s, k) if k > 0 => self.rho_kg_m3 * g * (s / k as f64 - self.x[i][1]),
                    _ => 0.0,
                })
                .collect(),
        )
    }

    /// ũ = uⁿ + Δt (g + f/m): f the Smagorinsky viscous forces of the kept tetrahedra
    /// (μ_e = μ + ρ (C_s h_e)² |S|, explicit), m the lumped mass ρV/4; a node in no kept
    /// tetrahedron flies ballistically. With the incremental split ũ also carries
    /// −γ (Δt/ρ) ∇pⁿ (the lumped nodal gradient). Also τ_e of each kept tetrahedron (`fem::tau`
    /// with μ_e and the mean speed of its nodes).
    fn predict(
        &self,
        mesh: &Tetrahedralisation,
        shape: &AlphaShape,
        elements: &[P1Tet],
        dt_s: f64,
    ) -> (Vec<Vector3<f64>>, Vec<f64>) {
        use crate::fem::tet::{strain_rate, tet_size, velocity_gradient, viscous_forces};
        let n = self.x.len();
        let mut mass = vec![0.0; n];
        let mut force = vec![Vector3::zeros(); n];
        let mut tau_e = Vec::with_capacity(elements.len());
        for (&t, e) in shape.kept.iter().zip(elements) {
            let v = mesh.tets[t as usize];
            let g = velocity_gradient(e, v.map(|i| self.u[i as usize]));
            let (s, magnitude) = strain_rate(&g);
            let size = tet_size(e.volume);
            let mu_e = crate::fem::smagorinsky_viscosity(
                self.mu_pa_s,
                self.rho_kg_m3,
                self.smagorinsky_cs,
                size,
                magnitude,
            );
            let speed = v
                .iter()
                .map(|&i| self.u[i as usize])
                .sum::<Vector3<f64>>()
                .norm()
                / 4.0;
            tau_e.push(crate::fem::tau(
                self.tau,
                self.rho_kg_m3,
                mu_e,
                size,
                dt_s,
                speed,
            ));
            let f = viscous_forces(e, mu_e, &s);
            for a in 0..4 {
                mass[v[a] as usize] += self.rho_kg_m3 * e.volume / 4.0;
                force[v[a] as usize] += f[a];
            }
        }
        let strong = self.weak_surface_m.is_none();
        let grad_p =
            (self.gamma != 0.0).then(|| nodal_gradient(mesh, shape, elements, &self.p, strong));
        let u_star = (0..n)
            .map(|i| {
                let mut accel = if mass[i] > 0.0 {
                    self.gravity_m_s2 + force[i] / mass[i]
                } else {
                    self.gravity_m_s2
                };
                if let Some(g) = &grad_p {
                    accel -= self.gamma / self.rho_kg_m3 * g[i];
                }
                self.u[i] + dt_s * accel
            })
            .collect();
        (u_star, tau_e)
    }

    /// The wall nodes' constraint on the corrected velocity (slip, on a node of the mesh: the
    /// components across each of the node's planes replaced by the plane's own velocity, 0 but
    /// on a piston, so an edge keeps the part along it and a corner none; no-slip or dry: the
    /// planes' velocity alone), then the fluid nodes moved by Δt uⁿ⁺¹ and put back on the
    /// water's side of every plane (at its end-of-step position) by the wall margin, their
    /// velocity into that wall, relative to it, removed. Wall nodes do not move here (a
    /// piston's band does, after). Returns how many fluid nodes were put back.
    fn move_nodes(&mut self, dt_s: f64, in_mesh: &[bool]) -> usize {
        let mut guarded = 0;
        for i in 0..self.x.len() {
            let mask = self.walls[i];
            if mask != 0 {
                // A dry wall node (in no kept tetrahedron) has no flow to slip with: it moves
                // with its wall, else it would keep falling under gravity step after step and
                // bring that speed into the first tetrahedron the rising water gives it.
                let u = if self.slip && in_mesh[i] {
                    self.u[i]
                } else {
                    Vector3::zeros()
                };
                self.u[i] = self.admissible_velocity(i, u);
                continue;
            }
            for k in 0..3 {
                self.x[i][k] += dt_s * self.u[i][k];
            }
            let mut put_back = false;
            for (b, plane) in self.planes.iter().enumerate() {
                if b == 0
                    && let Some(bed) = &self.bed
                {
                    put_back |= bed.guard(&mut self.x[i], &mut self.u[i], self.wall_margin_m);
                    continue;
                }
                if plane.distance(&self.x[i]) < self.wall_margin_m {
                    self.x[i][plane.axis] = plane.at_m + plane.inward * self.wall_margin_m;
                    if plane.inward * (self.u[i][plane.axis] - plane.velocity_m_s) < 0.0 {
                        self.u[i][plane.axis] = plane.velocity_m_s;
                    }
                    put_back = true;
                }
            }
            guarded += put_back as usize;
        }
        guarded
    }

    /// The nodes the step meshes, in index order: every fluid node, and the wall nodes whose
    /// grid cell (of side 4 α h + h) or a neighbouring one holds a fluid node. A kept
    /// tetrahedron has a circumradius below α h and a fluid node or a wetted wall node (one
    /// within 2 α h of a fluid node), so its circumsphere lies within 4 α h of a fluid node:
    /// no wall node farther than that can be inside it, and the kept tetrahedra of the
    /// Delaunay tetrahedralisation of these nodes are those of the whole cloud's. A tall dry
    /// wall is thus not tetrahedralised every step.
    fn near_water(&self) -> Vec<u32> {
        let cell = 4.0 * self.alpha_h_m + self.h_m;
        let key = |x: &[f64; 3]| x.map(|c| (c / cell).floor() as i64);
        let wet: std::collections::HashSet<[i64; 3]> = (0..self.x.len())
            .filter(|&i| self.walls[i] == 0)
            .map(|i| key(&self.x[i]))
            .collect();
        (0..self.x.len() as u32)
            .filter(|&i| {
                if self.walls[i as usize] == 0 {
                    return true;
                }
                let c = key(&self.x[i as usize]);
                (-1..=1).any(|a| {
                    (-1..=1)
                        .any(|b| (-1..=1).any(|d| wet.contains(&[c[0] + a, c[1] + b, c[2] + d])))
                })
            })
            .collect()
    }
}

/// Numbers a tetrahedralisation and α-shape built on the nodes `active` (in index order) as
/// the whole cloud of `n` nodes.
fn renumber(mesh: &mut Tetrahedralisation, shape: &mut AlphaShape, active: &[u32], n: usize) {
    if active.len() == n {
        return;
    }
    for t in &mut mesh.tets {
        *t = t.map(|i| active[i as usize]);
    }
    for d in &mut mesh.duplicates {
        *d = active[*d as usize];
    }
    for f in &mut shape.surface {
        *f = f.map(|i| active[i as usize]);
    }
    let spread = |flags: &[bool]| {
        let mut all = vec![false; n];
        for (k, &f) in flags.iter().enumerate() {
            all[active[k] as usize] = f;
        }
        all
    };
    shape.in_mesh = spread(&shape.in_mesh);
    shape.free_surface = spread(&shape.free_surface);
}

/// A tank of still water at rest for tests and `surflab bench3d`: `mesh3d::lattice_tank`
/// (nx × ny × nz nodes, ny up) with a flat top (the fluid nodes below it moved by up to
/// ± jitter/2 h), α = 1.2, water, gravity −y, no-slip walls, Cholesky.
pub fn still_tank(nx: usize, ny: usize, nz: usize, h: f64, jitter: f64) -> Flow3 {
    let (x, walls) =
        crate::mesh3d::lattice_tank([nx, ny, nz], h, jitter, false, 0x2545_f491_4f6c_dd1d);
    let n = x.len();
    let hi = [
        (nx - 1) as f64 * h,
        (ny - 1) as f64 * h,
        (nz - 1) as f64 * h,
    ];
    Flow3 {
        x,
        u: vec![Vector3::zeros(); n],
        walls,
        planes: box_planes([0.0; 3], hi),
        bed: None,
        slip: false,
        p: vec![0.0; n],
        tau: TauFormula::None,
        gamma: 0.0,
        pi: vec![Vector3::zeros(); n],
        h_m: h,
        alpha_h_m: 1.2 * h,
        wall_margin_m: 0.4 * h,
        rho_kg_m3: 1000.0,
        mu_pa_s: 1.0e-3,
        smagorinsky_cs: 0.12,
        gravity_m_s2: Vector3::new(0.0, -9.81, 0.0),
        solver: Solver3::Cholesky,
        weak_surface_m: None,
        in_mesh: vec![false; n],
        surface: Vec::new(),
        tetrahedra: Vec::new(),
        was_free: Vec::new(),
        mesher: Tetrahedraliser::default(),
        piston: None,
        insert_radius_m: None,
        remove_distance_m: None,
        merge_distance_m: None,
        surface_filter: None,
        relax: None,
    }
}

#[cfg(test)]
mod tests;
