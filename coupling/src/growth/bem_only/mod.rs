//! BEM-only crack growth (Liu, Li & Xie 2017 style, seed 002 ref. \[34\]): linear-elastic
//! fracture mechanics on the BEM body, re-meshed after every crack increment.
//!
//! Algorithm, for every load factor f of [`BemOnlyParams::loads`]:
//! 1. The current geometry (the body's loops, the crack polylines as grown so far) is
//!    meshed with the local-feature sizes of the static BEM mesh ([`sizing`]: every tip a
//!    source of min(base, L/80) over 1 L, L the tip's distance to the nearest boundary or
//!    its crack's length) and solved once at unit load ([`solve`]): the problem is
//!    linear, so K(f) = f K(1). SIFs come from the crack-opening fit
//!    ([`pdbem_bem::post::sif::cod_sif`]) over r < min(0.3 L, the straight run behind the
//!    tip). A geometry where a growing tip has K_I < 0 or a mouth closes is refined (tip
//!    elements halved, up to 4x) and, if that does not cure it, the run ends there with
//!    the reason in its notes: overlapping faces are never taken as a growth state.
//! 2. For every growing tip, the maximum-circumferential-stress kink angle theta and the
//!    equivalent K_eq ([`super::criterion`]) at load f. Tips with K_eq >= K_c each get
//!    one straight increment along the kink direction ([`Front::step_ahead`] with a
//!    margin of [`LIGAMENT_MARGIN`] increments): `da`, or near an obstacle ahead (the
//!    outline, a hole, another crack at distance s <= 2.5 da) the shorter s / 3, which
//!    leaves two increments of ligament ([`increment`]), down to [`MIN_INCREMENT`] da.
//!    Below that, or when a shortened increment leaves a geometry that is not a growth
//!    state (1.; the round is then taken again with the full `da`, and a note says so),
//!    the tip has reached the obstacle: **the outline**:
//!    the tip is taken onto it, and a crack that then connects two points of the outline
//!    cuts the body (failure, "tip reached the outline"); a hole: the crack joins it;
//!    another crack: the tip stops. So whether a tip reaches the boundary is decided by K
//!    along shrinking increments, not by the size of `da`: with a fixed `da` and a fixed
//!    margin, the shear plate of seed 002 (`growth_shear_edge`, BEM-only) failed at load
//!    0.40, 0.26 and 0.16 with da = 0.2, 0.5 and 1 m, because the tip, arrested 0.32 m
//!    from the clamped edge with da = 0.05 and 0.1 m (no failure up to 0.46), was taken
//!    onto it from up to 1.5 da away. Then the body is re-meshed and re-solved and 2. is
//!    repeated at the same load (unstable growth under load control runs within one
//!    step).
//! 3. When no tip is critical the step is recorded and the load grows. The run ends when
//!    the body is cut through (failure), when no tip can grow any more, when a geometry is
//!    not a growth state (1.), or when the load budget is spent.
//!
//! The increment `da` defaults to the crack's face element size (the size its elements
//! grow to away from the tips: `bem.element_size` on the seed plates, the PD-BEM dx).
//! Every accepted geometry adds one row per growing tip to the fracture-mechanics record
//! along the path ([`crate::growth::sif_path`]). The critical load of the current
//! geometry, f_c = K_c / K_eq(1), is reported with every solve (`solve` events), and
//! [`critical_loads`] gives it for the initial geometry.
//!
//! The engine reports through an [`EngineObserver`] and never prints or writes files.

mod body;
pub mod sizing;
pub(crate) mod solve;

mod initial;
mod rounds;

pub(crate) use self::body::fail;
pub use self::body::BemOnlyBody;
use self::initial::critical_factor;
pub use self::initial::{check_initial, critical_loads, InitialSolve, TipCritical};
pub use super::criterion::TipSif;

use std::time::Instant;

use pdbem_bem::post::FieldEvaluator;
use pdbem_geometry::{point_segment_projection, P2};
use serde_json::json;

use self::rounds::{failure_reason, full_increment_note, grow_tip, shortens, within_step};
use self::solve::{Checked, Engine, Sizes, Solved};
use super::checkpoint::{mismatch, BemOnlyCheckpoint, EngineCheckpoint};
use super::events::EngineObserver;
use super::front::Front;
use super::history::{FieldSnapshot, GrowthHistory, PathPoint, SifRow, StepRecord, TipPath};
use super::records::Scenario;
use super::verdict::{stop_after_step, unstable_note};
use crate::error::CouplingError;

/// A tip whose next increment would leave less than this many increments of ligament to
/// the outline is taken onto the outline (a hole or another crack: stops). With one
/// increment of margin, a tip 0.2000390 m from the edge (da = 0.1) stepped to 0.1 m, one
/// element, where the crack-opening fit returned K_I = -6.8e4 (closing) and growth
/// stopped short of failure.
pub const LIGAMENT_MARGIN: f64 = 1.5;

/// Smallest increment near an obstacle, as a fraction of `da` ([`increment`]): a tip
/// whose shortened increment would be shorter has reached the obstacle. 1/8 costs about
/// five more solves per approach (the increments shrink by 2/3 each).
pub const MIN_INCREMENT: f64 = 0.125;

/// The increment of a tip with `room` (m) to the first obstacle along its kink direction
/// ([`Front::room_ahead`]): `da` while the step leaves [`LIGAMENT_MARGIN`] increments of
/// ligament; closer, room / 3, which leaves two of its own increments (more than the
/// margin), as long as that is at least [`MIN_INCREMENT`] da; else `da`, with which
/// [`Front::step_ahead`] takes the tip onto the obstacle (or stops it before a crack).
pub fn increment(room: Option<f64>, da: f64) -> f64 {
    match room {
        Some(s) if s <= (1.0 + LIGAMENT_MARGIN) * da => {
            let a = s / 3.0;
            if a >= MIN_INCREMENT * da {
                a
            } else {
                da
            }
        }
        _ => da,
    }
}

/// Snapshot grid points per side over the body's bounding box.
const SNAPSHOT_GRID: usize = 60;

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
    /// A test hook: the geometries re-meshed in load step `Some(k)` fail to solve.
    pub fail_step: Option<usize>,
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
    json!({"geometry": geometry, "elements": s.mesh.len(), "refine": s.refine,
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
        tips: Vec::new(),
        groups: Vec::new(),
    }
}

/// Upper bound on increments within one load step: every tip crossing the body twice.
fn increment_cap(bounds: (P2, P2), front: &Front, sizes: &Sizes) -> usize {
    let (lo, hi) = bounds;
    let da = sizes.smallest_da();
    let per_tip = (2.0 * (hi - lo).norm() / da).ceil() as usize;
    per_tip.saturating_mul(front.tips.len()).saturating_add(10)
}

pub(crate) fn point(p: P2, step: usize, load: f64) -> PathPoint {
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
    let e_prime = body.material.e_prime();
    let mut engine = Engine::new(body, scenario);
    let first = factors.first().copied().unwrap_or(1.0);
    let sizes = engine.sizes(&front, params.da)?;
    let cap = increment_cap(bounds, &front, &sizes);
    let (mut history, mut geometry, next, mut within) = match resume {
        Some(cp) => {
            front.restore(&cp.front).map_err(mismatch)?;
            let mut h = cp.history;
            h.snapshots = cp.snapshots;
            (h, cp.geometry, cp.next_step, cp.within)
        }
        None => {
            observer.event(
                "start",
                json!({"mode": "bem-only", "k_c": k_c, "steps": factors.len(),
                       "da": sizes.da, "crack_element_size": sizes.element,
                       "local_sizing": body.sizing.is_some()}),
            );
            (fresh_history(&front, first), 0, 0, None)
        }
    };
    let mut solved = initial::solve_geometry(&mut engine, &front, &sizes, geometry)?;
    if next == 0 {
        observer.event("solve", solve_event(&front, &solved, k_c, geometry));
    }
    let mut current = true;
    let mut not_a_state = None;
    for (k, &f) in factors.iter().enumerate().skip(next) {
        let t0 = Instant::now();
        // A run resumed inside this step goes on after its checkpoint's increments, with
        // the state the step started from (the geometry's K rows are in its history).
        let resumed = within.take();
        let mut increments = resumed.as_ref().map_or(0, |w| w.increments);
        let mut solved_now = true;
        let saved = match &resumed {
            Some(w) => {
                let mut start = front.clone();
                start.restore(&w.front).map_err(mismatch)?;
                let mut h = w.history.clone();
                h.snapshots = w.snapshots.clone();
                (start, h, w.geometry)
            }
            None => (front.clone(), history.clone(), geometry),
        };
        let mut broken = None;
        let mut unstable = None;
        let mut snap = false;
        if resumed.is_none() {
            let rows = SifRow::rows(&front, &solved.sifs, solved.cmod, (k, f), e_prime);
            history.sif_path.extend(rows);
        }
        loop {
            let growing = critical_tips(&front, &solved, f, k_c);
            if growing.is_empty() {
                break;
            }
            if increments >= cap {
                if front.outline_points().is_none() {
                    unstable = Some(unstable_note(cap, f));
                } else {
                    broken = Some(format!(
                        "more than {cap} increments at load {f} (step {k}); increase growth.da"
                    ));
                }
                break;
            }
            if history.initiation_load.is_none() {
                history.initiation_load = Some(f);
                history
                    .snapshots
                    .push(displacement_snapshot(body, &front, bounds, &solved, f, k));
            }
            // The state before the round, for the fallback below; kept only when an
            // increment will be shortened (cloning the history every round is O(n)).
            let mut before = growing
                .iter()
                .any(|t| shortens(&front, t, &sizes))
                .then(|| (front.clone(), history.clone()));
            let mut shortened = Vec::new();
            for t in &growing {
                if grow_tip(
                    &mut front,
                    &mut history,
                    observer,
                    t,
                    &sizes,
                    (f, k, k_c),
                    snap,
                ) {
                    shortened.push(front.tips[t.tip].name.clone());
                }
            }
            snap = false;
            increments += 1;
            // When every tip has stopped, the geometry is solved once more only if a tip
            // joined a hole (the final fields and K are then those of the joined body).
            let joined = !front.holes_reached().is_empty();
            if front.separated() || (front.active().is_empty() && !joined) {
                solved_now = false;
                break;
            }
            geometry += 1;
            let checked = if params.fail_step == Some(k) {
                Err(fail("injected by the test hook fail_step".into()))
            } else {
                engine.solve_checked(&front, &sizes, true)
            };
            match checked {
                Ok(Checked::Ok(s)) => solved = *s,
                Ok(Checked::Overlap(why) | Checked::Unsettled(why))
                    if !shortened.is_empty() && before.is_some() =>
                {
                    // The approach to an obstacle reached a geometry the BEM cannot take
                    // as a growth state: the tips are taken onto it from where they were.
                    if let Some(b) = before.take() {
                        (front, history) = b;
                    }
                    let note = full_increment_note((k, f, geometry), &shortened, &why);
                    observer.event("note", json!({ "message": note }));
                    history.notes.push(note);
                    snap = true;
                    continue;
                }
                Err(e) if !shortened.is_empty() && before.is_some() => {
                    if let Some(b) = before.take() {
                        (front, history) = b;
                    }
                    let why = format!("it could not be meshed or solved: {e}");
                    let note = full_increment_note((k, f, geometry), &shortened, &why);
                    observer.event("note", json!({ "message": note }));
                    history.notes.push(note);
                    snap = true;
                    continue;
                }
                Ok(Checked::Overlap(why)) => {
                    not_a_state = Some(format!(
                        "run ended at load {f} (step {k}), geometry {geometry}: {why}; the crack \
                         faces overlap in the linear solution (no contact), which is not a \
                         growth state; the path ends at the last increment"
                    ));
                    solved_now = false;
                    break;
                }
                Ok(Checked::Unsettled(why)) => {
                    not_a_state = Some(format!(
                        "run ended at load {f} (step {k}), geometry {geometry}: {why}; the \
                         path ends at the last increment"
                    ));
                    solved_now = false;
                    break;
                }
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
            let rows = SifRow::rows(&front, &solved.sifs, solved.cmod, (k, f), e_prime);
            history.sif_path.extend(rows);
            // Unstable growth runs within one load step, for thousands of increments
            // with a small da: show each, and offer a checkpoint (the geometry is solved
            // anew from the front on resume, so results do not depend on where it is).
            let status = format!("load {f:.4e}: {increments} increments, geometry {geometry}");
            observer.progress(k, factors.len(), &status);
            let flow = observer.round_checkpoint(k, increments, &mut || {
                let cp = within_step((k, increments), (&front, &history, geometry), &saved);
                EngineCheckpoint::BemOnly(cp)
            });
            if flow.is_break() {
                return Err(CouplingError::InterruptedAtIncrement {
                    step: k,
                    increments,
                });
            }
        }
        if let Some(reason) = broken {
            // Back to the end of the last completed step, whose records stand.
            let initiation = history.initiation_load;
            (front, history, _) = saved;
            observer.event("note", json!({ "message": reason }));
            // A load at which the tips grew stays their initiation load.
            history.initiation_load = history.initiation_load.or(initiation);
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
        let cut = front.separated() || unstable.is_some();
        let why = unstable.unwrap_or_else(|| failure_reason(&front));
        if stop_after_step(&mut history, observer, &front, cut, k, f, &why) || !solved_now {
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
                    within: None,
                })
            });
            if flow.is_break() {
                return Err(CouplingError::Interrupted { step: k });
            }
        }
    }
    if let Some(why) = not_a_state {
        observer.event("note", json!({"message": why}));
        history.failure_reason.get_or_insert_with(|| why.clone());
        history.notes.push(why);
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
