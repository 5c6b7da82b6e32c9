//! Growth checkpoints on disk and `pdbem run --resume`.
//!
//! After every load step that does not end the run, the growth observers write
//! `<out>/.pdbem-checkpoint.ron` atomically (temp + rename, [`crate::output::write_atomic`]):
//! a [`RunCheckpoint`] holding the engine's state
//! ([`pdbem_coupling::growth::checkpoint`]), what the observer gathered (snapshots, the
//! PD-BEM initial window outlines and relocation count) and the text of
//! `growth_log.jsonl` so far. Full PD also writes one inside a load step, after a break
//! round at which its solvers are renewed, PD-BEM just after a relocation (where its
//! state is whole; the seed's runs grow the whole path in one load step) and BEM-only
//! after a growth round whose geometry was solved (unstable growth runs within one load
//! step: 3500 increments, 7 minutes, on `growth_tension_edge` with da = 0.0023 m), when
//! [`RunContext::round_checkpoint_every`] (5 minutes) has passed since the last
//! ([`save_within`]). It lives in the run folder, outside the staging folder, so it
//! survives a kill; a run that finishes (complete or not) deletes it with its commit.
//!
//! `pdbem run SCENE --out DIR --resume` reads it, refuses it when the scene (resolved:
//! after `--growth-mode`, as serialised) hashes differently or pdbem's version differs,
//! and continues the run from the next load step. The resumed run's outputs equal an
//! uninterrupted run's bit for bit except wall times (see the engines' checkpoint docs).
//!
//! Format: RON. Floats are written by Rust's shortest round-trip formatting and parsed
//! back exactly (`tests::ron_floats_round_trip_bit_for_bit`); NaN is written as `NaN` and
//! read back as NaN (its payload is not kept; none is used).

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use pdbem_coupling::growth::checkpoint::{EngineCheckpoint, PdBemCheckpoint};
use pdbem_coupling::growth::history::WindowOutline;
use serde::{Deserialize, Serialize};

use super::FieldSnapshot;
use crate::output::write_atomic;
use crate::runner::context::RunContext;
use crate::scene::Scene;

/// File name of the checkpoint in the run folder.
pub const CHECKPOINT_FILE: &str = ".pdbem-checkpoint.ron";

/// Format version of [`RunCheckpoint`].
const FORMAT: u32 = 1;

/// The engine part of a checkpoint (built once per checkpoint and moved whole: the size
/// difference of the variants does not matter).
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum EngineState {
    /// PD-BEM.
    PdBem(PdBemCheckpoint),
    /// BEM-only or full PD.
    Engine(EngineCheckpoint),
}

/// What the binary's observers gathered before the checkpoint.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ObserverState {
    /// Field snapshots taken so far (PD-BEM: window damage before relocations and at the
    /// snapshot steps).
    pub snapshots: Vec<FieldSnapshot>,
    /// PD-BEM: relocations so far (labels of the snapshots).
    pub relocations: usize,
    /// PD-BEM: outlines of the initial windows.
    pub initial_windows: Vec<WindowOutline>,
}

/// A checkpoint file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunCheckpoint {
    /// [`FORMAT`].
    pub format: u32,
    /// pdbem version that wrote it.
    pub version: String,
    /// [`scene_hash`] of the resolved scene.
    pub scene_hash: String,
    /// Growth mode (`pd-bem`, `bem-only`, `full-pd`).
    pub mode: String,
    /// The last completed load step (0-based); with `within`, the step in progress.
    pub step: usize,
    /// Written inside `step`, after a break round (full PD), a relocation (PD-BEM) or a
    /// growth round (BEM-only): the step is not complete.
    /// Absent in checkpoints written before it was kept (they were all at step ends or
    /// read as such).
    #[serde(default)]
    pub within: bool,
    /// The engine's state.
    pub engine: EngineState,
    /// The observer's.
    pub observer: ObserverState,
    /// `growth_log.jsonl` as written up to the checkpoint.
    pub log: String,
}

/// Path of the checkpoint of a run folder.
pub fn path(out_dir: &Path) -> PathBuf {
    out_dir.join(CHECKPOINT_FILE)
}

/// FNV-1a (64 bit) of the scene as serialised to JSON (field order fixed, maps sorted),
/// hex: the same resolved scene always hashes the same, in any process.
pub fn scene_hash(scene: &Scene) -> String {
    let text = serde_json::to_string(scene).unwrap_or_default();
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

impl RunCheckpoint {
    /// A checkpoint of `scene` after `step`.
    pub fn new(
        scene: &Scene,
        mode: &str,
        step: usize,
        engine: EngineState,
        observer: ObserverState,
        log: String,
    ) -> Self {
        RunCheckpoint {
            format: FORMAT,
            version: env!("CARGO_PKG_VERSION").to_string(),
            scene_hash: scene_hash(scene),
            mode: mode.to_string(),
            step,
            within: false,
            engine,
            observer,
            log,
        }
    }

    /// The load steps complete at this checkpoint.
    pub fn steps_done(&self) -> usize {
        if self.within {
            self.step
        } else {
            self.step + 1
        }
    }

    /// Writes it atomically into the run folder.
    pub fn write(&self, out_dir: &Path) -> Result<()> {
        let text = ron::to_string(self).context("serialising the growth checkpoint")?;
        let p = path(out_dir);
        write_atomic(&p, text.as_bytes()).with_context(|| format!("writing {}", p.display()))
    }

    /// Reads the checkpoint of `out_dir` for `scene` run in growth mode `mode`: an error
    /// when there is none, it cannot be read, or it belongs to another scene, mode or
    /// version.
    pub fn read_for(out_dir: &Path, scene: &Scene, mode: &str) -> Result<RunCheckpoint> {
        let p = path(out_dir);
        let text = std::fs::read_to_string(&p).with_context(|| {
            format!(
                "--resume: no checkpoint to resume from in {} ({} cannot be read); run \
                 without --resume to start afresh",
                out_dir.display(),
                p.display()
            )
        })?;
        let cp: RunCheckpoint = ron::from_str(&text)
            .with_context(|| format!("--resume: {} is not a pdbem checkpoint", p.display()))?;
        if cp.format != FORMAT || cp.version != env!("CARGO_PKG_VERSION") {
            bail!(
                "--resume: {} was written by pdbem {} (format {}), this is {} (format {}); \
                 run without --resume to start afresh",
                p.display(),
                cp.version,
                cp.format,
                env!("CARGO_PKG_VERSION"),
                FORMAT
            );
        }
        if cp.scene_hash != scene_hash(scene) || cp.mode != mode {
            bail!(
                "--resume: the checkpoint in {} belongs to another scene (or growth mode: \
                 {} there, {mode} here): the scene was changed since the interrupted run \
                 (hash {} there, {} here); restore the scene or run without --resume",
                out_dir.display(),
                cp.mode,
                cp.scene_hash,
                scene_hash(scene)
            );
        }
        Ok(cp)
    }

    /// Removes the checkpoint of a run folder (a finished run).
    pub fn remove(out_dir: &Path) {
        let _ = std::fs::remove_file(path(out_dir));
    }
}

/// The checkpoint a `--resume` run of `scene` in growth mode `mode` goes on from (None
/// without `--resume`).
pub fn resume_point(ctx: &RunContext, scene: &Scene, mode: &str) -> Result<Option<RunCheckpoint>> {
    if !ctx.resume {
        return Ok(None);
    }
    RunCheckpoint::read_for(&ctx.out_dir, scene, mode).map(Some)
}

/// Writes a checkpoint of the run of `ctx` (the log text read back from the staging
/// folder) and says whether the run is to stop here (the test hook
/// [`RunContext::stop_after`]).
pub fn save(
    ctx: &RunContext,
    scene: &Scene,
    mode: &str,
    step: usize,
    engine: EngineState,
    observer: ObserverState,
) -> Result<bool> {
    write_now(
        ctx,
        RunCheckpoint::new(scene, mode, step, engine, observer, String::new()),
    )?;
    Ok(ctx.stop_after == Some(step))
}

/// [`save`] inside load step `step`, after break round `round` (full PD) or with `round`
/// relocation records in the run (PD-BEM, just after a relocation); whether the run is to
/// stop here (the test hook [`RunContext::stop_within`]).
pub fn save_within(
    ctx: &RunContext,
    scene: &Scene,
    mode: &str,
    (step, round): (usize, usize),
    (engine, observer): (EngineState, ObserverState),
) -> Result<bool> {
    let mut cp = RunCheckpoint::new(scene, mode, step, engine, observer, String::new());
    cp.within = true;
    write_now(ctx, cp)?;
    Ok(ctx.stop_within == Some((step, round)))
}

/// After a checkpoint was written (or failed to be, `saved` of [`save`] or
/// [`save_within`]): restarts the interval at `last_saved`, keeps the first error in
/// `error` (the run reports it at its end); `Break` when the run is to stop there (the
/// test hooks).
pub fn after_save(
    saved: Result<bool>,
    last_saved: &mut Instant,
    error: &mut Option<anyhow::Error>,
) -> ControlFlow<()> {
    *last_saved = Instant::now();
    match saved {
        Ok(true) => ControlFlow::Break(()),
        Ok(false) => ControlFlow::Continue(()),
        Err(e) => {
            error.get_or_insert(e);
            ControlFlow::Continue(())
        }
    }
}

/// Writes `cp` into the run folder of `ctx` with the log as written so far.
fn write_now(ctx: &RunContext, mut cp: RunCheckpoint) -> Result<()> {
    let log_path = ctx.writer.staging_path(super::LOG_FILE);
    cp.log = std::fs::read_to_string(&log_path).unwrap_or_default();
    cp.write(&ctx.out_dir)
}

#[cfg(test)]
mod tests {
    use serde::{Deserialize, Serialize};

    #[derive(Serialize, Deserialize)]
    struct Floats(Vec<f64>);

    #[test]
    fn ron_floats_round_trip_bit_for_bit() {
        // Bit patterns over the whole range: subnormals, extremes, negative zero, a
        // scramble of mantissas (a fixed linear congruential sequence).
        let mut v = vec![
            0.0,
            -0.0,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            f64::MIN,
            1.0 / 3.0,
            0.1 + 0.2,
            f64::INFINITY,
            f64::NEG_INFINITY,
            3.3499999999999996,
        ];
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..20_000 {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let f = f64::from_bits(x);
            if f.is_finite() {
                v.push(f);
            }
        }
        let text = ron::to_string(&Floats(v.clone())).expect("ron");
        let back: Floats = ron::from_str(&text).expect("parse");
        assert_eq!(back.0.len(), v.len());
        for (a, b) in v.iter().zip(&back.0) {
            assert_eq!(a.to_bits(), b.to_bits(), "{a:e} came back as {b:e}");
        }
        let nan: Floats =
            ron::from_str(&ron::to_string(&Floats(vec![f64::NAN])).expect("ron")).expect("parse");
        assert!(nan.0[0].is_nan());
    }
}
