//! One evaluation of the fixed-point map $\tilde x = H(x)$ (module docs of
//! [`crate::iteration`], steps 1-4), and [`interface_map`] for analysis.

use std::time::Instant;

use pdbem_bem::Bc;
use rayon::prelude::*;

use super::params::{CouplingParams, PdSolve};
use super::prepared::PreparedBem;
use super::window_solve::solve_window_at;
use super::{CoupledProblem, CouplingInfo, Evaluation, WindowResult};
use crate::error::CouplingError;
use crate::maps::{bem_to_virtual, pd_to_tractions, BemView};
use crate::setup::WindowModel;

/// One evaluation of the fixed-point map $\tilde x = H(x)$ at load scale 1, for analysis
/// (e.g. [`crate::spectrum`]): the windows are solved from `x` with `params.pd_solve`
/// and keep the resulting state.
pub fn interface_map(
    problem: &mut CoupledProblem,
    bem: &PreparedBem,
    x: &[f64],
    params: &CouplingParams,
) -> Result<Vec<f64>, CouplingError> {
    let n: usize = problem.windows.iter().map(|w| w.interface.len()).sum();
    if x.len() != n {
        return Err(CouplingError::InvalidStep {
            message: format!("{} values for {n} interface unknowns", x.len()),
        });
    }
    let mut info = CouplingInfo::default();
    let pd_solve = params.pd_solve.at(1.0);
    Ok(evaluate(problem, bem, x, params, &pd_solve, 1.0, &mut info)?.1)
}

/// One evaluation of the fixed-point map: PD (parallel) -> tractions -> BEM -> x~, at load
/// scale `scale`; also returns the bond pairs broken in the PD solves.
pub(super) fn evaluate(
    problem: &mut CoupledProblem,
    bem: &PreparedBem,
    x: &[f64],
    params: &CouplingParams,
    pd_solve: &PdSolve,
    scale: f64,
    info: &mut CouplingInfo,
) -> Result<Evaluation, CouplingError> {
    let tp = Instant::now();
    let chunks = split_by_window(&problem.windows, x);
    let thickness = problem.thickness;
    let mesh = &problem.mesh;
    let results: Vec<WindowResult> = problem
        .windows
        .par_iter_mut()
        .zip(chunks)
        .enumerate()
        .map(|(i, (w, xw))| {
            let broken0 = w.model.broken_bonds();
            let iters =
                solve_window_at(w, xw, pd_solve, scale).map_err(|e| CouplingError::pd(i, e))?;
            let broke = w.model.broken_bonds().saturating_sub(broken0);
            let tm = Instant::now();
            let t = pd_to_tractions(params.traction_map, &w.model, &w.interface, mesh, thickness);
            Ok((iters, broke, t, tm.elapsed().as_secs_f64()))
        })
        .collect();
    let mut tractions = Vec::with_capacity(results.len());
    let mut map_s = 0.0;
    let mut broke = 0;
    for r in results {
        let (iters, b, t, dt) = r?;
        info.pd_iterations += iters;
        broke += b;
        map_s += dt;
        tractions.push(t);
    }
    info.timings.pd_s += tp.elapsed().as_secs_f64() - map_s;
    let mut bcs = problem.bcs.clone();
    for (w, t) in problem.windows.iter().zip(&tractions) {
        for (e, te) in w.interface.elements.iter().zip(t) {
            bcs[*e] = [Bc::Traction(te[0]), Bc::Traction(te[1])];
        }
    }
    let ts = Instant::now();
    let interface: Vec<usize> = problem
        .windows
        .iter()
        .flat_map(|w| w.interface.elements.iter().copied())
        .collect();
    let mut sol = bem.solve_scaled(&bcs, &interface, scale)?;
    info.timings.bem_substitution_s += ts.elapsed().as_secs_f64();
    let tm = Instant::now();
    let ifaces: Vec<_> = problem
        .windows
        .iter()
        .map(|w| w.interface.clone())
        .collect();
    let view = BemView {
        mesh: &problem.mesh,
        material: &problem.material,
        solution: &sol,
        background: problem.background,
    };
    let mut xt = bem_to_virtual(params.displacement_map, &view, &ifaces);
    if !bem.floating.is_empty() {
        bem.floating.correct(
            &problem.mesh,
            &problem.material,
            params.displacement_map,
            &ifaces,
            x,
            &mut sol,
            &mut xt,
        )?;
    }
    info.timings.mapping_s += map_s + tm.elapsed().as_secs_f64();
    Ok((sol, xt, tractions, broke))
}

/// Puts a window back at rest after a failed PD solve.
pub(super) fn reset_window(w: &mut WindowModel) {
    let zero = vec![[0.0; 2]; w.model.n_nodes()];
    // Same length by construction, so this cannot fail.
    let _ = w.model.set_displacements(&zero);
}

/// Splits the flat interface vector into per-window slices.
fn split_by_window<'a>(windows: &[WindowModel], x: &'a [f64]) -> Vec<&'a [f64]> {
    let mut out = Vec::with_capacity(windows.len());
    let mut start = 0;
    for w in windows {
        let n = w.interface.len();
        out.push(&x[start..start + n]);
        start += n;
    }
    out
}
