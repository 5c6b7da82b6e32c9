//! `pdbem plot-paths RUN_DIR... --out FILE`: the crack paths of several growth runs (e.g.
//! PD-BEM, BEM-only and full PD of one scene) in one figure over the body outline.
//!
//! Each run folder must hold the `growth.json` and `geometry.json` that
//! [`super::output::finish`] writes. The body and the initial cracks come from the first
//! run; a run whose outline differs gets a warning (the paths are still drawn). One colour
//! and one legend entry per run: `<growth mode> (<folder name>)`. `FILE` ending in `.png` or
//! `.svg` gives that format only, any other name is a stem for both; the files are written
//! atomically (staged, then moved).
//!
//! With two runs or more, `<stem>_deviation.csv` lists how far every later run's tip paths
//! lie from the first run's paths of the same tip ([`deviations`]): the Hausdorff distance
//! over the common reach from the initial tip (`pdbem_coupling::growth::compare`, the
//! measure `pdbem bench growth` reports).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use serde_json::Value;

use super::output::{GEOMETRY_FILE, HISTORY_FILE};
use super::GrowthHistory;
use crate::output::{CsvTable, OutputWriter};
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

/// How far one tip path of a run lies from the same tip's path in the first run.
#[derive(Debug, Clone, PartialEq)]
pub struct Deviation {
    /// Legend label of the run (`<mode> (<folder name>)`).
    pub run: String,
    /// Tip name.
    pub tip: String,
    /// Hausdorff distance of the two paths over their common reach (m).
    pub deviation: f64,
    /// The common reach from the initial tip (m).
    pub reach: f64,
}

/// The deviation of every tip path of `runs[1..]` from the first run's path of the same
/// tip; a tip the first run does not have gives a warning instead.
pub fn deviations(runs: &[RunPaths]) -> (Vec<Deviation>, Vec<String>) {
    let (mut out, mut warnings) = (Vec::new(), Vec::new());
    let Some(first) = runs.first() else {
        return (out, warnings);
    };
    for r in &runs[1..] {
        for p in &r.history.paths {
            match first.history.paths.iter().find(|q| q.name == p.name) {
                Some(q) => {
                    let (deviation, reach) = pdbem_coupling::growth::compare::path_deviation(q, p);
                    out.push(Deviation {
                        run: label(r),
                        tip: p.name.clone(),
                        deviation,
                        reach,
                    });
                }
                None => warnings.push(format!(
                    "{}: tip {} has no path in {}; no deviation for it",
                    r.dir.display(),
                    p.name,
                    first.dir.display()
                )),
            }
        }
    }
    (out, warnings)
}

/// The table of [`deviations`] against `reference` (the first run's label).
pub fn deviation_table(reference: &str, devs: &[Deviation]) -> CsvTable {
    let mut t = CsvTable::new(&["reference", "run", "tip", "deviation_m", "common_reach_m"]);
    for d in devs {
        t.push(vec![
            reference.to_string(),
            d.run.clone(),
            d.tip.clone(),
            format!("{:.6e}", d.deviation),
            format!("{:.6e}", d.reach),
        ]);
    }
    t
}

/// Formats and stem of `--out FILE`.
fn out_spec(out: &Path) -> (Vec<PlotFormat>, PathBuf) {
    match out.extension().and_then(|e| e.to_str()) {
        Some("png") => (vec![PlotFormat::Png], out.with_extension("")),
        Some("svg") => (vec![PlotFormat::Svg], out.with_extension("")),
        _ => (vec![PlotFormat::Png, PlotFormat::Svg], out.to_path_buf()),
    }
}

/// What [`plot_paths`] wrote and found.
#[derive(Debug, Clone, Default)]
pub struct Overlaid {
    /// The files written (figures, and the deviation table with two runs or more).
    pub files: Vec<PathBuf>,
    /// Warnings: outlines that differ, tips without a reference path.
    pub warnings: Vec<String>,
    /// Deviations of the later runs' paths from the first run's ([`deviations`]).
    pub deviations: Vec<Deviation>,
    /// Legend label of the first run (the reference of the deviations).
    pub reference: String,
}

/// Reads the runs and writes the overlay (and the deviation table) to `out`.
pub fn plot_paths(dirs: &[PathBuf], out: &Path) -> Result<Overlaid> {
    if dirs.is_empty() {
        bail!("plot-paths: give at least one run folder");
    }
    let runs = dirs
        .iter()
        .map(|d| read_run(d))
        .collect::<Result<Vec<_>>>()?;
    let (plot, mut warnings) = overlay(&runs);
    let (devs, dev_warnings) = deviations(&runs);
    warnings.extend(dev_warnings);
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
    if runs.len() > 1 {
        let table = deviation_table(&label(&runs[0]), &devs);
        let csv = format!("{name}_deviation.csv");
        w.write_csv(&csv, &table)
            .with_context(|| format!("cannot write {csv}"))?;
    }
    let files = w
        .commit()
        .with_context(|| format!("cannot move the plot into {}", folder.display()))?;
    Ok(Overlaid {
        files,
        warnings: warnings.into_iter().chain(s.notes).collect(),
        deviations: devs,
        reference: label(&runs[0]),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use pdbem_coupling::growth::history::{PathPoint, TipPath};

    fn run(dir: &str, mode: &str, paths: &[(&str, &[(f64, f64)])]) -> RunPaths {
        let history = GrowthHistory {
            mode: mode.into(),
            paths: paths
                .iter()
                .map(|(name, pts)| TipPath {
                    name: name.to_string(),
                    points: pts
                        .iter()
                        .map(|&(x, y)| PathPoint {
                            x,
                            y,
                            step: 0,
                            load: 0.0,
                        })
                        .collect(),
                    ended: None,
                })
                .collect(),
            ..Default::default()
        };
        RunPaths {
            dir: PathBuf::from(dir),
            history,
            geometry: Value::Null,
        }
    }

    #[test]
    fn a_path_shifted_sideways_deviates_by_the_shift_over_the_shorter_reach() {
        let a = run("a", "pd-bem", &[("crack.end", &[(0.0, 0.0), (1.0, 0.0)])]);
        // The same tip 0.02 m above, 0.6 m long; a tip the first run does not have.
        let b = run(
            "b",
            "full-pd",
            &[
                ("crack.end", &[(0.0, 0.02), (0.3, 0.02), (0.6, 0.02)]),
                ("other.end", &[(0.0, 0.0), (0.1, 0.0)]),
            ],
        );
        let (devs, warnings) = deviations(&[a, b]);
        assert_eq!(devs.len(), 1);
        assert_eq!(devs[0].run, "full-pd (b)");
        assert!((devs[0].deviation - 0.02).abs() < 1e-9, "{devs:?}");
        assert!((devs[0].reach - 0.6).abs() < 0.03, "{devs:?}");
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("other.end"));
        let t = deviation_table("pd-bem (a)", &devs);
        assert_eq!(t.rows.len(), 1);
        assert_eq!(t.rows[0][2], "crack.end");
    }
}
