//! The state of a PD-BEM run between load steps ([`GrowthState`]): taken at the start of
//! every step (the back-off of [`super::backoff`] returns to it) and after every completed
//! step (the checkpoint the observer may save), and put back by
//! [`Growth::set_state`] and [`Growth::resume`].

use super::step::{StepRun, TryCx};
use super::{build_geometry, join_name, Growth};
use crate::error::CouplingError;
use crate::growth::checkpoint::{
    mismatch, CrackState, GrowthState, PdBemCheckpoint, PdBemWithin, WindowState,
};
use crate::growth::params::GrowthParams;
use crate::growth::records::{GrowthResult, GrowthSetup, Scenario};
use crate::setup::MacroCrack;

/// Where a resumed run goes on: the records so far and the next step (and the place
/// inside it).
#[derive(Debug, Clone)]
pub(crate) struct ResumePoint {
    pub result: GrowthResult,
    pub noted_steps: usize,
    pub next_step: usize,
    pub within: Option<Box<PdBemWithin>>,
}

impl<'s, S: Scenario> Growth<'s, S> {
    /// The run's mutable state as it stands (between load steps).
    pub fn state(&self) -> GrowthState {
        GrowthState {
            cracks: self
                .setup
                .layout
                .cracks
                .iter()
                .enumerate()
                .map(|(i, c)| CrackState {
                    points: c.points.clone(),
                    element_size: c.element_size,
                    segment_elements: c.segment_elements,
                    join: (i >= self.scene_cracks).then(|| c.name.clone()),
                })
                .collect(),
            windows: self.setup.layout.windows.clone(),
            window_states: self
                .problem
                .windows
                .iter()
                .map(|w| WindowState::of(&w.model))
                .collect(),
            tips: self.tips.clone(),
            start: self.start.clone(),
            progress: self.progress.clone(),
            initial_s: self.initial_s.clone(),
            initial_tip: self.initial_tip.clone(),
            before: self.before.clone(),
            geometries: self.geometries,
        }
    }

    /// The checkpoint after a completed step: the state, the records so far and the step
    /// to go on with.
    pub(super) fn checkpoint(
        &self,
        next_step: usize,
        result: &GrowthResult,
        noted_steps: usize,
    ) -> PdBemCheckpoint {
        PdBemCheckpoint {
            next_step,
            state: self.state(),
            result: result.clone(),
            noted_steps,
            within: None,
        }
    }

    /// The checkpoint just after a relocation inside load step `k`, in the try `cx` whose
    /// counters are `run`.
    pub(super) fn checkpoint_within(
        &self,
        k: usize,
        cx: &TryCx<'_>,
        run: &StepRun,
        result: &GrowthResult,
    ) -> PdBemCheckpoint {
        PdBemCheckpoint {
            next_step: k,
            state: self.state(),
            result: result.clone(),
            noted_steps: cx.start.noted_steps,
            within: Some(Box::new(PdBemWithin {
                attempt: cx.attempt,
                first: cx.first,
                progress: run.progress(),
                step_start: cx.start.state.clone(),
                relocations_before: cx.relocations_before,
                initiation_before: cx.initiation_before,
            })),
        }
    }

    /// Puts `state` back: the geometry is rebuilt when its cracks or windows differ from
    /// the current ones, every window takes its PD state (its kept solvers dropped), the
    /// last solution is forgotten (the next step solves first).
    pub fn set_state(&mut self, state: &GrowthState) -> Result<(), CouplingError> {
        let base = self.scene_cracks;
        if state.cracks.len() < base || state.tips.len() != self.tips.len() {
            return Err(mismatch(format!(
                "{} cracks and {} tips in the checkpoint, {} and {} in the scene",
                state.cracks.len(),
                state.tips.len(),
                base,
                self.tips.len()
            )));
        }
        let cracks = self.cracks_of(state)?;
        let layout = &mut self.setup.layout;
        if layout.windows != state.windows || layout.cracks != cracks {
            layout.cracks = cracks;
            layout.windows.clone_from(&state.windows);
            let (problem, bem) = build_geometry(
                &self.setup.layout,
                &self.setup,
                self.scenario,
                self.params.trigger_ratio,
                &mut self.pairs,
            )?;
            self.problem = problem;
            self.bem = bem;
        }
        if state.window_states.len() != self.problem.windows.len() {
            return Err(mismatch(format!(
                "{} window states for {} windows",
                state.window_states.len(),
                self.problem.windows.len()
            )));
        }
        for (i, (w, s)) in self
            .problem
            .windows
            .iter_mut()
            .zip(&state.window_states)
            .enumerate()
        {
            s.apply(&mut w.model)
                .map_err(|e| mismatch(format!("window {i}: {e}")))?;
            w.solver.clear();
        }
        for (t, s) in self.tips.iter().zip(&state.tips) {
            if t.spec != s.spec {
                return Err(mismatch(format!(
                    "tip {} in the checkpoint, {} in the scene",
                    s.spec.name, t.spec.name
                )));
            }
        }
        self.tips.clone_from(&state.tips);
        self.start.clone_from(&state.start);
        self.progress.clone_from(&state.progress);
        self.initial_s.clone_from(&state.initial_s);
        self.initial_tip.clone_from(&state.initial_tip);
        self.before.clone_from(&state.before);
        self.geometries = state.geometries;
        self.last = None;
        Ok(())
    }

    /// The layout's cracks of `state`: the scene's with their grown polylines, then the
    /// cracks joining tips to holes (named, faces of the tip's crack).
    fn cracks_of(&self, state: &GrowthState) -> Result<Vec<MacroCrack>, CouplingError> {
        let base = self.scene_cracks;
        state
            .cracks
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let mut c = if i < base {
                    self.setup.layout.cracks[i].clone()
                } else {
                    let name = s.join.clone().ok_or_else(|| {
                        mismatch(format!("crack {i} of the checkpoint is not in the scene"))
                    })?;
                    let faces = self
                        .tips
                        .iter()
                        .find(|t| join_name(&t.spec.name) == name)
                        .map(|t| self.setup.layout.cracks[t.spec.crack].faces)
                        .ok_or_else(|| mismatch(format!("no tip for the joining crack {name}")))?;
                    MacroCrack {
                        name,
                        points: Vec::new(),
                        faces,
                        element_size: s.element_size,
                        segment_elements: s.segment_elements,
                    }
                };
                c.points.clone_from(&s.points);
                c.element_size = s.element_size;
                c.segment_elements = s.segment_elements;
                Ok(c)
            })
            .collect()
    }

    /// A run that goes on from `checkpoint` (taken from a run of the same setup and
    /// parameters): [`Growth::run`] then starts at its next step with its records, or
    /// inside it just after the relocation the checkpoint was taken at.
    pub fn resume(
        setup: GrowthSetup,
        scenario: &'s S,
        params: GrowthParams,
        checkpoint: PdBemCheckpoint,
    ) -> Result<Self, CouplingError> {
        let mut g = Growth::new(setup, scenario, params)?;
        g.set_state(&checkpoint.state)?;
        g.resume_from = Some(ResumePoint {
            result: checkpoint.result,
            noted_steps: checkpoint.noted_steps,
            next_step: checkpoint.next_step,
            within: checkpoint.within,
        });
        Ok(g)
    }
}
