//! The quasi-static solvers as ramp segments of [`super::limit::to_limit`]: Newton and
//! ADR take one load step per segment (the halved steps of a retry included), the
//! switching solver the rest of its ramp per segment with its increments halved at each
//! retry. Without a failure every solver does exactly what its `solve` does.

use std::cell::RefCell;
use std::time::Instant;

use super::adr::{Adr, AdrParams};
use super::implicit::{ImplicitParams, Newton};
use super::limit::{to_limit, LimitedSolve, RampEvent, Segment, SegmentFailure};
use super::switching::{self, SwitchingParams};
use super::{Iterating, PhaseKind, SolveInfo};
use crate::error::PdError;
use crate::model::PdModel;

/// A quasi-static solver and its parameters.
#[derive(Clone, Debug, PartialEq)]
pub enum QuasiStatic {
    /// Newton-Raphson ([`super::implicit`]).
    Implicit(ImplicitParams),
    /// Adaptive dynamic relaxation ([`super::adr`]) to equilibrium at every step
    /// (`iters_per_step: None`).
    Adr(AdrParams),
    /// The explicit-implicit switch ([`super::switching`]).
    Switching(SwitchingParams),
}

impl QuasiStatic {
    /// The solver's name in errors.
    pub fn name(&self) -> &'static str {
        match self {
            QuasiStatic::Implicit(_) => "implicit",
            QuasiStatic::Adr(_) => "adr",
            QuasiStatic::Switching(_) => "switching",
        }
    }
}

/// The load factors `lam0 + (target - lam0) k / steps`, k = 1..=steps, of a solver's
/// equal steps.
fn equal_steps(lam0: f64, target: f64, steps: usize) -> Vec<f64> {
    let steps = steps.max(1);
    (1..=steps)
        .map(|k| lam0 + (target - lam0) * k as f64 / steps as f64)
        .collect()
}

/// Solves from the model's state to the solver's target load by
/// [`super::limit::to_limit`], halving a failed step up to `max_cutbacks` times, and
/// closes the record (phases of Newton and ADR, bonds broken, wall time); `observe`
/// hears the ramp's events.
pub fn solve_to_limit(
    model: &mut PdModel,
    solver: &QuasiStatic,
    max_cutbacks: u32,
    observe: &mut dyn FnMut(&RampEvent),
) -> Result<LimitedSolve, PdError> {
    let t0 = Instant::now();
    let (lam0, broken0) = (model.load, model.broken_bonds());
    let name = solver.name();
    let mut out = match solver {
        QuasiStatic::Implicit(p) => {
            let mut newton = Newton::new(model)?;
            let loads = equal_steps(lam0, p.target_load, p.steps);
            to_limit(model, &loads, max_cutbacks, name, observe, |m, s, info| {
                info.iterations += newton.load_step(m, s.target, p, info)?;
                Ok(())
            })?
        }
        QuasiStatic::Adr(p) => {
            if p.iters_per_step.is_some() {
                return Err(PdError::invalid(
                    "iters_per_step",
                    "a ramp to the limit needs an equilibrium at every step: set None",
                ));
            }
            let mut adr = Adr::for_params(model, p);
            let loads = equal_steps(lam0, p.target_load, p.steps);
            // The ramp hears of steps, the step of its iterations: one observer, never
            // called by both at once.
            let observe = RefCell::new(observe);
            let mut ramp_events = |e: &RampEvent| (observe.borrow_mut())(e);
            // A restored state starts ADR from rest.
            to_limit(
                model,
                &loads,
                max_cutbacks,
                name,
                &mut ramp_events,
                |m, s, info| {
                    if s.restored {
                        adr.reset();
                    }
                    let mut progress =
                        |e: &Iterating| (observe.borrow_mut())(&RampEvent::Iterating(*e));
                    info.iterations += adr.load_step(m, s.target, p, info, &mut progress)?;
                    Ok(())
                },
            )?
        }
        QuasiStatic::Switching(p) => {
            let whole = p.target_load - lam0;
            let increment = whole / p.increments() as f64;
            // The ramp hears of segments, the segment of its increments: one observer,
            // never called by both at once.
            let observe = RefCell::new(observe);
            let mut ramp_events = |e: &RampEvent| (observe.borrow_mut())(e);
            to_limit(
                model,
                &[p.target_load],
                max_cutbacks,
                solver.name(),
                &mut ramp_events,
                |m, s, info| {
                    let mut increments = |e: &RampEvent| (observe.borrow_mut())(e);
                    switching_segment(m, s, p, (whole, increment), info, &mut increments)
                },
            )?
        }
    };
    let kind = match solver {
        QuasiStatic::Implicit(_) => Some(PhaseKind::Implicit),
        QuasiStatic::Adr(_) => Some(PhaseKind::Explicit),
        QuasiStatic::Switching(_) => None,
    };
    let dt = t0.elapsed().as_secs_f64();
    let broken = model.broken_bonds() - broken0;
    match kind {
        Some(kind) => out
            .info
            .finish_single_phase(kind, lam0, model.load, dt, broken),
        None => {
            out.info.final_load = model.load;
            out.info.bonds_broken = broken;
            out.info.wall_time_s = dt;
        }
    }
    Ok(out)
}

/// One segment of the switching solver: from the model's load to `s.target` with
/// increments of `increment / 2^level` and as many elastic Newton steps as the share of
/// the `whole` ramp the segment covers (so the first segment is the solver's own solve);
/// its record joins `info`, the load of every accepted step or increment and the progress
/// of long increments go to `observe`.
fn switching_segment(
    model: &mut PdModel,
    s: Segment,
    p: &SwitchingParams,
    (whole, increment): (f64, f64),
    info: &mut SolveInfo,
    observe: &mut dyn FnMut(&RampEvent),
) -> Result<(), SegmentFailure> {
    let start = model.load;
    let span = s.target - start;
    let size = increment * 0.5f64.powi(s.level as i32);
    // Rounding guard: a span of exactly n increments is n, not n + 1.
    let explicit_steps = ((span / size) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
    let implicit_steps = ((p.implicit_steps as f64 * span / whole) * (1.0 - 1e-12))
        .ceil()
        .max(1.0) as usize;
    let sp = SwitchingParams {
        target_load: s.target,
        explicit_steps,
        implicit_steps,
        ..p.clone()
    };
    let actual = span / sp.increments() as f64;
    let (part, end) = switching::solve_observed(model, &sp, observe);
    info.absorb(part);
    // A failed increment leaves the model where it started.
    end.map_err(|error| {
        let (reached, failed_at) = failed_increment(start, model.load, actual, s.target);
        SegmentFailure {
            error,
            reached,
            failed_at: Some(failed_at),
        }
    })
}

/// Where a segment from `start` towards `target` in increments of `actual` (signed)
/// stands after an increment failed from the load `now`: the converged load it reached,
/// if past `start`, and the load of the failed increment (not beyond `target`). Loads may
/// rise or fall.
fn failed_increment(start: f64, now: f64, actual: f64, target: f64) -> (Option<f64>, f64) {
    let rising = target >= start;
    let reached = if rising { now > start } else { now < start };
    let next = now + actual;
    let failed = if rising {
        next.min(target)
    } else {
        next.max(target)
    };
    (reached.then_some(now), failed)
}

#[cfg(test)]
#[path = "limit_solvers_tests.rs"]
mod tests;
