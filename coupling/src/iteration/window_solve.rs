//! The PD solve of one window with the interface displacements imposed
//! ([`solve_window`], [`solve_window_at`]), staggered bond breaking included.

use pdbem_pd::solvers::{adr, frozen, implicit, switching};

use super::params::{PdSolve, StaggeredParams};
use crate::setup::WindowModel;

/// [`PdSolve::Staggered`] on one model with its kept solvers; returns the solver
/// iterations.
///
/// Each equilibrium is the chord iteration's, with ADR on a trial budget, Newton and ADR on
/// its full budget where it fails ([`frozen::FrozenSolver`] with the windows'
/// [`frozen::Fallbacks`]).
fn staggered(
    model: &mut pdbem_pd::PdModel,
    slot: &mut frozen::SolverSlot,
    p: &StaggeredParams,
) -> Result<usize, pdbem_pd::PdError> {
    let mut info = pdbem_pd::SolveInfo::default();
    let solver = slot.get(model)?;
    let start = model.displacements().to_vec();
    solver.predict_to(model, p.newton.target_load, &mut info)?;
    let mut iters = solver
        .equilibrate(model, &p.newton, &start, &mut info)?
        .iterations();
    for _ in 0..p.rounds {
        if model.commit_history().newly_broken == 0 {
            break;
        }
        iters += solver
            .equilibrate(model, &p.newton, &start, &mut info)?
            .iterations();
    }
    Ok(iters)
}

/// Imposes `xw` on the coupled virtual nodes of window `w` and solves its PD model.
/// Returns the solver's iteration count.
pub fn solve_window(
    w: &mut WindowModel,
    xw: &[f64],
    solver: &PdSolve,
) -> Result<usize, pdbem_pd::PdError> {
    solve_window_at(w, xw, solver, 1.0)
}

/// [`solve_window`] at load factor `scale`: the model runs at that load factor (its outer
/// scene conditions scale with it) and the coupled virtual nodes get `xw` (their base
/// values are `xw / scale`). `solver` must target the same load factor.
pub fn solve_window_at(
    w: &mut WindowModel,
    xw: &[f64],
    solver: &PdSolve,
    scale: f64,
) -> Result<usize, pdbem_pd::PdError> {
    let mut base = w.interface.base.clone();
    for (k, &v) in w.interface.coupled.iter().enumerate() {
        base[v] = [xw[2 * k] / scale, xw[2 * k + 1] / scale];
    }
    if w.model.load_factor() != scale {
        w.model.set_load_factor(scale);
    }
    w.model.set_prescribed_displacements(&base)?;
    if is_unloaded(&w.model, &base) {
        // The solution is zero; the solvers' relative measures are undefined there.
        let zero = vec![[0.0; 2]; w.model.n_nodes()];
        w.model.set_displacements(&zero)?;
        return Ok(0);
    }
    let (name, iterations) = match solver {
        PdSolve::Switching(p) => ("switching", switching::solve(&mut w.model, p)?.iterations),
        PdSolve::Implicit(p) => ("implicit", implicit::solve(&mut w.model, p)?.iterations),
        PdSolve::Adr(p) => ("adr", adr::solve(&mut w.model, p)?.iterations),
        PdSolve::Staggered(p) => ("staggered", staggered(&mut w.model, &mut w.solver, p)?),
    };
    // A state no small-strain equilibrium reaches is an error, not a solution
    // (`pdbem_pd::solvers::check_bounded`).
    pdbem_pd::solvers::check_bounded(&w.model, name)?;
    Ok(iterations)
}

/// No prescribed displacement and no body force: the PD solution is zero.
fn is_unloaded(model: &pdbem_pd::PdModel, base: &[[f64; 2]]) -> bool {
    base.iter().all(|b| b[0] == 0.0 && b[1] == 0.0)
        && model
            .boundary()
            .body
            .iter()
            .all(|b| b[0] == 0.0 && b[1] == 0.0)
}
