//! surflab: a 2D Lagrangian wave flume solved with the Particle Finite Element Method.
//!
//! Layers, each knowing only those below it: `case` (what to run) → `geometry`, `particles`
//! (the state) → `mesh` (Delaunay + α-shape) → `fem` (P1 kernels) → `solver` (the fractional
//! step) → `wavemaker` (the paddle as a moving wall; its theory is in `waves`) → `simulation`
//! (clock, Δt) → `diagnostics` (observers that read) → `output` (observers
//! that write: .rrd, CSV, JSON) → `validation` (what `surflab validate` checks in the records
//! a run wrote). The 3D path (issue 26) grows beside them: `mesh3d` (tetrahedralisation,
//! α-shape), `fem::tet` (the tetrahedron's kernels), `solver3d` (the 3D step and its seeding
//! from a case with a width), `output::run3d` (its headless run and records).

// The numerics walk several parallel arrays (struct of arrays) by node index; an index loop
// says that more plainly than zipped iterators.
#![allow(clippy::needless_range_loop)]

pub mod case;
pub mod diagnostics;
pub mod fem;
pub mod geometry;
#[cfg(feature = "lab")]
pub mod lab;
pub mod mesh;
pub mod mesh3d;
pub mod output;
pub mod particles;
pub mod second_core;
pub mod simulation;
pub mod simulation3d;
pub mod solver;
pub mod solver3d;
pub mod study;
pub mod sweep;
pub mod validation;
pub mod wavemaker;
pub mod waves;

pub use case::Case;
pub use simulation::Simulation;
