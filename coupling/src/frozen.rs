//! Equilibrium of a window's PD model with the bond history frozen: Newton-Raphson
//! (seed 000 section 2, Eq. 5), and adaptive dynamic relaxation (seed 002 Eqs. 9-15)
//! from the last finite state when Newton fails.
//!
//! Newton stalls once the bonds left make the tangent nearly singular: a fragment held
//! by one bond, a node whose remaining bonds are collinear. Measured on the seed 001
//! two-crack plate (`cases/growth_two_parallel_cracks.ron`): the relative residual stopped
//! at 5e-5 after 50 iterations, in the step where the cracks ran through. ADR needs only
//! the forces, so such a state still equilibrates. No bond breaks in either solver; the
//! caller commits the history.

use pdbem_pd::forces::History;
use pdbem_pd::solvers::implicit::{ImplicitParams, Newton};
use pdbem_pd::solvers::{adr, Convergence};
use pdbem_pd::{PdError, PdModel, SolveInfo};

/// Newton to equilibrium at the model's load (history frozen), ADR when Newton does not
/// converge, diverges or produces non-finite values. `start` is a finite state of the
/// model to restart ADR from when Newton left a non-finite one. Returns the iterations of
/// the solver that succeeded.
pub fn equilibrate(
    newton: &mut Newton,
    model: &mut PdModel,
    params: &ImplicitParams,
    start: &[[f64; 2]],
    info: &mut SolveInfo,
) -> Result<usize, PdError> {
    match newton.equilibrate(model, params, info) {
        Ok((iters, _)) => Ok(iters),
        Err(
            PdError::NoConvergence { .. } | PdError::Diverged { .. } | PdError::NonFinite { .. },
        ) => equilibrate_adr(model, start, ADR_FALLBACK_TOL, ADR_FALLBACK_MAX_ITERS, info),
        Err(e) => Err(e),
    }
}

/// Relative residual of the ADR fallback of [`equilibrate`]: far below the interface
/// tolerance psi (1e-4 by default) at which the windows' forces are used.
const ADR_FALLBACK_TOL: f64 = 1e-8;

/// ADR steps allowed to the fallback (about a second for a 20 x 20 window).
const ADR_FALLBACK_MAX_ITERS: usize = 200_000;

/// ADR equilibrium at the model's load with the bond history frozen (no bond breaks),
/// from the current state if it is finite, else from `start`, to the relative residual
/// `tol` within `max_iters` steps. Returns the steps taken.
pub fn equilibrate_adr(
    model: &mut PdModel,
    start: &[[f64; 2]],
    tol: f64,
    max_iters: usize,
    info: &mut SolveInfo,
) -> Result<usize, PdError> {
    let finite = model
        .displacements()
        .iter()
        .all(|u| u[0].is_finite() && u[1].is_finite());
    if !finite {
        model.set_displacements(start)?;
    }
    let mut adr = adr::Adr::new(model, 1.5);
    adr.history = History::Frozen;
    let (iters, _, _) = adr.converge(
        model,
        Convergence::Residual { tol },
        1,
        max_iters,
        &mut info.residual_history,
    )?;
    Ok(iters)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pdbem_pd::cases::bar_tension;

    fn loaded_bar() -> PdModel {
        let case = bar_tension(0.005);
        let mut m = PdModel::new(&case.problem).unwrap();
        m.set_load_factor(case.target_load);
        m
    }

    #[test]
    fn adr_takes_over_a_failed_newton_solve_and_finds_the_same_equilibrium() {
        let params = ImplicitParams::default();
        let mut by_newton = loaded_bar();
        let start = by_newton.displacements().to_vec();
        let mut newton = Newton::new(&by_newton).unwrap();
        let mut info = SolveInfo::default();
        let it = equilibrate(&mut newton, &mut by_newton, &params, &start, &mut info).unwrap();
        assert!(
            it > 0 && it < 10,
            "Newton converges by itself ({it} iterations)"
        );
        // No Newton iteration allowed: Newton reports no convergence and ADR takes over.
        let mut by_adr = loaded_bar();
        let starved = ImplicitParams {
            max_iters: 0,
            ..params
        };
        let mut newton = Newton::new(&by_adr).unwrap();
        let it = equilibrate(&mut newton, &mut by_adr, &starved, &start, &mut info).unwrap();
        assert!(it > 100, "ADR steps: {it}");
        let (a, b) = (by_newton.displacements(), by_adr.displacements());
        let scale = a.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
        assert!(scale > 0.0);
        let diff = a
            .iter()
            .zip(b)
            .map(|(x, y)| (x[0] - y[0]).hypot(x[1] - y[1]))
            .fold(0.0, f64::max);
        assert!(
            diff < 1e-6 * scale,
            "ADR vs Newton: {diff:.3e} of {scale:.3e}"
        );
    }

    #[test]
    fn a_non_finite_newton_state_restarts_adr_from_the_given_start() {
        let mut m = loaded_bar();
        let start = m.displacements().to_vec();
        let mut bad = start.clone();
        bad[3] = [f64::NAN, 0.0];
        m.set_displacements(&bad).unwrap();
        let mut newton = Newton::new(&m).unwrap();
        let mut info = SolveInfo::default();
        equilibrate(
            &mut newton,
            &mut m,
            &ImplicitParams::default(),
            &start,
            &mut info,
        )
        .unwrap();
        assert!(m
            .displacements()
            .iter()
            .all(|u| u[0].is_finite() && u[1].is_finite()));
    }
}
