//! The moves of a growth run: the strain watch, one solve at a load factor
//! ([`Growth::solve_at`]) and the load-step loop ([`Growth::run`]).

use std::ops::ControlFlow;
use std::time::Instant;

use pdbem_bem::post::field::FieldEvaluator;
use pdbem_bem::V2;

use super::held::{held_end, held_notes};
use super::join::Joined;
use super::step::{StepRun, StepStart, TryCx};
use super::Growth;
use crate::error::CouplingError;
use crate::growth::checkpoint::TryProgress;
use crate::growth::fine_zone::path_leaves_fine_zone;
use crate::growth::geometry::turn_note;
use crate::growth::observer::Observer;
use crate::growth::overstrain::{self, Hotspot};
use crate::growth::params::GrowthParams;
use crate::growth::records::{
    fallback_note, Failure, GrowthResult, IterationEvent, Scenario, SolveOutcome, StepResult,
};
use crate::growth::summary::{overstrain_end, stray_end};
use crate::growth::tips::{passed_margin, reached_boundary, track, TipEnd, TipState};
use crate::iteration::{solve_prepared, StepOptions};
use crate::relaxation::SecantColumns;
use crate::setup::WindowModel;
use crate::window::{Body, Window};
use pdbem_pd::crack_path::CrackPath;

/// Spread-out candidates of the strain watch per step ([`overstrain::search`]: at least
/// four horizons apart, then every sample within that distance of the four most strained
/// of them): the interior field costs one pass over the elements per sample, the ranking
/// none. Measured in [`overstrain`].
const OVERSTRAIN_SAMPLES: usize = 32;

impl<'s, S: Scenario> Growth<'s, S> {
    /// The most strained point of the BEM body away from the windows in the last solution
    /// ([`overstrain`]; the field is evaluated at the [`OVERSTRAIN_SAMPLES`] samples behind
    /// the elements of largest boundary strain, and around the most strained of them);
    /// None without a solution, windows or a failure law.
    fn overstrain(&self) -> Option<Hotspot> {
        let sol = self.last.as_ref()?;
        let windows = &self.problem.windows;
        let first = windows.first()?;
        let delta = first.window.delta();
        let onset = Some(first.model.law().damage_onset()).filter(|s| s.is_finite())?;
        let mesh = &self.problem.mesh;
        let skip: Vec<usize> = windows
            .iter()
            .filter_map(|w| mesh.group(&w.group))
            .collect();
        let boxes: Vec<&Window> = windows.iter().map(|w| &w.window).collect();
        let tips: Vec<V2> = self.tips.iter().map(TipState::position).collect();
        let (w, h) = first.window.size();
        let clear = 0.5 * w.max(h);
        let samples = overstrain::sample_points(mesh, &skip, &boxes, &tips, delta, clear);
        let ranks = overstrain::boundary_strains(mesh, &self.problem.material, &sol.solution);
        let size = overstrain::SearchSize {
            candidates: OVERSTRAIN_SAMPLES,
            spread: 4.0 * delta,
            refined: 4,
        };
        let pb = &self.problem;
        let eval = FieldEvaluator::new(mesh, &pb.material, &sol.solution, pb.background);
        overstrain::search(&eval, &samples, &ranks, onset, size)
    }

    /// Algorithm 1 at load factor `load` on the current geometry (step `step`, for the
    /// observer), stopped early when a tip needs attention (past its window margin or at
    /// the outline or a hole). Updates the tips' traces.
    pub fn solve_at(
        &mut self,
        step: usize,
        load: f64,
        observer: &mut dyn Observer,
    ) -> Result<SolveOutcome, CouplingError> {
        let start = self
            .start
            .as_ref()
            .map(|(x, f)| x.iter().map(|v| v * load / f).collect());
        let holes = self.hole_names();
        let tips = &self.tips;
        let (body, params) = (&self.body, &self.params);
        let mut positions: Vec<V2> = tips.iter().map(TipState::position).collect();
        let mut trace_error: Option<CouplingError> = None;
        let mut monitor = |rep: &crate::iteration::IterationReport<'_>| {
            let mut stop = false;
            for (t, tip) in tips.iter().enumerate().filter(|(_, t)| t.active()) {
                let wm = &rep.windows[tip.window];
                match track(wm, tip.window, tip.entry, &params.path) {
                    Ok(p) if !p.is_empty() => {
                        positions[t] = V2::new(p.tip()[0], p.tip()[1]);
                        stop |= needs_attention(wm, tip.entry, &p, (body, &holes), params);
                    }
                    Ok(_) => {}
                    Err(e) => {
                        trace_error = Some(e);
                        stop = true;
                    }
                }
            }
            observer.iteration(&IterationEvent {
                step,
                load,
                iteration: rep.iteration,
                residual: rep.residual,
                bonds_broken: rep.bonds_broken,
                tips: &positions,
            });
            if stop {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        };
        let opts = StepOptions {
            load_scale: load,
            start,
            monitor: Some(&mut monitor),
            secants: std::mem::take(&mut self.secants),
        };
        let (sol, info) = solve_prepared(&mut self.problem, &self.bem, &params.coupling, opts)?;
        for n in &info.notes {
            observer.note(&format!("step {step} (load {load}): {n}"));
        }
        if let Some(e) = trace_error {
            return Err(e);
        }
        self.start = Some((sol.x_pd.clone(), load));
        let window_solves = (self.problem.windows.iter_mut())
            .map(|w| w.solver.take_tally())
            .sum();
        let mut sol = sol;
        self.secants = std::mem::take(&mut sol.secants);
        self.last = Some(sol);
        self.before = self.tips.iter().map(TipState::position).collect();
        self.retrace()?;
        Ok(SolveOutcome {
            converged: info.converged,
            iterations: info.iterations,
            residual: info.residuals.last().copied().unwrap_or(f64::NAN),
            bonds_broken: info.bonds_broken.iter().sum(),
            pd_s: info.timings.pd_s,
            window_solves,
            notes: info.notes,
        })
    }

    /// Tips past their window margin, or at the end of a refined window's fine cells.
    fn triggered(&self) -> Vec<usize> {
        (0..self.tips.len()).filter(|&t| self.triggers(t)).collect()
    }

    /// Whether active tip `t` is past its window margin, or at the end of a refined
    /// window's fine cells: its window moves on.
    pub(super) fn triggers(&self, t: usize) -> bool {
        let tip = &self.tips[t];
        let wm = &self.problem.windows[tip.window];
        tip.active()
            && !tip.path.is_empty()
            && (passed_margin(
                &wm.window,
                tip.position(),
                tip.entry,
                self.params.trigger_ratio,
            ) || path_leaves_fine_zone(wm, &tip.path, self.params.direction_length))
    }

    /// Broken bond pairs over all windows.
    fn broken_bonds(&self) -> usize {
        self.problem
            .windows
            .iter()
            .map(|w| w.model.broken_bonds())
            .sum()
    }

    /// One try at load step `k` at load `load` on the current state: Algorithm 1 with the
    /// geometry iteration (relocations) until the step converged or a tip ended the run.
    /// After every relocation the observer may take a checkpoint ([`TryCx`] says where in
    /// the step); `from` holds the counters of a try resumed from one.
    pub(super) fn attempt(
        &mut self,
        (k, load): (usize, f64),
        out: &mut GrowthResult,
        observer: &mut dyn Observer,
        cx: &TryCx<'_>,
        from: Option<&TryProgress>,
    ) -> Result<StepRun, CouplingError> {
        let mut run = from.map_or_else(
            || StepRun {
                load,
                ..StepRun::default()
            },
            StepRun::resumed,
        );
        // Every try at a step starts its quasi-Newton model afresh: a step's result
        // depends only on the state it starts from (back-offs, resumed runs).
        self.secants = SecantColumns::default();
        loop {
            let o = match self.solve_at(k, load, observer) {
                Ok(o) => o,
                Err(e) => match self.ligament_gave_way(&e) {
                    Some((t, what)) => {
                        observer.note(&format!(
                            "step {k} (load {load}): the PD ligament ahead of tip {} \
                             gave way ({what}): structural failure",
                            self.tips[t].spec.name
                        ));
                        run.gave_way = true;
                        run.residual = f64::NAN;
                        run.cut = Some(t);
                        return Ok(run);
                    }
                    None => return Err(e),
                },
            };
            run.iterations += o.iterations;
            run.pd_s += o.pd_s;
            run.window_solves += o.window_solves;
            run.noted = run.noted || !o.notes.is_empty();
            run.residual = o.residual;
            if o.bonds_broken > 0 && out.initiation_load.is_none() {
                out.initiation_load = Some(load);
            }
            if let Some(t) = self.end_tips(observer) {
                run.cut = Some(t);
                return Ok(run);
            }
            match self.join_holes(load, observer)? {
                Joined::Cuts(t) => return Ok(self.cut_by_join(t, run, observer)),
                // The next solve is on the joined geometry.
                Joined::Rebuilt(_) => continue,
                Joined::Nothing => {}
            }
            let which = self.triggered();
            if which.is_empty() {
                if o.converged {
                    run.converged = true;
                    return Ok(run);
                }
                // Stopped for a tip that has now ended: iterate on with the others.
                continue;
            }
            if run.relocations >= self.params.max_relocations_per_step {
                return Err(CouplingError::Relocation {
                    tip: self.tips[which[0]].spec.name.clone(),
                    reason: format!(
                        "more than {} relocations in step {k} (load {load}); lower the load step",
                        run.relocations
                    ),
                });
            }
            self.record_progress(k, load);
            let plan = self.plan(&which)?;
            if let Some(&t) = plan.at_outline.first() {
                let p = self.tips[t].position();
                observer.note(&format!(
                    "tip {} at ({:.4}, {:.4}): no window around it fits inside the body, \
                     the outer boundary is within the window's reach: the crack reaches \
                     it, structural failure",
                    self.tips[t].spec.name, p.x, p.y
                ));
                self.tips[t].ended = Some(TipEnd::Outline);
                run.cut = Some(t);
                return Ok(run);
            }
            if plan.cuts_body {
                let t = which[0];
                let p = self.tips[t].position();
                observer.note(&format!(
                    "tip {} at ({:.4}, {:.4}): its moved window reaches the outline and \
                     the cracks cut the BEM body apart; the windows alone hold the \
                     cut-off part",
                    self.tips[t].spec.name, p.x, p.y
                ));
            }
            let recs = self.apply(plan, k, load, observer)?;
            if recs.is_empty() {
                // Every triggered tip ended at a hole: joined to it, iterate on with the
                // others on the joined geometry.
                match self.join_holes(load, observer)? {
                    Joined::Cuts(t) => return Ok(self.cut_by_join(t, run, observer)),
                    Joined::Rebuilt(_) => continue,
                    Joined::Nothing => {}
                }
                if o.converged || self.tips.iter().all(|t| !t.active()) {
                    run.converged = o.converged;
                    return Ok(run);
                }
                continue;
            }
            run.relocations += recs.len();
            out.relocations.extend(recs);
            // Every window, the BEM system and the accelerator were built anew: the state
            // is whole here, and a run resumed from it repeats this one bit for bit.
            let n = out.relocations.len();
            let flow =
                observer.checkpoint_within(k, n, &mut || self.checkpoint_within(k, cx, &run, out));
            if flow.is_break() {
                return Err(CouplingError::InterruptedAtRelocation {
                    step: k,
                    relocation: n,
                });
            }
        }
    }

    /// Runs Algorithm 2 (see the module docs); a run made by [`Growth::resume`] goes on
    /// from its checkpoint. A step that no back-off solves ([`super::backoff`]) ends the
    /// run with [`GrowthResult::failure_reason`] and the records of the steps before it.
    pub fn run(&mut self, observer: &mut dyn Observer) -> Result<GrowthResult, CouplingError> {
        let (mut out, mut noted_steps, first, mut within) = match self.resume_from.take() {
            Some(r) => (r.result, r.noted_steps, r.next_step, r.within),
            None => {
                self.record_progress(0, self.params.loads.initial);
                (GrowthResult::default(), 0, 0, None)
            }
        };
        let count = self.params.loads.count;
        for k in first..count {
            let load = self.params.loads.factor(k);
            let prev = if k == 0 {
                0.0
            } else {
                self.params.loads.factor(k - 1)
            };
            let t0 = Instant::now();
            let resumed = within.take();
            let saved = match &resumed {
                Some(w) => w.step_start.clone(),
                None => self.state(),
            };
            let start = StepStart {
                state: &saved,
                resumed: resumed.as_deref(),
                noted_steps,
            };
            let run = match self.step_with_backoff((k, load, prev), &start, &mut out, observer)? {
                Ok(run) => run,
                Err(reason) => {
                    observer.note(&reason);
                    out.failure_reason = Some(reason);
                    break;
                }
            };
            // A step solved through half the load increment may have ended (structural
            // failure) at the half-way load.
            let load = run.load;
            let StepRun {
                converged,
                residual,
                cut,
                gave_way,
                ..
            } = run;
            self.record_progress(k, load);
            noted_steps += usize::from(run.noted);
            let rec = StepResult {
                step: k,
                load,
                iterations: run.iterations,
                residual,
                converged,
                broken_bonds: self.broken_bonds(),
                tips: self.tips.iter().map(TipState::position).collect(),
                // The last solution of a step whose ligament gave way is not an equilibrium,
                // and at a structural failure the body has come apart: its last state is
                // the collapse, outside small-strain BEM (the tension plate's right half
                // turned about the last PD bonds, CMOD 8.26 m in a 10 m plate). Neither
                // has a CMOD, as BEM-only reports none at its failure step.
                cmod: if gave_way || cut.is_some() {
                    None
                } else {
                    self.first_cmod()
                },
                relocations: run.relocations,
                wall_s: t0.elapsed().as_secs_f64(),
                pd_s: run.pd_s,
                // Only an equilibrium says how strained the body is.
                overstrain: if converged { self.overstrain() } else { None },
                stray: self.stray_damage(),
                held: if converged {
                    self.held_by_protection()
                } else {
                    None
                },
                window_solves: run.window_solves,
            };
            observer.step(&rec);
            observer.state(&rec, &self.problem, self.last.as_ref());
            out.steps.push(rec);
            if let Some(t) = cut {
                let name = self.tips[t].spec.name.clone();
                out.notes
                    .push(failure_note(k, load, &name, gave_way, &self.tips[t].ended));
                out.failure = Some(Failure {
                    step: k,
                    load,
                    tip: name,
                });
                break;
            }
            if let Some(reason) = held_end(&out.steps) {
                observer.note(&reason);
                out.failure_reason = Some(reason);
                break;
            }
            if let Some(reason) = overstrain_end(&self.params, &out.steps)
                .or_else(|| stray_end(&self.params, &out.steps))
            {
                observer.note(&reason);
                out.failure_reason = Some(reason);
                break;
            }
            if self.tips.iter().all(|t| !t.active()) {
                out.notes
                    .push(format!("every tip ended by step {k} (load {load})"));
                out.notes.extend(self.holds_note());
                break;
            }
            // The windows' kept factorisations end with the step, in every run, so that a
            // run resumed from the checkpoint below repeats this one bit for bit.
            for w in self.problem.windows.iter_mut() {
                w.solver.clear();
            }
            if k + 1 < count {
                let flow =
                    observer.checkpoint(k, &mut || self.checkpoint(k + 1, &out, noted_steps));
                if flow.is_break() {
                    return Err(CouplingError::Interrupted { step: k });
                }
            }
        }
        for t in &self.tips {
            if let Some(e) = &t.ended {
                out.notes.push(format!("tip {} ended: {e}", t.spec.name));
            }
        }
        let turns: Vec<String> = out.relocations.iter().filter_map(turn_note).collect();
        out.notes.extend(turns);
        out.notes.extend(self.damage_beyond_tips());
        out.notes.extend(held_notes(&out.steps));
        out.notes.extend(fallback_note(&out.steps));
        if noted_steps > 0 {
            out.notes.push(format!(
                "the interface accelerator restarted or handed over to IQN-ILS in \
                 {noted_steps} load step(s) (the run log has each note)"
            ));
        }
        Ok(out)
    }
}

impl StepRun {
    /// This try after `first` (half the load increment first): counters added.
    pub fn after(mut self, first: &StepRun) -> StepRun {
        self.iterations += first.iterations;
        self.pd_s += first.pd_s;
        self.window_solves += first.window_solves;
        self.relocations += first.relocations;
        self.noted |= first.noted;
        self
    }
}

/// The note of a structural failure at step `k` by tip `name`.
fn failure_note(k: usize, load: f64, name: &str, gave_way: bool, end: &Option<TipEnd>) -> String {
    if gave_way {
        format!(
            "structural failure at step {k} (load {load}): the PD ligament at tip \
             {name} gave way (the coupling broke down with the remaining ligament in \
             the window)"
        )
    } else if let Some(TipEnd::Hole(hole)) = end {
        format!(
            "structural failure at step {k} (load {load}): tip {name} ran into hole \
             {hole}, and its crack joined to the hole closes a chain of cracks that cuts \
             the body apart"
        )
    } else if let Some(TipEnd::Coalescence(other)) = end {
        format!(
            "structural failure at step {k} (load {load}): tip {name} joined the \
             crack of tip {other}; both cracks start on the outer boundary, so \
             together they cut the body"
        )
    } else {
        format!(
            "structural failure at step {k} (load {load}): tip {name} reached the \
             outer boundary"
        )
    }
}

/// Whether the traced `path` (entry `entry`) in window `wm` is past the margin, at the
/// end of a refined window's fine cells, or at the outline or a hole (`body` with its hole
/// names).
fn needs_attention(
    wm: &WindowModel,
    entry: V2,
    path: &CrackPath,
    (body, holes): (&Body, &[String]),
    params: &GrowthParams,
) -> bool {
    let w = &wm.window;
    let p = V2::new(path.tip()[0], path.tip()[1]);
    passed_margin(w, p, entry, params.trigger_ratio)
        || path_leaves_fine_zone(wm, path, params.direction_length)
        || reached_boundary(body, holes, p, params.boundary_reach * w.spec.dx).is_some()
}
