//! Growth checkpoints: everything a growth run needs to go on from the end of a completed
//! load step, as plain serialisable data (serde). The engines hand a checkpoint to their
//! observer after every load step that does not end the run ([`crate::growth::Observer::checkpoint`],
//! [`crate::growth::events::EngineObserver::checkpoint`]); the `pdbem` binary writes it
//! next to the run folder and `pdbem run --resume` starts the engine from it
//! ([`crate::growth::Growth::resume`], [`crate::growth::bem_only::run_from`],
//! [`crate::growth::full_pd::run_from`]).
//!
//! What is kept, per mode:
//! - PD-BEM ([`PdBemCheckpoint`]): the macro cracks as extended and the window specs as
//!   moved (the geometry is rebuilt from them: mesh, BEM factorisation and window models
//!   are deterministic functions of the layout), the PD state of every window
//!   ([`WindowState`]: displacements, bond flags, bond history, load factor, the virtual
//!   nodes' prescribed displacements), the tips and their traced paths, the interface
//!   state the next step starts from, the per-tip progress and the records so far; also
//!   inside a load step, just after a relocation ([`PdBemWithin`]: the try of the
//!   back-off, its counters and the state the step started from). A relocation builds
//!   the BEM system, every window and the accelerator anew in every run, so nothing the
//!   state leaves out is carried past it.
//! - BEM-only ([`BemOnlyCheckpoint`]): the crack front as grown and the history; every
//!   geometry is meshed and solved anew from the front; also inside a load step, after a
//!   growth round whose geometry was solved ([`BemOnlyWithin`]: unstable growth under load
//!   control runs within one step, thousands of increments with a small `da`).
//! - Full PD ([`FullPdCheckpoint`]): the model state, the front, the tracker's recorded
//!   arc lengths and the history, with the solver counters of the `solver` log event;
//!   also inside a load step, after a break round at which the solvers were renewed
//!   ([`WithinStep`]; the engine renews them every
//!   [`crate::growth::full_pd::RENEW_ROUNDS`] rounds in every run, whether a checkpoint
//!   is written there or not, so results do not depend on when checkpoints are taken).
//!
//! Solver state that is not kept (the kept factorisations of the frozen-history solvers,
//! the interface accelerator's secant data) is not carried across load steps by the
//! engines either: every run renews it at the end of every load step, so a resumed run
//! repeats the arithmetic of an uninterrupted one bit for bit. No random numbers are used.

use pdbem_bem::V2;
use pdbem_pd::solvers::frozen::Tally;
use pdbem_pd::{ModelState, PdError, PdModel};
use serde::{Deserialize, Serialize};

use super::front::FrontState;
use super::history::{FieldSnapshot, GrowthHistory};
use super::records::GrowthResult;
use super::tips::TipState;
use crate::error::CouplingError;
use crate::window::WindowSpec;

/// The PD state of one window (or of the whole-body model).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WindowState {
    /// Displacements, bond flags, bond history, load factor.
    pub model: ModelState,
    /// Prescribed displacement of every virtual node at load factor 1 (the coupling's
    /// last interface data).
    pub virtual_base: Vec<[f64; 2]>,
}

impl WindowState {
    /// The state of `model`.
    pub fn of(model: &PdModel) -> Self {
        WindowState {
            model: model.state(),
            virtual_base: model.prescribed_virtual(),
        }
    }

    /// Puts the state into `model` (built from the same problem).
    pub fn apply(&self, model: &mut PdModel) -> Result<(), PdError> {
        model.set_prescribed_displacements(&self.virtual_base)?;
        model.try_restore(&self.model)
    }
}

/// A macro crack as extended by the relocations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CrackState {
    /// Polyline (m).
    pub points: Vec<V2>,
    /// BEM element size along it (m).
    pub element_size: f64,
    /// One BEM element per polyline segment.
    pub segment_elements: bool,
    /// The name of a crack that joins a tip to a hole (after the scene's cracks,
    /// [`crate::growth::driver::join_name`]); None for the scene's cracks.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub join: Option<String>,
}

/// The mutable state of a PD-BEM run between two load steps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GrowthState {
    /// The layout's cracks.
    pub cracks: Vec<CrackState>,
    /// The layout's window specs.
    pub windows: Vec<WindowSpec>,
    /// The PD state of every window, in window order.
    pub window_states: Vec<WindowState>,
    /// The tips.
    pub tips: Vec<TipState>,
    /// Interface state the next solve starts from and its load factor.
    pub start: Option<(Vec<f64>, f64)>,
    /// Arc length, step and load of every tip at each record.
    pub progress: Vec<Vec<(f64, usize, f64)>>,
    /// Arc length of each initial tip along its crack.
    pub initial_s: Vec<f64>,
    /// Initial tip positions.
    pub initial_tip: Vec<V2>,
    /// Tip positions before the last solve.
    pub before: Vec<V2>,
    /// Geometries built so far.
    pub geometries: usize,
}

/// A PD-BEM checkpoint: the state after step `next_step - 1` and the records so far.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PdBemCheckpoint {
    /// The first load step still to run.
    pub next_step: usize,
    /// The engine state.
    pub state: GrowthState,
    /// Steps, relocations, notes so far.
    pub result: GrowthResult,
    /// Load steps so far in which the interface accelerator restarted or handed over.
    pub noted_steps: usize,
    /// Taken inside load step `next_step`, just after a relocation (None: before the
    /// step). Absent in checkpoints written before it was kept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub within: Option<Box<PdBemWithin>>,
}

/// The place of a PD-BEM checkpoint inside a load step: just after a relocation, where
/// every window, the BEM system and the accelerator were built anew (so the state is
/// whole in [`GrowthState`]), within one try of the step's back-off.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PdBemWithin {
    /// The try of the step (index into the back-off's tries).
    pub attempt: usize,
    /// A try with half the load increment solving at the step's own load: the counters
    /// of its half-way load, done (None: the try's first or only load).
    pub first: Option<TryProgress>,
    /// This try's counters so far.
    pub progress: TryProgress,
    /// The state the step started from (the back-off returns to it).
    pub step_start: GrowthState,
    /// Relocation records before the step.
    pub relocations_before: usize,
    /// Initiation load before the step.
    pub initiation_before: Option<f64>,
}

/// What a try at a load step has done so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct TryProgress {
    /// The load it solves at.
    pub load: f64,
    /// Algorithm 1 iterations.
    pub iterations: usize,
    /// PD seconds.
    pub pd_s: f64,
    /// Relocations.
    pub relocations: usize,
    /// The accelerator reported a restart or hand-over.
    pub noted: bool,
    /// The windows' PD equilibria, by solver.
    #[serde(default)]
    pub window_solves: Tally,
}

/// A BEM-only checkpoint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BemOnlyCheckpoint {
    /// The first load step still to run.
    pub next_step: usize,
    /// Cracks and tips as grown.
    pub front: FrontState,
    /// The history so far.
    pub history: GrowthHistory,
    /// Its field snapshots (not part of the history's serialised form).
    pub snapshots: Vec<FieldSnapshot>,
    /// Geometries solved so far (the `solve` events' counter).
    pub geometry: usize,
    /// Taken inside load step `next_step`, after a growth round whose geometry was solved
    /// (None: before the step). Absent in checkpoints written before it was kept.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub within: Option<Box<BemOnlyWithin>>,
}

/// The place of a BEM-only checkpoint inside a load step: after `increments` growth
/// rounds, with the state the step started from (a step that cannot solve a geometry
/// returns to it).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BemOnlyWithin {
    /// Growth rounds of the step so far.
    pub increments: usize,
    /// The cracks and tips at the step's start.
    pub front: FrontState,
    /// The history at the step's start.
    pub history: GrowthHistory,
    /// Its field snapshots.
    pub snapshots: Vec<FieldSnapshot>,
    /// Geometries solved before the step.
    pub geometry: usize,
}

/// The counters of the full-PD equilibrium solvers (the `solver` log event).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct SolverWork {
    /// Factorisations of the tangent.
    pub factorizations: usize,
    /// Triangular solve pairs of the chord iteration.
    pub chord_solves: usize,
    /// Seconds assembling.
    pub assembly_s: f64,
    /// Seconds factorising and solving.
    pub factor_and_solve_s: f64,
    /// Equilibria left by the chord iteration to Newton.
    pub newton: usize,
    /// Newton stalls accepted.
    pub loose: usize,
    /// Equilibria found by ADR.
    pub adr: usize,
}

/// A full-PD checkpoint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FullPdCheckpoint {
    /// The first load step still to run.
    pub next_step: usize,
    /// The whole-body model's state.
    pub model: ModelState,
    /// Cracks and tips as traced.
    pub front: FrontState,
    /// Arc length of each tip path already recorded (m).
    pub recorded: Vec<f64>,
    /// The body came apart other than by a tracked tip.
    pub apart: bool,
    /// Load factor of the first broken bond.
    pub first_break: Option<f64>,
    /// Solver counters so far.
    pub work: SolverWork,
    /// The history so far.
    pub history: GrowthHistory,
    /// Its field snapshots.
    pub snapshots: Vec<FieldSnapshot>,
    /// Where inside load step `next_step` the checkpoint was taken (None: before it).
    #[serde(default)]
    pub within: Option<WithinStep>,
}

/// The place of a full-PD checkpoint inside a load step: after a break round at which the
/// solvers were renewed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct WithinStep {
    /// The try of the step (index into the back-off's tries).
    pub attempt: usize,
    /// The load of the try being solved (a try with half the increment has two).
    pub load: usize,
    /// The last completed break round at that load (0-based).
    pub round: usize,
    /// Broken bonds at the start of the step.
    pub broken_at_start: usize,
}

/// The checkpoint of a BEM-only or full-PD run. (Built once per load step or checkpoint
/// interval and moved whole: the size difference of the variants does not matter.)
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum EngineCheckpoint {
    /// BEM-only.
    BemOnly(BemOnlyCheckpoint),
    /// Full PD.
    FullPd(FullPdCheckpoint),
}

/// A checkpoint error.
pub(crate) fn mismatch(message: impl Into<String>) -> CouplingError {
    CouplingError::Checkpoint {
        message: message.into(),
    }
}
