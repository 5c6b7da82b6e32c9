//! Stand-alone PD with adaptive particle refinement (`pd.refinement`, seed 004 section 3,
//! [`pdbem_pd::refine`]): the scene's grid becomes dual-horizon state-based particles,
//! the particles in the static regions (`near_cracks`, `circles`) and those damaged past
//! `critical_damage` by the pre-cracks (Eq. 15) split into four children (level by level
//! up to `max_level`), and the elastic equilibrium at the final load factor is solved by
//! conjugate gradients. Writes the particle table and plots like [`crate::run_pd`]
//! (`nodes.csv` holds the particles) and reports the particle counts and times. With
//! `pd.solver: Explicit` the refined body runs explicit dynamics instead
//! ([`crate::run_adaptive`]).

use std::time::Instant;

use anyhow::{Context, Result};
use pdbem_pd::refine::{run as refine_run, Refinement};
use pdbem_pd::Selection;
use serde_json::json;

use crate::runner::context::RunContext;
use crate::runner::summary::RunSummary;
use crate::scene::{PdRefinement, Scene};
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
    if let Some(d) = r.near_cracks {
        regions.extend(cracks.iter().map(|c| Selection::NearPolyline {
            points: c.clone(),
            distance: Some(d),
        }));
    }
    Refinement {
        critical_damage: r.critical_damage,
        strain_factor: None,
        regions,
        max_level: r.max_level,
        max_rounds: 0,
        tolerance: r.tolerance,
        keep_horizon: r.keep_horizon,
    }
}

/// Solves `scene` with refined particles and writes its fields (elastic; `pd.solver:
/// Explicit` runs the adaptive dynamics of [`crate::run_adaptive`] instead, chosen by
/// [`crate::run_pd::run`]).
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<RunSummary> {
    let t0 = Instant::now();
    let file = scene.file_label();
    let (problem, _) = labelled_problem_from_scene(scene)?;
    let pd = scene.pd.as_ref().context("no pd section")?;
    let r = pd.refinement.as_ref().context("no pd.refinement")?;
    let load = scene.load.factors().last().copied().unwrap_or(1.0);
    ctx.log(&format!("{}: PD solve with refinement", scene.name));
    let out = refine_run(&problem, &settings(r, &problem.cracks), load)
        .with_context(|| format!("{}: refined PD", file.display()))?;
    let b = &out.body;
    let base = b.level.iter().filter(|&&l| l == 0).count();
    ctx.log(&format!(
        "{}: {} particles ({} base, {} refined)",
        scene.name,
        b.len(),
        base,
        b.len() - base
    ));
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "pd".into(),
        ..Default::default()
    };
    let split: usize = out.rounds.iter().map(|x| x.split).sum();
    let levels: Vec<usize> = (0..=r.max_level)
        .map(|l| b.level.iter().filter(|&&x| x == l).count())
        .collect();
    let e = &mut summary.extra;
    e.insert("refinement".into(), json!(true));
    e.insert("traction".into(), json!(pd.traction));
    e.insert("particles".into(), json!(b.len()));
    e.insert("particles_per_level".into(), json!(levels));
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
    let phi = b.damage();
    crate::pd_fields::write_fields(scene, ctx, (b.positions(), &b.u, &phi), &mut summary)?;
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(summary)
}
