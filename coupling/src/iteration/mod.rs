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
//! The ordering above is [`Ordering::DisplacementToPd`], the default. With
//! [`Ordering::TractionToPd`] the conditions swap (module `traction`): the unknown x is
//! the BEM traction of every interface element, PD takes it through seed 001's
//! transfer functions on free interface sides ([`crate::traction_window`]), and BEM
//! takes the PD displacement extrapolated to the interface plus the rigid motion that
//! balances each floating window; $\tilde x$ is the BEM's interface traction. The
//! accelerators and the divergence rules below act on that x unchanged.
//!
//! Convergence: $e_k = \|\tilde x_k - x_k\|_2 / \|\tilde x_k\|_2 < \psi$ (seed 002
//! Algorithm 1 step 5). Otherwise the [`Relaxation`](crate::relaxation::Relaxation) proposes $x_{k+1}$ (constant w,
//! Aitken Eqs. 25-28, IQN-ILS). Divergence (NaN, residual growing for `growth_window`
//! consecutive iterations, or no 1 % improvement of the best residual in
//! `stagnation_window` iterations) restarts from the best iterate with half the
//! relaxation weight; after `max_backoffs` restarts [`CouplingError::Diverged`] carries
//! the residual history. What the accelerator reports (an Aitken restart, its hand-over
//! to IQN-ILS, [`crate::relaxation::RelaxationEvent`]) goes into [`CouplingInfo::notes`]
//! with its iteration; the runner copies them into `summary.json`'s `notes`, the growth
//! driver to its observer's `note`.
//!
//! Load steps on one geometry (Algorithm 2, seed 002 section 2.3.2): [`PreparedBem`] keeps
//! the assembled and factored BEM system, and [`solve_prepared`] runs Algorithm 1 on it at
//! a load scale $s$. The problem is linear in the scene loads and the interface
//! tractions, so the BEM solve at scale $s$ is $s$ times the solve of the factored
//! reference system with the tractions divided by $s$; the PD windows run at load factor
//! $s$ (their outer scene conditions scale with it). With bonds breaking, an iteration is
//! converged only when $e_k < \psi$ and no bond broke in its PD solves; a break restarts
//! the divergence counters and the relaxation weight, and `max_iter` counts the
//! iterations since the last break (at most
//! [`BREAK_ITERATION_FACTOR`] `max_iter` in all). A monitor called after every iteration
//! may stop the iteration early (Algorithm 2 step 6: the crack reached the window margin).
//!
//! Warm starts. A break changes the map: the accelerator closes its model
//! ([`crate::relaxation::Relaxation::end_map`]) and, with
//! [`CouplingParams::reuse_secants`], IQN-ILS keeps the old model's differences as reused
//! columns ([`crate::relaxation::SecantColumns`], module docs of [`crate::relaxation`]).
//! Bonds broken at a converged interface state (staggered solve with `rounds = 0`) broke
//! after the evaluation: that pair goes to the old model and the same x is evaluated
//! again. [`StepOptions::secants`] seeds a solve with the columns an earlier one returned
//! in [`CoupledSolution::secants`]. Measured on `growth_tension_edge` (n = 20): 921
//! coupling iterations before, 617 with the pre-break pair kept out of the new model,
//! 485 with the reuse too, the paths identical (`tests/growth_warm_start.rs`).
//!
//! Files of the module:
//! - `mod.rs`: the problem and result types ([`CoupledProblem`], [`CoupledSolution`],
//!   [`CouplingInfo`], [`Timings`]), the step options and monitor ([`StepOptions`],
//!   [`IterationReport`]), [`solve`] and [`relative_residual`].
//! - `params`: [`CouplingParams`], [`Acceleration`], [`PdSolve`], [`StaggeredParams`].
//! - `prepared`: [`PreparedBem`], the factored BEM system of one geometry.
//! - `algorithm`: [`solve_prepared`], the iteration itself.
//! - `evaluate`: one evaluation of the map, [`interface_map`].
//! - `window_solve`: the PD solve of one window, [`solve_window`], [`solve_window_at`].
//! - `traction`: one evaluation of the traction ordering and the windows' rigid-motion
//!   balance.

mod algorithm;
mod evaluate;
mod params;
mod prepared;
mod rigid;
mod traction;
mod window_solve;

pub use algorithm::solve_prepared;
pub use evaluate::interface_map;
pub use params::{Acceleration, CouplingParams, Ordering, PdSolve, StaggeredParams};
pub use prepared::PreparedBem;
pub use window_solve::{solve_window, solve_window_at};

use std::ops::ControlFlow;
use std::time::Instant;

use pdbem_bem::post::Background;
use pdbem_bem::{Bc, Material, Mesh, Solution, SolveParams};
use serde::Serialize;

use crate::error::CouplingError;
use crate::relaxation::SecantColumns;
use crate::setup::WindowModel;

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
    /// What the accelerator reported (Aitken restarts, the hand-over to IQN-ILS), each
    /// with the iteration it happened after.
    pub notes: Vec<String>,
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
    /// The accelerator's secant columns at the end (empty unless
    /// [`CouplingParams::reuse_secants`] and IQN-ILS): the next solve's
    /// [`StepOptions::secants`].
    pub secants: SecantColumns,
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
    let bem = PreparedBem::with_ordering(problem, params.ordering, None)?;
    let (sol, mut info) = solve_prepared(problem, &bem, params, StepOptions::default())?;
    info.timings.bem_assembly_s = bem.assembly_s();
    info.timings.bem_factor_s = bem.factor_s();
    info.timings.total_s = t0.elapsed().as_secs_f64();
    Ok((sol, info))
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
    /// Secant columns of an earlier solve on the same interface unknowns (ignored unless
    /// [`CouplingParams::reuse_secants`], dropped when their length differs). Default none.
    pub secants: SecantColumns,
}

impl Default for StepOptions<'_> {
    fn default() -> Self {
        StepOptions {
            load_scale: 1.0,
            start: None,
            monitor: None,
            secants: SecantColumns::default(),
        }
    }
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
