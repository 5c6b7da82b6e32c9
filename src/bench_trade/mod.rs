//! `pdbem bench trade --out DIR [--quick]`: the speed/accuracy trade of a PD-BEM growth
//! study (issue 18 item 7), the curve a user needs to pick window and coupling settings.
//!
//! Each case (`growth_tension_edge`, `growth_shear_edge`; seed 002 sections 3.2.2-3.2.3)
//! runs in PD-BEM mode over
//! - window resolution at the case's side (2 m): n = 20, 30, 40, 60 nodes per side
//!   (dx = 0.1 to 0.033 m);
//! - window side at the case's dx (0.1 m): side 3 and 4 m (n = 30, 40; side 2 m is the
//!   base run);
//! - relaxation: Aitken (w0 = 0.3) against the case's IQN-ILS (w0 = 0.5) at n = 20;
//! - coupling tolerance psi = 1e-3 and 1e-5 against the case's 1e-4 at n = 20;
//!
//! everything else as in the case file (BEM elements 0.1 m, window moves 0.5 m). Every run
//! is compared with the case's finest run (smallest dx: n = 60 at side 2 m):
//! - **path deviation** d(A, B): the deviation of `pdbem bench growth`
//!   ([`pdbem_coupling::growth::compare::path_deviation`]): both paths are cut where they
//!   first get as far from their initial tip as the shorter one ever gets (their common
//!   reach), and d is the Hausdorff distance of the cut polylines,
//!   max(sup_{a in A} dist(a, B), sup_{b in B} dist(b, A)), sampled at the vertices and 8
//!   points per segment; the largest over the tips of the case. On paths of one reach
//!   this is a metric (d(A, A) = 0, symmetric, triangle inequality up to the sampling);
//!   between paths of different reach it measures the shape over the part both grew,
//!   and the reach difference is reported apart (`reach_m`);
//! - **failure-load error**: (F - F_ref) / F_ref of the load factor at which the crack cut
//!   the body, when both runs failed; a run that did not fail while the reference did (or
//!   the other way) is reported as such, not as an error value. The load step is the
//!   resolution of this measure (0.05 / 3.3 = 1.5 % on the tension plate).
//!
//! Wall time is the whole run (setup, steps, outputs) with the K-along-path record and
//! plots turned off (as in `pdbem bench growth`). Writes `DIR/report.md`, `DIR/bench.json`
//! (docs/outputs.md), `DIR/trade_deviation.{png,svg}` and
//! `DIR/trade_failure_load.{png,svg}` ([`report`]); each run's folder is kept under
//! `DIR/<case>/<label>`. `--quick` (a smoke test): the tension case with its crack
//! started at 6 m instead of 2 m (6 relocations instead of 14), n = 20 and 24 and
//! psi = 1e-3. Runs that ended early (`complete: false`) or failed are rows without a
//! deviation or load error. `--collect` ([`collect`]) rebuilds the report from the run
//! folders without running anything.

pub mod report;

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};

use crate::growth::{GrowthHistory, TipPath};
use crate::output::atomic::write_atomic;
use crate::scene::{Relaxation, Scene};
use pdbem_coupling::growth::compare::path_deviation;

/// The cases of the full bench.
pub const CASES: [&str; 2] = ["growth_tension_edge", "growth_shear_edge"];

/// What a variant changes against the case file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Variant {
    /// Short label, also the run folder name (`n20`, `side3`, `aitken`, `psi1e-3`).
    pub label: String,
    /// The series it belongs to: `n` (resolution at fixed side), `side` (side at fixed
    /// dx), `relaxation`, `tolerance`; the base run (case settings) is `base`.
    pub series: String,
    /// Window side (m).
    pub side: f64,
    /// Nodes per window side.
    pub n: usize,
    /// `iqn-ils` or `aitken`.
    pub relaxation: String,
    /// Coupling tolerance.
    pub psi: f64,
}

impl Variant {
    /// Node spacing (m).
    pub fn dx(&self) -> f64 {
        self.side / self.n as f64
    }
}

/// One run of the bench.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct TradeRun {
    /// Label of the variant.
    pub label: String,
    /// Its series.
    pub series: String,
    /// Window side (m).
    pub side: f64,
    /// Nodes per side.
    pub n: usize,
    /// Node spacing (m).
    pub dx: f64,
    /// Relaxation scheme.
    pub relaxation: String,
    /// Coupling tolerance.
    pub psi: f64,
    /// Wall time of the run (s).
    pub wall_time_s: f64,
    /// Load steps run.
    pub steps: usize,
    /// Coupling iterations over all steps.
    pub coupling_iterations: usize,
    /// Window relocations.
    pub relocations: usize,
    /// The run went to its end (`complete` of summary.json).
    pub complete: bool,
    /// Why it ended early (`failure_reason`).
    pub failure_reason: Option<String>,
    /// A crack cut the body.
    pub failure: bool,
    /// Load factor at failure.
    pub failure_load: Option<f64>,
    /// Load factor of the last step run.
    pub end_load: Option<f64>,
    /// Largest reach of a tip path from its initial tip (m).
    pub reach_m: f64,
    /// Final tip positions (m).
    pub tips: Vec<[f64; 2]>,
    /// Path deviation from the case's finest run (m), largest over the tips.
    pub deviation_m: Option<f64>,
    /// The common reach it was measured over (m), that of the worst tip.
    pub common_reach_m: Option<f64>,
    /// (F - F_ref) / F_ref of the failure load (both failed).
    pub failure_load_err: Option<f64>,
    /// Load of the first BEM overstrain (`growth.overstrain`, where a run ends by
    /// default: the bench goes on past it).
    #[serde(default)]
    pub overstrain_load: Option<f64>,
    /// Path deviation from the finest run over the parts both tips reached below the
    /// first overstrain load of the two (`[deviation, common reach, load]`, m, m, load
    /// factor): the comparison of the part a run ending at its strain watch computes,
    /// given also for runs that ended early past that load.
    #[serde(default)]
    pub before_overstrain: Option<[f64; 3]>,
    /// The run failed to run (first line), `None` when it ran.
    pub error: Option<String>,
    /// Tip paths, not written to `bench.json` (read back from the run folder by
    /// [`collect`]).
    #[serde(skip)]
    pub paths: Vec<TipPath>,
}

/// The runs of one case.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CaseTrade {
    /// Scene name (file stem).
    pub case: String,
    /// Label of the finest run, the reference.
    pub reference: String,
    /// Runs in variant order.
    pub runs: Vec<TradeRun>,
}

/// `bench.json` of `bench trade`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TradeReport {
    /// "trade".
    pub bench: String,
    /// Threads rayon used.
    pub threads: usize,
    /// Smoke-test sizes.
    pub quick: bool,
    /// How the path deviation is measured.
    pub deviation_measure: String,
    /// One entry per case.
    pub cases: Vec<CaseTrade>,
}

/// The deviation measure in one line (report and `bench.json`).
pub const MEASURE: &str = "Hausdorff distance of the two tip paths cut at their common reach \
    (distance from the initial tip), largest over the tips (pdbem_coupling::growth::compare)";

fn variant(label: &str, series: &str, side: f64, n: usize, relax: &str, psi: f64) -> Variant {
    Variant {
        label: label.into(),
        series: series.into(),
        side,
        n,
        relaxation: relax.into(),
        psi,
    }
}

/// The variants of a case whose window is `side` x `n` (full bench) or the smoke test's.
pub fn variants(side: f64, n: usize, psi: f64, quick: bool) -> Vec<Variant> {
    let iqn = "iqn-ils";
    if quick {
        return vec![
            variant(&format!("n{n}"), "base", side, n, iqn, psi),
            variant("n24", "n", side, 24, iqn, psi),
            variant("psi1e-3", "tolerance", side, n, iqn, 1e-3),
        ];
    }
    let dx = side / n as f64;
    let mut v = vec![variant(&format!("n{n}"), "base", side, n, iqn, psi)];
    for m in [30, 40, 60] {
        v.push(variant(&format!("n{m}"), "n", side, m, iqn, psi));
    }
    for s in [3.0, 4.0] {
        let m = (s / dx).round() as usize;
        v.push(variant(&format!("side{s}"), "side", s, m, iqn, psi));
    }
    v.push(variant("aitken", "relaxation", side, n, "aitken", psi));
    for p in [1e-3, 1e-5] {
        v.push(variant(&format!("psi{p:e}"), "tolerance", side, n, iqn, p));
    }
    v
}

/// Index of the finest variant: smallest dx, then the largest side, then the smallest psi.
pub fn finest(v: &[Variant]) -> usize {
    let key = |x: &Variant| (x.dx(), -x.side, x.psi);
    (0..v.len())
        .min_by(|&a, &b| {
            key(&v[a])
                .partial_cmp(&key(&v[b]))
                .unwrap_or(std::cmp::Ordering::Equal)
        })
        .unwrap_or(0)
}

/// The case's scene with the variant's window and coupling (PD-BEM, no K record, no plots,
/// going on past a BEM overstrain: `growth.overstrain: Note`).
pub fn scene_for(base: &Scene, v: &Variant) -> Result<Scene> {
    let mut s = base.clone();
    let co = s
        .coupling
        .as_mut()
        .context("bench trade: the case needs `coupling`")?;
    co.side = v.side;
    co.n = v.n;
    co.psi = v.psi;
    co.relaxation = match v.relaxation.as_str() {
        "aitken" => Relaxation::Aitken(0.3),
        _ => Relaxation::IqnIls { w0: 0.5 },
    };
    let g = s
        .growth
        .as_mut()
        .context("bench trade: the case needs `growth`")?;
    g.mode = crate::scene::GrowthMode::PdBem;
    g.sif_spacing = Some(0.0);
    // The trade of the settings over the whole path, as measured before runs ended at the
    // first BEM overstrain (the shear plate's, at 0.20-0.24): the study compares the
    // windows' paths, not what the plate does beyond that load.
    g.overstrain = crate::scene::OverstrainAction::Note;
    s.outputs.plots = false;
    s.validate()?;
    Ok(s)
}

/// The smoke test's tension plate: the crack started at 6 m (a/W = 0.6), so the tip runs
/// 4 m to the far edge instead of 8 m.
pub fn quick_scene(mut base: Scene) -> Scene {
    if let Some(c) = base.cracks.first_mut() {
        c.length = Some(6.0);
    }
    base
}

/// Runs one variant into `dir` and records what it did (a run that fails is a row too).
pub fn run_variant(base: &Scene, v: &Variant, dir: &Path) -> TradeRun {
    let t0 = Instant::now();
    let result = scene_for(base, v).and_then(|s| {
        let summary = crate::runner::run_scene(&s, dir, true)?;
        let text = std::fs::read_to_string(dir.join(crate::growth::output::HISTORY_FILE))?;
        Ok((summary, serde_json::from_str::<GrowthHistory>(&text)?))
    });
    let mut run = TradeRun {
        label: v.label.clone(),
        series: v.series.clone(),
        side: v.side,
        n: v.n,
        dx: v.dx(),
        relaxation: v.relaxation.clone(),
        psi: v.psi,
        wall_time_s: t0.elapsed().as_secs_f64(),
        ..Default::default()
    };
    match result {
        Ok((summary, h)) => {
            run.failure_reason = summary.incomplete();
            run.complete = run.failure_reason.is_none();
            run.steps = h.steps.len();
            run.coupling_iterations = h.steps.iter().map(|s| s.coupling_iterations).sum();
            run.relocations = h.relocations.len();
            run.failure = h.failure;
            run.failure_load = h.failure_load;
            run.end_load = h.steps.last().map(|s| s.load);
            run.overstrain_load = h.overstrain.map(|o| o.load);
            run.tips = h.steps.last().map(|s| s.tips.clone()).unwrap_or_default();
            run.reach_m = h.paths.iter().map(path_reach).fold(0.0, f64::max);
            run.paths = h.paths;
        }
        Err(e) => {
            let msg = format!("{e:#}");
            let line = msg.lines().next().unwrap_or_default();
            run.error = Some(line.chars().take(300).collect());
        }
    }
    run
}

/// Largest distance of a path's points from its first point (m).
pub fn path_reach(p: &TipPath) -> f64 {
    let pts: Vec<_> = p
        .points
        .iter()
        .map(|q| pdbem_geometry::P2::new(q.x, q.y))
        .collect();
    pdbem_coupling::growth::compare::reach(&pts)
}

/// Deviation of two runs' paths: the largest over the tips both have, with the common
/// reach of that tip; `None` when they share no tip.
pub fn run_deviation(a: &[TipPath], b: &[TipPath]) -> Option<(f64, f64)> {
    a.iter()
        .filter_map(|pa| {
            let pb = b.iter().find(|p| p.name == pa.name)?;
            Some(path_deviation(pa, pb))
        })
        .max_by(|x, y| x.0.partial_cmp(&y.0).unwrap_or(std::cmp::Ordering::Equal))
}

/// Fills every run's deviation and failure-load error against run `reference`; runs that
/// did not run or ended early (`complete: false`) get none (their paths stop where their
/// coupling gave up), nor does anything when the reference did not complete. Where the run
/// or the reference overstrained the BEM body, the deviation below the first such load
/// ([`TradeRun::before_overstrain`]) is given for every run that ran to that load, ended
/// early after it or not.
pub fn compare_to(runs: &mut [TradeRun], reference: usize) {
    for run in runs.iter_mut() {
        run.deviation_m = None;
        run.common_reach_m = None;
        run.failure_load_err = None;
        run.before_overstrain = None;
    }
    if let Some(r) = runs.get(reference).filter(|r| r.error.is_none()).cloned() {
        for run in runs.iter_mut().filter(|x| x.error.is_none()) {
            run.before_overstrain = deviation_below_overstrain(run, &r);
        }
    }
    let done = |x: &TradeRun| x.error.is_none() && x.failure_reason.is_none();
    let Some(r) = runs.get(reference).filter(|r| done(r)).cloned() else {
        return;
    };
    for run in runs.iter_mut().filter(|x| done(x)) {
        if let Some((d, common)) = run_deviation(&run.paths, &r.paths) {
            run.deviation_m = Some(d);
            run.common_reach_m = Some(common);
        }
        run.failure_load_err = match (run.failure_load, r.failure_load) {
            (Some(f), Some(g)) if g != 0.0 => Some((f - g) / g),
            _ => None,
        };
    }
}

/// [`TradeRun::before_overstrain`] of `run` against `reference`: `None` when neither
/// overstrained, or either did not run to that load.
fn deviation_below_overstrain(run: &TradeRun, reference: &TradeRun) -> Option<[f64; 3]> {
    let load = match (run.overstrain_load, reference.overstrain_load) {
        (Some(a), Some(b)) => a.min(b),
        (a, b) => a.or(b)?,
    };
    let reached = |x: &TradeRun| x.end_load.is_some_and(|e| e >= load);
    if !(reached(run) && reached(reference)) {
        return None;
    }
    let below = |p: &[TipPath]| -> Vec<TipPath> {
        p.iter()
            .map(|t| pdbem_coupling::growth::compare::reached_below(t, load))
            .collect()
    };
    let (d, common) = run_deviation(&below(&run.paths), &below(&reference.paths))?;
    Some([d, common, load])
}

/// Runs every variant of `case` (a file stem in `cases/` or a scene path) into
/// `out/<case>/<label>`.
pub fn run_case(case: &str, out: &Path, quick: bool) -> Result<CaseTrade> {
    let mut base = Scene::load(crate::cases::case_path(case)?)?;
    if quick {
        base = quick_scene(base);
    }
    let co = base
        .coupling
        .clone()
        .context("bench trade: the case needs `coupling`")?;
    let vs = variants(co.side, co.n, co.psi, quick);
    let reference = finest(&vs);
    let stem = Path::new(case)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(case)
        .to_string();
    let mut runs = Vec::new();
    for v in &vs {
        eprintln!("bench trade: {stem} {} ...", v.label);
        let r = run_variant(&base, v, &out.join(&stem).join(&v.label));
        eprintln!(
            "bench trade: {stem} {} {:.2} s{}",
            r.label,
            r.wall_time_s,
            r.error
                .as_deref()
                .map(|e| format!(" (failed: {e})"))
                .unwrap_or_default()
        );
        runs.push(r);
    }
    compare_to(&mut runs, reference);
    Ok(CaseTrade {
        case: stem,
        reference: vs[reference].label.clone(),
        runs,
    })
}

/// `bench trade`: every case, then `report.md`, `bench.json` and the plots in `out`.
pub fn run(out: &Path, quick: bool) -> Result<TradeReport> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let cases: &[&str] = if quick { &CASES[..1] } else { &CASES[..] };
    let mut report = TradeReport {
        bench: "trade".into(),
        threads: rayon::current_num_threads(),
        quick,
        deviation_measure: MEASURE.into(),
        cases: Vec::new(),
    };
    for case in cases {
        report.cases.push(run_case(case, out, quick)?);
    }
    write_report(&report, out)?;
    Ok(report)
}

/// Writes `report.md`, `bench.json` and the plots of `report` into `out` (the table also
/// to stdout).
fn write_report(report: &TradeReport, out: &Path) -> Result<()> {
    let text = report::markdown(report);
    crate::console::out(&text);
    write_atomic(&out.join("report.md"), text.as_bytes())?;
    write_atomic(
        &out.join("bench.json"),
        serde_json::to_string_pretty(report)?.as_bytes(),
    )?;
    report::plots(report, out)
}

/// `bench trade --collect`: reads `out/bench.json` and every run's paths from
/// `out/<case>/<label>/growth.json`, compares the runs again with their case's reference
/// and rewrites the report (for a report whose rules changed after a long run).
pub fn collect(out: &Path) -> Result<TradeReport> {
    let file = out.join("bench.json");
    let text = std::fs::read_to_string(&file)
        .with_context(|| format!("bench trade --collect: cannot read {}", file.display()))?;
    let mut report: TradeReport = serde_json::from_str(&text).with_context(|| {
        format!(
            "bench trade --collect: {} is not a trade bench.json",
            file.display()
        )
    })?;
    for c in &mut report.cases {
        for run in c.runs.iter_mut().filter(|r| r.error.is_none()) {
            let h = out
                .join(&c.case)
                .join(&run.label)
                .join(crate::growth::output::HISTORY_FILE);
            let text = std::fs::read_to_string(&h)
                .with_context(|| format!("bench trade --collect: cannot read {}", h.display()))?;
            let h = serde_json::from_str::<GrowthHistory>(&text)?;
            run.overstrain_load = h.overstrain.map(|o| o.load);
            run.paths = h.paths;
        }
        let reference = c.runs.iter().position(|r| r.label == c.reference);
        compare_to(&mut c.runs, reference.unwrap_or(usize::MAX));
    }
    write_report(&report, out)?;
    Ok(report)
}

#[cfg(test)]
mod tests;
