//! The record of one completed try at a load step, shared by the step loop
//! ([`super::run`]), the back-off ([`super::backoff`]) and the crack-to-hole joins
//! ([`super::join`]), and what a try needs to offer a checkpoint inside the step.

use pdbem_pd::solvers::frozen::Tally;

use crate::growth::checkpoint::{GrowthState, PdBemWithin, TryProgress};

/// What one completed try at a load step did.
#[derive(Debug, Clone, Default)]
pub(super) struct StepRun {
    /// The load it ended at.
    pub load: f64,
    /// Converged (interface residual below psi, no bond breaking).
    pub converged: bool,
    /// Last interface residual (NaN when the coupling broke down).
    pub residual: f64,
    /// The tip that ended the run (structural failure).
    pub cut: Option<usize>,
    /// The PD ligament gave way (the coupling broke down).
    pub gave_way: bool,
    /// Algorithm 1 iterations.
    pub iterations: usize,
    /// PD seconds.
    pub pd_s: f64,
    /// Relocations.
    pub relocations: usize,
    /// The accelerator reported a restart or hand-over.
    pub noted: bool,
    /// The windows' PD equilibria, by solver.
    pub window_solves: Tally,
}

impl StepRun {
    /// Its counters, for a checkpoint.
    pub fn progress(&self) -> TryProgress {
        TryProgress {
            load: self.load,
            iterations: self.iterations,
            pd_s: self.pd_s,
            relocations: self.relocations,
            noted: self.noted,
            window_solves: self.window_solves,
        }
    }

    /// A try going on from the counters of a checkpoint.
    pub fn resumed(p: &TryProgress) -> StepRun {
        StepRun {
            load: p.load,
            iterations: p.iterations,
            pd_s: p.pd_s,
            relocations: p.relocations,
            noted: p.noted,
            window_solves: p.window_solves,
            ..StepRun::default()
        }
    }
}

/// Where a load step starts: the state the back-off returns to, the place inside the
/// step a resumed run goes on from, and the load steps noted so far.
pub(super) struct StepStart<'a> {
    pub state: &'a GrowthState,
    pub resumed: Option<&'a PdBemWithin>,
    pub noted_steps: usize,
}

/// A try at a load step as a checkpoint inside it records it ([`PdBemWithin`]).
#[derive(Clone, Copy)]
pub(super) struct TryCx<'a> {
    pub attempt: usize,
    /// The half-way load's counters once a try with half the increment is past it.
    pub first: Option<TryProgress>,
    pub start: &'a StepStart<'a>,
    pub relocations_before: usize,
    pub initiation_before: Option<f64>,
}
