//! PD-BEM crack growth of a scene (seed 002 Algorithm 2, sections 2.3.2-2.3.3).
//!
//! The scene gives the macro layout exactly as a static coupled solve does
//! ([`crate::run_coupled`]: outline with patches, holes, cracks, one window per crack tip
//! with axes along the crack, PD settings, Algorithm 1 parameters), the load steps
//! (`load`: initial factor, increment, count; every boundary value of the scene is
//! multiplied by the factor) and the growth settings (`growth`: trigger ratio, move
//! distance, elements per extension, damage threshold). The run itself is
//! [`pdbem_coupling::growth::Growth::run`]; this module adapts the scene to it (the
//! [`Scenario`](pdbem_coupling::growth::Scenario) of `setup::growth`: BEM conditions of
//! each rebuilt mesh and conditions on window sides lying on the outline, both at load
//! factor 1), shows a progress bar per load step with the coupling residual and the tip
//! positions, logs every relocation (run log and `growth_log.jsonl`), and turns the result
//! into a [`GrowthHistory`] ([`pdbem_coupling::growth::summary::history_of`]) with damage
//! snapshots of the windows (just before each relocation, labels
//! `damage_window<i>_step<kkk>_reloc<rrr>` (zero-padded, so the files sort in order) with r counting relocations, since a load step can
//! hold several; at the last step `damage_window<i>_step<kkk>`) and the displacement
//! magnitude over the PD nodes and BEM interior points at the last step (which needs the
//! scene's geometry, so it stays here).

use anyhow::{Context, Result};
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::V2;
use pdbem_coupling::growth::summary::{damage_snapshots, history_of, initial_windows};
use pdbem_coupling::growth::{Growth, IterationEvent, Observer, RelocationRecord, StepResult};
use pdbem_coupling::iteration::{CoupledProblem, CoupledSolution};
use pdbem_coupling::setup::WindowModel;
use serde_json::json;

use std::ops::ControlFlow;
use std::time::Instant;

use pdbem_coupling::growth::checkpoint::PdBemCheckpoint;
use pdbem_coupling::growth::history::WindowOutline;

use super::checkpoint::{self, resume_point, EngineState, ObserverState};
use super::log::{step_bar, GrowthLog};
use super::{FieldSnapshot, GrowthHistory};
use crate::geometry::{point_segment_projection, P2};
use crate::plot::ticks::human;
use crate::runner::context::RunContext;
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;
use crate::setup::growth::input;

/// Progress bar, run log, growth log and damage snapshots of a run.
struct Progress<'a> {
    ctx: &'a RunContext,
    scene: &'a Scene,
    bar: indicatif::ProgressBar,
    log: Option<GrowthLog>,
    tip_names: Vec<String>,
    snapshots: Vec<FieldSnapshot>,
    /// Relocations so far (several can happen in one load step).
    relocations: usize,
    /// Outlines of the initial windows (kept in checkpoints).
    initial_windows: Vec<WindowOutline>,
    /// When the last checkpoint was written (or the run started).
    last_saved: Instant,
    error: Option<anyhow::Error>,
}

impl Progress<'_> {
    fn log_event(&mut self, kind: &str, fields: serde_json::Value) {
        if let Some(l) = &self.log {
            if let Err(e) = l.event(kind, fields) {
                self.error.get_or_insert(e);
            }
        }
    }

    /// What a checkpoint keeps of this observer.
    fn observer_state(&self) -> ObserverState {
        ObserverState {
            snapshots: self.snapshots.clone(),
            relocations: self.relocations,
            initial_windows: self.initial_windows.clone(),
        }
    }

    /// After a checkpoint was written (or failed to be): [`checkpoint::after_save`].
    fn flow(&mut self, saved: Result<bool>) -> ControlFlow<()> {
        checkpoint::after_save(saved, &mut self.last_saved, &mut self.error)
    }

    fn tips_text(&self, tips: &[V2]) -> String {
        self.tip_names
            .iter()
            .zip(tips)
            .map(|(n, p)| format!("{n} ({:.3}, {:.3})", p.x, p.y))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl Observer for Progress<'_> {
    fn iteration(&mut self, e: &IterationEvent<'_>) {
        let msg = format!(
            "load factor {}, iteration {}, residual {:.2e}, {} bonds broke; {}",
            human(e.load, 4),
            e.iteration,
            e.residual,
            e.bonds_broken,
            self.tips_text(e.tips)
        );
        self.bar.set_message(msg);
    }

    fn step(&mut self, s: &StepResult) {
        self.bar.inc(1);
        self.log_event(
            "step",
            json!({"step": s.step, "load": s.load, "iterations": s.iterations,
                   "residual": s.residual, "converged": s.converged,
                   "broken_bonds": s.broken_bonds, "cmod": s.cmod,
                   "tips": s.tips.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(),
                   "relocations": s.relocations, "wall_time_s": s.wall_s, "pd_s": s.pd_s,
                   "window_solves": s.window_solves,
                   "overstrain": s.overstrain.map(|h| json!({
                       "position": [h.position.x, h.position.y],
                       "strain": h.strain, "onset": h.onset}))}),
        );
    }

    fn relocation(&mut self, r: &RelocationRecord) {
        // The damage snapshots taken just before this relocation show this tip.
        let tag = format!("_reloc{:03}", self.relocations);
        for snap in self.snapshots.iter_mut().rev() {
            if !snap.label.ends_with(&tag) {
                break;
            }
            snap.tips.push([r.tip_at.x, r.tip_at.y]);
        }
        let msg = format!(
            "load step {} (load factor {}): window of {} moved ({:.4}, {:.4}) -> ({:.4}, {:.4}), tip at ({:.4}, {:.4}), +{} BEM elements per face, {} elements ({:.0} % of the pairs reused), rebuild {:.2} s{}",
            r.step, human(r.load, 4), r.tip, r.from.x, r.from.y, r.to.x, r.to.y, r.tip_at.x, r.tip_at.y,
            r.elements_added, r.elements, 100.0 * r.bem_pairs_reused,
            r.rebuild_s * r.rebuild_shared_by as f64,
            if r.rebuild_shared_by > 1 {
                format!(" (shared by {} relocations)", r.rebuild_shared_by)
            } else {
                String::new()
            }
        );
        self.bar.suspend(|| self.ctx.log(&msg));
        self.log_event(
            "relocation",
            json!({"step": r.step, "load": r.load, "tip": r.tip, "from": [r.from.x, r.from.y],
                   "to": [r.to.x, r.to.y], "tip_at": [r.tip_at.x, r.tip_at.y],
                   "elements_added": r.elements_added, "elements": r.elements,
                   "precrack_deviation": r.precrack_deviation,
                   "transfer": {"exact_nodes": r.transfer.exact_nodes,
                                "near_nodes": r.transfer.near_nodes,
                                "bem_nodes": r.transfer.bem_nodes,
                                "bonds_copied": r.transfer.bonds_copied},
                   "rebuild_s": r.rebuild_s, "rebuild_shared_by": r.rebuild_shared_by,
                   "bem_assembly_s": r.bem_assembly_s, "bem_factor_s": r.bem_factor_s,
                   "bem_pairs_reused": r.bem_pairs_reused, "turned_deg": r.turned_deg}),
        );
    }

    fn note(&mut self, message: &str) {
        self.bar.suspend(|| self.ctx.log(message));
        self.log_event("note", json!({ "message": message }));
    }

    fn before_relocation(&mut self, step: usize, windows: &[WindowModel]) {
        self.relocations += 1;
        let tag = format!("_reloc{:03}", self.relocations);
        self.snapshots.extend(damage_snapshots(step, windows, &tag));
    }

    fn checkpoint(
        &mut self,
        step: usize,
        save: &mut dyn FnMut() -> PdBemCheckpoint,
    ) -> ControlFlow<()> {
        let observer = self.observer_state();
        let engine = EngineState::PdBem(save());
        let saved = checkpoint::save(self.ctx, self.scene, "pd-bem", step, engine, observer);
        self.flow(saved)
    }

    fn checkpoint_within(
        &mut self,
        step: usize,
        relocations: usize,
        save: &mut dyn FnMut() -> PdBemCheckpoint,
    ) -> ControlFlow<()> {
        if self.last_saved.elapsed() < self.ctx.round_checkpoint_every {
            return ControlFlow::Continue(());
        }
        let state = (EngineState::PdBem(save()), self.observer_state());
        let at = (step, relocations);
        let saved = checkpoint::save_within(self.ctx, self.scene, "pd-bem", at, state);
        self.flow(saved)
    }

    fn state(&mut self, s: &StepResult, pb: &CoupledProblem, sol: Option<&CoupledSolution>) {
        if !super::snapshot_steps(self.scene).contains(&s.step) {
            return;
        }
        self.snapshots
            .extend(damage_snapshots(s.step, &pb.windows, ""));
        if let Some(sol) = sol {
            self.snapshots
                .push(displacement_snapshot(self.scene, pb, sol, s.step));
        }
    }
}

/// Displacement magnitude at the PD nodes and at BEM interior points on a grid over the
/// body (outside windows and half an element from the boundary) at the last solution.
fn displacement_snapshot(
    scene: &Scene,
    pb: &CoupledProblem,
    sol: &CoupledSolution,
    step: usize,
) -> FieldSnapshot {
    let ev = FieldEvaluator::new(&pb.mesh, &pb.material, &sol.solution, pb.background);
    let geo = SceneGeometry::of(scene);
    let (lo, hi) = geo.bounds();
    let n = 60;
    let pts: Vec<V2> = crate::geometry::grid_centres(&lo, &hi, n)
        .into_iter()
        .filter(|x| {
            geo.contains(&P2::new(x.x, x.y))
                && !pb.windows.iter().any(|w| w.window.contains(*x, 0.0))
                && pb
                    .mesh
                    .elements
                    .iter()
                    .all(|e| point_segment_projection(x, &e.a, &e.b).0 > 0.5 * e.h)
        })
        .collect();
    let mut snap = FieldSnapshot {
        step,
        label: "displacement".into(),
        ..Default::default()
    };
    for (x, u) in pts.iter().zip(ev.displacements(&pts)) {
        snap.points.push([x.x, x.y]);
        snap.values.push(u[0].hypot(u[1]));
        snap.groups.push(0);
    }
    for w in &pb.windows {
        let (pos, u) = (w.model.positions(), w.model.displacements());
        for i in 0..w.model.n_real() {
            snap.points.push(pos[i]);
            snap.values.push(u[i][0].hypot(u[i][1]));
            snap.groups.push(1);
        }
    }
    snap
}

/// Runs PD-BEM growth of `scene`.
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<GrowthHistory> {
    let file = scene.file_label();
    let inp = input(scene)?;
    let coupling_notes = crate::setup::coupled::coupling_notes(scene, &inp.setup.layout);
    let count = inp.params.loads.count;
    ctx.log(&format!(
        "{}: PD-BEM growth, {} load steps from {} by {}, {} tip(s)",
        scene.name,
        count,
        inp.params.loads.initial,
        inp.params.loads.step,
        inp.setup.tips.len()
    ));
    let cp = resume_point(ctx, scene, "pd-bem")?;
    let log = match &cp {
        _ if GrowthLog::exists(ctx) => None,
        Some(c) => Some(GrowthLog::reopen(ctx, &c.log)?),
        None => Some(GrowthLog::open(ctx)?),
    };
    let tip_names = inp.setup.tips.iter().map(|t| t.name.clone()).collect();
    let (mut g, observed, at) = match cp {
        Some(c) => {
            let at = c.steps_done();
            let EngineState::PdBem(state) = c.engine else {
                anyhow::bail!("--resume: the checkpoint is not of a PD-BEM run");
            };
            ctx.log(&if c.within {
                format!(
                    "resuming inside load step {} after relocation {}",
                    c.step,
                    state.result.relocations.len()
                )
            } else {
                format!("resuming after load step {}", c.step)
            });
            let g = Growth::resume(inp.setup, &inp.scenario, inp.params, state)
                .with_context(|| format!("{}: PD-BEM growth resume", file.display()))?;
            (g, Some(c.observer), at)
        }
        None => {
            let g = Growth::new(inp.setup, &inp.scenario, inp.params)
                .with_context(|| format!("{}: PD-BEM growth setup", file.display()))?;
            (g, None, 0)
        }
    };
    let fresh = observed.is_none();
    let observed = observed.unwrap_or_else(|| ObserverState {
        initial_windows: initial_windows(&g),
        ..Default::default()
    });
    let mut progress = Progress {
        ctx,
        scene,
        bar: step_bar(ctx, count),
        log,
        tip_names,
        snapshots: observed.snapshots,
        relocations: observed.relocations,
        initial_windows: observed.initial_windows,
        last_saved: Instant::now(),
        error: None,
    };
    progress.bar.set_position(at as u64);
    if fresh {
        progress.log_event(
            "start",
            json!({"mode": "pd-bem", "steps": count, "elements": g.problem().mesh.len(),
                   "windows": g.problem().windows.len()}),
        );
    }
    let windows = progress.initial_windows.clone();
    let result = g
        .run(&mut progress)
        .with_context(|| format!("{}: PD-BEM growth", file.display()))?;
    progress.bar.finish_and_clear();
    if let Some(e) = progress.error.take() {
        return Err(e);
    }
    let mut h = history_of(&g, &result, windows);
    h.notes.splice(0..0, coupling_notes);
    let last = result.steps.len().saturating_sub(1);
    h.snapshots = std::mem::take(&mut progress.snapshots);
    h.snapshots
        .extend(damage_snapshots(last, &g.problem().windows, ""));
    if let Some(sol) = g.last_solution() {
        h.snapshots
            .push(displacement_snapshot(scene, g.problem(), sol, last));
    }
    for p in &h.paths {
        if let Some(why) = &p.ended {
            progress.log_event("tip_end", json!({"tip": p.name, "reason": why}));
        }
    }
    if let Some(f) = &result.failure {
        progress.log_event(
            "failure",
            json!({"step": f.step, "load": f.load, "tip": f.tip, "geometries": g.geometries()}),
        );
    }
    if let Some(e) = progress.error.take() {
        return Err(e);
    }
    super::sif_record::replay_record(scene, &mut h)?;
    Ok(h)
}
