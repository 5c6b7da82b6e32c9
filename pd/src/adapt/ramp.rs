//! The adaptive load ramp (module docs of [`super`]): solve a load step with the
//! scene's solver ([`crate::solvers::limit_solvers`], halving a failed step), check
//! seed 004's criteria, and while cells split solve the same load again on the refined
//! grid. The ramp ends at the last load or at the body's limit, as a ramp without
//! refinement does ([`crate::solvers::limit`]).

use std::collections::BTreeMap;
use std::time::Instant;

use super::transfer::refined_model;
use super::{breaking_cells, flagged_cells, static_cells, AdaptiveCells, CellCriteria};
use crate::error::PdError;
use crate::model::PdModel;
use crate::problem::PdProblem;
use crate::solvers::adr::AdrParams;
use crate::solvers::implicit::ImplicitParams;
use crate::solvers::limit::{LimitedSolve, RampEvent, Stop};
use crate::solvers::limit_solvers::{solve_to_limit, QuasiStatic};
use crate::solvers::switching::SwitchingParams;

/// One refinement: at which load factor, how many cells split, the real nodes after.
#[derive(Clone, Debug, PartialEq)]
pub struct Round {
    /// Load factor of the equilibrium the criteria fired at (0 for the set-up).
    pub load: f64,
    /// Cells split (or split deeper) in this round.
    pub cells: usize,
    /// Real nodes of the refined grid.
    pub nodes: usize,
}

/// What the adaptive ramp reports as it goes.
#[derive(Clone, Copy, Debug)]
pub enum AdaptEvent<'a> {
    /// An event of a load step's solve.
    Ramp(&'a RampEvent),
    /// Cells split; the step is solved again on the refined grid.
    Refined(&'a Round),
}

/// The result of [`ramp_to_limit`].
#[derive(Debug)]
pub struct AdaptiveRamp {
    /// The last converged model (on its refined grid).
    pub model: PdModel,
    /// The problem of that grid (the base problem with one zone per split cell).
    pub problem: PdProblem,
    /// The split cells.
    pub cells: AdaptiveCells,
    /// Steps (one record per load, the last solve of each), iterations and where the
    /// ramp stopped, if it did.
    pub solve: LimitedSolve,
    /// The refinements, in order.
    pub rounds: Vec<Round>,
    /// The ramp stopped because the refined grid found no equilibrium at a load its
    /// coarser grid carried (`solve.stop` says where; the model is the coarser one).
    pub refined_without_equilibrium: bool,
}

/// The solver of one load step to `target` (`checks` steps in the whole ramp).
fn one_step(solver: &QuasiStatic, target: f64, checks: usize) -> QuasiStatic {
    match solver {
        QuasiStatic::Implicit(p) => QuasiStatic::Implicit(ImplicitParams {
            target_load: target,
            steps: 1,
            ..p.clone()
        }),
        QuasiStatic::Adr(p) => QuasiStatic::Adr(AdrParams {
            target_load: target,
            steps: 1,
            ..p.clone()
        }),
        QuasiStatic::Switching(p) => QuasiStatic::Switching(SwitchingParams {
            target_load: target,
            implicit_steps: 1,
            explicit_steps: p.increments().div_ceil(checks.max(1)).max(1),
            ..p.clone()
        }),
    }
}

/// The solver of a load solved again on a refined grid: Newton and ADR as they are;
/// the switching solver by its damage phase's ADR (its load does not change).
fn same_load(solver: &QuasiStatic, target: f64) -> QuasiStatic {
    match solver {
        QuasiStatic::Switching(p) => QuasiStatic::Adr(AdrParams {
            target_load: target,
            steps: 1,
            convergence: p.convergence,
            max_iters: p.max_adr_iters,
            safety: p.safety,
            growth_tol: p.growth_tol,
            max_break_rounds: p.max_break_rounds,
            ..Default::default()
        }),
        other => one_step(other, target, 1),
    }
}

/// The load factors the criteria are checked at: the solver's own equal steps from
/// `lam0` to its target (Newton, ADR), or `checks` equal steps (the switching solver,
/// whose increments are its own).
fn checkpoints(solver: &QuasiStatic, lam0: f64, checks: usize) -> Vec<f64> {
    let (target, steps) = match solver {
        QuasiStatic::Implicit(p) => (p.target_load, p.steps),
        QuasiStatic::Adr(p) => (p.target_load, p.steps),
        QuasiStatic::Switching(p) => (p.target_load, checks),
    };
    let steps = steps.max(1);
    (1..=steps)
        .map(|k| lam0 + (target - lam0) * k as f64 / steps as f64)
        .collect()
}

/// The state of a ramp between load steps.
pub(super) struct Ramp<'a> {
    pub(super) cells: AdaptiveCells,
    pub(super) problem: PdProblem,
    pub(super) model: PdModel,
    pub(super) rounds: Vec<Round>,
    crit: &'a CellCriteria,
    /// The model and problem before the last split (taken only when cells split).
    kept: Option<(PdModel, PdProblem)>,
}

/// Bytes a directed bond of a model holds (geometry, coefficients, flags, history and
/// the tangent's share), for the size estimate of a split.
const BOND_BYTES: f64 = 96.0;

/// Refuses a split of `model`'s grid (split `cells` now) whose bonds would exceed the
/// memory budget ([`crate::tangent::factor_budget`]) before it is built: each cell raised
/// from level `l` to `L` adds `4^L - 4^l` nodes, each with the bonds of an average node
/// now.
fn check_size(
    cells: &AdaptiveCells,
    model: &PdModel,
    want: &BTreeMap<super::Cell, u32>,
) -> Result<(), PdError> {
    let now = cells.levels();
    let added: f64 = want
        .iter()
        .map(|(c, &l)| {
            let from = now.get(c).copied().unwrap_or(0);
            4f64.powi(l as i32) - 4f64.powi(from as i32)
        })
        .sum();
    let per_node = model.n_bonds() as f64 / model.n_nodes().max(1) as f64;
    let bytes = (model.n_nodes() as f64 + added) * per_node * BOND_BYTES;
    crate::tangent::check_budget(
        "the adaptively refined grid's bonds",
        bytes,
        crate::tangent::factor_budget(),
    )
}

/// What a split looks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Trigger {
    /// Eqs. 15-16 and the static criteria (the set-up).
    Setup,
    /// Eqs. 15-16 after a load's equilibrium and its bond breaking.
    Criteria,
    /// Before the bonds break: the cells that hold an end of a bond past its breaking
    /// stretch below the deepest level ([`breaking_cells`]).
    Breaking,
}

/// Splits the cells of `model`'s grid (over `problem`, split `cells`) that `trigger`
/// finds at `load`: the refined model, its problem and the round, with `cells` raised;
/// `None` when nothing fires.
pub(super) fn split_cells(
    model: &PdModel,
    problem: &PdProblem,
    cells: &mut AdaptiveCells,
    crit: &CellCriteria,
    load: f64,
    trigger: Trigger,
) -> Result<Option<(PdModel, PdProblem, Round)>, PdError> {
    let mut want = match trigger {
        Trigger::Breaking => breaking_cells(model, problem, crit),
        Trigger::Setup | Trigger::Criteria => flagged_cells(model, problem, crit),
    };
    if trigger == Trigger::Setup {
        for (c, l) in static_cells(model, problem, crit) {
            let e = want.entry(c).or_insert(0);
            *e = (*e).max(l);
        }
    }
    if want.is_empty() {
        return Ok(None);
    }
    check_size(cells, model, &want)?;
    let raised = cells.raise(&want);
    let problem = cells.problem();
    let model = refined_model(model, &problem)?;
    let round = Round {
        load,
        cells: raised,
        nodes: model.n_real(),
    };
    Ok(Some((model, problem, round)))
}

impl Ramp<'_> {
    /// Splits the cells `trigger` finds; the number of cells split.
    fn refine(&mut self, load: f64, trigger: Trigger) -> Result<usize, PdError> {
        let split = split_cells(
            &self.model,
            &self.problem,
            &mut self.cells,
            self.crit,
            load,
            trigger,
        )?;
        let Some((model, problem, round)) = split else {
            return Ok(0);
        };
        let raised = round.cells;
        self.kept = Some((
            std::mem::replace(&mut self.model, model),
            std::mem::replace(&mut self.problem, problem),
        ));
        self.rounds.push(round);
        Ok(raised)
    }
}

/// The set-up of a ramp: `base`'s model with the cells the static criteria and the
/// pre-cracks' damage split (Eq. 15 at load 0), until nothing fires.
pub(super) fn set_up_ramp<'a>(
    base: &PdProblem,
    crit: &'a CellCriteria,
    observe: &mut dyn FnMut(AdaptEvent),
) -> Result<Ramp<'a>, PdError> {
    crit.validate()?;
    let mut ramp = Ramp {
        cells: AdaptiveCells::new(base),
        problem: base.clone(),
        model: PdModel::new(base)?,
        rounds: Vec::new(),
        crit,
        kept: None,
    };
    while ramp.refine(0.0, Trigger::Setup)? > 0 {
        observe(AdaptEvent::Refined(ramp.rounds.last().expect("a round")));
    }
    Ok(ramp)
}

/// The model a ramp on `base` starts from after its set-up splits (so a check can size
/// it as the run will build it), and the cells split.
pub fn set_up(base: &PdProblem, crit: &CellCriteria) -> Result<(PdModel, AdaptiveCells), PdError> {
    let ramp = set_up_ramp(base, crit, &mut |_| {})?;
    Ok((ramp.model, ramp.cells))
}

/// Drives `base`'s model along `solver`'s ramp with refinement by `crit` (module docs of
/// [`super`]); `checks` load steps for the switching solver. A failed step is halved up
/// to `max_cutbacks` times before the ramp stops at the body's limit.
pub fn ramp_to_limit(
    base: &PdProblem,
    solver: &QuasiStatic,
    checks: usize,
    crit: &CellCriteria,
    max_cutbacks: u32,
    observe: &mut dyn FnMut(AdaptEvent),
) -> Result<AdaptiveRamp, PdError> {
    let t0 = Instant::now();
    let mut ramp = set_up_ramp(base, crit, observe)?;
    let mut total = LimitedSolve::default();
    let mut refused = false;
    let loads = checkpoints(solver, ramp.model.load_factor(), checks);
    'steps: for &target in &loads {
        let out = solve_to_limit(
            &mut ramp.model,
            &one_step(solver, target, loads.len()),
            max_cutbacks,
            &mut |e: &RampEvent| observe(AdaptEvent::Ramp(e)),
        )?;
        absorb(&mut total, out);
        if total.stop.is_some() {
            break;
        }
        loop {
            let cells_before = ramp.cells.clone();
            if ramp.refine(target, Trigger::Criteria)? == 0 {
                break;
            }
            observe(AdaptEvent::Refined(ramp.rounds.last().expect("a round")));
            let again =
                solve_to_limit(&mut ramp.model, &same_load(solver, target), 0, &mut |_| {})?;
            if let Some(stop) = again.stop {
                (ramp.model, ramp.problem) = ramp.kept.take().expect("kept by the split");
                ramp.cells = cells_before;
                total.info.iterations += again.info.iterations;
                total.stop = Some(Stop {
                    last_load: target,
                    failed_load: target,
                    cutbacks: 0,
                    error: stop.error,
                });
                refused = true;
                break 'steps;
            }
            // One record per load: the refined grid's solve replaces the coarser one's.
            total.info.steps.pop();
            absorb(&mut total, again);
        }
    }
    total.info.final_load = ramp.model.load_factor();
    total.info.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(AdaptiveRamp {
        model: ramp.model,
        problem: ramp.problem,
        cells: ramp.cells,
        solve: total,
        rounds: ramp.rounds,
        refined_without_equilibrium: refused,
    })
}

/// Joins a load step's solve into the ramp's.
fn absorb(total: &mut LimitedSolve, out: LimitedSolve) {
    total.info.absorb(out.info);
    total.retries += out.retries;
    if out.stop.is_some() {
        total.stop = out.stop;
    }
}
