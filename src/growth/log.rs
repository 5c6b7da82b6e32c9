//! Progress of a growth run: the machine-readable log `growth_log.jsonl` (one JSON object
//! per line: `{"event": "...", ...}`) and the per-load-step progress bar.
//!
//! The log is written while the run goes, into the run's staging folder, so it can be
//! followed with `tail -f <out>/.staging-<pid>/growth_log.jsonl`; like every output it
//! reaches the run folder only when the run succeeds. Events (docs/outputs.md):
//! `start`, `solve` (BEM-only: SIF of every tip at unit load), `grow` (one increment of a
//! tip), `tip_end`, `step` (one converged load step), `round` and `cut` (full PD: a break
//! round, a crack no tip followed cutting the body), `relocation` (PD-BEM), `failure`,
//! `note` and `end`. A solver that does not log (PD-BEM) gets its `step`, `relocation`,
//! `tip_end` and `note` events written from its [`GrowthHistory`] by the output layer.

use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{Context, Result};
use serde_json::{json, Value};

use std::ops::ControlFlow;

use crate::growth::checkpoint::{self, EngineState, RunCheckpoint};
use crate::growth::GrowthHistory;
use crate::runner::context::RunContext;
use crate::scene::Scene;
use pdbem_coupling::growth::checkpoint::EngineCheckpoint;
use pdbem_coupling::growth::events::EngineObserver;

pub use super::LOG_FILE;

/// The growth log of one run (usable through `&self`).
#[derive(Debug)]
pub struct GrowthLog {
    file: Mutex<BufWriter<File>>,
}

impl GrowthLog {
    /// Opens (appends to) the log in the run's staging folder and registers it.
    pub fn open(ctx: &RunContext) -> Result<GrowthLog> {
        let path = ctx.writer.staging_path(LOG_FILE);
        let file = OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
            .with_context(|| format!("cannot open {}", path.display()))?;
        ctx.writer.register(LOG_FILE);
        Ok(GrowthLog {
            file: Mutex::new(BufWriter::new(file)),
        })
    }

    /// Opens the log of a resumed run: the text of the interrupted run's log up to its
    /// checkpoint first, then appended to.
    pub fn reopen(ctx: &RunContext, text: &str) -> Result<GrowthLog> {
        ctx.writer
            .write_bytes(LOG_FILE, text.as_bytes())
            .with_context(|| format!("restoring {LOG_FILE}"))?;
        GrowthLog::open(ctx)
    }

    /// Whether a solver already opened the log of this run.
    pub fn exists(ctx: &RunContext) -> bool {
        ctx.writer.files().iter().any(|f| f == LOG_FILE)
    }

    /// Writes one event: `{"event": kind, ...fields}` (fields must be a JSON object) and
    /// flushes, so the line is complete on disk.
    pub fn event(&self, kind: &str, fields: Value) -> Result<()> {
        let mut obj = serde_json::Map::new();
        obj.insert("event".into(), json!(kind));
        if let Value::Object(m) = fields {
            obj.extend(m);
        }
        let line = serde_json::to_string(&Value::Object(obj)).context("growth log event")?;
        let mut f = self
            .file
            .lock()
            .map_err(|_| anyhow::anyhow!("growth log: writer poisoned"))?;
        writeln!(f, "{line}")
            .and_then(|_| f.flush())
            .with_context(|| format!("writing {LOG_FILE}"))
    }

    /// The events a [`GrowthHistory`] holds, for solvers that did not log while running:
    /// steps, relocations, tip ends, notes.
    pub fn replay(&self, history: &GrowthHistory) -> Result<()> {
        for s in &history.steps {
            self.event("step", json!(s))?;
        }
        for r in &history.relocations {
            self.event("relocation", json!(r))?;
        }
        for p in &history.paths {
            if let Some(why) = &p.ended {
                self.event("tip_end", json!({"tip": p.name, "reason": why}))?;
            }
        }
        for n in &history.notes {
            self.event("note", json!({ "message": n }))?;
        }
        Ok(())
    }
}

/// A progress bar over `steps` load steps with a message (hidden with `--quiet`).
pub fn step_bar(ctx: &RunContext, steps: usize) -> indicatif::ProgressBar {
    // On a terminal a bar; in lines (a log file) the step and message alone, so a line
    // is written when they change, not every second.
    ctx.styled_progress(
        steps as u64,
        "{elapsed_precise} [{bar:30}] {pos}/{len} load steps done; {msg}",
        "{pos}/{len} load steps done; {msg}",
    )
}

/// The binary's observer of the BEM-only and full-PD engines: every event goes to
/// `growth_log.jsonl`, progress to the step bar, messages to the run log (stderr unless
/// quiet). The first error writing the log is kept and returned by [`RunObserver::finish`].
pub struct RunObserver<'a> {
    ctx: &'a RunContext,
    log: GrowthLog,
    bar: indicatif::ProgressBar,
    error: Option<anyhow::Error>,
    /// The scene and growth mode whose checkpoints it writes (none without).
    checkpoints: Option<(&'a Scene, &'static str)>,
    stopped: bool,
    /// When the last checkpoint was written (or the run started).
    last_saved: Instant,
}

impl<'a> RunObserver<'a> {
    /// Opens the run's log and a bar over `steps` load steps.
    pub fn new(ctx: &'a RunContext, steps: usize) -> Result<RunObserver<'a>> {
        Ok(RunObserver {
            ctx,
            log: GrowthLog::open(ctx)?,
            bar: step_bar(ctx, steps),
            error: None,
            checkpoints: None,
            stopped: false,
            last_saved: Instant::now(),
        })
    }

    /// The observer of a growth run of `scene` in growth mode `mode` that writes a
    /// checkpoint after every load step; with `resume` (a checkpoint read by
    /// `--resume`) the log starts with the interrupted run's text and the bar at its step.
    pub fn for_scene(
        ctx: &'a RunContext,
        scene: &'a Scene,
        mode: &'static str,
        steps: usize,
        resume: Option<&RunCheckpoint>,
    ) -> Result<RunObserver<'a>> {
        let log = match resume {
            Some(cp) => GrowthLog::reopen(ctx, &cp.log)?,
            None => GrowthLog::open(ctx)?,
        };
        let bar = step_bar(ctx, steps);
        if let Some(cp) = resume {
            bar.set_position(cp.steps_done() as u64);
        }
        Ok(RunObserver {
            ctx,
            log,
            bar,
            error: None,
            checkpoints: Some((scene, mode)),
            stopped: false,
            last_saved: Instant::now(),
        })
    }

    /// Whether the run was stopped by [`RunContext::stop_after`].
    pub fn stopped(&self) -> bool {
        self.stopped
    }

    /// Clears the bar; the first log error, if any.
    pub fn finish(self) -> Result<()> {
        self.bar.finish_and_clear();
        match self.error {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

impl EngineObserver for RunObserver<'_> {
    fn event(&mut self, kind: &str, fields: Value) {
        if let Err(e) = self.log.event(kind, fields) {
            self.error.get_or_insert(e);
        }
    }

    fn progress(&mut self, done: usize, _total: usize, status: &str) {
        self.bar.set_position(done as u64);
        self.bar.set_message(status.to_string());
    }

    fn message(&mut self, text: &str) {
        self.bar.suspend(|| self.ctx.log(text));
    }

    fn checkpoint(
        &mut self,
        step: usize,
        save: &mut dyn FnMut() -> EngineCheckpoint,
    ) -> ControlFlow<()> {
        let Some((scene, mode)) = self.checkpoints else {
            return ControlFlow::Continue(());
        };
        let engine = EngineState::Engine(save());
        let saved = checkpoint::save(self.ctx, scene, mode, step, engine, Default::default());
        self.flow(saved)
    }

    fn round_checkpoint(
        &mut self,
        step: usize,
        round: usize,
        save: &mut dyn FnMut() -> EngineCheckpoint,
    ) -> ControlFlow<()> {
        let Some((scene, mode)) = self.checkpoints else {
            return ControlFlow::Continue(());
        };
        if self.last_saved.elapsed() < self.ctx.round_checkpoint_every {
            return ControlFlow::Continue(());
        }
        let engine = EngineState::Engine(save());
        let engine = (engine, Default::default());
        let saved = checkpoint::save_within(self.ctx, scene, mode, (step, round), engine);
        self.flow(saved)
    }
}

impl RunObserver<'_> {
    /// After a checkpoint was written (or failed to be): restarts the interval; `Break`
    /// when the run is to stop there.
    fn flow(&mut self, saved: Result<bool>) -> ControlFlow<()> {
        let flow = checkpoint::after_save(saved, &mut self.last_saved, &mut self.error);
        self.stopped |= flow.is_break();
        flow
    }
}
