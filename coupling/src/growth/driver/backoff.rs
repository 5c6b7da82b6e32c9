//! The back-off of a load step whose coupling does not converge (Algorithm 1 at its
//! `max_iter`, or diverging): the step is tried again from the state it started from
//! ([`super::state`]) with, in this order,
//! 1. four times the iteration cap, the scene's accelerator;
//! 2. IQN-ILS (for Aitken or constant relaxation, with the scene's weight) or, when IQN-ILS
//!    was in use already, IQN-ILS with half its first weight; four times the cap;
//! 3. as 2, with half the load increment: the step is solved at the load half-way from the
//!    last step's first (the first step: half its load), then at its own load.
//!
//! A step none of them solves ends the run: [`crate::growth::GrowthResult::failure_reason`]
//! names the step and every attempt with its outcome, the state is put back to the end
//! of the last completed step, whose records stand. Each retry is noted through the
//! observer. Other errors of a step (a window that cannot move, a geometry that cannot
//! be built) end the run the same way without a retry.

use super::step::{StepRun, StepStart, TryCx};
use super::Growth;
use crate::error::CouplingError;
use crate::growth::observer::Observer;
use crate::growth::records::{GrowthResult, Scenario};
use crate::iteration::{Acceleration, CouplingParams};

/// Iteration cap factor of the retries.
const MAX_ITER_FACTOR: usize = 4;

/// One way of trying a step.
#[derive(Debug, Clone)]
struct Attempt {
    /// What it changes, for the notes.
    label: String,
    /// The coupling parameters.
    coupling: CouplingParams,
    /// Solve first at the load half-way from the last step's.
    split: bool,
}

/// The attempts of a step: the scene's settings, then the back-off of the module docs.
fn attempts(base: &CouplingParams) -> Vec<Attempt> {
    let mut more = base.clone();
    more.max_iter = base.max_iter * MAX_ITER_FACTOR;
    let (iqn, iqn_label) = match base.acceleration {
        Acceleration::IqnIls(w) => (
            Acceleration::IqnIls(0.5 * w),
            format!("IQN-ILS with w0 = {}", 0.5 * w),
        ),
        Acceleration::Aitken(w) | Acceleration::Constant(w) => (
            Acceleration::IqnIls(w),
            format!(
                "IQN-ILS with w0 = {w} instead of {}",
                base.acceleration.name()
            ),
        ),
    };
    let mut switched = more.clone();
    switched.acceleration = iqn;
    vec![
        Attempt {
            label: format!(
                "the scene's settings ({}, max_iter {})",
                base.acceleration.name(),
                base.max_iter
            ),
            coupling: base.clone(),
            split: false,
        },
        Attempt {
            label: format!("max_iter {}", more.max_iter),
            coupling: more.clone(),
            split: false,
        },
        Attempt {
            label: format!("{iqn_label}, max_iter {}", switched.max_iter),
            coupling: switched.clone(),
            split: false,
        },
        Attempt {
            label: format!(
                "{iqn_label}, max_iter {}, half the load increment",
                switched.max_iter
            ),
            coupling: switched,
            split: true,
        },
    ]
}

/// Whether an error of a step is a coupling that a back-off may cure.
fn retryable(e: &CouplingError) -> bool {
    matches!(
        e,
        CouplingError::NoConvergence { .. } | CouplingError::Diverged { .. }
    )
}

/// A short account of an attempt's error (the residual history left out).
fn outcome(e: &CouplingError) -> String {
    match e {
        CouplingError::NoConvergence {
            iterations, last, ..
        } => format!("residual {last:.3e} after {iterations} iterations"),
        CouplingError::Diverged {
            reason, iterations, ..
        } => format!("diverged after {iterations} iterations ({reason})"),
        other => other.to_string(),
    }
}

impl<S: Scenario> Growth<'_, S> {
    /// Step `k` at load `load` (the last step's load `prev`) with the back-off of the
    /// module docs; `start.state` is the state at the start of the step, and a resumed run
    /// goes on inside the try of `start.resumed`. `Ok(Err(reason))`: no attempt solved it,
    /// the state is back at the step's start and `out` as it was.
    pub(super) fn step_with_backoff(
        &mut self,
        (k, load, prev): (usize, f64, f64),
        start: &StepStart<'_>,
        out: &mut GrowthResult,
        observer: &mut dyn Observer,
    ) -> Result<Result<StepRun, String>, CouplingError> {
        let saved = start.state;
        let base = self.params.coupling.clone();
        let (relocations, initiation) = match start.resumed {
            Some(w) => (w.relocations_before, w.initiation_before),
            None => (out.relocations.len(), out.initiation_load),
        };
        let mut tried = Vec::new();
        for (i, a) in attempts(&base).into_iter().enumerate() {
            // A resumed step goes on inside its try (the tries before it failed, and
            // their notes are in the log already).
            let here = match start.resumed {
                Some(w) if w.attempt > i => continue,
                Some(w) if w.attempt == i => Some(w),
                _ => None,
            };
            if i > 0 && here.is_none() {
                self.set_state(saved)?;
                out.relocations.truncate(relocations);
                out.initiation_load = initiation;
                observer.note(&format!(
                    "step {k} (load {load}): retry {i} of the step with {}",
                    a.label
                ));
            }
            self.params.coupling = a.coupling.clone();
            let cx = TryCx {
                attempt: i,
                first: None,
                start,
                relocations_before: relocations,
                initiation_before: initiation,
            };
            let r = if a.split {
                let mid = 0.5 * (prev + load);
                let first = match (here, here.and_then(|w| w.first.as_ref())) {
                    (_, Some(done)) => Ok(StepRun::resumed(done)),
                    (Some(w), None) => {
                        self.attempt((k, mid), out, observer, &cx, Some(&w.progress))
                    }
                    (None, None) => self.attempt((k, mid), out, observer, &cx, None),
                };
                first.and_then(|first| match first.cut {
                    Some(_) => Ok(first),
                    None => {
                        let cx = TryCx {
                            first: Some(first.progress()),
                            ..cx
                        };
                        let from = here.filter(|w| w.first.is_some()).map(|w| &w.progress);
                        self.attempt((k, load), out, observer, &cx, from)
                            .map(|second| second.after(&first))
                    }
                })
            } else {
                let from = here.map(|w| &w.progress);
                self.attempt((k, load), out, observer, &cx, from)
            };
            self.params.coupling = base.clone();
            match r {
                Ok(s) => return Ok(Ok(s)),
                // A stop inside the step (a checkpoint was offered): no retry.
                Err(e @ CouplingError::InterruptedAtRelocation { .. }) => return Err(e),
                Err(e) if retryable(&e) => tried.push(format!("{}: {}", a.label, outcome(&e))),
                Err(e) => {
                    tried.push(format!("{}: {e}", a.label));
                    break;
                }
            }
        }
        self.set_state(saved)?;
        out.relocations.truncate(relocations);
        out.initiation_load = initiation;
        Ok(Err(format!(
            "load step {k} (load factor {load}) could not be solved; tried {}",
            tried.join("; ")
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_back_off_switches_to_iqn_ils_and_halves_its_weight_when_in_use() {
        let aitken = CouplingParams::default();
        let a = attempts(&aitken);
        assert_eq!(a.len(), 4);
        assert_eq!(a[1].coupling.max_iter, 200);
        assert_eq!(a[2].coupling.acceleration, Acceleration::IqnIls(0.3));
        assert!(a[3].split && !a[2].split);
        let iqn = CouplingParams {
            acceleration: Acceleration::IqnIls(0.5),
            ..Default::default()
        };
        let a = attempts(&iqn);
        assert_eq!(a[2].coupling.acceleration, Acceleration::IqnIls(0.25));
        assert!(a[2].label.contains("w0 = 0.25"), "{}", a[2].label);
    }
}
