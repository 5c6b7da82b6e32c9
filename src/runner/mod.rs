//! Running a scene: pick the mode from the sections present, call the solver,
//! add reference values and errors, write `summary.json`, `tips.csv`,
//! `cracks.csv` and the plots, all-or-nothing.
//!
//! Entry points: [`run_scene`], [`mode_of`]; types [`RunContext`] (what a
//! solver gets), [`RunSummary`] (what it returns), [`TipResult`], [`CrackResult`].
//! Reference values: [`reference`](mod@reference); tables and plots: [`report`].

pub mod reference;
pub mod report;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use serde::{Deserialize, Serialize};

use crate::output::OutputWriter;
use crate::scene::{GrowthMode, Scene};

/// What a solver gets besides the scene.
#[derive(Debug)]
pub struct RunContext {
    /// Final run folder (files appear there only when the run succeeds).
    pub out_dir: PathBuf,
    /// No progress output.
    pub quiet: bool,
    /// Writer for every output file of the run (staged until success).
    pub writer: OutputWriter,
}

impl RunContext {
    /// Creates the run folder and its staging area.
    pub fn new(out_dir: &Path, quiet: bool) -> std::io::Result<RunContext> {
        Ok(RunContext {
            out_dir: out_dir.to_path_buf(),
            quiet,
            writer: OutputWriter::create_run(out_dir)?,
        })
    }

    /// Prints a progress message to stderr unless quiet.
    pub fn log(&self, message: &str) {
        if !self.quiet {
            eprintln!("{message}");
        }
    }

    /// A progress bar of `len` steps (hidden when quiet).
    pub fn progress(&self, len: u64) -> indicatif::ProgressBar {
        if self.quiet {
            indicatif::ProgressBar::hidden()
        } else {
            indicatif::ProgressBar::new(len)
        }
    }
}

/// Result of one run; serialised as `summary.json` (schema: docs/outputs.md).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// `bem`, `pd`, `coupled` or `growth`.
    pub mode: String,
    /// BEM elements (null when no BEM mesh).
    pub elements: Option<usize>,
    /// Wall time of the solve (s), set by the runner when the solver leaves 0.
    pub wall_time_s: f64,
    /// Crack tips.
    pub tips: Vec<TipResult>,
    /// Cracks.
    pub cracks: Vec<CrackResult>,
    /// Messages for the user (warnings, degraded plots).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// Mode-specific fields, written at the top level of `summary.json`
    /// (e.g. `nodes`, `bonds`, `coupling`, `relocations`).
    #[serde(flatten)]
    pub extra: serde_json::Map<String, serde_json::Value>,
    /// Mesh nodes / element end points for the geometry plot (not serialised).
    #[serde(skip)]
    pub plot_nodes: Vec<(f64, f64)>,
}

/// Results at one crack tip. SIFs in Pa sqrt(m), angles in degrees.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TipResult {
    /// Tip name, `<crack>.end` or `<crack>.start`.
    pub name: String,
    /// Tip position (m).
    pub position: [f64; 2],
    /// Reported K_I (the solver's preferred estimate).
    pub k1: f64,
    /// Reported K_II.
    pub k2: f64,
    /// Kink angle by maximum circumferential stress (from the crack line, CCW positive).
    pub kink_deg: f64,
    /// K_I from crack-opening displacement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_cod: Option<f64>,
    /// K_II from crack-opening displacement.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_cod: Option<f64>,
    /// K_I from the J / interaction integral.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_j: Option<f64>,
    /// K_II from the interaction integral.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_j: Option<f64>,
    /// Reference K_I.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_ref: Option<f64>,
    /// Reference K_II.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_ref: Option<f64>,
    /// Reference kink angle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kink_ref_deg: Option<f64>,
    /// Reference K_I from the FEM table (SENT, 0.1 <= a/W <= 0.8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_ref_fem: Option<f64>,
    /// Relative error of `k1` (see [`reference::relative_error`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_err: Option<f64>,
    /// Relative error of `k2`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k2_err: Option<f64>,
    /// Kink angle error (degrees).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kink_err_deg: Option<f64>,
    /// Relative error of `k1` against the FEM table.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k1_err_fem: Option<f64>,
}

/// Results of one crack.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct CrackResult {
    /// Crack name.
    pub name: String,
    /// Crack-mouth opening displacement (m), for cracks with a mouth on the outline.
    pub cmod: Option<f64>,
    /// Reference CMOD (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cmod_ref: Option<f64>,
    /// Relative CMOD error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cmod_err: Option<f64>,
}

/// How a scene is solved, from the sections it contains.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// No `pd`: BEM alone.
    Bem,
    /// `pd` without `coupling`: PD over the whole body.
    Pd,
    /// `coupling` without `growth`: static PD-BEM coupling (issue 4).
    Coupled,
    /// `growth`: crack growth (issue 5).
    Growth,
}

impl Mode {
    /// The `mode` string of `summary.json`.
    pub fn as_str(&self) -> &'static str {
        match self {
            Mode::Bem => "bem",
            Mode::Pd => "pd",
            Mode::Coupled => "coupled",
            Mode::Growth => "growth",
        }
    }
}

/// The mode of a scene.
pub fn mode_of(scene: &Scene) -> Mode {
    if scene.growth.is_some() {
        Mode::Growth
    } else if scene.coupling.is_some() {
        Mode::Coupled
    } else if scene.pd.is_some() {
        Mode::Pd
    } else {
        Mode::Bem
    }
}

/// Runs a validated scene into `out_dir`: solve, reference errors, outputs.
/// On error nothing is left in `out_dir` (and a folder this run created is removed).
pub fn run_scene(scene: &Scene, out_dir: &Path, quiet: bool) -> anyhow::Result<RunSummary> {
    let mode = mode_of(scene);
    let ctx = RunContext::new(out_dir, quiet)
        .with_context(|| format!("cannot create the run folder {}", out_dir.display()))?;
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
    reference::apply(scene, &mut summary);
    report::write_all(scene, &ctx, &mut summary)?;
    ctx.writer
        .commit()
        .with_context(|| format!("cannot move outputs into {}", out_dir.display()))?;
    Ok(summary)
}

/// Growth: the scene's `growth.mode` picks the solver; every mode's history goes through
/// the one output layer ([`crate::growth::output::finish`]).
fn run_growth(scene: &Scene, ctx: &RunContext) -> anyhow::Result<RunSummary> {
    use crate::growth::{bem_only, full_pd, pd_bem};
    let mode = scene.growth.as_ref().map(|g| g.mode).unwrap_or_default();
    let history = match mode {
        GrowthMode::PdBem => pd_bem::run(scene, ctx)?,
        GrowthMode::BemOnly => bem_only::run(scene, ctx)?,
        GrowthMode::FullPd => full_pd::run(scene, ctx)?,
    };
    crate::growth::output::finish(scene, ctx, &history)
}
