//! Stand-alone PD solve of a scene (issue 3): grid the body, cut the pre-cracks, apply the
//! scene's conditions (displacements on fictitious layers of depth delta, tractions as body
//! forces in a boundary layer one node column deep, seed 000 section 2.3, or through seed
//! 001's transfer functions with `pd.traction: TransferFunction`), solve with the scene's
//! solver, and report (`mode: "pd"`, `traction` names the choice).
//!
//! Three kinds of scene:
//! - elastic (`failure: Elastic`): one equilibrium at the final load factor;
//! - crack initiation (cracks + `CriticalStretch` / `FromGc`, several load steps): the load
//!   is ramped from `load.initial` by `load.step` with brittle breaking until the crack runs
//!   by two horizons ([`pdbem_pd::measure::ramp_to_initiation`]); the initiation load is
//!   reported in Pa (factor times the largest applied traction) and the kink angle from the
//!   damage in the annulus delta..4 delta around each tip;
//! - damage with the tanh degradation (seed 000): the scene's solver drives the load to the
//!   final factor.
//!
//! With `pd.refine_zones` the grid's cells inside the zones are split (`pdbem_pd::mixed`,
//! dual-horizon forces between the sizes, seed 004 Eq. 13) and every path above runs on
//! the mixed grid; `refined_nodes` counts the children. With `pd.refinement` on the
//! grid's cells (`on: Cells`, or the tanh law) seed 004's criteria split cells as the
//! load rises (`pdbem_pd::adapt`: the damage ramp by [`ramp_to_limit`], crack initiation
//! by [`pdbem_pd::adapt::initiation`]); seed 004's particles run elsewhere
//! ([`crate::run_refined`], [`crate::run_adaptive`]).
//!
//! Pure-traction scenes get two pins (the real node at the bottom middle: both components;
//! the one at the top middle: x) so the implicit tangent is regular; the loads are
//! self-equilibrated, so the pins carry no reaction.

use crate::load_displacement::LoadDisplacement;
use crate::pd_loads::{
    damaged_throughout_note, first_load_note, initiation_notes, initiation_ramp, load_unit,
    report_initiation, round12, scene_tips, traction_scale,
};
use crate::ramp_progress::RampProgress;
use crate::runner::context::RunContext;
use crate::runner::summary::RunSummary;
use crate::scene::{Failure, PdRefinement, PdSolver, Scene};
use crate::setup::pd::labelled_problem_from_scene;
use anyhow::{Context, Result};
use pdbem_pd::adapt::initiation::ramp_to_initiation as initiation_on_cells;
use pdbem_pd::adapt::ramp::{ramp_to_limit, AdaptEvent, Round};
use pdbem_pd::adapt::{AdaptiveCells, CellCriteria};
use pdbem_pd::error::factor_text;
use pdbem_pd::measure::{kink_angle, ramp_to_initiation_observed};
use pdbem_pd::solvers::limit::Stop;
use pdbem_pd::solvers::limit_solvers::{solve_to_limit, QuasiStatic};
use pdbem_pd::solvers::{adr, implicit, switching, Convergence};
use pdbem_pd::PdModel;
use serde_json::json;
use std::time::Instant;

/// The error of an explicit-dynamics scene on the equilibrium path.
fn unreachable_explicit(file: &std::path::Path) -> Result<pdbem_pd::SolveInfo> {
    anyhow::bail!(
        "{}: pd.solver: Explicit dynamics runs through `pdbem run` (crate::run_dynamic), not this equilibrium path",
        file.display()
    )
}

/// Solves `scene` with peridynamics over the whole body and writes the node table and
/// the damage and displacement plots through `ctx.writer`.
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<RunSummary> {
    if let Some((pd, r)) = scene
        .pd
        .as_ref()
        .and_then(|pd| pd.refinement.as_ref().map(|r| (pd, r)))
    {
        if crate::run_dynamic::explicit(scene).is_some() {
            return crate::run_adaptive::run(scene, ctx);
        }
        if !r.on_cells(&pd.failure, &pd.solver) {
            return crate::run_refined::run(scene, ctx);
        }
    }
    if crate::run_dynamic::is_dynamic(scene) {
        return crate::run_dynamic::run(scene, ctx);
    }
    let t0 = Instant::now();
    ctx.log(&format!("{}: PD solve", scene.name));
    let problem = crate::setup::pd::problem_from_scene(scene)?;
    let overload = crate::pd_loads::early_notes(scene, &problem, false, ctx);
    let last = scene.load.factors().last().copied().unwrap_or(1.0);
    let mut bar = RampProgress::new(ctx, last);
    let mut observe = |e: AdaptEvent| match e {
        AdaptEvent::Ramp(e) => bar.show(e),
        AdaptEvent::Refined(r) => bar.message(format!(
            "load factor {}: {} cells split, {} nodes",
            factor_text(r.load),
            r.cells,
            r.nodes
        )),
    };
    let solved = solve_observed(scene, &mut observe);
    bar.finish();
    let (mut summary, model, ld) = solved?;
    summary.notes.splice(0..0, overload);
    ctx.log(&format!(
        "{}: {} real nodes, {} bonds, {} broken",
        scene.name,
        model.n_real(),
        model.n_bonds() / 2,
        model.broken_bonds()
    ));
    let n = model.n_real();
    let (x, u, phi) = (model.positions(), model.displacements(), model.damage());
    crate::pd_fields::write_fields(scene, ctx, (&x[..n], &u[..n], &phi[..n]), &mut summary)?;
    crate::load_displacement::write(scene, ctx, &ld, &mut summary)?;
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(summary)
}

/// Solves `scene` with peridynamics over the whole body without writing anything: the
/// summary and the final model.
pub fn solve(scene: &Scene) -> Result<(RunSummary, PdModel)> {
    let (summary, model, _) = solve_recorded(scene)?;
    Ok((summary, model))
}

/// [`solve`] and the load-displacement record of its load steps.
pub fn solve_recorded(scene: &Scene) -> Result<(RunSummary, PdModel, LoadDisplacement)> {
    solve_observed(scene, &mut |_| {})
}

/// The library criteria of the scene's `pd.refinement` on the grid's cells.
pub fn cell_criteria(r: &PdRefinement) -> CellCriteria {
    let max_level = u32::from(r.max_level);
    CellCriteria {
        critical_damage: r.critical_damage,
        strain_factor: r.strain_factor,
        max_level,
        near_cracks: r.near_cracks,
        before_breaking: r.split_before_breaking.unwrap_or(true),
        circles: r
            .circles
            .iter()
            .map(|c| {
                let level = c.level.map_or(max_level, u32::from);
                ([c.centre.0, c.centre.1], c.radius, level)
            })
            .collect(),
    }
}

/// [`solve_recorded`], with the events of a damage ramp (and of its refinement) to
/// `observe`.
pub fn solve_observed(
    scene: &Scene,
    observe: &mut dyn FnMut(AdaptEvent),
) -> Result<(RunSummary, PdModel, LoadDisplacement)> {
    let t0 = Instant::now();
    let file = scene.file_label();
    let (problem, labels) = labelled_problem_from_scene(scene)?;
    let mut model = PdModel::new(&problem).with_context(|| format!("{}: pd", file.display()))?;
    let pd = scene.pd.as_ref().context("no pd section")?;
    let cells = pd
        .refinement
        .as_ref()
        .filter(|r| r.on_cells(&pd.failure, &pd.solver));
    if pd.refinement.is_some() && cells.is_none() {
        anyhow::bail!(
            "{}: pd.refinement runs through `pdbem run` (stand-alone PD), not this solver path",
            file.display()
        );
    }
    if matches!(pd.solver, PdSolver::Explicit(_)) {
        unreachable_explicit(&file)?;
    }
    crate::setup::ligament::refuse_loaded_loose_nodes(scene, &model)?;
    let factors = scene.load.factors();
    let last = factors.last().copied().unwrap_or(1.0);
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "pd".into(),
        ..Default::default()
    };
    // One rule for the routing and for the note on an unread solver.
    let info = if scene.runs_pd_initiation_ramp() {
        let tips = scene_tips(scene);
        let delta = problem.horizon();
        let ramp = initiation_ramp(scene, delta, INITIATION_ROUNDS);
        let init = match cells {
            Some(r) => {
                let out = initiation_on_cells(&problem, &cell_criteria(r), &tips, &ramp, observe)
                    .with_context(|| format!("{}: load ramp", file.display()))?;
                report_cells(&out.cells, &out.rounds, &mut summary);
                model = out.model;
                out.init
            }
            None => ramp_to_initiation_observed(&mut model, &tips, &ramp, &mut |e| {
                observe(AdaptEvent::Ramp(e))
            })
            .with_context(|| format!("{}: load ramp", file.display()))?,
        };
        let mut kinks: Vec<Option<f64>> = tips
            .iter()
            .map(|t| kink_angle(&model, *t, delta, 4.0 * delta))
            .collect();
        let n = model.n_real();
        let throughout =
            damaged_throughout_note(&model.damage()[..n], |k| model.grid().node_volume(k));
        if throughout.is_some() {
            kinks.iter_mut().for_each(|k| *k = None);
        }
        summary.notes.extend(throughout);
        report_initiation(
            scene,
            init.first_break_load,
            init.initiation_load,
            init.unstable,
            &kinks,
            &mut summary.extra,
        );
        initiation_notes(
            scene,
            init.first_break_load,
            init.initiation_load,
            init.extension,
            &init.unsettled_loads,
            &mut summary.notes,
        );
        init.info
    } else {
        // Elastic bonds: one equilibrium at the final load (module docs). A ramp of
        // `load.count` increments changes nothing but the cost: 70 Newton steps took
        // 230 s on the 200 x 200 seed 001 plate, one step 2.9 s.
        let elastic = pd.failure == Failure::Elastic;
        let steps = if elastic { 1 } else { factors.len().max(1) };
        let solver = quasi_static(&pd.solver, last, steps)
            .with_context(|| format!("{}: PD solve", file.display()))?;
        // An elastic solve that fails is an error; a ramp with damage stops at the last
        // load the solver brings to equilibrium after halving the failed step.
        let cutbacks = if elastic { 0 } else { RAMP_CUTBACKS };
        let mut refined_stop = false;
        let out = match cells {
            Some(r) => {
                let adaptive = ramp_to_limit(
                    &problem,
                    &solver,
                    steps,
                    &cell_criteria(r),
                    cutbacks,
                    observe,
                )
                .with_context(|| format!("{}: PD solve", file.display()))?;
                report_cells(&adaptive.cells, &adaptive.rounds, &mut summary);
                refined_stop = adaptive.refined_without_equilibrium;
                model = adaptive.model;
                adaptive.solve
            }
            None => solve_to_limit(&mut model, &solver, cutbacks, &mut |e| {
                observe(AdaptEvent::Ramp(e))
            })
            .with_context(|| format!("{}: PD solve", file.display()))?,
        };
        if let Some(stop) = &out.stop {
            if elastic {
                return Err(anyhow::Error::new(stop.error.clone()))
                    .with_context(|| format!("{}: PD solve", file.display()));
            }
            report_stop(scene, stop, refined_stop, &mut summary);
        } else if !elastic {
            summary.extra.insert("complete".into(), json!(true));
        }
        out.info
    };
    let first_break = info
        .steps
        .iter()
        .find(|s| s.broken_bonds > 0)
        .map(|s| s.load);
    if !summary.extra.contains_key("first_break_load") {
        let scale = traction_scale(scene).unwrap_or(1.0);
        summary.extra.insert(
            "first_break_load".into(),
            json!(first_break.map(|f| round12(f * scale))),
        );
        let first = info.steps.first().map(|s| s.load);
        summary
            .notes
            .extend(first.and_then(|f| first_load_note(f, first_break, None)));
    }
    // The unit of the loads above: the largest applied traction times the factor, or the
    // factor alone when the scene applies no traction.
    summary
        .extra
        .insert("load_unit".into(), json!(load_unit(scene)));
    summary.extra.insert("traction".into(), json!(pd.traction));
    summary.extra.insert("nodes".into(), json!(model.n_real()));
    if !pd.refine_zones.is_empty() || cells.is_some() {
        let g = model.grid();
        let fine = (0..model.n_real()).filter(|&i| g.node_dx(i) < g.dx).count();
        summary.extra.insert("refined_nodes".into(), json!(fine));
    }
    summary
        .extra
        .insert("bonds".into(), json!(model.n_bonds() / 2));
    summary
        .extra
        .insert("broken_bonds".into(), json!(model.broken_bonds()));
    summary
        .extra
        .insert("iterations".into(), json!(info.iterations));
    summary
        .extra
        .insert("factorizations".into(), json!(info.factorizations));
    summary
        .extra
        .insert("kept_factor_solves".into(), json!(info.kept_factor_solves));
    summary.extra.insert("phases".into(), json!(info.phases));
    summary
        .extra
        .insert("switch_points".into(), json!(info.switch_points));
    summary.extra.insert(
        "time_s".into(),
        json!({"implicit": info.time_implicit_s, "explicit": info.time_explicit_s,
               "assembly": info.time_assembly_s, "factorization": info.time_factorization_s}),
    );
    let ld = LoadDisplacement::from_pd(&labels, &info.steps);
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok((summary, model, ld))
}

/// `refinement` in the summary of a ramp on refined cells: the rounds (load factor,
/// cells split, real nodes after) and the split cells by level.
fn report_cells(cells: &AdaptiveCells, rounds: &[Round], summary: &mut RunSummary) {
    let by_level = |l: u32| cells.levels().values().filter(|&&v| v == l).count();
    let rounds: Vec<_> = rounds
        .iter()
        .map(|r| json!({"load_factor": round12(r.load), "cells": r.cells, "nodes": r.nodes}))
        .collect();
    summary.extra.insert(
        "refinement".into(),
        json!({
            "on": "cells",
            "cells_level_1": by_level(1),
            "cells_level_2": by_level(2),
            "rounds": rounds,
        }),
    );
}

/// Break-and-re-solve rounds of one load of the crack-initiation ramp before the load is
/// noted as unsettled: a crack growing stably at one load breaks a few bonds per round
/// (the displacement-controlled seed 004 plate on 0.5 mm cells needed more than 200 to
/// run its five horizons; docs/seed004.md).
pub const INITIATION_ROUNDS: usize = 1000;

/// Halvings of a failed load step before a damage ramp stops (a bracket of the last
/// converged load to 1/16 of the step).
pub const RAMP_CUTBACKS: u32 = 4;

/// The scene's quasi-static solver driving the load to `last` in `steps` equal steps
/// (Newton and ADR; the switching solver takes its own increments).
fn quasi_static(solver: &PdSolver, last: f64, steps: usize) -> Result<QuasiStatic> {
    let conv = |tol: f64| Convergence::Displacement { e0: tol };
    Ok(match solver {
        PdSolver::Explicit(_) => anyhow::bail!(
            "pd.solver: Explicit dynamics runs through `pdbem run` (crate::run_dynamic)"
        ),
        PdSolver::Implicit(p) => QuasiStatic::Implicit(implicit::ImplicitParams {
            target_load: last,
            steps,
            convergence: conv(p.tolerance),
            max_iters: p.max_iter,
            ..Default::default()
        }),
        PdSolver::Adr(p) => QuasiStatic::Adr(adr::AdrParams {
            target_load: last,
            steps,
            convergence: conv(p.tolerance),
            max_iters: p.max_iter,
            safety: p.safety_factor.max(1.0),
            ..Default::default()
        }),
        PdSolver::Switching(p) => QuasiStatic::Switching(switching::SwitchingParams {
            target_load: last,
            implicit_steps: p.implicit_steps,
            explicit_steps: p.explicit_steps,
            convergence: conv(p.tolerance),
            max_newton_iters: p.max_newton,
            max_adr_iters: p.max_adr,
            ..Default::default()
        }),
    })
}

/// A damage ramp that stopped before its last load (docs/outputs.md): `complete: false`,
/// `failure_reason` and `limit` (the last converged and the failed load in the scene's
/// load unit, the halvings tried) into the summary; the outputs are those of the last
/// converged state and the run exits with code 3.
fn report_stop(scene: &Scene, stop: &Stop, refined: bool, summary: &mut RunSummary) {
    let scale = traction_scale(scene).unwrap_or(1.0);
    let unit = load_unit(scene);
    let load = |f: f64| round12(f * scale);
    let text = |f: f64| {
        if unit == "Pa" {
            format!("load factor {} ({:.6e} Pa)", round12(f), load(f))
        } else {
            format!("load factor {}", round12(f))
        }
    };
    // Under prescribed loads the usual cause is the peak load; under prescribed
    // displacements alone a snap-back or an unstable crack (the load drops as the
    // displacement is held).
    let cause = if unit == "Pa" {
        "Under prescribed loads a softening body has no equilibrium past its peak load, which then lies between these two loads; prescribed displacements follow the softening branch beyond it"
    } else {
        "Under prescribed displacements this is a snap-back or a crack running unstably (the equilibrium path turns back in the displacement); a smaller load.step or another pd.solver may pass it"
    };
    let reason = if refined {
        format!(
            "pd.refinement split cells at {} and the refined grid found no equilibrium there ({}); the outputs hold the coarser grid's converged state at that load. {cause}",
            text(stop.last_load),
            stop.error,
        )
    } else {
        format!(
            "no equilibrium at {} after {} halvings of the load step ({}); the outputs hold the last converged state, at {}. {cause}",
            text(stop.failed_load),
            stop.cutbacks,
            stop.error,
            text(stop.last_load),
        )
    };
    summary.extra.insert("complete".into(), json!(false));
    summary.extra.insert("failure_reason".into(), json!(reason));
    summary.extra.insert(
        "limit".into(),
        json!({
            "last_converged_load": load(stop.last_load),
            "failed_load": load(stop.failed_load),
            "load_unit": unit,
            "cutbacks": stop.cutbacks,
        }),
    );
}
