//! The one error type of the crate: [`CouplingError`]. Every variant carries the numbers
//! that explain it and says what to change.

use pdbem_bem::{BemError, V2};
use pdbem_pd::PdError;

/// What can go wrong when placing windows or iterating PD against BEM.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CouplingError {
    /// A window parameter is out of range (side, dx, node count, angle).
    #[error("window {window}: {message}")]
    InvalidWindow {
        /// Window index.
        window: usize,
        /// What is wrong and what to change.
        message: String,
    },
    /// A window corner lies outside the body.
    #[error("window {window}: corner ({:.6}, {:.6}) lies outside the body; move or shrink the window", corner.x, corner.y)]
    OutsideBody {
        /// Window index.
        window: usize,
        /// The offending corner (m).
        corner: V2,
    },
    /// The outer boundary crosses the window (only whole window sides may lie on it).
    #[error("window {window}: the outer boundary crosses the window{}; a window may touch the outline only with whole sides lying on it", if *rotated { " (rotated window: an outline edge must run along the side it touches)" } else { "" })]
    CrossesBoundary {
        /// Window index.
        window: usize,
        /// The window is rotated (not a multiple of 90 degrees).
        rotated: bool,
    },
    /// A hole of the body overlaps the window.
    #[error("window {window}: overlaps hole {hole}; PD windows must lie in material (move the window off the hole)")]
    OverHole {
        /// Window index.
        window: usize,
        /// Hole index.
        hole: usize,
    },
    /// Fewer than 2 horizons of real nodes across the window.
    #[error("window {window}: {nodes} real nodes across a side give {width:.4e} m, less than 2 delta = {min:.4e} m; use at least {needed} nodes per side")]
    TooFewNodes {
        /// Window index.
        window: usize,
        /// Nodes across the narrower side.
        nodes: usize,
        /// Narrower side length (m).
        width: f64,
        /// Two horizons (m).
        min: f64,
        /// Smallest admissible node count.
        needed: usize,
    },
    /// Two windows overlap (their virtual layers would share material).
    #[error("windows {a} and {b} overlap (including their horizon layers); move them apart or shrink them")]
    WindowsOverlap {
        /// First window.
        a: usize,
        /// Second window.
        b: usize,
    },
    /// A crack cannot be split between BEM and a window.
    #[error("crack {crack}: {message}")]
    Crack {
        /// Crack index.
        crack: usize,
        /// What is wrong.
        message: String,
    },
    /// The BEM mesh does not match the window rows.
    #[error("window {window}: interface mismatch: {message}")]
    Interface {
        /// Window index.
        window: usize,
        /// What does not match.
        message: String,
    },
    /// Error from the BEM solver.
    #[error("BEM: {0}")]
    Bem(BemError),
    /// Error from the PD solver of a window.
    #[error("PD window {window}: {error}")]
    Pd {
        /// Window index.
        window: usize,
        /// The PD error, in the message (not a `source`, which `{:#}` would print a
        /// second time).
        error: PdError,
    },
    /// The iteration diverged or stagnated after every back-off of the relaxation.
    #[error("coupling diverged ({reason}) after {iterations} iterations and {backoffs} relaxation back-offs; residual history {residuals:?}; lower the relaxation weight or refine the interface")]
    Diverged {
        /// Why (growing residual, NaN, stagnation).
        reason: String,
        /// Iterations done.
        iterations: usize,
        /// Back-offs done.
        backoffs: usize,
        /// Residual of every iteration.
        residuals: Vec<f64>,
    },
    /// The iteration cap was reached before the residual fell below psi.
    #[error("coupling did not converge in {iterations} iterations ({scheme}): residual {last:.3e} > psi = {psi:.1e}; history {residuals:?}; {hint}", hint = convergence_hint(scheme))]
    NoConvergence {
        /// Iterations done.
        iterations: usize,
        /// The interface accelerator in use ([`crate::iteration::Acceleration::name`]).
        scheme: &'static str,
        /// Last residual.
        last: f64,
        /// Tolerance.
        psi: f64,
        /// Residual of every iteration.
        residuals: Vec<f64>,
    },
    /// A piece of the BEM body cut apart by cracks that the iteration cannot hold
    /// ([`crate::floating`]).
    #[error("BEM body cut apart: {message}")]
    FloatingPiece {
        /// Which piece, why, and what to change.
        message: String,
    },
    /// Bad options of one Algorithm 1 run ([`crate::iteration::solve_prepared`]).
    #[error("coupling step: {message}")]
    InvalidStep {
        /// What is wrong, with the numbers.
        message: String,
    },
    /// A crack-growth parameter is out of range (seed 002 Algorithm 2).
    #[error("growth parameter `{field}`: {message}")]
    InvalidGrowth {
        /// Parameter name.
        field: &'static str,
        /// What is wrong and what to change.
        message: String,
    },
    /// A BEM-only or full-PD growth run could not go on.
    #[error("{mode} growth: {message}")]
    Growth {
        /// `BEM-only` or `full-PD`.
        mode: &'static str,
        /// What happened and what to change.
        message: String,
    },
    /// Two tip windows would overlap and cannot be merged into one rectangle.
    #[error("tips {first} and {second}: their windows overlap and cannot be merged: {reason}")]
    WindowsCannotMerge {
        /// First tip.
        first: String,
        /// Second tip.
        second: String,
        /// Why (different orientation or spacing, merged rectangle outside the body, ...).
        reason: String,
    },
    /// No interaction-integral contour fits around a windowed tip: a circle that encloses
    /// the window would cross the outline or a hole ([`crate::post::window_tip_sif`]).
    #[error("window {window}: no interaction-integral contour: a circle around the tip must enclose the window (radius >= {min_radius:.4e} m, {min_factor} x the tip-to-corner distance {corner_distance:.4e} m) and keep clear of the outline and holes (radius <= {max_radius:.4e} m, {clearance_factor} x the tip's distance {clearance:.4e} m to them); shrink the window until its tip-to-corner distance is below {corner_limit:.4e} m (side {side_limit:.4e} m for a square centred on the tip) or keep the tip farther from the boundary")]
    NoSifContour {
        /// Window index.
        window: usize,
        /// Largest tip-to-corner distance of the window (m).
        corner_distance: f64,
        /// Smallest admissible radius (m).
        min_radius: f64,
        /// Largest admissible radius (m).
        max_radius: f64,
        /// The tip's distance to the outline and holes (m).
        clearance: f64,
        /// Smallest radius over the tip-to-corner distance.
        min_factor: f64,
        /// Largest radius over the clearance.
        clearance_factor: f64,
        /// Largest tip-to-corner distance that leaves a contour (m).
        corner_limit: f64,
        /// The side of a square window centred on the tip with that corner distance (m).
        side_limit: f64,
    },
    /// A window cannot be moved on along its crack.
    #[error("tip {tip}: cannot relocate its window: {reason}")]
    Relocation {
        /// Tip name.
        tip: String,
        /// Why, with the numbers.
        reason: String,
    },
    /// A growth run stopped by its observer after a completed load step (a checkpoint
    /// was offered first; the run can be resumed from it).
    #[error("growth run stopped by its observer after load step {step}")]
    Interrupted {
        /// The last completed step (0-based).
        step: usize,
    },
    /// A full-PD growth run was stopped by its observer inside a load step, after the
    /// checkpoint of a break round was offered (the run can be resumed from it).
    #[error("growth run stopped by its observer in load step {step} after break round {round}")]
    InterruptedWithin {
        /// The load step in progress (0-based).
        step: usize,
        /// The last completed break round of it (0-based).
        round: usize,
    },
    /// A PD-BEM growth run was stopped by its observer inside a load step, just after a
    /// relocation whose checkpoint was offered (the run can be resumed from it).
    #[error(
        "growth run stopped by its observer in load step {step} after relocation {relocation}"
    )]
    InterruptedAtRelocation {
        /// The load step in progress (0-based).
        step: usize,
        /// Relocation records of the run so far.
        relocation: usize,
    },
    /// A BEM-only growth run was stopped by its observer inside a load step, after the
    /// checkpoint of a growth round was offered (the run can be resumed from it).
    #[error(
        "growth run stopped by its observer in load step {step} after increment round {increments}"
    )]
    InterruptedAtIncrement {
        /// The load step in progress (0-based).
        step: usize,
        /// Growth rounds of the step so far.
        increments: usize,
    },
    /// A growth checkpoint does not fit the run it is to resume (another scene or
    /// version).
    #[error("checkpoint: {message}")]
    Checkpoint {
        /// What does not fit.
        message: String,
    },
}

/// The BEM error in the message, not as a `source` (which `{:#}` would print a second
/// time: "BEM: solve: ...: solve: ...").
impl From<BemError> for CouplingError {
    fn from(e: BemError) -> Self {
        CouplingError::Bem(e)
    }
}

impl CouplingError {
    /// Wraps a PD error of window `window`.
    pub fn pd(window: usize, source: PdError) -> Self {
        CouplingError::Pd {
            window,
            error: source,
        }
    }
}

/// What to change after a coupling that did not converge with the accelerator `scheme`:
/// IQN-ILS is advised only when it is not already in use.
fn convergence_hint(scheme: &str) -> &'static str {
    if scheme == "iqn-ils" {
        "raise max_iter, lower the IQN-ILS first weight w0, or lower the load step"
    } else {
        "raise max_iter or use IQN-ILS"
    }
}

#[cfg(test)]
mod message_tests {
    use super::*;
    use std::error::Error;

    /// The wrapped BEM and PD errors are part of the message and not repeated by a
    /// printer that walks the source chain (the CLI prints `{:#}`).
    #[test]
    fn wrapped_errors_appear_once() {
        let bem = CouplingError::from(BemError::Mesh("no element".into()));
        assert_eq!(bem.to_string(), "BEM: mesh: no element");
        assert!(bem.source().is_none());
        let pd = CouplingError::pd(0, PdError::invalid("coupling.refine", "too wide"));
        assert!(pd
            .to_string()
            .starts_with("PD window 0: invalid input `coupling.refine`"));
        assert!(pd.source().is_none());
    }
}
