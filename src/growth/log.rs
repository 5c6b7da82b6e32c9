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

use anyhow::{Context, Result};
use serde_json::{json, Value};

use crate::growth::GrowthHistory;
use crate::runner::context::RunContext;

/// File name of the log.
pub const LOG_FILE: &str = "growth_log.jsonl";

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
    let bar = ctx.progress(steps as u64);
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{elapsed_precise} [{bar:30}] step {pos}/{len} {msg}",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// The end-of-step verdict of the BEM-only and full-PD loops at step `step` (load `load`):
/// with `failed` (a crack cut the body; `why` says how) the history records the failure
/// and the log a `failure` event; otherwise, when no tip is active any more, a note.
/// Returns whether the run stops.
pub fn stop_after_step(
    history: &mut GrowthHistory,
    log: &GrowthLog,
    front: &pdbem_coupling::growth::front::Front,
    failed: bool,
    step: usize,
    load: f64,
    why: &str,
) -> Result<bool> {
    if failed {
        history.failure = true;
        history.failure_load = Some(load);
        log.event("failure", json!({"step": step, "load": load}))?;
        history
            .notes
            .push(format!("failure at load {load} (step {step}): {why}"));
        return Ok(true);
    }
    if front.active().is_empty() {
        history
            .notes
            .push(format!("every tip stopped by step {step} (load {load})"));
        return Ok(true);
    }
    Ok(false)
}
