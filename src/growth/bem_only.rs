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
/// Returns the cost of that solve ([`cost_line`] turns it into the run's estimate).
pub fn check(scene: &Scene) -> Result<engine::InitialSolve> {
    let input = bem_only_input(scene)?;
    engine::check_initial(&input.body, &input.front, input.params.da, &input.scenario)
        .with_context(|| scene.file_label().display().to_string())
}

/// A run whose estimate ([`cost_line`]) exceeds this many seconds gets a note from
/// `pdbem check`.
pub const LONG_RUN_S: f64 = 3600.0;

/// The line `pdbem check` prints on what a BEM-only run can cost: every growth round
/// meshes and solves the body anew, as long as the first solve took; a tip crossing the
/// body takes its diagonal over `da` rounds. With the note when that exceeds
/// [`LONG_RUN_S`]. (`growth_tension_edge` with da = 0.0023 m: 0.15-0.2 s a solve, 8700
/// rounds across, up to 26 minutes; the run grows 3500 increments in its first step.)
pub fn cost_line(s: &engine::InitialSolve) -> (String, Option<String>) {
    let total = s.seconds * s.increments_across;
    let line = format!(
        "BEM-only growth: the first geometry solved in {:.3} s ({} elements); every increment \
         is a solve like it, and tips crossing the body take up to {:.0} increments of da = \
         {:.4e} m: up to {}",
        s.seconds,
        s.elements,
        s.increments_across,
        s.da,
        duration_text(total)
    );
    let note = (total > LONG_RUN_S).then(|| {
        format!(
            "growth.da: a BEM-only run of this scene can take {} (up to {:.0} increments of \
             {:.3} s each); progress is checkpointed every 5 minutes (pdbem run --resume), or \
             take a larger da",
            duration_text(total),
            s.increments_across,
            s.seconds
        )
    });
    (line, note)
}

/// Seconds as `12 s`, `3.4 min` or `5.6 h`.
fn duration_text(t: f64) -> String {
    if t < 60.0 {
        format!("{t:.0} s")
    } else if t < 3600.0 {
        format!("{:.1} min", t / 60.0)
    } else {
        format!("{:.1} h", t / 3600.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solve(seconds: f64, increments_across: f64) -> engine::InitialSolve {
        engine::InitialSolve {
            elements: 841,
            seconds,
            da: 2.3e-3,
            increments_across,
        }
    }

    #[test]
    fn the_cost_line_multiplies_the_first_solve_by_the_increments_across() {
        let (line, note) = cost_line(&solve(0.25, 9722.0));
        assert!(line.contains("up to 9722 increments") && line.ends_with("up to 40.5 min"));
        assert!(note.is_none());
        let (line, note) = cost_line(&solve(4.0, 1e4));
        assert!(line.ends_with("up to 11.1 h"), "{line}");
        let note = note.expect("a run over an hour is noted");
        assert!(note.starts_with("growth.da: a BEM-only run of this scene can take 11.1 h"));
        assert!(cost_line(&solve(0.01, 100.0)).0.ends_with("up to 1 s"));
    }
}
