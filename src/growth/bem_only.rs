//! BEM-only crack growth (Liu, Li & Xie 2017 style, seed 002 ref. \[34\]): linear-elastic
//! fracture mechanics on the BEM body, re-meshed after every crack increment.
//!
//! Algorithm, for every load factor f of the scene (`load.initial + k load.step`):
//! 1. The current geometry (scene outline and holes, crack polylines as grown so far) is
//!    meshed and solved once at unit load: the problem is linear, so K(f) = f K(1).
//!    SIFs come from the crack-opening fit of [`pdbem_bem::post::sif::analyze_tips`].
//! 2. For every growing tip, the maximum-circumferential-stress kink angle theta and the
//!    equivalent K_eq ([`super::criterion`]) at load f. Tips with K_eq >= K_c =
//!    sqrt(E' G_c) (or the scene's `fracture.k_c`) each get one straight increment `da`
//!    along the kink direction ([`Front::step_ahead`] with a margin of 1.5 increments:
//!    a tip that would end within 1.5 da of the outline is taken onto it, one that would
//!    end within 1.5 da of a hole or another crack stops; closer, the crack-opening fit has
//!    too few elements left in the ligament), then the body is re-meshed and
//!    re-solved and 2. is repeated at the same load (unstable growth under load control
//!    runs within one step).
//! 3. When no tip is critical the step is recorded and the load grows. The run ends when
//!    the body is cut through (failure), when no tip can grow any more, or when the load
//!    budget is spent.
//!
//! Crack elements keep the size the scene's meshing rule gave the initial cracks
//! (`bem.group_sizes.<crack>` or the default rule of [`crate::setup::sizing`]), so a long grown
//! crack does not get finer; `growth.da` defaults to that size. A grown crack is straight
//! only over its last increment: the crack-opening fit of a kinked crack reaching across
//! the kink mixes the two directions (measured on the 45-degree crack: K_II of the kinked
//! tip 0.4 K_I instead of about 0, and the next kink reversed). So once cracks have grown,
//! the elements within one increment of every tip are refined to da/8 (uniform,
//! REFERENCES.md) and the fit is restricted to r < da; the initial geometry is meshed and
//! fitted exactly like a static BEM run. The critical load of the
//! current geometry, f_c = K_c / K_eq(1), is logged with every solve (`solve` events of
//! `growth_log.jsonl`), and [`critical_loads`] gives it for the initial geometry.

use std::time::Instant;

use anyhow::{bail, Context, Result};
use serde_json::json;

use super::log::{step_bar, stop_after_step, GrowthLog};
use super::{FieldSnapshot, GrowthHistory, PathPoint, StepRecord, TipPath};
use crate::geometry::{rotate, P2};
use crate::run_bem::{solve_level_with, Level};
use crate::runner::context::RunContext;
use crate::scene::{Crack, Scene, TipRefinement};
use pdbem_bem::PairCache;
use pdbem_coupling::growth::criterion::mcs;
use pdbem_coupling::growth::front::{Front, Obstacle};

/// SIFs of one tip at unit load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipSif {
    /// Index into [`Front::tips`].
    pub tip: usize,
    /// K_I at load factor 1 (Pa sqrt(m)).
    pub k1: f64,
    /// K_II at load factor 1.
    pub k2: f64,
    /// Kink angle (radians, counter-clockwise from the crack line).
    pub theta: f64,
    /// Equivalent K at load factor 1.
    pub k_eq: f64,
}

/// Critical load of one tip of the initial geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct TipCritical {
    /// Tip name.
    pub tip: String,
    /// K_I, K_II at load factor 1 (Pa sqrt(m)).
    pub k: [f64; 2],
    /// Kink angle (degrees).
    pub kink_deg: f64,
    /// Load factor at which K_eq reaches K_c (infinite when K_eq <= 0).
    pub load: f64,
}

/// One solved geometry.
struct Solved {
    level: Level,
    sifs: Vec<TipSif>,
    /// CMOD of the first edge crack at load factor 1 (m).
    cmod: Option<f64>,
    solve_s: f64,
}

/// Fixed meshing data of a run: crack element sizes and increments.
struct Sizes {
    /// Element size of each crack (m).
    element: Vec<f64>,
    /// Increment of each crack (m).
    da: Vec<f64>,
}

/// A tip whose next increment would leave less than this many increments of ligament to
/// the outline is taken onto the outline (a hole or another crack: stops). With one
/// increment of margin, a tip 0.2000390 m from the edge (da = 0.1) stepped to 0.1 m, one
/// element, where the crack-opening fit returned K_I = -6.8e4 (closing) and growth
/// stopped short of failure.
const LIGAMENT_MARGIN: f64 = 1.5;

/// Crack-opening stations wanted within one increment once cracks have grown: the fit
/// over them then has its full four terms (`cod_sif` uses 4 terms from 7 stations).
const STATIONS_PER_INCREMENT: f64 = 8.0;

impl Sizes {
    /// Tip refinement of grown geometries: elements of da / 8 (at most the crack size)
    /// within one increment of every tip; the SIF fit stays inside that zone.
    fn tip_zone(&self) -> TipRefinement {
        let da = self.da.iter().copied().fold(f64::INFINITY, f64::min);
        let h = self.element.iter().copied().fold(f64::INFINITY, f64::min);
        TipRefinement {
            element_size: h.min(da / STATIONS_PER_INCREMENT),
            radius: da,
        }
    }
}

/// The scene with the front's crack polylines and fixed crack element sizes; once the
/// cracks have grown (`grown`), with the tip zone of [`Sizes::tip_zone`].
fn geometry_scene(scene: &Scene, front: &Front, sizes: &Sizes, grown: bool) -> Scene {
    let mut s = scene.clone();
    for (i, c) in front.cracks.iter().enumerate() {
        let old = &scene.cracks[i];
        s.cracks[i] = Crack {
            name: old.name.clone(),
            start: None,
            center: None,
            angle_deg: None,
            length: None,
            points: Some(c.points.iter().map(|p| (p.x, p.y)).collect()),
            faces: old.faces,
        };
        s.bem.group_sizes.insert(old.name.clone(), sizes.element[i]);
    }
    if grown {
        s.bem.tip_refinement = Some(sizes.tip_zone());
    }
    s
}

/// Element size of every crack in the initial mesh, and the increments.
fn sizes_of(scene: &Scene) -> Result<Sizes> {
    let setup = crate::setup::bem::build(scene, 1.0, 1.0)?;
    let element: Vec<f64> = setup
        .mesh
        .cracks
        .iter()
        .map(|c| {
            c.upper
                .iter()
                .map(|&e| setup.mesh.elements[e].h)
                .fold(0.0, f64::max)
        })
        .collect();
    let da = match scene.growth.as_ref().and_then(|g| g.da) {
        Some(da) => vec![da; element.len()],
        None => element.clone(),
    };
    Ok(Sizes { element, da })
}

/// SIFs of every tip of a solved geometry by the crack-opening fit over r < fit_fraction L
/// (the scene's rule, as in a static BEM run), capped at `cap` (m): a grown crack is
/// straight only over its last increment, and the fit must not reach across a kink.
fn tip_sifs(scene: &Scene, front: &Front, level: &Level, cap: f64) -> Result<Vec<TipSif>> {
    use pdbem_bem::post::sif::{cod_sif, tip_length_scale};
    let mesh = &level.setup.mesh;
    let mut sifs = Vec::new();
    for (ci, at_end, pos, _) in mesh.tips() {
        let end = if at_end { "end" } else { "start" };
        let name = format!("{}.{end}", mesh.cracks[ci].name);
        let Some(t) = front.tips.iter().position(|f| f.name == name) else {
            continue;
        };
        let fit = (scene.bem.cod_fit_fraction * tip_length_scale(mesh, ci, pos)).min(cap);
        let (k1, k2, _) = cod_sif(
            mesh,
            &level.setup.material,
            &level.solution,
            ci,
            at_end,
            fit,
        );
        if !(k1.is_finite() && k2.is_finite()) {
            bail!(
                "{}: tip {name}: no SIF (no crack element within {fit:.3e} m of the tip)",
                scene.file_label().display()
            );
        }
        let (theta, k_eq) = mcs(k1, k2);
        sifs.push(TipSif {
            tip: t,
            k1,
            k2,
            theta,
            k_eq,
        });
    }
    Ok(sifs)
}

/// Meshes and solves the current geometry at unit load, reusing the element-pair blocks
/// of the last geometry (`pairs`: the outline and the crack away from the tips stay).
fn solve_geometry(
    scene: &Scene,
    front: &Front,
    sizes: &Sizes,
    grown: bool,
    pairs: &mut PairCache,
) -> Result<Solved> {
    let t0 = Instant::now();
    let gs = geometry_scene(scene, front, sizes, grown);
    let level = solve_level_with(&gs, 1.0, 1.0, Some(pairs))?;
    let cap = if grown {
        sizes.tip_zone().radius
    } else {
        f64::INFINITY
    };
    let sifs = tip_sifs(scene, front, &level, cap)?;
    let cmod = level.cracks.iter().find_map(|c| c.cmod);
    Ok(Solved {
        level,
        sifs,
        cmod,
        solve_s: t0.elapsed().as_secs_f64(),
    })
}

/// K_c of the scene, or an error naming the missing field.
fn scene_toughness(scene: &Scene) -> Result<f64> {
    scene.material.k_c().with_context(|| {
        format!(
            "{}: material.fracture: BEM-only growth needs g_c (J/m^2) or k_c (Pa m^0.5)",
            scene.file_label().display()
        )
    })
}

/// Critical load factor of every tip of the initial geometry: K_c / K_eq at unit load.
pub fn critical_loads(scene: &Scene) -> Result<Vec<TipCritical>> {
    let k_c = scene_toughness(scene)?;
    let front = crate::setup::growth::front(scene);
    let sizes = sizes_of(scene)?;
    let solved = solve_geometry(scene, &front, &sizes, false, &mut PairCache::default())?;
    Ok(solved
        .sifs
        .iter()
        .map(|s| TipCritical {
            tip: front.tips[s.tip].name.clone(),
            k: [s.k1, s.k2],
            kink_deg: s.theta.to_degrees(),
            load: critical_factor(k_c, s.k_eq),
        })
        .collect())
}

fn critical_factor(k_c: f64, k_eq: f64) -> f64 {
    if k_eq > 0.0 {
        k_c / k_eq
    } else {
        f64::INFINITY
    }
}

/// The `solve` event of a geometry.
fn solve_event(front: &Front, s: &Solved, k_c: f64, geometry: usize) -> serde_json::Value {
    let tips: Vec<_> = s
        .sifs
        .iter()
        .map(|t| {
            json!({
                "tip": front.tips[t.tip].name, "k1": t.k1, "k2": t.k2,
                "kink_deg": t.theta.to_degrees(), "k_eq": t.k_eq,
                "critical_load": critical_factor(k_c, t.k_eq),
            })
        })
        .collect();
    json!({"geometry": geometry, "elements": s.level.setup.mesh.len(),
           "solve_s": s.solve_s, "unit_load": tips})
}

/// Tips whose K_eq at load `f` reaches K_c, with their SIFs.
fn critical_tips(front: &Front, s: &Solved, f: f64, k_c: f64) -> Vec<TipSif> {
    s.sifs
        .iter()
        .filter(|t| front.tips[t.tip].ended.is_none() && f * t.k_eq >= k_c)
        .copied()
        .collect()
}

/// Displacement magnitude at load `f` on a grid over the body (for the snapshot plots).
fn displacement_snapshot(scene: &Scene, s: &Solved, f: f64, step: usize) -> FieldSnapshot {
    use pdbem_bem::post::FieldEvaluator;
    let setup = &s.level.setup;
    let ev = FieldEvaluator::new(
        &setup.mesh,
        &setup.material,
        &s.level.solution,
        setup.background,
    );
    let geo = crate::scene::shapes::SceneGeometry::of(scene);
    let (lo, hi) = geo.bounds();
    let n = 60;
    let mesh = &setup.mesh;
    let clear = |p: &P2| {
        mesh.elements.iter().all(|e| {
            let d = e.b - e.a;
            let t = ((p - e.a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            (e.a + t * d - p).norm() > 0.25 * e.h
        })
    };
    let pts: Vec<P2> = (0..n * n)
        .map(|k| {
            let (i, j) = ((k % n) as f64 + 0.5, (k / n) as f64 + 0.5);
            P2::new(
                lo.x + (hi.x - lo.x) * i / n as f64,
                lo.y + (hi.y - lo.y) * j / n as f64,
            )
        })
        .filter(|p| geo.contains(p) && clear(p))
        .collect();
    let u = ev.displacements(&pts);
    FieldSnapshot {
        step,
        label: "displacement".into(),
        points: pts.iter().map(|p| [p.x, p.y]).collect(),
        values: u.iter().map(|v| f * v[0].hypot(v[1])).collect(),
    }
}

/// Upper bound on increments within one load step: every tip crossing the body twice.
fn increment_cap(scene: &Scene, front: &Front, sizes: &Sizes) -> usize {
    let (lo, hi) = crate::scene::shapes::SceneGeometry::of(scene).bounds();
    let da = sizes.da.iter().copied().fold(f64::INFINITY, f64::min);
    let per_tip = (2.0 * (hi - lo).norm() / da).ceil() as usize;
    per_tip.saturating_mul(front.tips.len()).saturating_add(10)
}

/// Runs BEM-only growth of `scene` (see the module documentation).
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<GrowthHistory> {
    let file = scene.file_label();
    let k_c = scene_toughness(scene)?;
    let factors = scene.load.factors();
    let mut front = crate::setup::growth::front(scene);
    let sizes = sizes_of(scene)?;
    let log = GrowthLog::open(ctx)?;
    log.event(
        "start",
        json!({"mode": "bem-only", "k_c": k_c, "steps": factors.len(),
               "da": sizes.da, "crack_element_size": sizes.element}),
    )?;
    let first = factors.first().copied().unwrap_or(1.0);
    let snapshot_steps = super::snapshot_steps(scene);
    let mut history = GrowthHistory {
        mode: "bem-only".into(),
        paths: front
            .tips
            .iter()
            .map(|t| TipPath {
                name: t.name.clone(),
                points: vec![point(t.initial, 0, first)],
                ended: None,
            })
            .collect(),
        ..Default::default()
    };
    let mut geometry = 0;
    let mut pairs = PairCache::default();
    let mut solved = solve_geometry(scene, &front, &sizes, false, &mut pairs)
        .with_context(|| format!("{}: BEM-only growth, initial geometry", file.display()))?;
    log.event("solve", solve_event(&front, &solved, k_c, geometry))?;
    let cap = increment_cap(scene, &front, &sizes);
    let bar = step_bar(ctx, factors.len());
    let mut current = true;
    for (k, &f) in factors.iter().enumerate() {
        let t0 = Instant::now();
        let mut increments = 0;
        let mut solved_now = true;
        loop {
            let growing = critical_tips(&front, &solved, f, k_c);
            if growing.is_empty() {
                break;
            }
            if increments >= cap {
                bail!(
                    "{}: BEM-only growth: more than {cap} increments at load {f} (step {k}); \
                     increase growth.da",
                    file.display()
                );
            }
            if history.initiation_load.is_none() {
                history.initiation_load = Some(f);
                history
                    .snapshots
                    .push(displacement_snapshot(scene, &solved, f, k));
            }
            for t in &growing {
                grow_tip(&mut front, &mut history, &log, t, &sizes, f, k, k_c)?;
            }
            increments += 1;
            if front.separated() || front.active().is_empty() {
                solved_now = false;
                break;
            }
            geometry += 1;
            solved =
                solve_geometry(scene, &front, &sizes, true, &mut pairs).with_context(|| {
                    format!(
                        "{}: BEM-only growth, step {k} (load {f}), geometry {geometry}",
                        file.display()
                    )
                })?;
            log.event("solve", solve_event(&front, &solved, k_c, geometry))?;
        }
        let rec = StepRecord {
            step: k,
            load: f,
            cmod: if solved_now {
                solved.cmod.map(|c| c * f)
            } else {
                None
            },
            tips: front.tip_positions(),
            wall_time_s: t0.elapsed().as_secs_f64(),
            coupling_residual: Some(0.0),
            ..Default::default()
        };
        log.event("step", json!(rec))?;
        history.steps.push(rec);
        current = solved_now;
        if solved_now && snapshot_steps.contains(&k) {
            history
                .snapshots
                .push(displacement_snapshot(scene, &solved, f, k));
        }
        bar.set_message(format!("load {f:.4e}, {geometry} re-meshes"));
        bar.inc(1);
        let cut = front.separated();
        if stop_after_step(
            &mut history,
            &log,
            &front,
            cut,
            k,
            f,
            "a crack cut the body through",
        )? {
            break;
        }
        if !solved_now {
            break;
        }
    }
    bar.finish_and_clear();
    // A last snapshot when the solved geometry is the final one.
    if current && !history.steps.is_empty() {
        let f = history.steps.last().map_or(first, |s| s.load);
        history.snapshots.push(displacement_snapshot(
            scene,
            &solved,
            f,
            history.steps.len().saturating_sub(1),
        ));
    }
    if history.initiation_load.is_none() {
        history.notes.push(format!(
            "no tip reached K_c = {k_c:.4e} Pa m^0.5 within the load budget (last factor {})",
            factors.last().copied().unwrap_or(first)
        ));
    }
    for (p, t) in history.paths.iter_mut().zip(&front.tips) {
        p.ended = t.ended.clone();
    }
    Ok(history)
}

fn point(p: P2, step: usize, load: f64) -> PathPoint {
    PathPoint {
        x: p.x,
        y: p.y,
        step,
        load,
    }
}

/// One increment of one tip: direction by MCS, `Front::step_ahead`, path point and events.
fn grow_tip(
    front: &mut Front,
    history: &mut GrowthHistory,
    log: &GrowthLog,
    t: &TipSif,
    sizes: &Sizes,
    f: f64,
    step: usize,
    k_c: f64,
) -> Result<()> {
    let tip = t.tip;
    let from = front.tip_position(tip);
    let dir = rotate(&front.tip_direction(tip), t.theta);
    let crack = front.tips[tip].crack;
    let da = sizes.da[crack];
    let hit = front.step_ahead(tip, dir, da, LIGAMENT_MARGIN * da);
    let to = front.tip_position(tip);
    if to != from {
        history.paths[tip].points.push(point(to, step, f));
    }
    log.event(
        "grow",
        json!({"step": step, "load": f, "tip": front.tips[tip].name,
               "from": [from.x, from.y], "to": [to.x, to.y],
               "kink_deg": t.theta.to_degrees(), "k_eq": f * t.k_eq, "k_c": k_c}),
    )?;
    if hit != Obstacle::None {
        log.event(
            "tip_end",
            json!({"step": step, "load": f, "tip": front.tips[tip].name,
                   "reason": front.tips[tip].ended}),
        )?;
    }
    Ok(())
}
