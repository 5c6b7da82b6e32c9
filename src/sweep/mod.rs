//! `pdbem sweep`: run a scene for every combination of `--vary FIELD=v1,v2,...`
//! values (a grid when several are given), one CSV row per run, and plots of K
//! against the first parameter (with the analytic curve where the scene has a
//! reference) and of error against wall time.
//!
//! Each run writes its own folder `<out>/run_<k>/` all-or-nothing; a failed or
//! invalid combination becomes a row with an `error` and the sweep goes on. A
//! path that does not exist in the scene stops the sweep before any run.
//! Outputs: `<out>/sweep.csv`, `<out>/sweep_k.{png,svg}`, `<out>/sweep_error_time.{png,svg}`,
//! and for a sweep over `bem.tolerance` `<out>/sweep_tolerance.{png,svg}` and
//! `<out>/sweep_tolerance_time.{png,svg}` ([`plots`]).
//!
//! Spread over machines: [`shard`] (`--shard I/N`, `--collect`), or the ranks of
//! `mpirun` (`src/sweep/mpi.rs`, feature `mpi`; [`ranks`] for the launcher's environment
//! and threads per rank, [`schedule`] for the load-balance measures, [`bench`] for
//! `pdbem bench sweep-mpi`).

pub mod bench;
#[cfg(feature = "mpi")]
pub mod mpi;
pub mod plots;
pub mod ranks;
pub mod schedule;
pub mod shard;

use std::path::Path;

use anyhow::Context;
use serde_json::Value;

use crate::output::csv::{num, opt};
use crate::output::{CsvTable, OutputWriter};
use crate::runner::run_scene;
use crate::runner::summary::RunSummary;
use crate::scene::path::{parse_value, with_overrides};
use crate::scene::{Scene, SceneError};

/// One `--vary FIELD=v1,v2,...`.
#[derive(Debug, Clone, PartialEq)]
pub struct Vary {
    /// Dotted path into the scene.
    pub path: String,
    /// Values as typed.
    pub raw: Vec<String>,
    /// Values parsed (JSON / RON tuple / bare string).
    pub values: Vec<Value>,
}

/// Parses `FIELD=v1,v2,...` (commas inside `()` or `[]` do not split).
pub fn parse_vary(text: &str) -> Result<Vary, String> {
    let (path, list) = text
        .split_once('=')
        .ok_or_else(|| format!("--vary {text}: expected FIELD=v1,v2,..."))?;
    let path = path.trim().to_string();
    if path.is_empty() {
        return Err(format!("--vary {text}: the field path is empty"));
    }
    let raw = split_top_level(list);
    if raw.iter().any(|v| v.is_empty()) {
        return Err(format!("--vary {text}: empty value in the list"));
    }
    let values = raw.iter().map(|v| parse_value(v)).collect();
    Ok(Vary { path, raw, values })
}

/// Splits on commas outside brackets and parentheses.
fn split_top_level(list: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut depth = 0i32;
    let mut cur = String::new();
    for ch in list.chars() {
        match ch {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ',' if depth == 0 => {
                out.push(cur.trim().to_string());
                cur.clear();
                continue;
            }
            _ => {}
        }
        cur.push(ch);
    }
    out.push(cur.trim().to_string());
    out
}

/// Every combination (first parameter varies slowest), as value indices.
pub fn grid(varies: &[Vary]) -> Vec<Vec<usize>> {
    let mut combos: Vec<Vec<usize>> = vec![Vec::new()];
    for v in varies {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                (0..v.values.len()).map(move |i| {
                    let mut c = c.clone();
                    c.push(i);
                    c
                })
            })
            .collect();
    }
    combos
}

/// Overrides of one combination.
fn overrides(varies: &[Vary], combo: &[usize]) -> Vec<(String, Value)> {
    varies
        .iter()
        .zip(combo)
        .map(|(v, i)| (v.path.clone(), v.values[*i].clone()))
        .collect()
}

/// One row of the sweep.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct SweepRow {
    /// Values as typed, one per `--vary`.
    pub params: Vec<String>,
    /// The run's summary when it succeeded.
    pub summary: Option<RunSummary>,
    /// Why the run failed.
    pub error: Option<String>,
}

impl SweepRow {
    /// Why the run did not give a complete result: its error, or the `failure_reason`
    /// of a run that ended early with its outputs written (`complete: false`).
    pub fn problem(&self) -> Option<String> {
        self.error
            .clone()
            .or_else(|| self.summary.as_ref().and_then(|s| s.incomplete()))
    }
}

/// Runs the sweep; returns the rows (also written to `<out>/sweep.csv`).
pub fn run_sweep(
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    quiet: bool,
) -> anyhow::Result<Vec<SweepRow>> {
    check_sweep(scene, varies)?;
    let writer = OutputWriter::create_run(out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let all: Vec<usize> = (0..grid(varies).len()).collect();
    let rows = run_rows(scene, varies, out_dir, &all, quiet);
    write_results(scene, varies, &rows, &writer)?;
    writer.commit()?;
    Ok(rows)
}

/// The sweep's table and plots, through `writer` (not committed).
pub fn write_results(
    scene: &Scene,
    varies: &[Vary],
    rows: &[SweepRow],
    writer: &OutputWriter,
) -> anyhow::Result<()> {
    writer.write_csv("sweep.csv", &table(varies, rows))?;
    plots::write_plots(scene, varies, rows, writer)
}

/// A sweep needs a `--vary` and paths that exist in the scene.
pub fn check_sweep(scene: &Scene, varies: &[Vary]) -> anyhow::Result<()> {
    if varies.is_empty() {
        anyhow::bail!("sweep needs at least one --vary FIELD=v1,v2,...");
    }
    check_paths(scene, varies)
}

/// Runs the combinations of the grid with the given indices, each into
/// `<out>/run_<k>/`; a run that fails is a row with its error.
pub fn run_rows(
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    indices: &[usize],
    quiet: bool,
) -> Vec<SweepRow> {
    let bar = crate::runner::context::progress_bar(indices.len() as u64, quiet);
    let mut rows = Vec::new();
    for &k in indices {
        rows.push(run_one(scene, varies, out_dir, k));
        bar.inc(1);
    }
    bar.finish_and_clear();
    rows
}

/// Runs combination `k` of the grid into `<out>/run_<k>/`: its row, with the error of a
/// run that fails (a panic included: one run must not end a sweep).
pub fn run_one(scene: &Scene, varies: &[Vary], out_dir: &Path, k: usize) -> SweepRow {
    let combo = &grid(varies)[k];
    let params: Vec<String> = varies
        .iter()
        .zip(combo)
        .map(|(v, i)| v.raw[*i].clone())
        .collect();
    let run_dir = out_dir.join(format!("run_{k:03}"));
    let run = || {
        with_overrides(scene, &overrides(varies, combo))
            .map_err(anyhow::Error::from)
            .and_then(|s| run_scene(&s, &run_dir, true))
    };
    let result = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(run)) {
        Ok(r) => r,
        Err(p) => Err(anyhow::anyhow!("the run panicked: {}", panic_text(&*p))),
    };
    match result {
        Ok(s) => SweepRow {
            params,
            summary: Some(s),
            error: None,
        },
        Err(e) => SweepRow {
            params,
            summary: None,
            error: Some(format!("{e:#}")),
        },
    }
}

/// The message of a panic payload.
fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".into())
}

/// Runs the sweep in this process, or over the ranks when an MPI launcher started it
/// (`mpirun -np K pdbem sweep ...`, `src/sweep/mpi.rs`, feature `mpi`). Returns the rows on the
/// process that wrote the table (rank 0), `None` on the other ranks. A pdbem built
/// without the feature refuses to run as one of several ranks: each would run the whole
/// sweep into the same folder.
pub fn run_sweep_launched(
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    quiet: bool,
) -> anyhow::Result<Option<Vec<SweepRow>>> {
    match ranks::launcher_world_size() {
        None => run_sweep(scene, varies, out_dir, quiet).map(Some),
        Some(n) => launched(scene, varies, out_dir, quiet, n),
    }
}

#[cfg(feature = "mpi")]
fn launched(
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    quiet: bool,
    _ranks: usize,
) -> anyhow::Result<Option<Vec<SweepRow>>> {
    mpi::run_mpi_sweep(scene, varies, out_dir, quiet)
}

#[cfg(not(feature = "mpi"))]
fn launched(
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    quiet: bool,
    ranks: usize,
) -> anyhow::Result<Option<Vec<SweepRow>>> {
    if ranks == 1 {
        return run_sweep(scene, varies, out_dir, quiet).map(Some);
    }
    anyhow::bail!(
        "started as one of {ranks} MPI ranks, but this pdbem was built without the `mpi` \
         feature: every rank would run the whole sweep into {}. Build with \
         `cargo build --release --features mpi`, or split the sweep with --shard I/N \
         (docs/cluster.md)",
        out_dir.display()
    )
}

/// Paths must exist in the scene (values may still be invalid per combination).
fn check_paths(scene: &Scene, varies: &[Vary]) -> anyhow::Result<()> {
    for v in varies {
        if v.values.is_empty() {
            anyhow::bail!("--vary {}: no values", v.path);
        }
        let mut json = scene.to_json();
        if let Err(reason) = crate::scene::path::set_path(&mut json, &v.path, v.values[0].clone()) {
            return Err(SceneError::Path {
                file: scene.file_label(),
                path: v.path.clone(),
                reason,
            }
            .into());
        }
    }
    Ok(())
}

/// Tip and crack names over all successful rows, in order of appearance.
pub(crate) fn names(rows: &[SweepRow]) -> (Vec<String>, Vec<String>) {
    let mut tips: Vec<String> = Vec::new();
    let mut cracks: Vec<String> = Vec::new();
    for s in rows.iter().filter_map(|r| r.summary.as_ref()) {
        for t in &s.tips {
            if !tips.contains(&t.name) {
                tips.push(t.name.clone());
            }
        }
        for c in &s.cracks {
            if !cracks.contains(&c.name) {
                cracks.push(c.name.clone());
            }
        }
    }
    (tips, cracks)
}

/// Columns of `sweep.csv` per tip (prefixed `<tip>.`); `*_err` are relative errors
/// against the reference, `*_err_est` absolute error estimates (Pa m^0.5).
const TIP_COLUMNS: [&str; 9] = [
    "k1",
    "k2",
    "kink_deg",
    "k1_err",
    "k1_err_fem",
    "k2_err",
    "kink_err_deg",
    "k1_err_est",
    "k2_err_est",
];
/// Columns per crack (prefixed `<crack>.`): CMOD (m), relative error, estimate (m).
const CRACK_COLUMNS: [&str; 3] = ["cmod", "cmod_err", "cmod_err_est"];

/// `sweep.csv`: parameters, status, wall time, elements, per-tip K, errors and
/// estimates, per-crack CMOD, error and estimate, error message.
pub fn table(varies: &[Vary], rows: &[SweepRow]) -> CsvTable {
    let (tips, cracks) = names(rows);
    let mut header: Vec<String> = vec!["run".into()];
    header.extend(varies.iter().map(|v| v.path.clone()));
    header.extend(["status", "wall_time_s", "elements"].map(String::from));
    for t in &tips {
        header.extend(TIP_COLUMNS.map(|c| format!("{t}.{c}")));
    }
    for c in &cracks {
        header.extend(CRACK_COLUMNS.map(|k| format!("{c}.{k}")));
    }
    header.push("error".into());
    let mut t = CsvTable::new(&header);
    for (k, r) in rows.iter().enumerate() {
        let mut row = vec![k.to_string()];
        row.extend(r.params.iter().cloned());
        match &r.summary {
            Some(s) => {
                let incomplete = s.incomplete();
                row.extend([
                    if incomplete.is_some() {
                        "incomplete"
                    } else {
                        "ok"
                    }
                    .to_string(),
                    num(s.wall_time_s),
                    s.elements.map(|e| e.to_string()).unwrap_or_default(),
                ]);
                for name in &tips {
                    let tip = s.tips.iter().find(|x| &x.name == name);
                    row.push(tip.map(|x| num(x.k1)).unwrap_or_default());
                    row.push(tip.map(|x| num(x.k2)).unwrap_or_default());
                    row.push(tip.map(|x| num(x.kink_deg)).unwrap_or_default());
                    row.push(opt(tip.and_then(|x| x.k1_err)));
                    row.push(opt(tip.and_then(|x| x.k1_err_fem)));
                    row.push(opt(tip.and_then(|x| x.k2_err)));
                    row.push(opt(tip.and_then(|x| x.kink_err_deg)));
                    row.push(opt(tip.and_then(|x| x.k1_err_est)));
                    row.push(opt(tip.and_then(|x| x.k2_err_est)));
                }
                for name in &cracks {
                    let c = s.cracks.iter().find(|x| &x.name == name);
                    row.push(opt(c.and_then(|x| x.cmod)));
                    row.push(opt(c.and_then(|x| x.cmod_err)));
                    row.push(opt(c.and_then(|x| x.cmod_err_est)));
                }
                row.push(incomplete.unwrap_or_default().replace('\n', " | "));
            }
            None => {
                row.extend(["failed".to_string(), String::new(), String::new()]);
                row.extend(std::iter::repeat_n(
                    String::new(),
                    TIP_COLUMNS.len() * tips.len() + CRACK_COLUMNS.len() * cracks.len(),
                ));
                row.push(r.error.clone().unwrap_or_default().replace('\n', " | "));
            }
        }
        t.push(row);
    }
    t
}

/// x value of a row for plots: the first parameter as a number, else the row index.
pub(crate) fn x_of(raw: &str, k: usize) -> f64 {
    parse_value(raw).as_f64().unwrap_or(k as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vary_splits_outside_brackets() {
        let v = parse_vary("cracks.0.start=(1,2),(3, 4)").expect("parses");
        assert_eq!(v.raw, vec!["(1,2)", "(3, 4)"]);
        assert_eq!(v.values[1], serde_json::json!([3, 4]));
        assert!(parse_vary("novalue").is_err());
        assert!(parse_vary("a=1,,2").is_err());
    }

    #[test]
    fn grid_is_cartesian() {
        let a = parse_vary("a=1,2").expect("parses");
        let b = parse_vary("b=1,2,3").expect("parses");
        let g = grid(&[a, b]);
        assert_eq!(g.len(), 6);
        assert_eq!(g[0], vec![0, 0]);
        assert_eq!(g[5], vec![1, 2]);
    }
}
