//! BEM-only crack growth of a scene: the engine is [`pdbem_coupling::growth::bem_only`]
//! (SIF at the tip, MCS kink, fixed increment `da`, critical load from K_c); its input
//! comes from the setup layer ([`crate::setup::growth::bem_only_input`]) and its events
//! go to `growth_log.jsonl` and the progress bar ([`super::log::RunObserver`]).

use anyhow::{Context, Result};
use pdbem_coupling::growth::bem_only::{self as engine, TipCritical};

use super::checkpoint::{resume_point, EngineState};
use super::log::RunObserver;
use super::GrowthHistory;
use crate::runner::context::RunContext;
use crate::scene::Scene;
use crate::setup::growth::bem_only_input;
use pdbem_coupling::growth::checkpoint::EngineCheckpoint;

/// Runs BEM-only growth of `scene`.
/// With `ctx.resume` it goes on from the run folder's checkpoint
/// ([`super::checkpoint`]).
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<GrowthHistory> {
    let mut input = bem_only_input(scene)?;
    input.params.fail_step = ctx.fail_tries.map(|(k, _)| k);
    let cp = resume_point(ctx, scene, "bem-only")?;
    let steps = input.params.loads.len();
    let mut observer = RunObserver::for_scene(ctx, scene, "bem-only", steps, cp.as_ref())?;
    let resume = match cp.map(|c| c.engine) {
        Some(EngineState::Engine(EngineCheckpoint::BemOnly(c))) => Some(c),
        Some(_) => anyhow::bail!("--resume: the checkpoint is not of a BEM-only run"),
        None => None,
    };
    let history = engine::run_from(
        &input.body,
        input.front.clone(),
        &input.params,
        &input.scenario,
        &mut observer,
        resume,
    )
    .with_context(|| scene.file_label().display().to_string());
    observer.finish()?;
    let mut history = history?;
    if let (_, Some(note)) = crate::setup::growth::toughness(scene)? {
        history.notes.insert(0, note);
    }
    Ok(history)
}

/// Critical load factor of every tip of the scene's initial geometry: K_c / K_eq at unit
/// load.
pub fn critical_loads(scene: &Scene) -> Result<Vec<TipCritical>> {
    let input = bem_only_input(scene)?;
    engine::critical_loads(&input.body, &input.front, input.params.k_c, &input.scenario)
        .with_context(|| scene.file_label().display().to_string())
}

/// Refuses a scene whose initial geometry the run would refuse at its first solve (faces
/// that overlap under the loads, a K that does not settle): `pdbem check` calls it for
/// BEM-only growth scenes.
pub fn check(scene: &Scene) -> Result<()> {
    let input = bem_only_input(scene)?;
    engine::check_initial(&input.body, &input.front, input.params.da, &input.scenario)
        .with_context(|| scene.file_label().display().to_string())
}
