//! `pdbem bench growth --out DIR [--quick]`: one growth scene three ways in one process,
//! PD-BEM (moving windows), BEM-only (SIF + kink + da) and full PD at the windows' node
//! spacing, with wall time per mode, per load step and per relocation, and the ratio
//! full-PD / PD-BEM. Each mode's run folder is kept (`DIR/pd-bem`, `DIR/bem-only`,
//! `DIR/full-pd`, overlaid in `DIR/paths.{png,svg}`); the table goes to stdout and
//! `DIR/bench.txt`, the numbers to `DIR/bench.json` (docs/outputs.md). A mode that fails
//! is a row with its error; the others still run. A case with refined windows
//! (`coupling.refine`) runs full PD at the windows' finest spacing (equal tip resolution)
//! and gets a fourth run, `pd-bem-fine`: PD-BEM on uniform windows at the finest spacing,
//! with the ratio of its wall time to the refined run's.
//!
//! Scene: `cases/growth_tension_edge.ron` (seed 002 section 3.2.2). BEM-only needs K_c:
//! when the scene gives no fracture data, G_c is taken from the PD critical stretch at the
//! window's horizon (the same material the PD modes see): G_c = 9 E delta s0^2 / (4 pi)
//! (plane stress) or 12 E delta s0^2 / (5 pi) (plane strain), the inverse of
//! [`pdbem_bem::analytic::pd_critical_stretch`]. `--quick` runs full PD at twice the
//! window spacing (so its ratio to PD-BEM is not the same-resolution one) and BEM-only
//! with da = 5 dx; PD-BEM is unchanged.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use serde::Serialize;

use super::GrowthHistory;
use crate::output::atomic::write_atomic;
use crate::scene::{Failure, Fracture, GrowthMode, Scene};

/// The scene of the benchmark.
pub const CASE: &str = "growth_tension_edge";

/// Wall-time statistics of a set of events (s).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Times {
    /// Number of events.
    pub count: usize,
    /// Sum (s).
    pub total: f64,
    /// Mean (s), 0 without events.
    pub mean: f64,
    /// Largest (s).
    pub max: f64,
}

impl Times {
    fn of(v: impl Iterator<Item = f64>) -> Times {
        let v: Vec<f64> = v.collect();
        let total = v.iter().fold(0.0, |a, b| a + b);
        Times {
            count: v.len(),
            total,
            mean: if v.is_empty() {
                0.0
            } else {
                total / v.len() as f64
            },
            max: v.iter().copied().fold(0.0, f64::max),
        }
    }
}

/// One mode of the benchmark.
#[derive(Debug, Clone, Default, Serialize)]
pub struct GrowthBenchRun {
    /// `pd-bem`, `bem-only`, `full-pd`.
    pub mode: String,
    /// Wall time of the whole run including outputs (s).
    pub wall_time_s: f64,
    /// Load steps.
    pub steps: Times,
    /// Window relocations (rebuild time).
    pub relocations: Times,
    /// A crack cut the body through.
    pub failure: bool,
    /// Load factor at failure.
    pub failure_load: Option<f64>,
    /// Load factor of the first growth.
    pub initiation_load: Option<f64>,
    /// Final tip positions (m).
    pub tips: Vec<[f64; 2]>,
    /// PD-BEM: where and when the BEM body first reached the PD onset stretch
    /// (`bem_overstrain` of the run's summary).
    pub overstrain: Option<super::Overstrain>,
    /// Why the run failed (first line), `None` when it ran.
    pub error: Option<String>,
    /// The run's history (paths), not written to `bench.json`.
    #[serde(skip)]
    pub history: Option<GrowthHistory>,
}

/// Deviation between the paths of one tip in two modes ([`pdbem_coupling::growth::compare`]).
#[derive(Debug, Clone, Serialize)]
pub struct PathDeviation {
    /// First mode.
    pub a: String,
    /// Second mode.
    pub b: String,
    /// Tip name.
    pub tip: String,
    /// Hausdorff distance over the common length (m).
    pub max_m: f64,
    /// The same in node spacings dx.
    pub max_dx: f64,
    /// Common reach compared: distance from the initial tip (m).
    pub common_reach_m: f64,
    /// The deviation (m) and common reach (m) of the paths as far as they got at loads
    /// below PD-BEM's `bem_overstrain` load: up to where the tip-only modes stop modelling
    /// what full PD does (a crack starting away from the tips); `None` when PD-BEM did not
    /// run or its BEM body never reached the PD critical stretch.
    pub before_overstrain: Option<[f64; 2]>,
}

/// `bench.json` of `bench growth`.
#[derive(Debug, Serialize)]
pub struct GrowthBenchReport {
    /// "growth".
    pub bench: &'static str,
    /// Threads rayon used.
    pub threads: usize,
    /// Scene file stem.
    pub case: String,
    /// Smaller sizes.
    pub quick: bool,
    /// PD node spacing of the windows (m); the full-PD body's too unless `quick`.
    pub dx: f64,
    /// PD node spacing of the full-PD body (m).
    pub full_pd_dx: f64,
    /// Finest PD node spacing of the windows (m): `dx / 2^levels` with `coupling.refine`,
    /// else `dx`. The deviations are also given in it: "within one fine dx" (issue 20).
    pub tip_dx: f64,
    /// One entry per mode.
    pub runs: Vec<GrowthBenchRun>,
    /// Wall time of full PD over PD-BEM (`None` when either failed).
    pub ratio_full_pd_to_pd_bem: Option<f64>,
    /// Refined windows: wall time of PD-BEM on uniform windows at the finest spacing over
    /// the refined PD-BEM run ([`uniform_fine_scene`]; `None` without refinement or when
    /// either failed).
    pub ratio_uniform_fine_to_refined: Option<f64>,
    /// Path deviations between every two modes that ran, per tip.
    pub path_deviations: Vec<PathDeviation>,
}

/// Deviations of the same-named tip paths between every two runs that succeeded.
pub fn deviations(runs: &[GrowthBenchRun], dx: f64) -> Vec<PathDeviation> {
    let overstrain_load = runs.iter().find_map(|r| r.overstrain.map(|o| o.load));
    let mut out = Vec::new();
    for (i, ra) in runs.iter().enumerate() {
        for rb in &runs[i + 1..] {
            let (Some(ha), Some(hb)) = (&ra.history, &rb.history) else {
                continue;
            };
            for pa in &ha.paths {
                if let Some(pb) = hb.paths.iter().find(|p| p.name == pa.name) {
                    let (d, common) = pdbem_coupling::growth::compare::path_deviation(pa, pb);
                    let before = overstrain_load.map(|f| {
                        let (d, common) = pdbem_coupling::growth::compare::path_deviation(
                            &pdbem_coupling::growth::compare::reached_below(pa, f),
                            &pdbem_coupling::growth::compare::reached_below(pb, f),
                        );
                        [d, common]
                    });
                    out.push(PathDeviation {
                        a: ra.mode.clone(),
                        b: rb.mode.clone(),
                        tip: pa.name.clone(),
                        max_m: d,
                        max_dx: d / dx,
                        common_reach_m: common,
                        before_overstrain: before,
                    });
                }
            }
        }
    }
    out
}

pub use crate::setup::growth::gc_from_stretch;

/// The benchmark scene in `mode`. `quick`: full PD on a grid of twice the window
/// spacing (its cost falls about 30-fold; PD-BEM keeps its windows: at fewer than about
/// 20 nodes per side the window cannot hold a growing tip, measured: 10 never holds it,
/// 12 and 14 stop in the coupling or the window's Newton solve), BEM-only with
/// da = 5 dx.
pub fn scene_for(base: &Scene, mode: GrowthMode, quick: bool) -> Result<Scene> {
    let mut s = base.clone();
    if quick && mode == GrowthMode::FullPd {
        if let Some(co) = s.coupling.as_mut() {
            co.n = (co.n / 2).max(4);
        }
    }
    if mode == GrowthMode::FullPd {
        // Equal tip resolution: with refined windows, full PD at their finest spacing.
        if let Some(co) = s.coupling.as_mut() {
            to_finest_uniform(co);
        }
    }
    let co = s
        .coupling
        .clone()
        .context("bench growth: the case needs `coupling`")?;
    let dx = co.side / co.n as f64;
    let g = s
        .growth
        .as_mut()
        .context("bench growth: the case needs `growth`")?;
    g.mode = mode;
    if mode != GrowthMode::BemOnly {
        // The K record of the PD modes is a post-processing (BEM solves of the path):
        // not part of the timings compared here.
        g.sif_spacing = Some(0.0);
    }
    if mode == GrowthMode::BemOnly {
        g.da = Some(if quick { 5.0 * dx } else { dx });
        if s.material.k_c().is_none() {
            let pd = s.pd.as_ref().context("bench growth: the case needs `pd`")?;
            let Failure::CriticalStretch(s0) = pd.failure else {
                anyhow::bail!("bench growth: no K_c for BEM-only: give material.fracture")
            };
            let delta = pd.horizon_factor * dx;
            s.material.fracture = Some(Fracture {
                g_c: Some(gc_from_stretch(s.material.e, delta, s0, s.material.plane)),
                ..Default::default()
            });
        }
    }
    s.outputs.plots = true;
    s.validate()?;
    Ok(s)
}

fn mode_name(m: GrowthMode) -> &'static str {
    match m {
        GrowthMode::PdBem => "pd-bem",
        GrowthMode::BemOnly => "bem-only",
        GrowthMode::FullPd => "full-pd",
    }
}

/// Uniform windows at the finest spacing of `co`'s refinement zone (`n` times
/// 2^levels, no zone); unchanged without one.
fn to_finest_uniform(co: &mut crate::scene::Coupling) {
    if let Some(r) = co.refine.take() {
        co.n <<= r.levels;
    }
}

/// Name of the run of [`uniform_fine_scene`].
pub const UNIFORM_FINE: &str = "pd-bem-fine";

/// For a case with refined windows (`coupling.refine`): its PD-BEM run on uniform windows
/// of the same side at the finest spacing (`n` times 2^levels), the reference the refined
/// windows' path and time are measured against (docs/coupled_refined.md); `None`
/// without refinement.
pub fn uniform_fine_scene(base: &Scene, quick: bool) -> Option<Result<Scene>> {
    base.coupling.as_ref()?.refine?;
    Some(scene_for(base, GrowthMode::PdBem, quick).and_then(|mut s| {
        let co = s
            .coupling
            .as_mut()
            .context("bench growth: the case needs `coupling`")?;
        to_finest_uniform(co);
        s.validate()?;
        Ok(s)
    }))
}

/// Runs one mode into `DIR/<mode>` and summarises it.
fn run_mode(base: &Scene, mode: GrowthMode, out: &Path, quick: bool) -> GrowthBenchRun {
    run_named(mode_name(mode), scene_for(base, mode, quick), out)
}

/// Runs `scene` into `DIR/<name>` and summarises it.
fn run_named(name: &str, scene: Result<Scene>, out: &Path) -> GrowthBenchRun {
    let t0 = Instant::now();
    let result = scene.and_then(|s| {
        crate::runner::run_scene(&s, &out.join(name), true)?;
        let text = std::fs::read_to_string(out.join(name).join(super::output::HISTORY_FILE))?;
        Ok(serde_json::from_str::<GrowthHistory>(&text)?)
    });
    let wall = t0.elapsed().as_secs_f64();
    match result {
        Ok(h) => GrowthBenchRun {
            mode: name.into(),
            wall_time_s: wall,
            steps: Times::of(h.steps.iter().map(|s| s.wall_time_s)),
            relocations: Times::of(h.relocations.iter().map(|r| r.rebuild_s)),
            failure: h.failure,
            failure_load: h.failure_load,
            initiation_load: h.initiation_load,
            tips: h.steps.last().map(|s| s.tips.clone()).unwrap_or_default(),
            overstrain: h.overstrain,
            error: None,
            history: Some(h),
        },
        Err(e) => GrowthBenchRun {
            mode: name.into(),
            wall_time_s: wall,
            error: Some(short_error(&format!("{e:#}"))),
            ..Default::default()
        },
    }
}

/// First line of an error, without a coupling residual history, at most 300 characters.
fn short_error(msg: &str) -> String {
    let line = msg.lines().next().unwrap_or_default();
    let line = line.split("; residual history").next().unwrap_or(line);
    line.chars().take(300).collect()
}

/// The readable table.
pub fn table(r: &GrowthBenchReport) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "growth benchmark ({} threads): {}, dx = {:e} m{}",
        r.threads,
        r.case,
        r.dx,
        if r.quick {
            format!(
                " (quick: full PD at dx = {:e} m, its ratio is not at the same resolution)",
                r.full_pd_dx
            )
        } else if r.full_pd_dx < r.dx {
            format!(
                " (refined windows: full PD at their finest spacing, dx = {:e} m)",
                r.full_pd_dx
            )
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        t,
        "{:<9} {:>9} {:>6} {:>10} {:>10} {:>6} {:>10} {:>8} {:>10} {:>10}",
        "mode",
        "wall_s",
        "steps",
        "step_mean",
        "step_max",
        "reloc",
        "reloc_mean",
        "failure",
        "fail_load",
        "init_load"
    );
    let o = |v: Option<f64>| v.map(|x| format!("{x:.4}")).unwrap_or_else(|| "-".into());
    for e in &r.runs {
        if let Some(err) = &e.error {
            let _ = writeln!(
                t,
                "{:<9} failed after {:.2} s: {err}",
                e.mode, e.wall_time_s
            );
            continue;
        }
        let _ = writeln!(
            t,
            "{:<9} {:>9.2} {:>6} {:>10.4} {:>10.4} {:>6} {:>10.4} {:>8} {:>10} {:>10}",
            e.mode,
            e.wall_time_s,
            e.steps.count,
            e.steps.mean,
            e.steps.max,
            e.relocations.count,
            e.relocations.mean,
            e.failure,
            o(e.failure_load),
            o(e.initiation_load)
        );
    }
    let _ = writeln!(
        t,
        "full-PD / PD-BEM wall time: {}",
        r.ratio_full_pd_to_pd_bem
            .map(|x| format!("{x:.2}"))
            .unwrap_or_else(|| "- (a run failed)".into())
    );
    if let Some(x) = r.ratio_uniform_fine_to_refined {
        let _ = writeln!(
            t,
            "{UNIFORM_FINE} (uniform windows at the finest spacing) / refined PD-BEM wall time: {x:.2}"
        );
    }
    for (mode, o) in r.runs.iter().filter_map(|e| Some((&e.mode, e.overstrain?))) {
        let _ = writeln!(
            t,
            "{mode}: the BEM body reaches the PD onset stretch {} at load {} (strain {:.4} one \
             horizon inside the boundary at ({:.3}, {:.3})): a crack may start there in full PD",
            o.onset, o.load, o.strain, o.position[0], o.position[1]
        );
    }
    for d in &r.path_deviations {
        let _ = writeln!(
            t,
            "path deviation {} vs {} ({}): {:.4} m = {:.2} dx{} over a reach of {:.3} m{}",
            d.a,
            d.b,
            d.tip,
            d.max_m,
            d.max_dx,
            in_tip_spacings(d.max_m, r),
            d.common_reach_m,
            d.before_overstrain
                .map(|[m, r]| format!("; below PD-BEM's overstrain load {m:.4} m over {r:.3} m"))
                .unwrap_or_default()
        );
    }
    t
}

/// " (N tip dx of T m)" when the windows' finest spacing is finer than `dx` (refined windows).
fn in_tip_spacings(m: f64, r: &GrowthBenchReport) -> String {
    if r.tip_dx < r.dx {
        format!(" ({:.2} tip dx of {:e} m)", m / r.tip_dx, r.tip_dx)
    } else {
        String::new()
    }
}

/// `bench growth` on `cases/<case>.ron` under the current folder, or a scene file
/// (default [`CASE`]; [`crate::cases::case_path`]).
pub fn run(out: &Path, quick: bool, case: Option<&str>) -> Result<()> {
    let case = case.unwrap_or(CASE);
    let base = Scene::load(crate::cases::case_path(case)?)?;
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let modes = [GrowthMode::PdBem, GrowthMode::BemOnly, GrowthMode::FullPd];
    let mut runs = Vec::new();
    for m in modes {
        eprintln!("bench growth: {} ...", mode_name(m));
        let r = run_mode(&base, m, out, quick);
        eprintln!(
            "bench growth: {} {:.2} s{}",
            r.mode,
            r.wall_time_s,
            r.error
                .as_deref()
                .map(|e| format!(" (failed: {e})"))
                .unwrap_or_default()
        );
        runs.push(r);
    }
    if let Some(scene) = uniform_fine_scene(&base, quick) {
        eprintln!("bench growth: {UNIFORM_FINE} (uniform windows at the refined spacing) ...");
        let r = run_named(UNIFORM_FINE, scene, out);
        eprintln!("bench growth: {UNIFORM_FINE} {:.2} s", r.wall_time_s);
        runs.push(r);
    }
    let ok = |m: &str| {
        runs.iter()
            .find(|r| r.mode == m && r.error.is_none())
            .map(|r| r.wall_time_s)
    };
    let over = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) if b > 0.0 => Some(a / b),
        _ => None,
    };
    let ratio = over(ok("full-pd"), ok("pd-bem"));
    let fine_ratio = over(ok(UNIFORM_FINE), ok("pd-bem"));
    let spacing = |m: GrowthMode| {
        scene_for(&base, m, quick)
            .ok()
            .and_then(|s| s.coupling.map(|c| c.side / c.n as f64))
            .unwrap_or(f64::NAN)
    };
    let (dx, full_pd_dx) = (spacing(GrowthMode::PdBem), spacing(GrowthMode::FullPd));
    let tip_dx = match base.coupling.as_ref().and_then(|c| c.refine) {
        Some(r) => dx * 0.5f64.powi(r.levels.min(30) as i32),
        None => dx,
    };
    let report = GrowthBenchReport {
        bench: "growth",
        threads: rayon::current_num_threads(),
        case: case.into(),
        quick,
        dx,
        full_pd_dx,
        tip_dx,
        path_deviations: deviations(&runs, dx),
        runs,
        ratio_full_pd_to_pd_bem: ratio,
        ratio_uniform_fine_to_refined: fine_ratio,
    };
    let text = table(&report);
    crate::console::out(&text);
    write_atomic(&out.join("bench.txt"), text.as_bytes())?;
    write_atomic(
        &out.join("bench.json"),
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    let done: Vec<_> = report
        .runs
        .iter()
        .filter(|r| r.error.is_none())
        .map(|r| out.join(&r.mode))
        .collect();
    if !done.is_empty() {
        if let Err(e) = super::overlay::plot_paths(&done, &out.join("paths")) {
            eprintln!("bench growth: no path overlay: {e:#}");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Plane;

    #[test]
    fn gc_inverts_the_critical_stretch() {
        for plane in [Plane::Stress, Plane::Strain] {
            let g = gc_from_stretch(30e9, 7.5e-4, 0.0026, plane);
            let s0 = pdbem_bem::analytic::pd_critical_stretch(g, 30e9, 7.5e-4, plane);
            assert!((s0 - 0.0026).abs() < 1e-15, "{plane:?}: {s0}");
        }
    }

    #[test]
    fn times_of_nothing_are_zero() {
        let t = Times::of(std::iter::empty());
        assert_eq!((t.count, t.total, t.mean, t.max), (0, 0.0, 0.0, 0.0));
        let t = Times::of([1.0, 3.0].into_iter());
        assert_eq!((t.count, t.mean, t.max), (2, 2.0, 3.0));
    }

    /// A run of one tip whose path points are `(x, y, load)`.
    fn run_of(mode: &str, pts: &[(f64, f64, f64)], overstrain: Option<f64>) -> GrowthBenchRun {
        let o = overstrain.map(|load| super::super::Overstrain {
            step: 6,
            load,
            position: [10.05, 0.15],
            strain: 0.0219,
            onset: 0.02,
        });
        let path = super::super::TipPath {
            name: "crack.end".into(),
            points: pts
                .iter()
                .map(|&(x, y, load)| super::super::PathPoint {
                    x,
                    y,
                    step: 0,
                    load,
                })
                .collect(),
            ended: None,
        };
        GrowthBenchRun {
            mode: mode.into(),
            overstrain: o,
            history: Some(GrowthHistory {
                paths: vec![path],
                overstrain: o,
                ..Default::default()
            }),
            ..Default::default()
        }
    }

    #[test]
    fn deviations_below_the_overstrain_load_leave_out_what_came_after() {
        // Both paths run straight down; full PD turns 1 m sideways at load 0.2, the load
        // at which PD-BEM's body reached the onset stretch.
        let pdbem = run_of(
            "pd-bem",
            &[(10.0, 5.0, 0.08), (10.0, 3.0, 0.1), (10.0, 1.0, 0.3)],
            Some(0.2),
        );
        let full = run_of(
            "full-pd",
            &[(10.0, 5.0, 0.08), (10.0, 2.0, 0.18), (11.0, 1.5, 0.2)],
            None,
        );
        let d = deviations(&[pdbem.clone(), full], 0.1);
        assert_eq!(d.len(), 1);
        assert!((d[0].max_m - 1.0).abs() < 0.1, "{d:?}");
        let [m, reach] = d[0].before_overstrain.expect("cut below the load");
        assert!(m < 1e-12 && (reach - 2.0).abs() < 1e-12, "{d:?}");
        let report = GrowthBenchReport {
            bench: "growth",
            threads: 1,
            case: "c".into(),
            quick: false,
            dx: 0.1,
            full_pd_dx: 0.1,
            tip_dx: 0.1,
            runs: vec![pdbem],
            ratio_full_pd_to_pd_bem: None,
            ratio_uniform_fine_to_refined: Some(4.35),
            path_deviations: d,
        };
        let t = table(&report);
        assert!(!t.contains("refined windows: full PD"), "{t}");
        assert!(!t.contains("tip dx"), "{t}");
        // Refined windows: full PD at their finest spacing, said in the header.
        let fine = GrowthBenchReport {
            full_pd_dx: 0.05,
            tip_dx: 0.05,
            ..report
        };
        // Refined windows: the deviation in tip spacings too (1.0 m = 10 dx = 20 tip dx).
        assert!(
            table(&fine).contains("= 10.00 dx (20.00 tip dx of 5e-2 m) over a reach"),
            "{}",
            table(&fine)
        );
        assert!(
            table(&fine).contains("refined windows: full PD at their finest spacing, dx = 5e-2 m"),
            "{}",
            table(&fine)
        );
        assert!(
            t.contains("pd-bem-fine (uniform windows at the finest spacing) / refined PD-BEM wall time: 4.35"),
            "{t}"
        );
        assert!(
            t.contains("pd-bem: the BEM body reaches the PD onset stretch 0.02 at load 0.2"),
            "{t}"
        );
        assert!(
            t.contains("below PD-BEM's overstrain load 0.0000 m over 2.000 m"),
            "{t}"
        );
    }

    #[test]
    fn a_refined_case_is_measured_against_uniform_windows_at_its_finest_spacing() {
        let base =
            Scene::load(crate::cases::case_path("growth_tension_edge_refined").unwrap()).unwrap();
        let fine = uniform_fine_scene(&base, false).unwrap().unwrap();
        let co = fine.coupling.unwrap();
        assert_eq!((co.n, co.side, co.refine.is_none()), (60, 3.0, true));
        assert_eq!(fine.growth.unwrap().sif_spacing, Some(0.0));
        // Full PD at the same tip resolution: dx = 0.05 m.
        let full = scene_for(&base, GrowthMode::FullPd, false).unwrap();
        let co = full.coupling.unwrap();
        assert_eq!((co.n, co.refine.is_none()), (60, true));
        let plain = Scene::load(crate::cases::case_path("growth_tension_edge").unwrap()).unwrap();
        assert!(uniform_fine_scene(&plain, false).is_none());
    }
}
