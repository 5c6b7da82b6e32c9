//! Checkpoints and the back-off of full-PD load steps.
//!
//! - [`checkpoint`] / [`restore`]: the run's state after a load step, or inside one after
//!   a break round at which the solvers were renewed ([`FullPdCheckpoint`]), and back.
//! - [`Saved`]: the state at the start of a step, which every retry starts from.
//! - [`ATTEMPTS`]: a step whose equilibrium fails before any bond broke is tried with the
//!   scene's budgets, then with [`EFFORT`] times the iteration budgets of the chord
//!   iteration, Newton and ADR, then with those and half the load increment (the step
//!   goes through the load half-way from the last step's first).

use pdbem_pd::{ModelState, PdModel};

use super::rounds::{pd_fail, Equilibrium};
use super::Tracker;
use crate::error::CouplingError;
use crate::growth::checkpoint::{mismatch, FullPdCheckpoint, WithinStep};
use crate::growth::front::Front;
use crate::growth::history::GrowthHistory;

/// Iteration budget factor of the retries.
pub(super) const EFFORT: usize = 5;

/// One way of trying a load step.
pub(super) struct Attempt {
    /// What it changes, for the notes.
    pub label: &'static str,
    /// Iteration budgets over the scene's.
    pub effort: usize,
    /// Through the load half-way from the last step's first.
    pub split: bool,
}

impl Attempt {
    /// The loads to solve at, from the last step's load `prev` to `f`.
    pub fn loads(&self, prev: f64, f: f64) -> Vec<f64> {
        if self.split {
            vec![0.5 * (prev + f), f]
        } else {
            vec![f]
        }
    }
}

/// The tries of a load step (module docs).
pub(super) const ATTEMPTS: [Attempt; 3] = [
    Attempt {
        label: "the scene's budgets",
        effort: 1,
        split: false,
    },
    Attempt {
        label: "5 times the chord, Newton and ADR iteration budgets",
        effort: EFFORT,
        split: false,
    },
    Attempt {
        label: "5 times the budgets and half the load increment",
        effort: EFFORT,
        split: true,
    },
];

/// The state at the start of a step.
pub(super) struct Saved {
    model: ModelState,
    front: Front,
    recorded: Vec<f64>,
    apart: bool,
    history: GrowthHistory,
}

impl Saved {
    /// Takes the state.
    pub fn take(model: &PdModel, front: &Front, tr: &Tracker, history: &GrowthHistory) -> Saved {
        Saved {
            model: model.state(),
            front: front.clone(),
            recorded: tr.recorded.clone(),
            apart: tr.apart,
            history: history.clone(),
        }
    }

    /// Puts it back.
    pub fn put_back(
        &self,
        model: &mut PdModel,
        front: &mut Front,
        tr: &mut Tracker,
        history: &mut GrowthHistory,
    ) {
        model.restore(&self.model);
        front.clone_from(&self.front);
        tr.recorded.clone_from(&self.recorded);
        tr.apart = self.apart;
        history.clone_from(&self.history);
    }
}

/// What a checkpoint is taken of: the model, front, tracker, history, the load of the
/// first broken bond and the solvers.
pub(super) type RunParts<'a> = (
    &'a PdModel,
    &'a Front,
    &'a Tracker,
    &'a GrowthHistory,
    Option<f64>,
    &'a Equilibrium,
);

/// The checkpoint after a step (`within` None, `next_step` the step after it) or inside
/// step `next_step` (`within`: where).
pub(super) fn checkpoint(
    next_step: usize,
    (model, front, tr, history, first_break, eq): RunParts<'_>,
    within: Option<WithinStep>,
) -> crate::growth::checkpoint::EngineCheckpoint {
    crate::growth::checkpoint::EngineCheckpoint::FullPd(FullPdCheckpoint {
        next_step,
        model: model.state(),
        front: front.state(),
        recorded: tr.recorded.clone(),
        apart: tr.apart,
        first_break,
        work: eq.work_done(),
        history: history.clone(),
        snapshots: history.snapshots.clone(),
        within,
    })
}

/// Puts a checkpoint's state into the model, front, tracker and history of a run.
pub(super) fn restore(
    cp: &FullPdCheckpoint,
    model: &mut PdModel,
    front: &mut Front,
    tr: &mut Tracker,
    history: &mut GrowthHistory,
) -> Result<(), CouplingError> {
    model
        .try_restore(&cp.model)
        .map_err(|e| mismatch(format!("the whole-body model: {}", pd_fail(e))))?;
    front.restore(&cp.front).map_err(mismatch)?;
    if cp.recorded.len() != tr.recorded.len() {
        return Err(mismatch("tip count of the tracker"));
    }
    tr.recorded.clone_from(&cp.recorded);
    tr.apart = cp.apart;
    *history = cp.history.clone();
    history.snapshots.clone_from(&cp.snapshots);
    Ok(())
}
