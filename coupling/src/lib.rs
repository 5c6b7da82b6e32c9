//! # pdbem-coupling: PD windows iterated against the BEM body (seed 002 section 2.3)
//!
//! The crack-tip regions are PD windows (square, n x n real nodes of spacing dx, possibly
//! rotated or against the outline); the rest of the body is BEM with the windows cut out,
//! one interface element of length dx per PD node row. Algorithm 1 (seed 002 section
//! 2.3.1) iterates: PD takes interface displacements on its virtual layers (Eq. 23), its
//! virtual-on-real forces become BEM tractions (Eq. 24), BEM returns new displacements by
//! one substitution, and an accelerator (Eqs. 25-28 or IQN-ILS) relaxes them.
//!
//! Map of the crate:
//! - [`window`]: window geometry, placement rules, BEM hole / outline cut, crack split.
//! - [`pd_window`]: the PD problem of a window (virtual layers, outer conditions, bulk
//!   stiffness calibration).
//! - [`interface`]: element <-> virtual node <-> bond matching of one window.
//! - [`maps`]: BEM -> PD displacement maps (copy, interior, Taylor) and PD -> BEM tractions.
//! - [`setup`]: from a macro layout to mesh + windows ([`setup::build`]).
//! - [`traction_window`]: a window loaded by interface tractions through seed 001's
//!   transfer functions (the traction ordering of Algorithm 1).
//! - [`iteration`]: Algorithm 1 ([`iteration::solve`]: params in, `Result<(solution, info), CouplingError>` out).
//! - [`relaxation`]: interface acceleration behind one trait: constant, Aitken (seed 002
//!   Eqs. 25-28) and IQN-ILS.
//! - [`spectrum`]: Ritz values of the interface operator (why a scheme needs the
//!   iterations it needs).
//! - [`post`]: post-processing of a coupled solution (interaction-integral SIFs of a tip
//!   inside a window, [`post::window_tip_sif`]).
//! - [`growth`]: Algorithm 2 (seed 002 sections 2.3.2-2.3.3): load steps with moving
//!   tip windows, crack extension and structural failure ([`growth::Growth`]).
//! - [`error`]: the crate's error type, [`CouplingError`].

pub mod error;
pub mod floating;
pub mod growth;
pub mod interface;
pub mod iteration;
pub mod maps;
pub mod pd_window;
pub mod post;
pub mod relaxation;
pub mod setup;
pub mod spectrum;
pub mod traction_window;
pub mod window;

pub use error::CouplingError;
pub use iteration::{
    interface_map, solve, solve_prepared, Acceleration, CoupledProblem, CoupledSolution,
    CouplingInfo, CouplingParams, Ordering, PdSolve, PreparedBem, StaggeredParams, StepOptions,
    Timings,
};
pub use maps::{DisplacementMap, TractionMap};
pub use setup::{build, Built, Layout, MacroCrack, WindowModel};
pub use window::{Body, SideKind, Window, WindowSpec};
