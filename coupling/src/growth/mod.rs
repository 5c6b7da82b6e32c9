//! # Crack growth with moving PD windows (seed 002 Algorithm 2, sections 2.3.2-2.3.3)
//!
//! Load steps, each solved by Algorithm 1 to convergence on a BEM system factored once
//! per geometry (the load factor only scales the right-hand side,
//! [`crate::iteration::PreparedBem`]). After every iteration the macro crack in each
//! window ($\varphi > 0.38$ connected to the crack's entry into the window,
//! [`pdbem_pd::crack_path`]) gives the tip. When a tip passes the window margin the window
//! moves by the move distance along the growth direction, both BEM crack faces are
//! extended along the smoothed PD path by a set number of elements, the BEM system is
//! rebuilt and refactored, and the new window starts from the old PD state where the
//! grids overlap (broken bonds included) and from the BEM field elsewhere, at the same
//! load. Several tips each have a window, solved in parallel; windows that would overlap
//! are merged into one rectangle.
//!
//! How the crack is kept inside its window (choices of this implementation, measured on
//! `cases/growth_tension_edge.ron`, where the crack runs under load control at up to 30
//! times K_c):
//! - The PD windows are solved with [`crate::iteration::PdSolve::Staggered`]: bonds break
//!   only at converged interface states, the most stretched first
//!   ([`crate::breaking`]), a few rounds with the interface held; the step converges when
//!   the residual is below psi and no bond breaks. Breaking inside every PD solve lets
//!   the crack run through the whole window in one solve and spread damage sideways.
//! - A band of $(1 - r)$ times the window side along the interface sides ($r$ = trigger
//!   ratio, 0.9 in the seed) has unbreakable bonds, so no damage reaches the coupling
//!   layer; the window moves once the tip is within the band plus a horizon and a dx of
//!   an interface side ([`tips::margins`]).
//! - Structural failure (Algorithm 2 step 9): a tip reaching the outline, two edge cracks
//!   meeting, or a relocation after which the remaining ligament would lie wholly in PD
//!   windows ([`topology`]: the BEM body would be cut apart and a floating part cannot be
//!   held by the Dirichlet-Neumann iteration). A tip reaching a hole or another crack
//!   ends; the others go on.
//!
//! Map:
//! - [`driver`]: [`Growth`] (the run: [`Growth::run`], [`Growth::solve_at`]).
//! - [`geometry`]: the geometry iteration ([`Growth::plan`], [`Growth::apply`],
//!   [`Growth::relocate`]).
//! - [`records`]: the [`Scenario`] and [`Observer`] traits, the setup and the records.
//! - [`params`]: [`GrowthParams`], [`LoadSteps`].
//! - [`tips`]: tip specs and state, tracking, the margin and end tests.
//! - [`relocate`]: the moved window and the extended crack (the geometry iteration).
//! - [`transfer`]: the new window's initial state.
//! - [`merge`]: merging overlapping windows.
//! - [`topology`]: whether cracks and windows cut the BEM body apart (structural failure).
//! - [`polyline`]: small polyline helpers.

pub mod driver;
pub mod geometry;
pub mod merge;
pub mod params;
pub mod polyline;
pub mod records;
pub mod relocate;
pub mod tips;
pub mod topology;
pub mod transfer;

pub use driver::Growth;
pub use params::{GrowthParams, LoadSteps};
pub use records::{
    Failure, GrowthResult, GrowthSetup, IterationEvent, Observer, RelocationPlan, RelocationRecord,
    Scenario, Silent, SolveOutcome, StepResult,
};
pub use tips::{TipEnd, TipSpec, TipState};
pub use transfer::TransferInfo;

/// Shared test fixtures: the seed 002 plate (20 m x 10 m) and a 1 m window in it.
#[cfg(test)]
pub(crate) mod fixtures {
    use pdbem_bem::V2;

    use crate::window::{Body, Window, WindowSpec};

    /// The 20 m x 10 m plate of seed 002 section 3.2.
    pub(crate) fn body() -> Body {
        Body {
            outline: vec![
                V2::new(0.0, 0.0),
                V2::new(20.0, 0.0),
                V2::new(20.0, 10.0),
                V2::new(0.0, 10.0),
            ],
            holes: vec![],
        }
    }

    /// A 20 x 20 window of dx = 0.05 m centred at (cx, cy).
    pub(crate) fn window(cx: f64, cy: f64) -> Window {
        let spec = WindowSpec {
            center: V2::new(cx, cy),
            angle: 0.0,
            dx: 0.05,
            nx: 20,
            ny: 20,
            horizon_factor: 3.015,
        };
        Window::place(0, spec, &body()).unwrap()
    }
}
