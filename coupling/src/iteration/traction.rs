//! One evaluation of the traction ordering ([`Ordering::TractionToPd`](super::Ordering)):
//! the unknown x is the BEM traction $t_e$ of every interface element.
//!
//! 1. Each window takes $p_e = -t_e$ through seed 001's transfer functions and is solved
//!    ([`crate::traction_window`], windows in parallel).
//! 2. The window's interface displacement $u_e$ (extrapolated to the outline) plus a
//!    rigid motion $R_w q_w$ per floating window is prescribed on the BEM interface
//!    elements; BEM solves by one substitution.
//! 3. $\tilde x$ = the BEM tractions of the interface elements.
//!
//! The rigid motions: a floating window is in equilibrium only under a self-balanced
//! load, $G_w = \sum_e t_e h_e - F^{outer}_w / \text{thickness} = 0$ and
//! $\sum_e (x_e - c_w) \times t_e h_e - M^{outer}_w / \text{thickness} = 0$ (the window's
//! outer conditions, if any, carry the rest). The BEM tractions are affine in the rigid
//! motions, $G(q) = G_0 + A q$, with $A$ the resultants of the BEM tractions of unit
//! rigid motions ([`super::rigid::RigidBalance`], 3 solves per floating window, once per geometry).
//! $q = -A^{+} G_0$ (pseudo-inverse, singular values below $10^{-6} E$ dropped): in a
//! body held elsewhere this balances every window exactly; where the BEM body has no
//! other support (a free plate), moving every window together only moves the body
//! ($A$ has those directions in its null space), its tractions are balanced by the
//! body's own equilibrium, and the windows' pins fix the gauge. A fixed point has
//! $t = \tilde t$: PD in equilibrium under $-t$ and BEM under the PD displacement, with
//! continuous displacement and traction across the interface (seed 002 section 2.3).

use pdbem_bem::{Bc, Solution, V2};
use pdbem_pd::solvers::{adr, implicit, switching};
use rayon::prelude::*;

use super::params::PdSolve;
use super::prepared::PreparedBem;
use super::rigid::balance_windows;
use super::{CoupledProblem, CouplingInfo, Evaluation};
use crate::error::CouplingError;
use crate::traction_window::TractionWindow;

/// The traction windows of `problem`, built once per solve.
pub(super) fn traction_windows(
    problem: &CoupledProblem,
) -> Result<Vec<TractionWindow>, CouplingError> {
    problem
        .windows
        .iter()
        .enumerate()
        .map(|(i, w)| TractionWindow::new(i, w, &problem.mesh, problem.thickness))
        .collect()
}

/// Solves one traction window at load factor `scale` under BEM tractions `t`; returns
/// the solver iterations.
fn solve_one(
    tw: &mut TractionWindow,
    t: &[f64],
    solver: &PdSolve,
    scale: f64,
) -> Result<usize, pdbem_pd::PdError> {
    if tw.model.load_factor() != scale {
        tw.model.set_load_factor(scale);
    }
    tw.load(t, scale)?;
    let bc = tw.model.boundary();
    let unloaded = bc.body.iter().all(|b| b[0] == 0.0 && b[1] == 0.0)
        && bc.base.iter().all(|b| b[0] == 0.0 && b[1] == 0.0);
    if unloaded {
        let zero = vec![[0.0; 2]; tw.model.n_nodes()];
        tw.model.set_displacements(&zero)?;
        return Ok(0);
    }
    let info = match solver {
        PdSolve::Switching(p) => switching::solve(&mut tw.model, p)?,
        PdSolve::Implicit(p) => implicit::solve(&mut tw.model, p)?,
        PdSolve::Adr(p) => adr::solve(&mut tw.model, p)?,
        PdSolve::Staggered(_) => {
            return Err(pdbem_pd::PdError::invalid(
                "coupling.ordering",
                "the traction ordering solves static windows only (no staggered bond breaking)"
                    .to_string(),
            ))
        }
    };
    Ok(info.iterations)
}

/// One evaluation of the traction ordering (module docs) at load scale `scale`.
pub(super) fn evaluate_traction(
    problem: &CoupledProblem,
    bem: &PreparedBem,
    tws: &mut [TractionWindow],
    x: &[f64],
    pd_solve: &PdSolve,
    scale: f64,
    info: &mut CouplingInfo,
) -> Result<Evaluation, CouplingError> {
    let tp = std::time::Instant::now();
    let mut chunks = Vec::with_capacity(tws.len());
    let mut start = 0;
    for tw in tws.iter() {
        chunks.push(&x[start..start + tw.len()]);
        start += tw.len();
    }
    let iters: Vec<Result<usize, CouplingError>> = tws
        .par_iter_mut()
        .zip(chunks)
        .enumerate()
        .map(|(i, (tw, t))| solve_one(tw, t, pd_solve, scale).map_err(|e| CouplingError::pd(i, e)))
        .collect();
    for r in iters {
        info.pd_iterations += r?;
    }
    info.timings.pd_s += tp.elapsed().as_secs_f64();
    let ts = std::time::Instant::now();
    let mut bcs = problem.bcs.clone();
    let interface: Vec<usize> = tws.iter().flat_map(|t| t.elements.clone()).collect();
    for tw in tws.iter_mut() {
        tw.motion = [0.0; 3];
        tw.given = tw.interface_displacements();
        put(&mut bcs, tw);
    }
    let mut sol = bem.solve_scaled(&bcs, &interface, scale)?;
    if let Some(rb) = &bem.rigid {
        if balance_windows(problem, rb, tws, &sol, scale) {
            for tw in tws.iter() {
                put(&mut bcs, tw);
            }
            sol = bem.solve_scaled(&bcs, &interface, scale)?;
        }
    }
    info.timings.bem_substitution_s += ts.elapsed().as_secs_f64();
    let tractions: Vec<Vec<[f64; 2]>> = tws
        .iter()
        .map(|tw| tw.elements.iter().map(|&e| sol.t[e]).collect())
        .collect();
    let xt: Vec<f64> = tractions.iter().flatten().flatten().copied().collect();
    Ok((sol, xt, tractions, 0))
}

/// Prescribes window `tw`'s last interface displacements on its BEM elements.
fn put(bcs: &mut [[Bc; 2]], tw: &TractionWindow) {
    for (&e, u) in tw.elements.iter().zip(&tw.given) {
        bcs[e] = [Bc::Displacement(u[0]), Bc::Displacement(u[1])];
    }
}

/// After convergence: the virtual-node displacements (x_pd: what the window gave the
/// BEM on its element; x_bem: the BEM displacement of that element, equal by
/// construction) and the window models' state (the traction window's real-node
/// displacements with its rigid motion, the coupled virtual nodes at x_bem).
pub(super) fn finish(
    problem: &mut CoupledProblem,
    tws: &[TractionWindow],
    sol: &Solution,
    scale: f64,
) -> Result<(Vec<f64>, Vec<f64>), CouplingError> {
    let (mut x_pd, mut x_bem) = (Vec::new(), Vec::new());
    for (i, (w, tw)) in problem.windows.iter_mut().zip(tws).enumerate() {
        let mut base = w.interface.base.clone();
        for (k, &s) in w.interface.coupled.iter().zip(&w.interface.node_element) {
            let e = w.interface.elements[s];
            x_pd.extend(tw.given[s]);
            x_bem.extend(sol.u[e]);
            base[*k] = [sol.u[e][0] / scale, sol.u[e][1] / scale];
        }
        if w.model.load_factor() != scale {
            w.model.set_load_factor(scale);
        }
        w.model
            .set_prescribed_displacements(&base)
            .map_err(|e| CouplingError::pd(i, e))?;
        let mut u = w.model.displacements().to_vec();
        let pos = tw.model.positions();
        for (k, ui) in tw.model.displacements()[..tw.model.n_real()]
            .iter()
            .enumerate()
        {
            let r = tw.rigid_at(V2::new(pos[k][0], pos[k][1]));
            u[k] = [ui[0] + r[0], ui[1] + r[1]];
        }
        w.model
            .set_displacements(&u)
            .map_err(|e| CouplingError::pd(i, e))?;
    }
    Ok((x_pd, x_bem))
}
