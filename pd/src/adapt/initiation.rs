//! The crack-initiation ramp of stand-alone PD on a grid whose cells split by seed 004's
//! criteria: [`crate::measure::ramp_to_initiation`] (at each load Newton on the
//! nonlinear stretch, every bond past its breaking stretch broken and the load solved
//! again until none breaks; the initiation load is the first at which the crack runs
//! `run_length` ahead of a pre-crack tip) with the refinement of [`super`] after every
//! equilibrium: while Eq. 15 ($\phi_k > \phi_c$) or Eq. 16 (the accumulated strains past
//! $\alpha s_c$) fires, the cells split and the same load is solved again on the refined
//! grid (the seed's per-step steps 3-5). The set-up splits the static criteria's cells and
//! those the pre-cracks damage past $\phi_c$, as [`super::ramp`] does. Children break at
//! the breaking stretch of their own horizon ($s_0\sqrt{\delta/\delta_k}$, G_c held,
//! [`crate::mixed`]).

use std::cell::RefCell;

use super::ramp::{set_up_ramp, split_cells, AdaptEvent, Round, Trigger};
use super::{AdaptiveCells, CellCriteria};
use crate::error::PdError;
use crate::measure::{ramp_to_initiation_with, Initiation, RampParams, SplitStage, Tip};
use crate::model::PdModel;
use crate::problem::PdProblem;
use crate::solvers::limit::RampEvent;

/// The result of [`ramp_to_initiation`].
#[derive(Debug)]
pub struct AdaptiveInitiation {
    /// The model at the end of the ramp (on its refined grid).
    pub model: PdModel,
    /// The problem of that grid (the base problem with one zone per split cell).
    pub problem: PdProblem,
    /// The split cells.
    pub cells: AdaptiveCells,
    /// Loads, extension and the solver record, as on a uniform grid.
    pub init: Initiation,
    /// The refinements, in order (the set-up's at load 0).
    pub rounds: Vec<Round>,
}

/// Ramps `base`'s load to crack initiation at `tips` (module docs) with its cells split
/// by `crit`; `observe` sees every refinement and the load of every settled step.
pub fn ramp_to_initiation(
    base: &PdProblem,
    crit: &CellCriteria,
    tips: &[Tip],
    params: &RampParams,
    observe: &mut dyn FnMut(AdaptEvent),
) -> Result<AdaptiveInitiation, PdError> {
    let start = set_up_ramp(base, crit, observe)?;
    let (mut model, mut problem, mut cells, mut rounds) =
        (start.model, start.problem, start.cells, start.rounds);
    // The ramp hears of steps, its hook of refinements: one observer, never called by
    // both at once.
    let observe = RefCell::new(observe);
    let mut steps = |e: &RampEvent| (observe.borrow_mut())(AdaptEvent::Ramp(e));
    let mut hook = |m: &mut PdModel, load: f64, stage: SplitStage| {
        let trigger = match stage {
            SplitStage::BeforeBreaking => Trigger::Breaking,
            SplitStage::AfterBreaking => Trigger::Criteria,
        };
        let Some((refined, p, round)) = split_cells(m, &problem, &mut cells, crit, load, trigger)?
        else {
            return Ok(false);
        };
        *m = refined;
        problem = p;
        (observe.borrow_mut())(AdaptEvent::Refined(&round));
        rounds.push(round);
        Ok(true)
    };
    let init = ramp_to_initiation_with(&mut model, tips, params, &mut hook, &mut steps)?;
    Ok(AdaptiveInitiation {
        model,
        problem,
        cells,
        init,
        rounds,
    })
}
