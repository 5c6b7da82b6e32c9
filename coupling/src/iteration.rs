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
//!
//! Load steps on one geometry (Algorithm 2, seed 002 section 2.3.2): [`PreparedBem`] keeps
//! the assembled and factored BEM system, and [`solve_prepared`] runs Algorithm 1 on it at
//! a load scale $s$. The problem is linear in the scene loads and the interface
//! tractions, so the BEM solve at scale $s$ is $s$ times the solve of the factored
//! reference system with the tractions divided by $s$; the PD windows run at load factor
//! $s$ (their outer scene conditions scale with it). With bonds breaking, an iteration is
//! converged only when $e_k < \psi$ and no bond broke in its PD solves; a break restarts
//! the divergence counters and the relaxation weight (the accelerator keeps its secant
//! data: a break changes the map only near a tip), and `max_iter` counts the iterations
//! since the last break (at most
//! [`BREAK_ITERATION_FACTOR`] `max_iter` in all). A monitor called after every iteration
//! may stop the iteration early (Algorithm 2 step 6: the crack reached the window margin).

use std::ops::ControlFlow;
use std::time::Instant;

use pdbem_bem::post::Background;
use pdbem_bem::{Bc, BemSystem, Material, Mesh, PairCache, Solution, SolveParams};
use pdbem_pd::solvers::{adr, frozen, implicit, switching, Convergence};
use rayon::prelude::*;
use serde::Serialize;

use crate::error::CouplingError;
use crate::floating::FloatingPieces;
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
    /// Crack growth: Newton equilibrium with the bond state frozen, then at most `rounds`
    /// break rounds (break every bond past its critical stretch, re-equilibrate). With
    /// `rounds = 0` bonds break only at converged interface states: once the residual is
    /// below psi, [`solve_prepared`] commits every window's bond history and iterates on
    /// while bonds break. Either way the coupling iterations carry the growth, so a crack
    /// advances by about one break front at a time and the tip can be checked in between
    /// (Algorithm 2).
    Staggered(StaggeredParams),
}

/// Parameters of [`PdSolve::Staggered`].
#[derive(Debug, Clone, PartialEq)]
pub struct StaggeredParams {
    /// Newton settings of each equilibrium (`target_load` is the load factor).
    pub newton: implicit::ImplicitParams,
    /// Break rounds per PD solve; 0: break only at converged interface states.
    pub rounds: usize,
    /// At converged interface states, break only the bonds within this relative band of
    /// the largest stretch ([`pdbem_pd::breaking`]); 1 breaks every bond past its critical
    /// stretch.
    pub break_fraction: f64,
    /// Break-and-re-equilibrate rounds of the PD model (interface held) per converged
    /// interface state (>= 1).
    pub break_rounds: usize,
    // Measured on cases/growth_tension_edge.ron (mode I, K up to 30 K_c at the end):
    // break_fraction 0.05 puts the crack one lattice column off its line after 0.3 m
    // (path 1 dx off), 0.1 keeps it on the line within 0.05 m over 7 m, 0.2 and 0.3
    // let it wander by 0.25 m once K exceeds 10 K_c.
}

impl Default for StaggeredParams {
    /// Bonds break at converged interface states only, those within 10 % of the largest
    /// stretch at a time, in up to 10 rounds with the interface held (a crack advances
    /// by a few bonds per interface re-convergence); Newton to a relative residual of
    /// 1e-9.
    fn default() -> Self {
        StaggeredParams {
            newton: implicit::ImplicitParams {
                convergence: Convergence::Residual { tol: 1e-9 },
                residual_tol: 1e-9,
                ..Default::default()
            },
            rounds: 0,
            break_fraction: 0.1,
            break_rounds: 10,
        }
    }
}

/// [`PdSolve::Staggered`] on one model with its kept solvers; returns the solver
/// iterations.
///
/// Each equilibrium is the chord iteration's, with ADR and then Newton where it fails
/// ([`frozen::FrozenSolver`] with the windows' [`frozen::Fallbacks`]).
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
    /// Bond pairs broken in the PD solves of every iteration (all windows).
    pub bonds_broken: Vec<usize>,
    /// The monitor of [`solve_prepared`] stopped the iteration before convergence.
    pub interrupted: bool,
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

/// One map evaluation: BEM solution, mapped displacements, tractions per window, bond
/// pairs broken.
type Evaluation = (Solution, Vec<f64>, Vec<Vec<[f64; 2]>>, usize);

/// One window's PD result: solver iterations, bond pairs broken, tractions, mapping time.
type WindowResult = Result<(usize, usize, Vec<[f64; 2]>, f64), CouplingError>;

/// Total iteration cap of [`solve_prepared`] as a multiple of `max_iter` when bonds keep
/// breaking (each break restarts the `max_iter` count).
pub const BREAK_ITERATION_FACTOR: usize = 10;

/// Runs Algorithm 1 on `problem` (assembles and factors the BEM system, then
/// [`solve_prepared`] at load scale 1 from zero interface displacements).
pub fn solve(
    problem: &mut CoupledProblem,
    params: &CouplingParams,
) -> Result<(CoupledSolution, CouplingInfo), CouplingError> {
    let t0 = Instant::now();
    let bem = PreparedBem::new(problem)?;
    let (sol, mut info) = solve_prepared(problem, &bem, params, StepOptions::default())?;
    info.timings.bem_assembly_s = bem.assembly_s();
    info.timings.bem_factor_s = bem.factor_s();
    info.timings.total_s = t0.elapsed().as_secs_f64();
    Ok((sol, info))
}

/// The BEM system of one coupled geometry, assembled and factored once with the scene
/// conditions of [`CoupledProblem::bcs`] (the reference load) and the interface groups
/// variable; reused for every iteration and every load step on that geometry.
pub struct PreparedBem {
    system: BemSystem,
    /// Pieces of a body cut apart that only the windows hold ([`crate::floating`]).
    floating: FloatingPieces,
}

impl PreparedBem {
    /// Marks the interface groups variable (traction) in `problem`, then assembles and
    /// factors. Changing the mesh or the scene conditions needs a new `PreparedBem`.
    pub fn new(problem: &mut CoupledProblem) -> Result<Self, CouplingError> {
        Self::with_cache(problem, None)
    }

    /// The same, reusing the element-pair blocks `pairs` holds from an earlier geometry
    /// and leaving this one's there ([`PairCache`]).
    pub fn with_cache(
        problem: &mut CoupledProblem,
        pairs: Option<&mut PairCache>,
    ) -> Result<Self, CouplingError> {
        let system = factor_bem(problem, pairs)?;
        let floating = FloatingPieces::new(&problem.mesh, &system)?;
        Ok(PreparedBem { system, floating })
    }

    /// Assembly wall time (s).
    pub fn assembly_s(&self) -> f64 {
        self.system.info().assembly_s
    }

    /// Element pairs of the assembly copied from a [`PairCache`] (0 without one).
    pub fn reused_pairs(&self) -> usize {
        self.system.info().reused_pairs
    }

    /// Factorization and response precomputation wall time (s).
    pub fn factor_s(&self) -> f64 {
        self.system.info().factor_s + self.system.info().response_s
    }

    /// Pieces of the BEM body held only by the windows (cut off by cracks).
    pub fn floating_pieces(&self) -> usize {
        self.floating.len()
    }

    /// Number of BEM unknowns.
    pub fn unknowns(&self) -> usize {
        self.system.info().unknowns
    }

    /// Solves at load scale `scale` with interface conditions `bcs` (physical tractions
    /// at that scale): `scale` times the reference solve with the tractions over `scale`.
    fn solve_scaled(
        &self,
        bcs: &[[Bc; 2]],
        interface: &[usize],
        scale: f64,
    ) -> Result<Solution, CouplingError> {
        if scale == 1.0 {
            return Ok(self.system.solve_with(bcs)?);
        }
        let mut reference = bcs.to_vec();
        for &e in interface {
            for c in 0..2 {
                reference[e][c] = Bc::Traction(bcs[e][c].value() / scale);
            }
        }
        let mut sol = self.system.solve_with(&reference)?;
        for v in sol
            .u
            .iter_mut()
            .chain(sol.t.iter_mut())
            .chain(sol.du.iter_mut())
        {
            v[0] *= scale;
            v[1] *= scale;
        }
        for l in &mut sol.lambda {
            *l *= scale;
        }
        Ok(sol)
    }
}

/// What the monitor of [`solve_prepared`] sees after every iteration.
pub struct IterationReport<'a> {
    /// Iterations done (1-based).
    pub iteration: usize,
    /// Relative interface residual e_k of this iteration.
    pub residual: f64,
    /// Bond pairs broken in this iteration's PD solves.
    pub bonds_broken: usize,
    /// The windows after their PD solves.
    pub windows: &'a [WindowModel],
}

/// Monitor of [`solve_prepared`]: `Break` stops the iteration (the result then has
/// `interrupted = true` and `converged = false`).
pub type Monitor<'a> = &'a mut dyn FnMut(&IterationReport<'_>) -> ControlFlow<()>;

/// Options of one run of Algorithm 1 on a prepared system.
pub struct StepOptions<'a> {
    /// Load scale s (> 0): the scene conditions are s times those the system was factored
    /// with, and the PD windows run at load factor s. Default 1.
    pub load_scale: f64,
    /// Initial interface displacements (length: interface unknowns). Default zero.
    pub start: Option<Vec<f64>>,
    /// Called after every iteration. Default none.
    pub monitor: Option<Monitor<'a>>,
}

impl Default for StepOptions<'_> {
    fn default() -> Self {
        StepOptions {
            load_scale: 1.0,
            start: None,
            monitor: None,
        }
    }
}

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
    let n: usize = problem.windows.iter().map(|w| w.interface.len()).sum();
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
    let pd_solve = pd_solve_at(&params.pd_solve, scale);
    let commit_at_convergence = match &pd_solve {
        PdSolve::Staggered(p) if p.rounds == 0 => Some(p.clone()),
        _ => None,
    };
    let mut weight_scale = 1.0;
    let mut relax = params.acceleration.build(weight_scale);
    let mut best = (f64::INFINITY, x.clone());
    let mut since_best = 0;
    let mut growing = 0;
    let mut since_break = 0;
    let mut backoffs_since_break = 0;
    let mut pd_failure: Option<String> = None;
    loop {
        let evaluated = evaluate(problem, bem, &x, params, &pd_solve, scale, &mut info);
        info.iterations += 1;
        since_break += 1;
        let (e, xt, state, broke) = match evaluated {
            Ok((sol, xt, tractions, broke)) => (
                relative_residual(&x, &xt),
                xt,
                Some((sol, tractions)),
                broke,
            ),
            Err(CouplingError::Pd { window, source }) => {
                // A failed PD solve counts as divergence: restart its state from rest.
                reset_window(&mut problem.windows[window]);
                pd_failure = Some(format!("PD window {window} failed: {source}"));
                (f64::NAN, x.clone(), None, 0)
            }
            Err(other) => return Err(other),
        };
        let mut broke = broke;
        if let Some(sp) = &commit_at_convergence {
            if state.is_some() && e.is_finite() && e < params.psi && broke == 0 {
                broke = commit_windows(&mut problem.windows, sp)?;
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
            info.timings.total_s = t0.elapsed().as_secs_f64();
            let out = CoupledSolution {
                solution: sol,
                x_pd: x,
                x_bem: xt,
                tractions,
            };
            return Ok((out, info));
        }
        if broke > 0 {
            // The map changed a little (a few bonds near a tip): the accelerator keeps its
            // secant data, the divergence history restarts, back-offs are forgiven.
            since_break = 0;
            weight_scale = 1.0;
            relax = params.acceleration.build(weight_scale);
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
                last: e,
                psi: params.psi,
                residuals: info.residuals,
            });
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
    }
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

/// The PD solver with its target load set to the load scale.
fn pd_solve_at(solve: &PdSolve, scale: f64) -> PdSolve {
    let mut s = solve.clone();
    match &mut s {
        PdSolve::Switching(p) => p.target_load = scale,
        PdSolve::Implicit(p) => p.target_load = scale,
        PdSolve::Adr(p) => p.target_load = scale,
        PdSolve::Staggered(p) => p.newton.target_load = scale,
    }
    s
}

/// Assembles and factors the BEM system with the interface groups variable.
fn factor_bem(
    problem: &mut CoupledProblem,
    pairs: Option<&mut PairCache>,
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
    Ok(BemSystem::new_with_cache(
        &problem.mesh,
        &problem.material,
        &problem.bcs,
        &problem.bem_params,
        pairs,
    )?)
}

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
    let pd_solve = pd_solve_at(&params.pd_solve, 1.0);
    Ok(evaluate(problem, bem, x, params, &pd_solve, 1.0, &mut info)?.1)
}

/// One evaluation of the fixed-point map: PD (parallel) -> tractions -> BEM -> x~, at load
/// scale `scale`; also returns the bond pairs broken in the PD solves.
fn evaluate(
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
    let info = match solver {
        PdSolve::Switching(p) => switching::solve(&mut w.model, p)?,
        PdSolve::Implicit(p) => implicit::solve(&mut w.model, p)?,
        PdSolve::Adr(p) => adr::solve(&mut w.model, p)?,
        PdSolve::Staggered(p) => return staggered(&mut w.model, &mut w.solver, p),
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
