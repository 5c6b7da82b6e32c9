//! Algorithm 1 of seed 002 (section 2.3.1, Fig. 7): the partitioned PD-BEM iteration.
//!
//! The unknown is the vector x of the coupled virtual-node displacements of every window.
//! One evaluation of the fixed-point map $\tilde x = H(x)$:
//! 1. each window's PD model takes x on its virtual layers and is solved, warm-started
//!    from its last state (windows in parallel, rayon);
//! 2. the forces virtual nodes exert on real nodes become BEM interface tractions
//!    (seed 002 Eq. 24, [`crate::maps::pd_to_tractions`]);
//! 3. BEM solves by one substitution with the factorization kept from the start;
//! 4. the BEM displacement is mapped back to the virtual nodes (Eq. 23 or better,
//!    [`crate::maps::bem_to_virtual`]).
//!
//! Convergence: $e_k = \|\tilde x_k - x_k\|_2 / \|\tilde x_k\|_2 < \psi$ (seed 002
//! Algorithm 1 step 5). Otherwise the [`Relaxation`] proposes $x_{k+1}$ (constant w,
//! Aitken Eqs. 25-28, IQN-ILS). Divergence (NaN, residual growing for `growth_window`
//! consecutive iterations, or no 1 % improvement of the best residual in
//! `stagnation_window` iterations) restarts from the best iterate with half the
//! relaxation weight; after `max_backoffs` restarts [`CouplingError::Diverged`] carries
//! the residual history.

use std::time::Instant;

use pdbem_bem::post::Background;
use pdbem_bem::{Bc, BemSystem, Material, Mesh, Solution, SolveParams};
use pdbem_pd::solvers::{adr, implicit, switching, Convergence};
use rayon::prelude::*;
use serde::Serialize;

use crate::error::CouplingError;
use crate::maps::{bem_to_virtual, pd_to_tractions, BemView, DisplacementMap, TractionMap};
use crate::relaxation::{Aitken, Constant, IqnIls, Relaxation};
use crate::setup::WindowModel;

/// Interface acceleration scheme.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Acceleration {
    /// Constant relaxation w in (0, 1] (seed 002 Eq. 25).
    Constant(f64),
    /// Aitken's dynamic relaxation from w0 (seed 002 Eqs. 25-28).
    Aitken(f64),
    /// IQN-ILS with first weight w0.
    IqnIls(f64),
}

impl Acceleration {
    /// The scheme with its weights scaled by `scale` (back-off).
    fn build(&self, scale: f64) -> Box<dyn Relaxation> {
        match *self {
            Acceleration::Constant(w) => Box::new(Constant { w: w * scale }),
            Acceleration::Aitken(w) => {
                let mut a = Aitken::new(w * scale);
                a.w_max = scale.min(1.0);
                Box::new(a)
            }
            Acceleration::IqnIls(w) => Box::new(IqnIls::new(w * scale)),
        }
    }

    /// Short name.
    pub fn name(&self) -> &'static str {
        match self {
            Acceleration::Constant(_) => "constant",
            Acceleration::Aitken(_) => "aitken",
            Acceleration::IqnIls(_) => "iqn-ils",
        }
    }
}

/// PD solver of the windows.
#[derive(Debug, Clone, PartialEq)]
pub enum PdSolve {
    /// Explicit-implicit switching (implicit while undamaged), the engine's default.
    Switching(switching::SwitchingParams),
    /// Newton-Raphson.
    Implicit(implicit::ImplicitParams),
    /// Adaptive dynamic relaxation.
    Adr(adr::AdrParams),
}

impl Default for PdSolve {
    /// Switching with one implicit step from the warm start and a residual tolerance of
    /// 1e-9 (two Newton iterations at the small strains of the seed cases).
    fn default() -> Self {
        PdSolve::Switching(switching::SwitchingParams {
            target_load: 1.0,
            implicit_steps: 1,
            explicit_steps: 1,
            convergence: Convergence::Residual { tol: 1e-9 },
            ..Default::default()
        })
    }
}

/// Parameters of Algorithm 1.
#[derive(Debug, Clone, PartialEq)]
pub struct CouplingParams {
    /// Acceleration. Default Aitken from 0.3 (seed 002 section 3.1.3 uses w = 0.3).
    pub acceleration: Acceleration,
    /// Tolerance psi on the relative interface residual. Default 1e-4.
    pub psi: f64,
    /// Iteration cap. Default 50.
    pub max_iter: usize,
    /// BEM -> PD map. Default Taylor.
    pub displacement_map: DisplacementMap,
    /// PD -> BEM map. Default bond crossing.
    pub traction_map: TractionMap,
    /// Consecutive growing residuals that count as divergence. Default 4.
    pub growth_window: usize,
    /// Iterations without 1 % improvement that count as stagnation. Default 25.
    pub stagnation_window: usize,
    /// Restarts with halved weights before giving up. Default 3.
    pub max_backoffs: usize,
    /// PD solver.
    pub pd_solve: PdSolve,
}

impl Default for CouplingParams {
    fn default() -> Self {
        CouplingParams {
            acceleration: Acceleration::Aitken(0.3),
            psi: 1e-4,
            max_iter: 50,
            displacement_map: DisplacementMap::default(),
            traction_map: TractionMap::default(),
            growth_window: 4,
            stagnation_window: 25,
            max_backoffs: 3,
            pd_solve: PdSolve::default(),
        }
    }
}

/// Wall time per phase (s).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Timings {
    /// BEM assembly.
    pub bem_assembly_s: f64,
    /// BEM LU factorization.
    pub bem_factor_s: f64,
    /// BEM substitutions.
    pub bem_substitution_s: f64,
    /// PD solves (all windows, parallel).
    pub pd_s: f64,
    /// Interface maps (tractions and displacements).
    pub mapping_s: f64,
    /// Whole solve.
    pub total_s: f64,
}

/// What Algorithm 1 did.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct CouplingInfo {
    /// Acceleration scheme.
    pub scheme: String,
    /// Map evaluations (PD solve + BEM substitution each).
    pub iterations: usize,
    /// Whether e < psi was reached.
    pub converged: bool,
    /// e_k of every iteration.
    pub residuals: Vec<f64>,
    /// Relaxation weight used after every iteration (None: quasi-Newton step).
    pub weights: Vec<Option<f64>>,
    /// Restarts with halved weights.
    pub backoffs: usize,
    /// Interface unknowns (2 per coupled virtual node).
    pub interface_unknowns: usize,
    /// Newton / ADR iterations of PD over all windows and iterations.
    pub pd_iterations: usize,
    /// Timings.
    pub timings: Timings,
}

/// The coupled problem: BEM body (mesh, material, scene conditions) and the windows.
pub struct CoupledProblem {
    /// BEM mesh without the windows.
    pub mesh: Mesh,
    /// BEM material.
    pub material: Material,
    /// Scene conditions per element; interface elements get tractions each iteration.
    pub bcs: Vec<[Bc; 2]>,
    /// BEM solver parameters (`variable_groups` is filled in).
    pub bem_params: SolveParams,
    /// Remote field of infinite bodies.
    pub background: Background,
    /// Thickness (m) dividing PD forces into tractions.
    pub thickness: f64,
    /// Windows (their PD state is updated in place).
    pub windows: Vec<WindowModel>,
}

/// The converged interface state.
#[derive(Debug, Clone)]
pub struct CoupledSolution {
    /// BEM solution of the last iteration.
    pub solution: Solution,
    /// Virtual-node displacements given to PD in the last iteration.
    pub x_pd: Vec<f64>,
    /// The same nodes' displacements from the last BEM solution.
    pub x_bem: Vec<f64>,
    /// Interface tractions (Pa) of the last iteration, per window, per interface element.
    pub tractions: Vec<Vec<[f64; 2]>>,
}

/// One map evaluation: BEM solution, mapped displacements, tractions per window.
type Evaluation = (Solution, Vec<f64>, Vec<Vec<[f64; 2]>>);

/// One window's PD result: solver iterations, tractions, mapping time.
type WindowResult = Result<(usize, Vec<[f64; 2]>, f64), CouplingError>;

/// Runs Algorithm 1 on `problem`.
pub fn solve(
    problem: &mut CoupledProblem,
    params: &CouplingParams,
) -> Result<(CoupledSolution, CouplingInfo), CouplingError> {
    let t0 = Instant::now();
    let mut info = CouplingInfo {
        scheme: params.acceleration.name().into(),
        ..Default::default()
    };
    let sys = factor_bem(problem, &mut info)?;
    let n: usize = problem.windows.iter().map(|w| w.interface.len()).sum();
    info.interface_unknowns = n;
    let mut x = vec![0.0; n];
    let mut scale = 1.0;
    let mut relax = params.acceleration.build(scale);
    let mut best = (f64::INFINITY, x.clone());
    let mut since_best = 0;
    let mut growing = 0;
    let mut pd_failure: Option<String> = None;
    loop {
        let evaluated = evaluate(problem, &sys, &x, params, &mut info);
        info.iterations += 1;
        let (e, xt, state) = match evaluated {
            Ok((sol, xt, tractions)) => (relative_residual(&x, &xt), xt, Some((sol, tractions))),
            Err(CouplingError::Pd { window, source }) => {
                // A failed PD solve counts as divergence: restart its state from rest.
                reset_window(&mut problem.windows[window]);
                pd_failure = Some(format!("PD window {window} failed: {source}"));
                (f64::NAN, x.clone(), None)
            }
            Err(other) => return Err(other),
        };
        info.residuals.push(e);
        if let (true, Some((sol, tractions))) = (e.is_finite() && e < params.psi, state) {
            info.converged = true;
            info.timings.total_s = t0.elapsed().as_secs_f64();
            let out = CoupledSolution {
                solution: sol,
                x_pd: x,
                x_bem: xt,
                tractions,
            };
            return Ok((out, info));
        }
        if info.iterations >= params.max_iter {
            return Err(CouplingError::NoConvergence {
                iterations: info.iterations,
                last: e,
                psi: params.psi,
                residuals: info.residuals,
            });
        }
        growing = if info.residuals.len() > 1 && e > info.residuals[info.residuals.len() - 2] {
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
            if info.backoffs >= params.max_backoffs {
                return Err(CouplingError::Diverged {
                    reason,
                    iterations: info.iterations,
                    backoffs: info.backoffs,
                    residuals: info.residuals,
                });
            }
            info.backoffs += 1;
            scale *= 0.5;
            relax = params.acceleration.build(scale);
            x = best.1.clone();
            growing = 0;
            since_best = 0;
            info.weights.push(Some(0.0));
            continue;
        }
        x = relax.next(&x, &xt);
        info.weights.push(relax.last_weight());
    }
}

/// Assembles and factors the BEM system with the interface groups variable.
fn factor_bem(
    problem: &mut CoupledProblem,
    info: &mut CouplingInfo,
) -> Result<BemSystem, CouplingError> {
    for w in &problem.windows {
        if let Some(g) = problem.mesh.group(&w.group) {
            if !problem.bem_params.variable_groups.contains(&g) {
                problem.bem_params.variable_groups.push(g);
            }
            for e in &w.interface.elements {
                problem.bcs[*e] = [Bc::Traction(0.0), Bc::Traction(0.0)];
            }
        }
    }
    // Every iteration changes only the interface tractions: precompute the response of the
    // unknowns to them once (one blocked substitution with a few hundred columns), so each
    // iteration costs a product with it instead of a substitution through the whole factor.
    problem.bem_params.precompute_response = true;
    let sys = BemSystem::new(
        &problem.mesh,
        &problem.material,
        &problem.bcs,
        &problem.bem_params,
    )?;
    info.timings.bem_assembly_s = sys.info().assembly_s;
    info.timings.bem_factor_s = sys.info().factor_s + sys.info().response_s;
    Ok(sys)
}

/// One evaluation of the fixed-point map: PD (parallel) -> tractions -> BEM -> x~.
fn evaluate(
    problem: &mut CoupledProblem,
    sys: &BemSystem,
    x: &[f64],
    params: &CouplingParams,
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
            let iters =
                solve_window(w, xw, &params.pd_solve).map_err(|e| CouplingError::pd(i, e))?;
            let tm = Instant::now();
            let t = pd_to_tractions(params.traction_map, &w.model, &w.interface, mesh, thickness);
            Ok((iters, t, tm.elapsed().as_secs_f64()))
        })
        .collect();
    let mut tractions = Vec::with_capacity(results.len());
    let mut map_s = 0.0;
    for r in results {
        let (iters, t, dt) = r?;
        info.pd_iterations += iters;
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
    let sol = sys.solve_with(&bcs)?;
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
    let xt = bem_to_virtual(params.displacement_map, &view, &ifaces);
    info.timings.mapping_s += map_s + tm.elapsed().as_secs_f64();
    Ok((sol, xt, tractions))
}

/// Puts a window back at rest after a failed PD solve.
fn reset_window(w: &mut WindowModel) {
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

/// Imposes `xw` on the coupled virtual nodes of window `w` and solves its PD model.
/// Returns the solver's iteration count.
pub fn solve_window(
    w: &mut WindowModel,
    xw: &[f64],
    solver: &PdSolve,
) -> Result<usize, pdbem_pd::PdError> {
    let mut base = w.interface.base.clone();
    for (k, &v) in w.interface.coupled.iter().enumerate() {
        base[v] = [xw[2 * k], xw[2 * k + 1]];
    }
    w.model.set_prescribed_displacements(&base)?;
    if is_unloaded(&w.model, &base) {
        // The solution is zero; the solvers' relative measures are undefined there.
        let zero = vec![[0.0; 2]; w.model.n_nodes()];
        w.model.set_displacements(&zero)?;
        return Ok(0);
    }
    let info = match solver {
        PdSolve::Switching(p) => switching::solve(&mut w.model, p)?,
        PdSolve::Implicit(p) => implicit::solve(&mut w.model, p)?,
        PdSolve::Adr(p) => adr::solve(&mut w.model, p)?,
    };
    Ok(info.iterations)
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

/// $\|\tilde x - x\|_2 / \|\tilde x\|_2$ (the absolute change when x~ = 0).
pub fn relative_residual(x: &[f64], xt: &[f64]) -> f64 {
    let d: f64 = x.iter().zip(xt).map(|(a, b)| (a - b).powi(2)).sum();
    let s: f64 = xt.iter().map(|a| a * a).sum();
    if s > 0.0 {
        (d / s).sqrt()
    } else {
        d.sqrt()
    }
}
