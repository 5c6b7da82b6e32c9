//! Running a scene: pick the mode from the sections present, call the solver,
//! add reference values and errors, write `summary.json`, `tips.csv`,
//! `cracks.csv` and the plots, all-or-nothing.
//!
//! Entry points: [`run_scene`], [`mode_of`]; types [`RunContext`] (what a
//! solver gets), [`RunSummary`] (what it returns), [`TipResult`], [`CrackResult`].
//! Reference values: [`reference`](mod@reference); notes on results that are not what
//! they seem: [`plausibility`]; tables and plots: [`report`].

pub mod context;
pub mod marks;
pub mod mode;
pub mod plausibility;
pub mod reference;
pub mod report;
pub mod summary;

pub use context::RunContext;
pub use mode::{mode_of, Mode};
pub use summary::{CrackResult, RunSummary, TipResult};

use std::path::Path;
use std::time::Instant;

use anyhow::Context;

use crate::scene::{GrowthMode, Scene};

/// Runs a validated scene into `out_dir`: size budget ([`crate::setup::estimate`]), solve,
/// plausibility notes ([`plausibility::review`]), reference errors, a check that every
/// reported number is finite, outputs.
/// On error nothing is left in `out_dir` (and a folder this run created is removed).
pub fn run_scene(scene: &Scene, out_dir: &Path, quiet: bool) -> anyhow::Result<RunSummary> {
    let options = RunOptions {
        quiet,
        ..Default::default()
    };
    run_scene_with(scene, out_dir, &options)
}

/// How [`run_scene_with`] runs a scene.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct RunOptions {
    /// No progress output.
    pub quiet: bool,
    /// Growth runs: go on from the run folder's checkpoint (`pdbem run --resume`).
    pub resume: bool,
    /// Growth runs: stop after this load step once its checkpoint is written (a test hook
    /// standing in for a kill; the run then fails and leaves only the checkpoint).
    pub stop_after: Option<usize>,
    /// Growth runs: failures injected into the tries of a load step (a test hook of the
    /// back-off, [`RunContext::fail_tries`]).
    pub fail_tries: Option<(usize, usize)>,
    /// Full PD and PD-BEM: the least time between checkpoints inside load steps (None: 5
    /// minutes, [`context::ROUND_CHECKPOINT_INTERVAL`]).
    pub round_checkpoint_every: Option<std::time::Duration>,
    /// Inside load step k, `Some((k, r))`, once its checkpoint is written, stop (a test
    /// hook): full PD after break round r, PD-BEM after the relocation that brings the
    /// run's relocation records to r.
    pub stop_within: Option<(usize, usize)>,
}

/// [`run_scene`] with [`RunOptions`]. A growth run writes a checkpoint after every load
/// step ([`crate::growth::checkpoint`]), deleted when the run's outputs are committed.
/// A run whose growth ended early (`complete: false` in the summary) still writes every
/// output and returns its summary; [`RunSummary::incomplete`] says why.
pub fn run_scene_with(
    scene: &Scene,
    out_dir: &Path,
    options: &RunOptions,
) -> anyhow::Result<RunSummary> {
    in_pool(|| run_in_pool(scene, out_dir, options))
}

/// Runs `f` on a thread of rayon's pool (inline when already on one). The solvers'
/// parallel loops are short (a window's 500 nodes, a BEM interface of 80 points), and a
/// loop started from a thread outside the pool hands its work over and puts the caller to
/// sleep on a lock each time: on `growth_tension_edge` (thousands of coupling
/// iterations) that cost 15 % of the CPU in the kernel and 26 % of the wall time
/// (7.8 s against 5.8 s on 2 cores). From inside the pool a loop runs inline unless an
/// idle thread steals part of it.
fn in_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| f())
}

fn run_in_pool(scene: &Scene, out_dir: &Path, options: &RunOptions) -> anyhow::Result<RunSummary> {
    let mode = mode_of(scene);
    crate::setup::estimate::check(scene)?;
    crate::setup::reference_loads::check(scene)?;
    crate::setup::fit_stations::check(scene)?;
    let stops = options.stop_after.is_some() || options.stop_within.is_some();
    if (options.resume || stops) && mode != Mode::Growth {
        anyhow::bail!(
            "{}: --resume applies to growth runs (scenes with a `growth` section)",
            scene.file_label().display()
        );
    }
    let mut ctx = RunContext::new(out_dir, options.quiet)
        .with_context(|| format!("cannot create the run folder {}", out_dir.display()))?;
    ctx.resume = options.resume;
    ctx.stop_after = options.stop_after;
    ctx.fail_tries = options.fail_tries;
    ctx.stop_within = options.stop_within;
    if let Some(every) = options.round_checkpoint_every {
        ctx.round_checkpoint_every = every;
    }
    let provenance = crate::provenance::Provenance::now();
    let start = Instant::now();
    let mut summary = match mode {
        Mode::Pd => crate::run_pd::run(scene, &ctx)?,
        Mode::Coupled => crate::run_coupled::run(scene, &ctx)?,
        Mode::Growth => run_growth(scene, &ctx)?,
        Mode::Bem => crate::run_bem::run(scene, &ctx)?,
    };
    if summary.wall_time_s == 0.0 {
        summary.wall_time_s = start.elapsed().as_secs_f64();
    }
    summary.scene = scene.name.clone();
    if summary.mode.is_empty() {
        summary.mode = mode.as_str().to_string();
    }
    plausibility::review(scene, &mut summary);
    reference::apply(scene, &mut summary);
    if let Some(field) = summary.non_finite() {
        let hint = if field.contains("_ref") || field.contains("_err") {
            "the analytic reference overflows double precision: check `reference` (its sigma and sizes)"
        } else {
            "the loading or the geometry is out of the range double precision can carry: check the boundary values, load factors and sizes"
        };
        anyhow::bail!(
            "{}: the run gave a non-finite result, {field}: {hint}",
            scene.file_label().display()
        );
    }
    record_provenance(scene, &ctx, &provenance, &mut summary)?;
    report::write_all(scene, &ctx, &mut summary)?;
    ctx.writer
        .commit()
        .with_context(|| format!("cannot move outputs into {}", out_dir.display()))?;
    crate::growth::checkpoint::RunCheckpoint::remove(out_dir);
    Ok(summary)
}

/// `scene.ron` (the resolved scene) and `provenance` in the summary.
fn record_provenance(
    scene: &Scene,
    ctx: &RunContext,
    p: &crate::provenance::Provenance,
    summary: &mut RunSummary,
) -> anyhow::Result<()> {
    let ron = crate::provenance::resolved_scene_ron(scene, p).context("writing scene.ron")?;
    ctx.writer.write_bytes("scene.ron", ron.as_bytes())?;
    summary
        .extra
        .insert("provenance".into(), serde_json::to_value(p)?);
    Ok(())
}

/// Growth: the scene's `growth.mode` picks the solver; every mode's history gets the
/// thin-ligament note of its paths ([`crate::growth::ligaments`]) and goes through the one
/// output layer ([`crate::growth::output::finish`]).
fn run_growth(scene: &Scene, ctx: &RunContext) -> anyhow::Result<RunSummary> {
    use crate::growth::{bem_only, full_pd, pd_bem};
    let mode = scene.growth.as_ref().map(|g| g.mode).unwrap_or_default();
    let mut history = match mode {
        GrowthMode::PdBem => pd_bem::run(scene, ctx)?,
        GrowthMode::BemOnly => bem_only::run(scene, ctx)?,
        GrowthMode::FullPd => full_pd::run(scene, ctx)?,
    };
    let ligaments = crate::growth::ligaments::notes(scene, &history);
    history.notes.extend(ligaments);
    crate::growth::output::finish(scene, ctx, &history)
}

#[cfg(test)]
mod tests {
    #[test]
    fn scenes_run_on_a_thread_of_the_pool() {
        assert_eq!(
            rayon::current_thread_index(),
            None,
            "the test thread is outside"
        );
        assert!(super::in_pool(rayon::current_thread_index).is_some());
        // Already inside: inline, on the same thread.
        let (outer, inner) = super::in_pool(|| {
            (
                rayon::current_thread_index(),
                super::in_pool(rayon::current_thread_index),
            )
        });
        assert_eq!(outer, inner);
    }
}
