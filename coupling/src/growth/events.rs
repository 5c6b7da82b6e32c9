//! What the BEM-only and full-PD growth engines report while they run
//! ([`EngineObserver`]): run-log events, progress and messages. The engines never print
//! or write files; the `pdbem` binary's observer writes `growth_log.jsonl` and a progress
//! line, tests use [`Quiet`]. PD-BEM growth reports through [`super::Observer`].
//!
//! Events (kind: fields), as docs/outputs.md lists them for `growth_log.jsonl`:
//! `start` (mode and settings), `solve` (BEM-only: one solved geometry with the unit-load
//! SIFs of every tip), `grow` (BEM-only: one increment of one tip), `round` (full PD: one
//! break round), `tip_end` (a tip stopped, and why), `step` (a load step's record),
//! `failure` (the body was cut through), `solver` (full PD: the equilibrium solver's work).
//! After every load step that does not end the run the observer is offered a checkpoint
//! ([`EngineObserver::checkpoint`]).

use std::ops::ControlFlow;

use serde_json::Value;

use super::checkpoint::EngineCheckpoint;

/// Receives what a BEM-only or full-PD growth run reports.
pub trait EngineObserver {
    /// A run-log event of `kind` with its `fields`.
    fn event(&mut self, _kind: &str, _fields: Value) {}
    /// After `done` of `total` load steps, or within a step (`done` unchanged), with a
    /// one-line status.
    fn progress(&mut self, _done: usize, _total: usize, _status: &str) {}
    /// A message for the person running it (the model built, its size).
    fn message(&mut self, _text: &str) {}
    /// After every load step that does not end the run: `save` builds the checkpoint of
    /// the run as it stands (call it only when one is wanted). `Break` stops the run there
    /// with [`crate::CouplingError::Interrupted`].
    fn checkpoint(
        &mut self,
        _step: usize,
        _save: &mut dyn FnMut() -> EngineCheckpoint,
    ) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
    /// Full PD, inside load step `step`, after break round `round` at which the engine
    /// renewed its solvers (every [`crate::growth::full_pd::RENEW_ROUNDS`] rounds, in
    /// every run); BEM-only, after growth round `round` of the step, its geometry solved:
    /// `save` builds the checkpoint of the run as it stands (call it only when one is
    /// wanted). `Break` stops the run there with
    /// [`crate::CouplingError::InterruptedWithin`] (full PD) or
    /// [`crate::CouplingError::InterruptedAtIncrement`] (BEM-only).
    fn round_checkpoint(
        &mut self,
        _step: usize,
        _round: usize,
        _save: &mut dyn FnMut() -> EngineCheckpoint,
    ) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// An observer that ignores everything.
pub struct Quiet;

impl EngineObserver for Quiet {}
