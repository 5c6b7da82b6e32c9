//! Algorithm 1 at a load scale on a prepared BEM system ([`solve_prepared`]): the
//! iteration with relaxation, back-offs and bond breaking.

use std::time::Instant;

use rayon::prelude::*;

use super::evaluate::{evaluate, reset_window};
use super::params::{CouplingParams, Ordering, PdSolve, StaggeredParams};
use super::prepared::PreparedBem;
use super::traction::{evaluate_traction, finish, traction_windows};
use super::{
    relative_residual, CoupledProblem, CoupledSolution, CouplingInfo, IterationReport, StepOptions,
    BREAK_ITERATION_FACTOR,
};
use crate::error::CouplingError;
use crate::setup::WindowModel;

/// Runs Algorithm 1 on `problem` with the prepared BEM system `bem` (see the module docs
/// for the load scale, bond breaking and the monitor).
pub fn solve_prepared(
    problem: &mut CoupledProblem,
    bem: &PreparedBem,
    params: &CouplingParams,
    mut opts: StepOptions<'_>,
) -> Result<(CoupledSolution, CouplingInfo), CouplingError> {
    let t0 = Instant::now();
    let mut info = CouplingInfo {
        scheme: params.acceleration.name().into(),
        ..Default::default()
    };
    let mut tws = match params.ordering {
        Ordering::DisplacementToPd => None,
        Ordering::TractionToPd => Some(traction_windows(problem)?),
    };
    check_ordering(bem, params)?;
    let n: usize = match &tws {
        None => problem.windows.iter().map(|w| w.interface.len()).sum(),
        Some(t) => t.iter().map(|w| w.len()).sum(),
    };
    info.interface_unknowns = n;
    let scale = opts.load_scale;
    if !(scale.is_finite() && scale > 0.0) {
        return Err(CouplingError::InvalidStep {
            message: format!("load scale {scale} must be positive and finite"),
        });
    }
    let mut x = match opts.start.take() {
        Some(x0) if x0.len() == n => x0,
        Some(x0) => {
            return Err(CouplingError::InvalidStep {
                message: format!(
                    "start vector has {} values for {n} interface unknowns",
                    x0.len()
                ),
            })
        }
        None => vec![0.0; n],
    };
    let pd_solve = params.pd_solve.at(scale);
    let commit_at_convergence = match &pd_solve {
        PdSolve::Staggered(p) if p.rounds == 0 => Some(p.clone()),
        _ => None,
    };
    let mut weight_scale = 1.0;
    let mut relax = params.acceleration.build(weight_scale);
    if params.reuse_secants {
        relax.seed(std::mem::take(&mut opts.secants).for_unknowns(n));
    }
    let mut best = (f64::INFINITY, x.clone());
    let mut since_best = 0;
    let mut growing = 0;
    let mut since_break = 0;
    let mut backoffs_since_break = 0;
    let mut pd_failure: Option<String> = None;
    loop {
        let evaluated = match &mut tws {
            None => evaluate(problem, bem, &x, params, &pd_solve, scale, &mut info),
            Some(t) => evaluate_traction(problem, bem, t, &x, &pd_solve, scale, &mut info),
        };
        info.iterations += 1;
        since_break += 1;
        let (e, xt, state, broke) = match evaluated {
            Ok((sol, xt, tractions, broke)) => (
                relative_residual(&x, &xt),
                xt,
                Some((sol, tractions)),
                broke,
            ),
            Err(CouplingError::Pd {
                window,
                error: source,
            }) => {
                // A failed PD solve counts as divergence: restart its state from rest.
                match &mut tws {
                    None => reset_window(&mut problem.windows[window]),
                    Some(t) => {
                        let zero = vec![[0.0; 2]; t[window].model.n_nodes()];
                        // Same length by construction, so this cannot fail.
                        let _ = t[window].model.set_displacements(&zero);
                    }
                }
                pd_failure = Some(format!("PD window {window} failed: {source}"));
                (f64::NAN, x.clone(), None, 0)
            }
            Err(other) => return Err(other),
        };
        let mut broke = broke;
        let mut committed = false;
        if let Some(sp) = &commit_at_convergence {
            if state.is_some() && e.is_finite() && e < params.psi && broke == 0 {
                broke = commit_windows(&mut problem.windows, sp)?;
                committed = broke > 0;
            }
        }
        info.residuals.push(e);
        info.bonds_broken.push(broke);
        let stop = opts.monitor.as_mut().is_some_and(|m| {
            m(&IterationReport {
                iteration: info.iterations,
                residual: e,
                bonds_broken: broke,
                windows: &problem.windows,
            })
            .is_break()
        });
        let converged = e.is_finite() && e < params.psi && broke == 0;
        if let (true, Some((sol, tractions))) = (converged || stop, state) {
            info.converged = converged;
            info.interrupted = !converged;
            let secants = if params.reuse_secants {
                relax.end_map(Some((&x, &xt)));
                relax.take_secants()
            } else {
                Default::default()
            };
            let (x_pd, x_bem) = match &tws {
                None => (x, xt),
                Some(t) => finish(problem, t, &sol, scale)?,
            };
            info.timings.total_s = t0.elapsed().as_secs_f64();
            let out = CoupledSolution {
                solution: sol,
                x_pd,
                x_bem,
                tractions,
                secants,
            };
            return Ok((out, info));
        }
        if broke > 0 {
            // The map changed a little (a few bonds near a tip): the divergence history
            // restarts, back-offs are forgiven, and the accelerator starts a new model
            // (with the old one's differences as reused columns when asked). Bonds
            // broken at convergence changed the map after this evaluation: (x, xt) lies on
            // the old map, so it goes to the old model and x is evaluated again.
            since_break = 0;
            weight_scale = 1.0;
            let old_pair = committed.then_some((x.as_slice(), xt.as_slice()));
            let carried = if params.reuse_secants {
                relax.end_map(old_pair);
                relax.take_secants()
            } else {
                Default::default()
            };
            relax = params.acceleration.build(weight_scale);
            relax.seed(carried);
            best = (f64::INFINITY, xt.clone());
            since_best = 0;
            growing = 0;
            backoffs_since_break = 0;
        }
        if since_break >= params.max_iter
            || info.iterations >= BREAK_ITERATION_FACTOR * params.max_iter
        {
            return Err(CouplingError::NoConvergence {
                iterations: info.iterations,
                scheme: params.acceleration.name(),
                last: e,
                psi: params.psi,
                residuals: info.residuals,
            });
        }
        if committed {
            // x is evaluated again on the new map; its old-map residual is no best.
            info.weights.push(None);
            continue;
        }
        growing = if broke == 0
            && info.residuals.len() > 1
            && e > info.residuals[info.residuals.len() - 2]
        {
            growing + 1
        } else {
            0
        };
        if e < 0.99 * best.0 {
            best = (e, x.clone());
            since_best = 0;
        } else {
            since_best += 1;
        }
        let reason = if !e.is_finite() {
            Some(
                pd_failure
                    .take()
                    .unwrap_or_else(|| "non-finite residual".to_string()),
            )
        } else if growing >= params.growth_window {
            Some(format!("residual grew {growing} times in a row"))
        } else if since_best >= params.stagnation_window {
            Some(format!("no 1 % improvement in {since_best} iterations"))
        } else {
            None
        };
        if let Some(reason) = reason {
            if backoffs_since_break >= params.max_backoffs {
                return Err(CouplingError::Diverged {
                    reason,
                    iterations: info.iterations,
                    backoffs: info.backoffs,
                    residuals: info.residuals,
                });
            }
            info.backoffs += 1;
            backoffs_since_break += 1;
            weight_scale *= 0.5;
            relax = params.acceleration.build(weight_scale);
            x = best.1.clone();
            growing = 0;
            since_best = 0;
            info.weights.push(Some(0.0));
            continue;
        }
        x = relax.next(&x, &xt);
        info.weights.push(relax.last_weight());
        for event in relax.take_events() {
            info.notes
                .push(format!("iteration {}: {event}", info.iterations));
        }
    }
}

/// The prepared system must be factored for the ordering, and the traction ordering
/// takes static solves only.
fn check_ordering(bem: &PreparedBem, params: &CouplingParams) -> Result<(), CouplingError> {
    if bem.ordering() != params.ordering {
        return Err(CouplingError::InvalidStep {
            message: format!(
                "the BEM system was factored for the {:?} ordering, the parameters ask for {:?}",
                bem.ordering(),
                params.ordering
            ),
        });
    }
    if params.ordering == Ordering::TractionToPd && matches!(params.pd_solve, PdSolve::Staggered(_))
    {
        return Err(CouplingError::InvalidStep {
            message: "the TractionToPd ordering solves static windows only (no staggered bond \
                      breaking, so no crack growth)"
                .into(),
        });
    }
    Ok(())
}

/// Break rounds in every window with its interface held ([`pdbem_pd::breaking`]); returns the
/// bond pairs broken.
fn commit_windows(
    windows: &mut [WindowModel],
    p: &StaggeredParams,
) -> Result<usize, CouplingError> {
    let counts: Vec<Result<usize, CouplingError>> = windows
        .par_iter_mut()
        .enumerate()
        .map(|(i, w)| {
            let (model, slot) = (&mut w.model, &mut w.solver);
            pdbem_pd::breaking::break_rounds(
                model,
                slot,
                p.break_fraction,
                p.break_rounds,
                &p.newton,
            )
            .map_err(|e| CouplingError::pd(i, e))
        })
        .collect();
    counts.into_iter().sum()
}
