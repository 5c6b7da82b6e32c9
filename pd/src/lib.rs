//! Bond-based peridynamics for pdbem (seed 002 section 2.1, seed 000
//! sections 2-4, seed 001 sections 3-6).
//!
//! Map of the crate:
//! - [`problem`]: the data-in description [`PdProblem`] (region, grid, material,
//!   failure, pre-cracks, boundary conditions) and its `validate()`.
//! - [`grid`], [`bonds`], [`surface`], [`boundary`]: discretisation (regular
//!   grid with fictitious layers, CSR bond families with partial volumes,
//!   surface correction, boundary data).
//! - [`state_based`]: ordinary state-based PD (seed 004 section 2.1), any Poisson
//!   ratio in [0, 1/2) ([`problem::MIN_STATE_BASED_NU`]), chosen by
//!   [`PdProblem::material`]; the solvers call the model-agnostic
//!   methods of [`PdModel`] (`new_tangent`, `assemble_tangent`, ...).
//! - [`mixed`]: mixed-spacing grids (refinement zones) with dual-horizon PMB forces
//!   (seed 004 section 2.2) in [`PdModel`] and every solver.
//! - [`refine`]: adaptive particle refinement on dual horizons (seed 004 section 3).
//! - [`traction`]: tractions on the boundary surface through seed 001's
//!   transfer functions (the alternative to the body-force layer).
//! - [`dynamics`]: explicit dynamics (velocity Verlet, stable time step, bond breaking
//!   every step; seed 004 section 2.3) with crack tip and branching measures.
//! - [`material`], [`forces`], [`damage`]: PMB micromodulus, critical stretch,
//!   tanh degradation; parallel force gather; damage `phi`.
//! - [`model`]: [`PdModel`], the state and the operations the solvers and the
//!   coupling use (`set_prescribed_displacements`, `virtual_node_forces`, ...).
//! - [`solvers`]: [`solvers::adr`], [`solvers::implicit`] and
//!   [`solvers::switching`], each `params in, Result<SolveInfo, PdError> out`;
//!   [`solvers::frozen`]: a model's equilibrium with frozen bonds (the chord
//!   iteration on a kept factor, Newton and ADR where it fails).
//! - [`breaking`]: progressive bond breaking at converged states, most
//!   stretched bonds first, re-equilibrating with [`solvers::frozen`].
//! - [`measure`]: initiation load and kink angle from the damage field.
//! - [`crack_path`]: tip tracking: the macro crack connected to an entry
//!   point, its tip and smoothed path ([`crack_path::trace_crack`]).
//! - [`edge_crack`]: seed 004's edge-crack plate (Table 2) and Irwin's opening.
//! - [`cases`]: the seed cases as problem constructors (CLI tests, integration
//!   tests, benchmarks).
//! - `bench` (cargo feature `bench`): benchmarks for `pdbem bench pd` and the
//!   `bench_full` example.

pub mod adapt;
#[cfg(any(test, feature = "bench"))]
pub mod bench;
pub mod bonds;
pub mod boundary;
pub mod breaking;
pub mod cases;
pub mod crack_path;
pub mod damage;
mod detach;
pub mod dynamics;
pub mod edge_crack;
pub mod error;
pub mod forces;
pub mod geometry;
pub mod grid;
pub mod material;
pub mod measure;
pub mod mixed;
pub mod model;
pub mod pieces;
pub mod problem;
pub mod reaction;
pub mod refine;
pub mod refine_zone;
pub mod solvers;
pub mod state_based;
pub mod surface;
pub mod tangent;
pub mod traction;

pub use error::PdError;
pub use model::{ModelState, PdModel};
pub use problem::{
    BoundaryCondition, Failure, Hole, Layer, PdMaterial, PdProblem, Plane, Region, Selection,
};
pub use solvers::{Convergence, SolveInfo};
pub use traction::TractionLoad;
