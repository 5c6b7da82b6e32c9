//! BEM-only crack growth (Liu, Li & Xie 2017 style, seed 002 ref. \[34\]): linear-elastic
//! fracture mechanics on the BEM body, re-meshed after every crack increment.
//!
//! Algorithm, for every load factor f of [`BemOnlyParams::loads`]:
//! 1. The current geometry (the body's loops, the crack polylines as grown so far) is
//!    meshed and solved once at unit load: the problem is linear, so K(f) = f K(1). SIFs
//!    come from the crack-opening fit ([`pdbem_bem::post::sif::cod_sif`]).
//! 2. For every growing tip, the maximum-circumferential-stress kink angle theta and the
//!    equivalent K_eq ([`super::criterion`]) at load f. Tips with K_eq >= K_c each get
//!    one straight increment `da` along the kink direction ([`Front::step_ahead`] with a
//!    margin of [`LIGAMENT_MARGIN`] increments: a tip that would end within 1.5 da of the
//!    outline is taken onto it, one that would end within 1.5 da of a hole or another
//!    crack stops; closer, the crack-opening fit has too few elements left in the
//!    ligament), then the body is re-meshed and re-solved and 2. is repeated at the same
//!    load (unstable growth under load control runs within one step).
//! 3. When no tip is critical the step is recorded and the load grows. The run ends when
//!    the body is cut through (failure), when no tip can grow any more, or when the load
//!    budget is spent.
//!
//! Crack elements keep the size the initial mesh gave them (the largest element of each
//! crack's upper face), so a long grown crack does not get finer; the increment `da`
//! defaults to that size. A grown crack is straight only over its last increment: the
//! crack-opening fit of a kinked crack reaching across the kink mixes the two directions
//! (measured on the 45-degree crack: K_II of the kinked tip 0.4 K_I instead of about 0,
//! and the next kink reversed). So once cracks have grown, the elements within one
//! increment of every tip are refined to da/8 (uniform, REFERENCES.md) and the fit is
//! restricted to r < da; the initial geometry is meshed and fitted exactly like a static
//! BEM run. The critical load of the current geometry, f_c = K_c / K_eq(1), is reported
//! with every solve (`solve` events), and [`critical_loads`] gives it for the initial
//! geometry.
//!
//! The engine reports through an [`EngineObserver`] and never prints or writes files.

use std::time::Instant;

use pdbem_bem::mesh::{CrackSpec, LoopSpec, TipRefinement};
use pdbem_bem::post::sif::{cmod, cod_sif, tip_length_scale};
use pdbem_bem::post::{Background, FieldEvaluator};
use pdbem_bem::{BemSystem, Material, Mesh, MeshBuilder, PairCache, Solution, SolveParams};
use pdbem_geometry::{point_segment_projection, rotate, P2};
use serde_json::json;

use super::checkpoint::{mismatch, BemOnlyCheckpoint, EngineCheckpoint};
use super::criterion::mcs;
use super::events::EngineObserver;
use super::front::{Front, Obstacle};
use super::history::{FieldSnapshot, GrowthHistory, PathPoint, StepRecord, TipPath};
use super::records::Scenario;
use super::verdict::stop_after_step;
use crate::error::CouplingError;

/// A tip whose next increment would leave less than this many increments of ligament to
/// the outline is taken onto the outline (a hole or another crack: stops). With one
/// increment of margin, a tip 0.2000390 m from the edge (da = 0.1) stepped to 0.1 m, one
/// element, where the crack-opening fit returned K_I = -6.8e4 (closing) and growth
/// stopped short of failure.
pub const LIGAMENT_MARGIN: f64 = 1.5;

/// Crack-opening stations wanted within one increment once cracks have grown: the fit
/// over them then has its full four terms (`cod_sif` uses 4 terms from 7 stations).
const STATIONS_PER_INCREMENT: f64 = 8.0;

/// Snapshot grid points per side over the body's bounding box.
const SNAPSHOT_GRID: usize = 60;

/// The body of a BEM-only run: what every re-meshed geometry shares.
#[derive(Debug, Clone)]
pub struct BemOnlyBody {
    /// Outline (split at its groups) and hole loops with their element sizes.
    pub loops: Vec<LoopSpec>,
    /// The initial cracks in front order: name, polyline, faces, element size and the
    /// tip refinement of the initial mesh.
    pub cracks: Vec<CrackSpec>,
    /// Material.
    pub material: Material,
    /// Solver parameters.
    pub params: SolveParams,
    /// Remote stress at unit load (infinite plates; zero otherwise).
    pub background: Background,
    /// Crack-opening fit range as a fraction of the tip length scale.
    pub fit_fraction: f64,
}

/// Parameters of a BEM-only run.
#[derive(Debug, Clone, PartialEq)]
pub struct BemOnlyParams {
    /// Toughness K_c (Pa sqrt(m)).
    pub k_c: f64,
    /// Load factors, one per step.
    pub loads: Vec<f64>,
    /// Crack increment (m), the same for every crack; `None`: each crack's element size.
    pub da: Option<f64>,
    /// Steps (0-based) after which a displacement snapshot is taken as well.
    pub snapshot_steps: Vec<usize>,
}

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

/// One solved geometry at unit load.
struct Solved {
    mesh: Mesh,
    solution: Solution,
    sifs: Vec<TipSif>,
    /// CMOD of the first crack with a mouth at load factor 1 (m).
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

impl Sizes {
    /// Tip refinement of grown geometries: elements of da / 8 (at most the crack size)
    /// within one increment of every tip; the SIF fit stays inside that zone.
    fn tip_zone(&self) -> TipRefinement {
        let da = self.da.iter().copied().fold(f64::INFINITY, f64::min);
        let h = self.element.iter().copied().fold(f64::INFINITY, f64::min);
        TipRefinement {
            size: h.min(da / STATIONS_PER_INCREMENT),
            radius: da,
        }
    }
}

fn fail(message: String) -> CouplingError {
    CouplingError::Growth {
        mode: "BEM-only",
        message,
    }
}

/// The context of one run: body, conditions and the pair cache of the last mesh.
struct Engine<'a> {
    body: &'a BemOnlyBody,
    scenario: &'a dyn Scenario,
    pairs: PairCache,
}

impl Engine<'_> {
    /// Meshes the front's cracks: with `sizes` each crack at its fixed element size, and
    /// once they have `grown` with the tip zone of [`Sizes::tip_zone`] (else with the
    /// initial tip refinement); without `sizes`, the initial crack specifications.
    fn mesh(
        &self,
        front: &Front,
        sizes: Option<&Sizes>,
        grown: bool,
    ) -> Result<Mesh, CouplingError> {
        let mut b = MeshBuilder::new();
        for l in &self.body.loops {
            b.add_loop(l.clone());
        }
        for (i, (spec, c)) in self.body.cracks.iter().zip(&front.cracks).enumerate() {
            let mut spec = CrackSpec {
                points: c.points.clone(),
                ..spec.clone()
            };
            if let Some(s) = sizes {
                spec.element_size = s.element[i];
                if grown {
                    spec.tip = Some(s.tip_zone());
                }
            }
            b.add_crack(spec);
        }
        Ok(b.build()?)
    }

    /// Element size of every crack in the initial mesh (the largest element of its upper
    /// face: the size the rounding to whole elements gave), and the increments.
    fn sizes(&self, front: &Front, da: Option<f64>) -> Result<Sizes, CouplingError> {
        let mesh = self.mesh(front, None, false)?;
        let element: Vec<f64> = mesh
            .cracks
            .iter()
            .map(|c| {
                c.upper
                    .iter()
                    .map(|&e| mesh.elements[e].h)
                    .fold(0.0, f64::max)
            })
            .collect();
        let da = match da {
            Some(da) => vec![da; element.len()],
            None => element.clone(),
        };
        Ok(Sizes { element, da })
    }

    /// Meshes and solves the current geometry at unit load, reusing the element-pair
    /// blocks of the last geometry (the outline and the crack away from the tips stay).
    /// `grown`: the cracks have grown (tip zone and capped fit).
    fn solve(
        &mut self,
        front: &Front,
        sizes: &Sizes,
        grown: bool,
    ) -> Result<Solved, CouplingError> {
        let t0 = Instant::now();
        let mesh = self.mesh(front, Some(sizes), grown)?;
        let bcs = self
            .scenario
            .bem_conditions(&mesh)
            .map_err(|m| fail(format!("boundary conditions: {m}")))?;
        let sys = BemSystem::new_with_cache(
            &mesh,
            &self.body.material,
            &bcs,
            &self.body.params,
            Some(&mut self.pairs),
        )?;
        let solution = sys.solve()?;
        let cap = if grown {
            sizes.tip_zone().radius
        } else {
            f64::INFINITY
        };
        let sifs = self.tip_sifs(front, &mesh, &solution, cap)?;
        let cmod = (0..mesh.cracks.len()).find_map(|i| cmod(&mesh, &solution, i));
        Ok(Solved {
            mesh,
            solution,
            sifs,
            cmod,
            solve_s: t0.elapsed().as_secs_f64(),
        })
    }

    /// SIFs of every tip by the crack-opening fit over r < fit_fraction L (as in a static
    /// BEM run), capped at `cap` (m): a grown crack is straight only over its last
    /// increment, and the fit must not reach across a kink.
    fn tip_sifs(
        &self,
        front: &Front,
        mesh: &Mesh,
        solution: &Solution,
        cap: f64,
    ) -> Result<Vec<TipSif>, CouplingError> {
        let mut sifs = Vec::new();
        for (ci, at_end, pos, _) in mesh.tips() {
            let end = if at_end { "end" } else { "start" };
            let name = format!("{}.{end}", mesh.cracks[ci].name);
            let Some(t) = front.tips.iter().position(|f| f.name == name) else {
                continue;
            };
            let fit = (self.body.fit_fraction * tip_length_scale(mesh, ci, pos)).min(cap);
            let (k1, k2, _) = cod_sif(mesh, &self.body.material, solution, ci, at_end, fit);
            if !(k1.is_finite() && k2.is_finite()) {
                return Err(fail(format!(
                    "tip {name}: no SIF (no crack element within {fit:.3e} m of the tip)"
                )));
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
}

/// Critical load factor of every tip of the initial geometry: K_c / K_eq at unit load.
pub fn critical_loads(
    body: &BemOnlyBody,
    front: &Front,
    k_c: f64,
    scenario: &dyn Scenario,
) -> Result<Vec<TipCritical>, CouplingError> {
    let mut engine = Engine {
        body,
        scenario,
        pairs: PairCache::default(),
    };
    let sizes = engine.sizes(front, None)?;
    let solved = engine.solve(front, &sizes, false)?;
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
    json!({"geometry": geometry, "elements": s.mesh.len(),
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

/// Displacement magnitude at load `f` on a grid over `bounds` (for the snapshot plots):
/// points in the body and clear of the elements by a quarter element.
fn displacement_snapshot(
    body: &BemOnlyBody,
    front: &Front,
    bounds: (P2, P2),
    s: &Solved,
    f: f64,
    step: usize,
) -> FieldSnapshot {
    let ev = FieldEvaluator::new(&s.mesh, &body.material, &s.solution, body.background);
    let (lo, hi) = bounds;
    let n = SNAPSHOT_GRID;
    let clear = |p: &P2| {
        s.mesh
            .elements
            .iter()
            .all(|e| point_segment_projection(p, &e.a, &e.b).0 > 0.25 * e.h)
    };
    let pts: Vec<P2> = pdbem_geometry::grid_centres(&lo, &hi, n)
        .into_iter()
        .filter(|p| front.contains(p) && clear(p))
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
fn increment_cap(bounds: (P2, P2), front: &Front, sizes: &Sizes) -> usize {
    let (lo, hi) = bounds;
    let da = sizes.da.iter().copied().fold(f64::INFINITY, f64::min);
    let per_tip = (2.0 * (hi - lo).norm() / da).ceil() as usize;
    per_tip.saturating_mul(front.tips.len()).saturating_add(10)
}

fn point(p: P2, step: usize, load: f64) -> PathPoint {
    PathPoint {
        x: p.x,
        y: p.y,
        step,
        load,
    }
}

/// Runs BEM-only growth of `front` in `body` (see the module documentation). The
/// scenario gives the boundary conditions of every mesh at unit load.
pub fn run(
    body: &BemOnlyBody,
    front: Front,
    params: &BemOnlyParams,
    scenario: &dyn Scenario,
    observer: &mut dyn EngineObserver,
) -> Result<GrowthHistory, CouplingError> {
    run_from(body, front, params, scenario, observer, None)
}

/// [`run`], going on from `resume` when given (a checkpoint of a run of the same body,
/// front and parameters, [`crate::growth::checkpoint`]): the front and history are taken
/// from it and the current geometry is solved again. A geometry of a load step that
/// cannot be meshed or solved, or a step past its increment cap, ends the run with
/// [`GrowthHistory::failure_reason`] and the steps before it (no retry: the geometry does
/// not depend on the load).
pub fn run_from(
    body: &BemOnlyBody,
    mut front: Front,
    params: &BemOnlyParams,
    scenario: &dyn Scenario,
    observer: &mut dyn EngineObserver,
    resume: Option<BemOnlyCheckpoint>,
) -> Result<GrowthHistory, CouplingError> {
    let k_c = params.k_c;
    let factors = &params.loads;
    // Bounds, sizes and cap come from the initial front, also in a resumed run.
    let bounds = front.bounds();
    let mut engine = Engine {
        body,
        scenario,
        pairs: PairCache::default(),
    };
    let first = factors.first().copied().unwrap_or(1.0);
    let sizes = engine.sizes(&front, params.da)?;
    let cap = increment_cap(bounds, &front, &sizes);
    let (mut history, mut geometry, next) = match resume {
        Some(cp) => {
            front.restore(&cp.front).map_err(mismatch)?;
            let mut h = cp.history;
            h.snapshots = cp.snapshots;
            (h, cp.geometry, cp.next_step)
        }
        None => {
            observer.event(
                "start",
                json!({"mode": "bem-only", "k_c": k_c, "steps": factors.len(),
                       "da": sizes.da, "crack_element_size": sizes.element}),
            );
            (fresh_history(&front, first), 0, 0)
        }
    };
    let mut solved = engine
        .solve(&front, &sizes, geometry > 0)
        .map_err(|e| fail(format!("geometry {geometry}: {e}")))?;
    if next == 0 {
        observer.event("solve", solve_event(&front, &solved, k_c, geometry));
    }
    let mut current = true;
    for (k, &f) in factors.iter().enumerate().skip(next) {
        let t0 = Instant::now();
        let mut increments = 0;
        let mut solved_now = true;
        let saved = (front.clone(), history.clone(), geometry);
        let mut broken = None;
        loop {
            let growing = critical_tips(&front, &solved, f, k_c);
            if growing.is_empty() {
                break;
            }
            if increments >= cap {
                broken = Some(format!(
                    "more than {cap} increments at load {f} (step {k}); increase growth.da"
                ));
                break;
            }
            if history.initiation_load.is_none() {
                history.initiation_load = Some(f);
                history
                    .snapshots
                    .push(displacement_snapshot(body, &front, bounds, &solved, f, k));
            }
            for t in &growing {
                grow_tip(&mut front, &mut history, observer, t, &sizes, f, k, k_c);
            }
            increments += 1;
            if front.separated() || front.active().is_empty() {
                solved_now = false;
                break;
            }
            geometry += 1;
            match engine.solve(&front, &sizes, true) {
                Ok(s) => solved = s,
                Err(e) => {
                    broken = Some(format!(
                        "step {k} (load {f}): geometry {geometry} could not be meshed or \
                         solved ({e}); no retry applies (the geometry does not depend on \
                         the load)"
                    ));
                    break;
                }
            }
            observer.event("solve", solve_event(&front, &solved, k_c, geometry));
        }
        if let Some(reason) = broken {
            // Back to the end of the last completed step, whose records stand.
            (front, history, _) = saved;
            observer.event("note", json!({ "message": reason }));
            history.failure_reason = Some(reason);
            current = false;
            break;
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
        observer.event("step", json!(rec));
        history.steps.push(rec);
        current = solved_now;
        if solved_now && params.snapshot_steps.contains(&k) {
            history
                .snapshots
                .push(displacement_snapshot(body, &front, bounds, &solved, f, k));
        }
        observer.progress(
            k + 1,
            factors.len(),
            &format!("load {f:.4e}, {geometry} re-meshes"),
        );
        let cut = front.separated();
        let why = "a crack cut the body through";
        if stop_after_step(&mut history, observer, &front, cut, k, f, why) || !solved_now {
            break;
        }
        if k + 1 < factors.len() {
            let flow = observer.checkpoint(k, &mut || {
                EngineCheckpoint::BemOnly(BemOnlyCheckpoint {
                    next_step: k + 1,
                    front: front.state(),
                    history: history.clone(),
                    snapshots: history.snapshots.clone(),
                    geometry,
                })
            });
            if flow.is_break() {
                return Err(CouplingError::Interrupted { step: k });
            }
        }
    }
    // A last snapshot when the solved geometry is the final one.
    if current && !history.steps.is_empty() {
        let f = history.steps.last().map_or(first, |s| s.load);
        let last = history.steps.len().saturating_sub(1);
        history.snapshots.push(displacement_snapshot(
            body, &front, bounds, &solved, f, last,
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

/// The history of a run that has not started: one path per tip at its initial position.
fn fresh_history(front: &Front, first: f64) -> GrowthHistory {
    GrowthHistory {
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
    }
}

/// One increment of one tip: direction by MCS, `Front::step_ahead`, path point and events.
fn grow_tip(
    front: &mut Front,
    history: &mut GrowthHistory,
    observer: &mut dyn EngineObserver,
    t: &TipSif,
    sizes: &Sizes,
    f: f64,
    step: usize,
    k_c: f64,
) {
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
    observer.event(
        "grow",
        json!({"step": step, "load": f, "tip": front.tips[tip].name,
               "from": [from.x, from.y], "to": [to.x, to.y],
               "kink_deg": t.theta.to_degrees(), "k_eq": f * t.k_eq, "k_c": k_c}),
    );
    if hit != Obstacle::None {
        observer.event(
            "tip_end",
            json!({"step": step, "load": f, "tip": front.tips[tip].name,
                   "reason": front.tips[tip].ended}),
        );
    }
}
