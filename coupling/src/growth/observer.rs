//! The progress [`Observer`] of PD-BEM growth (Algorithm 2): callbacks after every
//! Algorithm 1 iteration, load step and relocation, and the checkpoint hook of a resumable
//! run. The engines never print or write files; the binary implements this.

use std::ops::ControlFlow;

use crate::growth::checkpoint::PdBemCheckpoint;
use crate::growth::records::{IterationEvent, RelocationRecord, StepResult};
use crate::iteration::{CoupledProblem, CoupledSolution};
use crate::setup::WindowModel;

/// Progress callbacks (all optional).
pub trait Observer {
    /// After every Algorithm 1 iteration.
    fn iteration(&mut self, _event: &IterationEvent<'_>) {}
    /// After every converged (or failed) load step.
    fn step(&mut self, _step: &StepResult) {}
    /// After every window relocation.
    fn relocation(&mut self, _record: &RelocationRecord) {}
    /// A message for the user (tip ended, windows merged, ...).
    fn note(&mut self, _message: &str) {}
    /// Just before a relocation, with the windows whose state triggered it.
    fn before_relocation(&mut self, _step: usize, _windows: &[WindowModel]) {}
    /// After every load step (just after [`Observer::step`]), with the coupled problem and
    /// its last solution (None before the first solve of a rebuilt geometry), for field
    /// snapshots.
    fn state(
        &mut self,
        _step: &StepResult,
        _problem: &CoupledProblem,
        _solution: Option<&CoupledSolution>,
    ) {
    }
    /// After every load step that does not end the run (just after [`Observer::state`]):
    /// `save` builds the checkpoint of the run as it stands (call it only when one is
    /// wanted: it copies the windows' state). `Break` stops the run there with
    /// [`crate::CouplingError::Interrupted`] (a test's stand-in for a kill).
    fn checkpoint(
        &mut self,
        _step: usize,
        _save: &mut dyn FnMut() -> PdBemCheckpoint,
    ) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
    /// Just after a relocation inside load step `step` (`relocations` records in the run
    /// so far), where the run's state is whole ([`crate::growth::checkpoint::PdBemWithin`]):
    /// `save` builds the checkpoint (call it only when one is wanted, e.g. when some time
    /// has passed since the last). `Break` stops the run there with
    /// [`crate::CouplingError::InterruptedAtRelocation`] (a test's stand-in for a kill).
    fn checkpoint_within(
        &mut self,
        _step: usize,
        _relocations: usize,
        _save: &mut dyn FnMut() -> PdBemCheckpoint,
    ) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// An observer that ignores everything.
pub struct Silent;

impl Observer for Silent {}
