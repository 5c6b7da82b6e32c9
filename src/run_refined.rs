//! Stand-alone PD with adaptive particle refinement (`pd.refinement`, seed 004 section 3,
//! [`pdbem_pd::refine`]): the scene's grid becomes dual-horizon state-based particles,
//! the particles in the static regions (`near_cracks`, `circles`) and those damaged past
//! `critical_damage` by the pre-cracks (Eq. 15) split into four children (level by level
//! up to `max_level`), and the elastic equilibrium at the final load factor is solved by
//! conjugate gradients. With a breaking law (`CriticalStretch`, `FromGc`), pre-cracks
//! and a load ramp, the body runs the crack-initiation ramp of stand-alone PD instead
//! ([`pdbem_pd::refine::ramp`]: at every load, solve, split while Eq. 15 or Eq. 16 fires,
//! break, until the crack runs two horizons) and reports the same loads as
//! [`crate::run_pd`] (`first_break_load`, `initiation_load`, `kink_deg`). Writes the
//! particle table and plots like [`crate::run_pd`] (`nodes.csv` holds the particles) and
//! reports the particle counts and times. With `pd.solver: Explicit` the refined body runs
//! explicit dynamics instead ([`crate::run_adaptive`]).

use std::time::Instant;

use anyhow::{Context, Result};
use pdbem_pd::measure::Tip;
use pdbem_pd::refine::direct::Solver;
use pdbem_pd::refine::{ramp_observed, run as refine_run, RefinedRamp, Refinement};
use pdbem_pd::Selection;
use serde_json::json;

use crate::pd_loads::{
    damaged_throughout_note, initiation_notes, initiation_ramp, load_unit, report_initiation,
    scene_tips,
};
use crate::ramp_progress::RampProgress;
use crate::runner::context::RunContext;
use crate::runner::summary::RunSummary;
use crate::scene::{Failure, PdRefinement, Scene};
use crate::setup::pd::labelled_problem_from_scene;

/// The library settings of the scene's `pd.refinement` on the problem's pre-cracks.
pub fn settings(r: &PdRefinement, cracks: &[Vec<[f64; 2]>]) -> Refinement {
    let mut regions: Vec<Selection> = r
        .circles
        .iter()
        .map(|c| Selection::Circle {
            centre: [c.centre.0, c.centre.1],
            radius: c.radius,
        })
        .collect();
    let mut region_levels: Vec<u8> = r
        .circles
        .iter()
        .map(|c| c.level.unwrap_or(r.max_level))
        .collect();
    if let Some(d) = r.near_cracks {
        regions.extend(cracks.iter().map(|c| Selection::NearPolyline {
            points: c.clone(),
            distance: Some(d),
        }));
        region_levels.resize(regions.len(), r.max_level);
    }
    Refinement {
        critical_damage: r.critical_damage,
        strain_factor: r.strain_factor,
        regions,
        region_levels,
        max_level: r.max_level,
        max_rounds: 0,
        tolerance: r.tolerance,
        keep_horizon: r.keep_horizon,
    }
}

/// Solves `scene` with refined particles and writes its fields: the elastic solve, or with
/// a breaking law the crack-initiation ramp ([`pdbem_pd::refine::ramp`]); `pd.solver:
/// Explicit` runs the adaptive dynamics of [`crate::run_adaptive`] instead, chosen by
/// [`crate::run_pd::run`].
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<RunSummary> {
    let t0 = Instant::now();
    let file = scene.file_label();
    let (problem, _) = labelled_problem_from_scene(scene)?;
    let pd = scene.pd.as_ref().context("no pd section")?;
    let r = pd.refinement.as_ref().context("no pd.refinement")?;
    ctx.log(&format!("{}: PD solve with refinement", scene.name));
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "pd".into(),
        notes: crate::pd_loads::early_notes(scene, &problem, false, ctx),
        ..Default::default()
    };
    let breaking = matches!(pd.failure, Failure::CriticalStretch(_) | Failure::FromGc);
    let settings = settings(r, &problem.cracks);
    let body = if breaking {
        let tips = scene_tips(scene);
        let params = initiation_ramp(scene, problem.horizon(), 400);
        let mut bar = RampProgress::new(ctx, params.max_load);
        let out = ramp_observed(
            &problem,
            &settings,
            &tips,
            &params,
            Solver::default(),
            &mut |s| {
                let detail = format!(
                    "{} particles ({} split), crack extension {:.3e} m",
                    s.particles, s.split, s.extension
                );
                bar.converged(s.load, &detail)
            },
        );
        bar.finish();
        let out = out.with_context(|| format!("{}: refined PD load ramp", file.display()))?;
        report_ramp(scene, &out, &tips, problem.horizon(), &mut summary);
        out.body
    } else {
        let load = scene.load.factors().last().copied().unwrap_or(1.0);
        let out = refine_run(&problem, &settings, load)
            .with_context(|| format!("{}: refined PD", file.display()))?;
        let split: usize = out.rounds.iter().map(|x| x.split).sum();
        let e = &mut summary.extra;
        e.insert("split".into(), json!(split));
        e.insert(
            "iterations".into(),
            json!(out.rounds.iter().map(|x| x.iterations).sum::<usize>()),
        );
        e.insert(
            "time_s".into(),
            json!({"refinement": out.rounds.iter().map(|x| x.split_s).sum::<f64>(),
                   "solve": out.rounds.iter().map(|x| x.solve_s).sum::<f64>()}),
        );
        out.body
    };
    let base = body.level.iter().filter(|&&l| l == 0).count();
    ctx.log(&format!(
        "{}: {} particles ({} base, {} refined)",
        scene.name,
        body.len(),
        base,
        body.len() - base
    ));
    let levels: Vec<usize> = (0..=r.max_level)
        .map(|l| body.level.iter().filter(|&&x| x == l).count())
        .collect();
    let e = &mut summary.extra;
    e.insert("refinement".into(), json!(true));
    e.insert("traction".into(), json!(pd.traction));
    e.insert("particles".into(), json!(body.len()));
    e.insert("particles_per_level".into(), json!(levels));
    let phi = body.damage();
    crate::pd_fields::write_fields(scene, ctx, (body.positions(), &body.u, &phi), &mut summary)?;
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(summary)
}

/// The ramp's loads (Pa: the factor times the largest applied traction, as
/// [`crate::run_pd`]), kink angles and counts into `summary`; a ramp that reached its
/// last load without the crack running gets a note.
fn report_ramp(
    scene: &Scene,
    out: &RefinedRamp,
    tips: &[Tip],
    delta: f64,
    summary: &mut RunSummary,
) {
    let rec = &out.record;
    let b = &out.body;
    let mut kinks: Vec<Option<f64>> = tips
        .iter()
        .map(|t| b.kink_angle(*t, delta, 4.0 * delta))
        .collect();
    let real: Vec<usize> = (0..b.len()).filter(|&k| !b.layer[k]).collect();
    let phi: Vec<f64> = real.iter().map(|&k| b.damage_of(k)).collect();
    let throughout = damaged_throughout_note(&phi, |i| b.dh.volume[real[i]]);
    if throughout.is_some() {
        kinks.iter_mut().for_each(|k| *k = None);
    }
    summary.notes.extend(throughout);
    if let Some(why) = &rec.plain_cg {
        summary.notes.push(format!(
            "the refined ramp solved by plain conjugate gradients, same results but slower: {why}; raise --max-memory to precondition"
        ));
    }
    let unsettled: Vec<f64> = rec
        .steps
        .iter()
        .filter(|s| !s.settled)
        .map(|s| s.load)
        .collect();
    initiation_notes(
        scene,
        rec.first_break_load,
        rec.initiation_load,
        rec.extension,
        &unsettled,
        &mut summary.notes,
    );
    report_initiation(
        scene,
        rec.first_break_load,
        rec.initiation_load,
        rec.unstable,
        &kinks,
        &mut summary.extra,
    );
    let e = &mut summary.extra;
    e.insert("load_unit".into(), json!(load_unit(scene)));
    e.insert("extension".into(), json!(rec.extension));
    let split: usize = rec.setup_split + rec.steps.iter().map(|s| s.split).sum::<usize>();
    e.insert("split".into(), json!(split));
    e.insert("iterations".into(), json!(rec.iterations));
    e.insert("ramp".into(), json!(rec.steps));
    e.insert(
        "time_s".into(),
        json!({"refinement": rec.split_s, "solve": rec.solve_s}),
    );
}
