//! Full-PD crack growth of a scene: the engine is [`pdbem_coupling::growth::full_pd`]
//! (the whole body in PD at the window spacing, frozen-history equilibria and break
//! rounds, tip tracking on the damage); its model comes from the setup layer
//! ([`crate::setup::pd::full_pd_problem`]) and its events go to `growth_log.jsonl` and the
//! progress bar ([`super::log::RunObserver`]).

use anyhow::{Context, Result};
use pdbem_coupling::growth::full_pd::{self as engine, FullPdParams};
use pdbem_pd::PdModel;

use super::checkpoint::{resume_point, EngineState};
use super::log::RunObserver;
use super::GrowthHistory;
use crate::runner::context::RunContext;
use crate::scene::Scene;
use pdbem_coupling::growth::checkpoint::EngineCheckpoint;

/// The PD model of the scene at the window spacing, that spacing and the horizon.
pub fn model_of(scene: &Scene) -> Result<(PdModel, f64, f64)> {
    let file = scene.file_label();
    let problem = crate::setup::pd::full_pd_problem(scene)?;
    let (dx, delta) = (problem.dx, problem.horizon());
    let model = PdModel::new(&problem).with_context(|| format!("{}: pd", file.display()))?;
    crate::setup::ligament::refuse_loaded_loose_nodes(scene, &model)?;
    Ok((model, dx, delta))
}

/// Runs full-PD growth of `scene` (with `ctx.resume`, from the run folder's checkpoint,
/// [`super::checkpoint`]).
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<GrowthHistory> {
    let (mut model, dx, delta) = model_of(scene)?;
    let growth = scene.growth.as_ref();
    let params = FullPdParams {
        dx,
        delta,
        loads: scene.load.factors(),
        damage_threshold: growth.map_or(0.38, |g| g.damage_threshold),
        snapshot_steps: growth.map(|g| g.snapshot_steps.clone()).unwrap_or_default(),
        fail_tries: ctx.fail_tries,
    };
    let front = crate::setup::growth::front(scene);
    let cp = resume_point(ctx, scene, "full-pd")?;
    let steps = params.loads.len();
    let mut obs = RunObserver::for_scene(ctx, scene, "full-pd", steps, cp.as_ref())?;
    let resume = match cp.map(|c| c.engine) {
        Some(EngineState::Engine(EngineCheckpoint::FullPd(c))) => Some(c),
        Some(_) => anyhow::bail!("--resume: the checkpoint is not of a full-PD run"),
        None => None,
    };
    let history = engine::run_from(&scene.name, &mut model, front, &params, &mut obs, resume)
        .with_context(|| scene.file_label().display().to_string());
    obs.finish()?;
    let mut history = history?;
    super::sif_record::replay_record(scene, &mut history)?;
    // Damage in the loaded edges' rows, which a body without the surface correction can
    // take before its crack (a horizon factor of 6 on the tension plate tore the pulled
    // edge off at the first load: failure declared, no tip moved).
    let problem = crate::setup::pd::full_pd_problem(scene)?;
    let damage = model.damage();
    history
        .notes
        .extend(crate::dynamic_notes::loaded_edge_damage_note(
            &problem,
            model.positions(),
            &damage,
        ));
    Ok(history)
}
