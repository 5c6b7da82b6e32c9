//! Load-controlled ramps that end at the body's limit instead of failing whole.
//!
//! A softening body (the tanh law of seed 000 Eq. 12, or brittle bonds breaking
//! unstably) under prescribed loads has no equilibrium past its peak load: the load
//! factor $\lambda$ of $F(u) + \lambda b = 0$ cannot grow beyond the limit point, where
//! the tangent $K = -\partial F / \partial u$ turns singular. Seed 000 follows softening
//! under prescribed displacements; under load control the solvers' honest answer is the
//! converged path up to the limit and where it lies.
//!
//! [`to_limit`] drives the load through the given load factors, one segment at a time,
//! from a snapshot of the last converged state. A segment that fails to reach
//! equilibrium is tried again from that state with the increment halved, up to
//! `max_cutbacks` times (so the last converged load brackets the limit to
//! $\Delta\lambda / 2^{c}$, $c$ the cutbacks); when the smallest increment fails too the
//! ramp stops there and returns its converged steps with the [`Stop`]. Errors that are not
//! a failed equilibrium (input, memory budget) end the ramp as errors. A segment that
//! converges to a runaway state ([`super::check_bounded`]) has failed too.
//!
//! The bracket says where the solvers stopped finding equilibria, not that the tangent
//! is singular there: a step too large for the solver can fail below the limit, which is
//! why the cutbacks halve it before the ramp stops.

use crate::error::PdError;
use crate::model::{ModelState, PdModel};

use super::{Iterating, SolveInfo};

/// Most halvings of a step [`to_limit`] takes (a larger `max_cutbacks` is this): an
/// increment of 2^-30 of the step.
pub const MAX_CUTBACKS: u32 = 30;

/// Where a ramp stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct Stop {
    /// Load factor of the last converged state (the model holds it).
    pub last_load: f64,
    /// Load factor of the smallest increment that failed.
    pub failed_load: f64,
    /// Halvings of the increment tried before stopping.
    pub cutbacks: u32,
    /// The failure of the smallest increment.
    pub error: PdError,
}

/// What [`to_limit`] did: the converged record and, if the ramp ended early, where.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LimitedSolve {
    /// Steps, iterations and phases of every converged segment (failed attempts add
    /// their iterations only).
    pub info: SolveInfo,
    /// `None` when every load factor was reached.
    pub stop: Option<Stop>,
    /// Segments tried again with a halved increment.
    pub retries: usize,
}

/// A segment that did not reach its target.
#[derive(Debug)]
pub struct SegmentFailure {
    /// Why.
    pub error: PdError,
    /// `Some(l)`: the model holds the converged state at load factor `l`, past the
    /// segment's start (a solver of several increments that failed in a later one);
    /// `None`: nothing the segment did is kept (the ramp restores its snapshot).
    pub reached: Option<f64>,
    /// The load factor the segment failed at, when not its target (the increment after
    /// `reached`).
    pub failed_at: Option<f64>,
}

impl From<PdError> for SegmentFailure {
    fn from(error: PdError) -> Self {
        SegmentFailure {
            error,
            reached: None,
            failed_at: None,
        }
    }
}

/// What a segment is asked: move the model from its converged state to `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Segment {
    /// Load factor to reach.
    pub target: f64,
    /// Halvings of the ramp's increment so far (0: the given load factors).
    pub level: u32,
    /// The model was restored from a snapshot since the last segment (solvers that keep
    /// a state of their own, ADR's velocities, start again from rest).
    pub restored: bool,
}

/// What a ramp reports as it goes (observers draw progress from it).
#[derive(Clone, Debug, PartialEq)]
pub enum RampEvent {
    /// A segment converged at this load factor.
    Converged {
        /// Load factor reached.
        load: f64,
    },
    /// A segment failed; it is tried again with the increment halved `level` times.
    Halving {
        /// Load factor the segment failed at.
        failed_load: f64,
        /// Halvings from now on.
        level: u32,
        /// The most allowed.
        max: u32,
    },
    /// An equilibrium search (ADR's) is still iterating at a load: sent every
    /// [`super::PROGRESS_EVERY`] iterations.
    Iterating(Iterating),
}

/// Whether `e` is a failed equilibrium (no convergence, divergence, a non-finite value,
/// bond history that did not settle, a runaway state, a failed linear solve), which a
/// smaller increment may cure, rather than an input or budget error.
pub fn is_equilibrium_failure(e: &PdError) -> bool {
    matches!(
        e,
        PdError::NoConvergence { .. }
            | PdError::Diverged { .. }
            | PdError::NonFinite { .. }
            | PdError::Unsettled { .. }
            | PdError::Runaway { .. }
            | PdError::LinearSolve { .. }
    )
}

/// Drives `model` from its current load through `loads` (load factors in order, rising or
/// falling) by `segment`, halving a failed segment's increment up to `max_cutbacks` times
/// (at most [`MAX_CUTBACKS`]; module docs). `segment` records its converged steps in the [`SolveInfo`] it is given; a
/// halving is kept for the rest of the ramp. `solver` names the solver in a runaway error;
/// `observe` hears of every converged segment and every halving.
pub fn to_limit<F>(
    model: &mut PdModel,
    loads: &[f64],
    max_cutbacks: u32,
    solver: &'static str,
    observe: &mut dyn FnMut(&RampEvent),
    mut segment: F,
) -> Result<LimitedSolve, PdError>
where
    F: FnMut(&mut PdModel, Segment, &mut SolveInfo) -> Result<(), SegmentFailure>,
{
    let mut out = LimitedSolve::default();
    let mut saved = ModelState::default();
    let (mut level, mut restored) = (0u32, false);
    let max_cutbacks = max_cutbacks.min(MAX_CUTBACKS);
    let mut prev = model.load;
    for &goal in loads {
        // Loads may fall as well as rise (a compressive ramp): `sign` is the direction.
        let step = goal - prev;
        let sign = if step < 0.0 { -1.0 } else { 1.0 };
        let close = 1e-12 * goal.abs().max(step.abs());
        while sign * (goal - model.load) > close {
            let start = model.load;
            let target = if level == 0 {
                goal
            } else {
                let halved = start + step * 0.5f64.powi(level as i32);
                if sign > 0.0 {
                    halved.min(goal)
                } else {
                    halved.max(goal)
                }
            };
            model.save_into(&mut saved);
            let records = out.info.steps.len();
            let ask = Segment {
                target,
                level,
                restored,
            };
            let failure = match segment(model, ask, &mut out.info) {
                Ok(()) => match super::check_bounded(model, solver) {
                    Ok(()) => None,
                    Err(e) => Some(SegmentFailure::from(e)),
                },
                Err(f) => Some(f),
            };
            restored = false;
            let Some(f) = failure else {
                observe(&RampEvent::Converged { load: model.load });
                continue;
            };
            if !is_equilibrium_failure(&f.error) {
                return Err(f.error);
            }
            if !f.reached.is_some_and(|l| sign * (l - start) > 0.0) {
                // Nothing of the segment is kept: neither its state nor a step it recorded
                // before the state was found a runaway.
                model.restore(&saved);
                out.info.steps.truncate(records);
                restored = true;
            }
            if level >= max_cutbacks {
                out.info.final_load = model.load;
                out.stop = Some(Stop {
                    last_load: model.load,
                    failed_load: f.failed_at.unwrap_or(target),
                    cutbacks: level,
                    error: f.error,
                });
                return Ok(out);
            }
            level += 1;
            out.retries += 1;
            observe(&RampEvent::Halving {
                failed_load: f.failed_at.unwrap_or(target),
                level,
                max: max_cutbacks,
            });
        }
        prev = goal;
    }
    out.info.final_load = model.load;
    Ok(out)
}

#[cfg(test)]
#[path = "limit_tests.rs"]
pub(crate) mod tests;
