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
//! rigid motions ([`RigidBalance`], 3 solves per floating window, once per geometry).
//! $q = -A^{+} G_0$ (pseudo-inverse, singular values below $10^{-6} E$ dropped): in a
//! body held elsewhere this balances every window exactly; where the BEM body has no
//! other support (a free plate), moving every window together only moves the body
//! ($A$ has those directions in its null space), its tractions are balanced by the
//! body's own equilibrium, and the windows' pins fix the gauge. A fixed point has
//! $t = \tilde t$: PD in equilibrium under $-t$ and BEM under the PD displacement, with
//! continuous displacement and traction across the interface (seed 002 section 2.3).

use nalgebra::{DMatrix, DVector};
use pdbem_bem::{Bc, BemSystem, Solution, V2};
use pdbem_pd::solvers::{adr, implicit, switching};
use rayon::prelude::*;

use super::params::PdSolve;
use super::prepared::PreparedBem;
use super::{CoupledProblem, CouplingInfo, Evaluation};
use crate::error::CouplingError;
use crate::traction_window::{is_floating, TractionWindow};

/// Singular values of the balance matrix below this times E are dropped.
const RANK_TOLERANCE: f64 = 1e-6;

/// The BEM side of the windows' rigid-motion balance (module docs).
pub struct RigidBalance {
    /// Floating windows (indices).
    floating: Vec<usize>,
    /// Per floating window: centre (m) and rotation length scale (m).
    frames: Vec<(V2, f64)>,
    /// Pseudo-inverse of the balance matrix A (3 per floating window, square).
    pinv: DMatrix<f64>,
}

impl RigidBalance {
    /// Unit rigid-motion responses of `system` (factored with displacement interfaces).
    pub(super) fn new(problem: &CoupledProblem, system: &BemSystem) -> Result<Self, CouplingError> {
        let floating: Vec<usize> = (0..problem.windows.len())
            .filter(|&i| is_floating(&problem.windows[i]))
            .collect();
        let frames: Vec<(V2, f64)> = floating
            .iter()
            .map(|&i| {
                let w = &problem.windows[i].window;
                let (lx, ly) = w.size();
                (w.spec.center, 0.5 * lx.hypot(ly))
            })
            .collect();
        let m = 3 * floating.len();
        let mut bcs = problem.bcs.clone();
        let base = system.solve_with(&bcs)?;
        let mut a = DMatrix::zeros(m, m);
        for (col, &wi) in floating.iter().enumerate() {
            for mode in 0..3 {
                let mut q = [0.0; 3];
                q[mode] = 1.0;
                set_rigid(problem, wi, frames[col], q, &mut bcs);
                let sol = system.solve_with(&bcs)?;
                let g = resultants(problem, &floating, &frames, &sol, Some(&base));
                for (row, v) in g.iter().enumerate() {
                    a[(row, 3 * col + mode)] = *v;
                }
                set_rigid(problem, wi, frames[col], [0.0; 3], &mut bcs);
            }
        }
        let cut = RANK_TOLERANCE * problem.material.e;
        let pinv = if m == 0 {
            DMatrix::zeros(0, 0)
        } else {
            a.svd(true, true)
                .pseudo_inverse(cut)
                .map_err(|e| CouplingError::InvalidStep {
                    message: format!("rigid balance of the windows: {e}"),
                })?
        };
        Ok(RigidBalance {
            floating,
            frames,
            pinv,
        })
    }
}

/// Rigid motion of unknowns q = (a_x, a_y, theta L) on window `wi`'s interface elements.
fn set_rigid(
    problem: &CoupledProblem,
    wi: usize,
    (c, l): (V2, f64),
    q: [f64; 3],
    bcs: &mut [[Bc; 2]],
) {
    for &e in &problem.windows[wi].interface.elements {
        let r = problem.mesh.elements[e].mid - c;
        let th = q[2] / l;
        bcs[e] = [
            Bc::Displacement(q[0] - th * r.y),
            Bc::Displacement(q[1] + th * r.x),
        ];
    }
}

/// Traction resultants of every floating window (3 each: F_x, F_y, M / L per unit
/// thickness) of `sol`, minus those of `base` when given.
fn resultants(
    problem: &CoupledProblem,
    floating: &[usize],
    frames: &[(V2, f64)],
    sol: &Solution,
    base: Option<&Solution>,
) -> Vec<f64> {
    let mut g = vec![0.0; 3 * floating.len()];
    for (k, &wi) in floating.iter().enumerate() {
        let (c, l) = frames[k];
        for &e in &problem.windows[wi].interface.elements {
            let el = &problem.mesh.elements[e];
            let mut t = sol.t[e];
            if let Some(b) = base {
                t = [t[0] - b.t[e][0], t[1] - b.t[e][1]];
            }
            let r = el.mid - c;
            g[3 * k] += t[0] * el.h;
            g[3 * k + 1] += t[1] * el.h;
            g[3 * k + 2] += (r.x * t[1] - r.y * t[0]) * el.h / l;
        }
    }
    g
}

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

/// Sets the floating windows' rigid motions that balance them against the BEM solution
/// `sol` (computed without motions) and adds them to their `given` displacements;
/// whether any motion is non-zero.
fn balance_windows(
    problem: &CoupledProblem,
    rb: &RigidBalance,
    tws: &mut [TractionWindow],
    sol: &Solution,
    scale: f64,
) -> bool {
    if rb.floating.is_empty() {
        return false;
    }
    let mut g = resultants(problem, &rb.floating, &rb.frames, sol, None);
    for (k, &wi) in rb.floating.iter().enumerate() {
        let tw = &tws[wi];
        let (f, m) = tw.outer_resultant(scale);
        let th = problem.thickness;
        g[3 * k] -= f[0] / th;
        g[3 * k + 1] -= f[1] / th;
        g[3 * k + 2] -= m / th / rb.frames[k].1;
    }
    let q = -(&rb.pinv * DVector::from_vec(g));
    if q.iter().all(|v| *v == 0.0) {
        return false;
    }
    for (k, &wi) in rb.floating.iter().enumerate() {
        let tw = &mut tws[wi];
        tw.motion = [q[3 * k], q[3 * k + 1], q[3 * k + 2] / rb.frames[k].1];
        let shifts: Vec<[f64; 2]> = tw
            .elements
            .iter()
            .map(|&e| tw.rigid_at(problem.mesh.elements[e].mid))
            .collect();
        for (u, r) in tw.given.iter_mut().zip(shifts) {
            u[0] += r[0];
            u[1] += r[1];
        }
    }
    true
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
