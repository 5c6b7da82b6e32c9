//! Sharded sweeps (issue 22): `pdbem sweep ... --shard I/N` runs the I-th of N disjoint
//! parts of the grid into the sweep's folder, and `pdbem sweep ... --collect` joins the
//! parts into the sweep's table and plots, equal to those of a sweep run in one piece
//! (wall times aside). This is what a Slurm job array, GNU parallel or a Kubernetes
//! indexed job needs (`docs/cluster.md`).
//!
//! Shard I of N takes the grid indices k with k mod N = I - 1 (round robin: runs along
//! the first parameter often grow in cost, and a round robin spreads them over the
//! shards). Each run writes `<out>/run_<k>/` as in a serial sweep; the shard writes its
//! rows to `<out>/shard-<I>-of-<N>/rows.json`, all-or-nothing, with the scene name and
//! the `--vary` arguments, which `--collect` checks against its own before it joins the
//! shards. Shards write to distinct folders, so they may run at the same time.

use std::path::{Path, PathBuf};

use anyhow::Context;
use serde::{Deserialize, Serialize};

use super::{check_sweep, grid, run_rows, write_results, SweepRow, Vary};
use crate::output::OutputWriter;
use crate::scene::Scene;

/// Most shards a sweep may be split into.
pub const MAX_SHARDS: usize = 1_000_000;

/// Part `index` (1-based) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 1-based index.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// Parses `I/N` with 1 <= I <= N <= [`MAX_SHARDS`].
    pub fn parse(text: &str) -> Result<Shard, String> {
        let bad = |why: &str| format!("--shard {text}: {why}");
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| bad("expected I/N, e.g. 3/16"))?;
        let parse = |v: &str| {
            v.trim()
                .parse::<usize>()
                .map_err(|_| bad("I and N must be whole numbers"))
        };
        let (index, count) = (parse(i)?, parse(n)?);
        if count == 0 || count > MAX_SHARDS {
            return Err(bad(&format!("N must lie in [1, {MAX_SHARDS}]")));
        }
        if index == 0 || index > count {
            return Err(bad("I must lie in [1, N] (shards count from 1)"));
        }
        Ok(Shard { index, count })
    }

    /// The grid indices of this shard among `total` combinations.
    pub fn indices(&self, total: usize) -> Vec<usize> {
        (self.index - 1..total).step_by(self.count).collect()
    }

    /// The shard's folder name.
    pub fn folder(&self) -> String {
        format!("shard-{}-of-{}", self.index, self.count)
    }
}

/// What a shard leaves for `--collect`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShardRecord {
    /// Scene name.
    pub scene: String,
    /// The `--vary` arguments, as `FIELD=v1,v2,...`.
    pub vary: Vec<String>,
    /// Which part.
    pub shard: Shard,
    /// Grid index and row of every run of the shard.
    pub rows: Vec<(usize, SweepRow)>,
}

/// The `--vary` arguments of `varies`, normalised.
fn vary_args(varies: &[Vary]) -> Vec<String> {
    varies
        .iter()
        .map(|v| format!("{}={}", v.path, v.raw.join(",")))
        .collect()
}

/// Runs shard `shard` of the sweep into `out_dir`; returns its rows.
pub fn run_shard(
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    shard: Shard,
    quiet: bool,
) -> anyhow::Result<Vec<SweepRow>> {
    check_sweep(scene, varies)?;
    let dir = out_dir.join(shard.folder());
    let writer = OutputWriter::create_run(&dir)
        .with_context(|| format!("cannot create {}", dir.display()))?;
    let indices = shard.indices(grid(varies).len());
    let rows = run_rows(scene, varies, out_dir, &indices, quiet);
    let record = ShardRecord {
        scene: scene.name.clone(),
        vary: vary_args(varies),
        shard,
        rows: indices.into_iter().zip(rows.iter().cloned()).collect(),
    };
    writer.write_json("rows.json", &record)?;
    writer.commit()?;
    Ok(rows)
}

/// The shard folders under `out_dir` (`shard-I-of-N`).
fn shard_folders(out_dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(out_dir)
        .with_context(|| format!("--collect: cannot read {}", out_dir.display()))?;
    let mut dirs: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("shard-") && p.join("rows.json").is_file())
        })
        .collect();
    dirs.sort();
    Ok(dirs)
}

/// Joins the shards in `out_dir` into the sweep's table and plots; returns the rows in
/// grid order. An error names what does not fit: a shard of another sweep, shards of
/// different counts, missing shards (by their `--shard` argument).
pub fn collect(scene: &Scene, varies: &[Vary], out_dir: &Path) -> anyhow::Result<Vec<SweepRow>> {
    check_sweep(scene, varies)?;
    let total = grid(varies).len();
    let args = vary_args(varies);
    let mut slots: Vec<Option<SweepRow>> = vec![None; total];
    let mut count: Option<usize> = None;
    for dir in shard_folders(out_dir)? {
        let file = dir.join("rows.json");
        let text = std::fs::read_to_string(&file)
            .with_context(|| format!("--collect: cannot read {}", file.display()))?;
        let rec: ShardRecord = serde_json::from_str(&text)
            .with_context(|| format!("--collect: {} is not a shard record", file.display()))?;
        if rec.scene != scene.name || rec.vary != args {
            anyhow::bail!(
                "--collect: {} belongs to another sweep (scene {}, --vary {}); this one is \
                 scene {}, --vary {}",
                file.display(),
                rec.scene,
                rec.vary.join(" --vary "),
                scene.name,
                args.join(" --vary ")
            );
        }
        match count {
            Some(n) if n != rec.shard.count => anyhow::bail!(
                "--collect: {} has {} shards, others {n}: remove the shards of the older split",
                file.display(),
                rec.shard.count
            ),
            _ => count = Some(rec.shard.count),
        }
        for (k, row) in rec.rows {
            if k >= total {
                anyhow::bail!(
                    "--collect: {} has run {k} of a grid of {total}",
                    file.display()
                );
            }
            slots[k] = Some(row);
        }
    }
    let Some(n) = count else {
        anyhow::bail!(
            "--collect: no shard folders (shard-I-of-N/rows.json) in {}",
            out_dir.display()
        );
    };
    let missing: Vec<String> = (1..=n)
        .map(|i| Shard { index: i, count: n })
        .filter(|s| s.indices(total).iter().any(|&k| slots[k].is_none()))
        .map(|s| format!("{}/{}", s.index, s.count))
        .collect();
    if !missing.is_empty() {
        anyhow::bail!(
            "--collect: shards {} of the sweep in {} have not finished (run them with --shard)",
            missing.join(", "),
            out_dir.display()
        );
    }
    let rows: Vec<SweepRow> = slots.into_iter().flatten().collect();
    let writer = OutputWriter::create_run(out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    write_results(scene, varies, &rows, &writer)?;
    writer.commit()?;
    Ok(rows)
}
