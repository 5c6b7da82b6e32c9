//! `pdbem plot-paths RUN_DIR... --out FILE`: the crack paths of several growth runs (e.g.
//! PD-BEM, BEM-only and full PD of one scene) in one figure over the body outline.
//!
//! Each run folder must hold the `growth.json` and `geometry.json` that
//! [`super::output::finish`] writes. The body and the initial cracks come from the first
//! run; a run whose outline differs gets a warning (the paths are still drawn). One colour
//! and one legend entry per run: `<growth mode> (<folder name>)`. `FILE` ending in `.png` or
//! `.svg` gives that format only, any other name is a stem for both; the files are written
//! atomically (staged, then moved).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use serde_json::Value;

use super::output::{GEOMETRY_FILE, HISTORY_FILE};
use super::GrowthHistory;
use crate::output::OutputWriter;
use crate::plot::{PathGroup, PathsPlot};
use crate::runner::summary::RunSummary;
use crate::scene::PlotFormat;

/// One growth run read back from its folder.
#[derive(Debug, Clone)]
pub struct RunPaths {
    /// The folder.
    pub dir: PathBuf,
    /// Its history.
    pub history: GrowthHistory,
    /// Its `geometry.json`.
    pub geometry: Value,
}

/// Reads `growth.json` and `geometry.json` of a run folder.
pub fn read_run(dir: &Path) -> Result<RunPaths> {
    let read = |name: &str| -> Result<String> {
        let p = dir.join(name);
        std::fs::read_to_string(&p).with_context(|| {
            format!(
                "{}: cannot read {name}; is it the folder of a growth run (pdbem run on a scene with `growth`)?",
                dir.display()
            )
        })
    };
    let history: GrowthHistory = serde_json::from_str(&read(HISTORY_FILE)?)
        .with_context(|| format!("{}: {HISTORY_FILE} is not a growth history", dir.display()))?;
    let geometry: Value = serde_json::from_str(&read(GEOMETRY_FILE)?)
        .with_context(|| format!("{}: {GEOMETRY_FILE} is not JSON", dir.display()))?;
    Ok(RunPaths {
        dir: dir.to_path_buf(),
        history,
        geometry,
    })
}

fn points(v: &Value) -> Vec<(f64, f64)> {
    v.as_array()
        .map(|a| {
            a.iter()
                .filter_map(|p| Some((p.get(0)?.as_f64()?, p.get(1)?.as_f64()?)))
                .collect()
        })
        .unwrap_or_default()
}

/// Legend label of a run: `<mode> (<folder name>)`.
fn label(r: &RunPaths) -> String {
    let name = r
        .dir
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| r.dir.display().to_string());
    format!("{} ({name})", r.history.mode)
}

/// The overlay figure of several runs (body from the first); warnings for runs whose
/// outline differs from the first.
pub fn overlay(runs: &[RunPaths]) -> (PathsPlot, Vec<String>) {
    let mut warnings = Vec::new();
    let Some(first) = runs.first() else {
        return (PathsPlot::default(), warnings);
    };
    let g = &first.geometry;
    let mut loops = Vec::new();
    let outline = points(&g["outline"]);
    if !outline.is_empty() {
        loops.push(outline);
    }
    if let Some(holes) = g["holes"].as_array() {
        loops.extend(holes.iter().map(points));
    }
    let cracks = g["cracks"]
        .as_array()
        .map(|a| a.iter().map(|c| points(&c["points"])).collect())
        .unwrap_or_default();
    for r in &runs[1..] {
        if r.geometry["outline"] != g["outline"] {
            warnings.push(format!(
                "{}: outline differs from {}; drawing the first",
                r.dir.display(),
                first.dir.display()
            ));
        }
    }
    let groups = runs
        .iter()
        .map(|r| PathGroup {
            label: label(r),
            lines: r
                .history
                .paths
                .iter()
                .map(|p| p.points.iter().map(|q| (q.x, q.y)).collect())
                .collect(),
        })
        .collect();
    let unit = g["unit"].as_str().unwrap_or("m").to_string();
    let plot = PathsPlot {
        title: "crack paths".into(),
        unit,
        loops,
        cracks,
        windows: Vec::new(),
        groups,
        marks: Vec::new(),
    };
    (plot, warnings)
}

/// Formats and stem of `--out FILE`.
fn out_spec(out: &Path) -> (Vec<PlotFormat>, PathBuf) {
    match out.extension().and_then(|e| e.to_str()) {
        Some("png") => (vec![PlotFormat::Png], out.with_extension("")),
        Some("svg") => (vec![PlotFormat::Svg], out.with_extension("")),
        _ => (vec![PlotFormat::Png, PlotFormat::Svg], out.to_path_buf()),
    }
}

/// Reads the runs and writes the overlay to `out`; returns the written files and warnings.
pub fn plot_paths(dirs: &[PathBuf], out: &Path) -> Result<(Vec<PathBuf>, Vec<String>)> {
    if dirs.is_empty() {
        bail!("plot-paths: give at least one run folder");
    }
    let runs = dirs
        .iter()
        .map(|d| read_run(d))
        .collect::<Result<Vec<_>>>()?;
    let (plot, warnings) = overlay(&runs);
    let (formats, stem) = out_spec(out);
    let folder = match stem.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = stem
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .context("plot-paths: --out needs a file name")?;
    let w = OutputWriter::create(&folder)
        .with_context(|| format!("cannot create {}", folder.display()))?;
    let mut s = RunSummary::default();
    crate::runner::report::save_plot(&w, &name, &plot, &formats, &mut s)?;
    let files = w
        .commit()
        .with_context(|| format!("cannot move the plot into {}", folder.display()))?;
    Ok((files, warnings.into_iter().chain(s.notes).collect()))
}
