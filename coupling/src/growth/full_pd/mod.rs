//! Full-PD crack growth: the whole body in bond-based peridynamics at the PD-BEM window's
//! resolution (dx = coupling.side / coupling.n), the reference the PD-BEM windows are
//! meant to reproduce at a fraction of the cost.
//!
//! Algorithm:
//! 1. The caller builds the whole-body [`PdModel`] at the window spacing (the `pdbem`
//!    binary: `setup::pd::full_pd_problem`, the scene's conditions, pre-cracks and failure
//!    law) and the crack [`Front`].
//! 2. For every load factor, warm-started from the previous equilibrium:
//!    equilibrium with the bond history frozen (tolerances 1e-6 as in
//!    [`pdbem_pd::measure::ramp_to_initiation`]) by the chord iteration on a kept
//!    factorisation for brittle bonds, Newton for degrading ones, with Newton and ADR as
//!    fallbacks (`rounds`), then break rounds until no bond breaks: sequentially linear
//!    for brittle bonds (the 20 most stretched bonds break at the load where they reach
//!    s0, see `rounds::load_step`), Jacobi for degrading ones.
//! 3. After every round each growing tip is traced by
//!    [`pdbem_pd::crack_path::trace_crack_beyond`] from its initial position, beyond its
//!    previous position (a crack that joins the path behind the tip does not take the
//!    tip over), on the damage ahead of it (nodes more than 1.5 dx behind the initial
//!    tip, or within 2 dx of
//!    another crack, are left out so the trace neither runs back along the pre-crack nor
//!    into a neighbouring crack). A tip within one horizon of the outline has reached it
//!    (its path is ended on the outline by the PD-BEM rule,
//!    `pdbem_coupling::growth::polyline::end_on_outline`), within one horizon of a hole
//!    is arrested there (its path joined to the hole along its approach,
//!    `polyline::join_boundary`), within 3 dx of another crack has joined it ([`Front`] decides
//!    failure).
//! 4. Failure ends the run: a crack cut the body through, either a tracked tip reached
//!    the outline ([`Front::separated`]) or the macro cracks of the damage, with the
//!    tracked cracks counted in, cut it (`cut::crack_cuts_body`: one reaching the outline
//!    at two places more than two horizons apart, or a chain through the holes, such as
//!    the tracked crack into a hole and a crack nucleated at the hole's far side running
//!    to the outline; also cracks nucleated away from the tips, or branches). When the
//!    chord iteration and Newton fail (nearly singular tangents once
//!    pieces hang by a few bonds), ADR looks
//!    for the equilibrium. Under load control the last equilibria before separation do not
//!    exist: a failure of all three after bonds broke in the same step is taken as collapse
//!    (failure, with the solvers' messages in the notes); a failure without breaking is
//!    an error.
//!
//! Initiation: the first load step after which a tracked tip has advanced by more than
//! one horizon (bonds break at the sharp pre-crack tip well below the Griffith load; that
//! is damage, not growth; the first break is reported in the notes).
//!
//! CMOD (edge cracks): opening of the two real nodes straddling the crack at the mouth.

use std::time::Instant;

use cut::crack_cuts_body;
use pdbem_geometry::P2;
use pdbem_pd::crack_path::{trace_crack_beyond, PathParams};
use pdbem_pd::PdModel;
pub use rounds::RENEW_ROUNDS;
use rounds::{load_step, message_of, pd_fail, renews_after, Equilibrium, Tracked, LOOSE_MEASURE};
use serde_json::json;

use super::checkpoint::{FullPdCheckpoint, WithinStep};
use super::events::EngineObserver;
use super::front::{Front, Obstacle};
use super::history::{FieldSnapshot, GrowthHistory, PathPoint, StepRecord, TipPath};
use super::polyline;
use super::verdict::stop_after_step;
use crate::error::CouplingError;

mod cut;
mod resume;
mod rounds;

/// Nodes this far behind a tip's initial position (in dx) are not traced from it.
const BEHIND_DX: f64 = 1.5;
/// Nodes this close to another crack (in dx) are not traced from a tip.
const OTHER_CRACK_DX: f64 = 2.0;
/// A tip this close to another crack (in dx) has joined it.
const JOIN_DX: f64 = 3.0;

/// Parameters of a full-PD run.
#[derive(Debug, Clone, PartialEq)]
pub struct FullPdParams {
    /// Grid spacing dx (m).
    pub dx: f64,
    /// Horizon delta (m).
    pub delta: f64,
    /// Load factors, one per step.
    pub loads: Vec<f64>,
    /// Damage above which a node belongs to a macro crack (the tip tracker's threshold).
    pub damage_threshold: f64,
    /// Steps (0-based) after which damage and displacement snapshots are taken as well.
    pub snapshot_steps: Vec<usize>,
    /// A test hook: `Some((k, n))` makes the first `n` tries of load step `k` fail as an
    /// equilibrium failure before any bond broke does (the back-off then retries it).
    pub fail_tries: Option<(usize, usize)>,
}

/// Per-tip tracking state.
struct Tracker {
    /// Initial unit direction of each tip.
    dir0: Vec<P2>,
    /// Arc length of each tip path already recorded (m).
    recorded: Vec<f64>,
    dx: f64,
    delta: f64,
    /// The body came apart other than by a tracked tip reaching the outline.
    apart: bool,
    /// Start of the run (for the `round` events).
    start: Instant,
}

impl Tracker {
    /// Damage with the nodes tip `t` must not trace through set to 0.
    fn masked_damage(&self, front: &Front, t: usize, x: &[[f64; 2]], phi: &[f64]) -> Vec<f64> {
        let (o, d) = (front.tips[t].initial, self.dir0[t]);
        let own = front.tips[t].crack;
        let others: Vec<&Vec<P2>> = front
            .cracks
            .iter()
            .enumerate()
            .filter(|(i, _)| *i != own)
            .map(|(_, c)| &c.points)
            .collect();
        let near_other = |p: &P2| {
            others.iter().any(|c| {
                c.windows(2).any(|w| {
                    pdbem_geometry::point_segment_distance(p, &w[0], &w[1])
                        < OTHER_CRACK_DX * self.dx
                })
            })
        };
        x.iter()
            .zip(phi)
            .map(|(xi, &f)| {
                let p = P2::new(xi[0], xi[1]);
                if f == 0.0 || (p - o).dot(&d) < -BEHIND_DX * self.dx || near_other(&p) {
                    0.0
                } else {
                    f
                }
            })
            .collect()
    }

    /// Traces tip `t`; returns its path from the initial position when it has moved ahead.
    fn trace(
        &self,
        front: &Front,
        t: usize,
        (x, phi): (&[[f64; 2]], &[f64]),
        params: &PathParams,
    ) -> Result<Option<Vec<P2>>, CouplingError> {
        let masked = self.masked_damage(front, t, x, phi);
        let (o, last) = (front.tips[t].initial, front.tip_position(t));
        let path = trace_crack_beyond(x, &masked, self.dx, [o.x, o.y], [last.x, last.y], params)
            .map_err(pd_fail)?;
        let tip = path.tip();
        let ahead = (P2::new(tip[0], tip[1]) - o).dot(&self.dir0[t]);
        if path.is_empty() || ahead <= 0.5 * self.dx {
            return Ok(None);
        }
        Ok(Some(
            path.points.iter().map(|p| P2::new(p[0], p[1])).collect(),
        ))
    }
}

/// What stops tip `t` at `tip` (direction `dir`): outline, hole, another crack.
fn obstacle_at(front: &Front, t: usize, tip: &P2, tr: &Tracker) -> Obstacle {
    if front.outline_distance(tip) <= tr.delta {
        Obstacle::Outline
    } else if let Some(h) = front.hole_within(tip, tr.delta) {
        Obstacle::Hole(h)
    } else if let Some(c) = front.crack_within(t, tip, JOIN_DX * tr.dx) {
        Obstacle::Crack(c)
    } else {
        Obstacle::None
    }
}

/// Appends the part of `path` beyond the recorded arc length to the history path.
fn record_path(hp: &mut TipPath, path: &[P2], recorded: &mut f64, step: usize, load: f64, dx: f64) {
    let mut s = 0.0;
    for w in path.windows(2) {
        s += (w[1] - w[0]).norm();
        if s > *recorded + 0.5 * dx {
            hp.points.push(PathPoint {
                x: w[1].x,
                y: w[1].y,
                step,
                load,
            });
            *recorded = s;
        }
    }
}

/// Opening of the first edge crack at its mouth: the real nodes nearest to the points half
/// a spacing on either side of the crack, half a spacing in from the mouth.
fn cmod(model: &PdModel, front: &Front, dx: f64) -> Option<f64> {
    let c = front.cracks.iter().find(|c| c.mouth)?;
    let (m, next) = (c.points[0], c.points[1]);
    let t = (next - m) / (next - m).norm();
    let nrm = P2::new(-t.y, t.x);
    let n = model.n_real();
    let x = &model.positions()[..n];
    let nearest = |q: P2| {
        (0..n).min_by(|&a, &b| {
            let da = (P2::new(x[a][0], x[a][1]) - q).norm();
            let db = (P2::new(x[b][0], x[b][1]) - q).norm();
            da.total_cmp(&db)
        })
    };
    let inward = m + t * (0.5 * dx);
    let (up, lo) = (
        nearest(inward + nrm * (0.5 * dx))?,
        nearest(inward - nrm * (0.5 * dx))?,
    );
    if up == lo {
        return None;
    }
    let u = model.displacements();
    Some((u[up][0] - u[lo][0]) * nrm.x + (u[up][1] - u[lo][1]) * nrm.y)
}

/// Damage and displacement magnitude of every real node.
fn snapshots(model: &PdModel, step: usize) -> [FieldSnapshot; 2] {
    let n = model.n_real();
    let points: Vec<[f64; 2]> = model.positions()[..n].to_vec();
    let u = model.displacements();
    [
        FieldSnapshot {
            step,
            label: "damage".into(),
            points: points.clone(),
            values: model.damage()[..n].to_vec(),
            tips: Vec::new(),
            groups: Vec::new(),
        },
        FieldSnapshot {
            step,
            label: "displacement".into(),
            points,
            values: (0..n).map(|i| u[i][0].hypot(u[i][1])).collect(),
            tips: Vec::new(),
            groups: Vec::new(),
        },
    ]
}

/// Runs full-PD growth of `model` (at rest, its pre-cracks cut) from the crack `front`
/// (see the module documentation); `name` labels the start message.
pub fn run(
    name: &str,
    model: &mut PdModel,
    front: Front,
    p: &FullPdParams,
    obs: &mut dyn EngineObserver,
) -> Result<GrowthHistory, CouplingError> {
    run_from(name, model, front, p, obs, None)
}

/// [`run`], going on from `resume` when given (a checkpoint of a run of the same model,
/// front and parameters, [`crate::growth::checkpoint`]). A load step whose equilibrium
/// fails before any bond broke is tried again ([`resume::EFFORT`] times the iteration
/// budgets, then also half the load increment); when no try solves it the run ends with
/// [`GrowthHistory::failure_reason`] and the steps before it.
pub fn run_from(
    name: &str,
    model: &mut PdModel,
    mut front: Front,
    p: &FullPdParams,
    obs: &mut dyn EngineObserver,
    resume: Option<FullPdCheckpoint>,
) -> Result<GrowthHistory, CouplingError> {
    let (dx, delta) = (p.dx, p.delta);
    let factors = &p.loads[..];
    let params = PathParams {
        threshold: p.damage_threshold,
        ..Default::default()
    };
    if resume.is_none() {
        obs.event(
            "start",
            json!({"mode": "full-pd", "dx": dx, "horizon": delta, "nodes": model.n_real(),
                   "bonds": model.n_bonds() / 2, "steps": factors.len()}),
        );
    }
    obs.message(&format!(
        "{name}: full PD, {} real nodes, dx = {dx:e} m",
        model.n_real()
    ));
    let mut tr = Tracker {
        dir0: (0..front.tips.len())
            .map(|t| front.tip_direction(t))
            .collect(),
        recorded: vec![0.0; front.tips.len()],
        dx,
        delta,
        apart: false,
        start: Instant::now(),
    };
    let first = factors.first().copied().unwrap_or(1.0);
    let mut history = GrowthHistory {
        mode: "full-pd".into(),
        paths: front
            .tips
            .iter()
            .map(|t| TipPath {
                name: t.name.clone(),
                points: vec![PathPoint {
                    x: t.initial.x,
                    y: t.initial.y,
                    step: 0,
                    load: first,
                }],
                ended: None,
            })
            .collect(),
        ..Default::default()
    };
    let mut first_break = None;
    let (next, mut within) = match &resume {
        Some(cp) => {
            resume::restore(cp, model, &mut front, &mut tr, &mut history)?;
            first_break = cp.first_break;
            (cp.next_step, cp.within)
        }
        None => (0, None),
    };
    let mut eq = Equilibrium::new(model).map_err(pd_fail)?;
    if let Some(cp) = &resume {
        eq.set_work(&cp.work);
    }
    let n_side = (model.n_real() as f64).sqrt().ceil() as usize;
    let max_rounds = 20 * n_side.max(10);
    for (k, &f) in factors.iter().enumerate().skip(next) {
        let t0 = Instant::now();
        // A run resumed inside this step goes on from the checkpoint's try, load and round.
        let resumed = within.take();
        let broken0 = resumed.map_or(model.broken_bonds(), |w| w.broken_at_start);
        let prev = if k == 0 { 0.0 } else { factors[k - 1] };
        let saved = resume::Saved::take(model, &front, &tr, &history);
        let mut tried = Vec::new();
        let mut outcome = None;
        let first_try = resumed.map_or(0, |w| w.attempt);
        for (i, attempt) in resume::ATTEMPTS.iter().enumerate().skip(first_try) {
            if i > first_try {
                saved.put_back(model, &mut front, &mut tr, &mut history);
                eq.renew(model).map_err(pd_fail)?;
                let message = format!("step {k} (load {f}): retry {i} with {}", attempt.label);
                obs.event("note", json!({ "message": message }));
            }
            eq.set_effort(attempt.effort);
            let loads = attempt.loads(prev, f);
            let mut r = injected_failure(p, k, i);
            let first_load = resumed.filter(|w| w.attempt == i).map_or(0, |w| w.load);
            for (j, &fl) in loads.iter().enumerate().skip(first_load) {
                if r.is_err() {
                    break;
                }
                let first_round = resumed
                    .filter(|w| w.attempt == i && w.load == j)
                    .map_or(0, |w| w.round + 1);
                r = load_step(
                    model,
                    &mut eq,
                    (fl, first_round),
                    max_rounds,
                    |m, eq, round| {
                        let tracked =
                            track(&mut front, &mut tr, &mut history, m, &params, k, fl, obs)?;
                        // A step can run for many minutes on a fine grid: show every round.
                        let status = round_message(fl, m.broken_bonds(), &front.tip_positions());
                        obs.progress(k, factors.len(), &status);
                        if matches!(tracked, Tracked::Continue) && renews_after(round) {
                            let here = WithinStep {
                                attempt: i,
                                load: j,
                                round,
                                broken_at_start: broken0,
                            };
                            let flow = obs.round_checkpoint(k, round, &mut || {
                                let cp = (m, &front, &tr, &history, first_break, eq);
                                resume::checkpoint(k, cp, Some(here))
                            });
                            if flow.is_break() {
                                return Err(CouplingError::InterruptedWithin { step: k, round });
                            }
                        }
                        Ok(tracked)
                    },
                );
                if r.is_err() || tr.apart || front.separated() {
                    break;
                }
            }
            eq.set_effort(1);
            match r {
                Err(e @ CouplingError::InterruptedWithin { .. }) => return Err(e),
                Ok(()) => outcome = Some(None),
                Err(e) if model.broken_bonds() > broken0 => outcome = Some(Some(message_of(&e))),
                Err(e) => {
                    tried.push(format!("{}: {}", attempt.label, message_of(&e)));
                    continue;
                }
            }
            break;
        }
        let Some(collapsed) = outcome else {
            saved.put_back(model, &mut front, &mut tr, &mut history);
            let reason = format!(
                "load step {k} (load factor {f}): no equilibrium before any bond broke; tried {}",
                tried.join("; ")
            );
            obs.event("note", json!({ "message": reason }));
            history.failure_reason = Some(reason);
            break;
        };
        let grown = (0..front.tips.len()).any(|t| front.extension(t) > delta);
        if history.initiation_load.is_none() && grown {
            history.initiation_load = Some(f);
            history.snapshots.extend(snapshots(model, k));
        } else if p.snapshot_steps.contains(&k) {
            history.snapshots.extend(snapshots(model, k));
        }
        if first_break.is_none() && model.broken_bonds() > 0 {
            first_break = Some(f);
        }
        // A step that ended in collapse or with the body apart has no CMOD (its state is
        // not an equilibrium of the body in one piece), as in the other modes.
        let came_apart = collapsed.is_some() || front.separated() || tr.apart;
        let rec = StepRecord {
            step: k,
            load: f,
            cmod: if came_apart {
                None
            } else {
                cmod(model, &front, dx)
            },
            tips: front.tip_positions(),
            broken_bonds: model.broken_bonds(),
            wall_time_s: t0.elapsed().as_secs_f64(),
            coupling_residual: Some(0.0),
            ..Default::default()
        };
        obs.event("step", json!(rec));
        history.steps.push(rec);
        let status = round_message(f, model.broken_bonds(), &front.tip_positions());
        obs.progress(k + 1, factors.len(), &status);
        if let Some(msg) = collapsed {
            history.notes.push(format!(
                "no equilibrium at load {f} (step {k}) after bonds broke: taken as collapse ({msg})"
            ));
            history.failure = true;
        }
        let failed = history.failure || front.separated() || tr.apart;
        let why = if front.separated() || !tr.apart {
            "the body came apart"
        } else {
            "the body came apart along damage no tracked tip followed (a crack from elsewhere)"
        };
        if stop_after_step(&mut history, obs, &front, failed, k, f, why) {
            break;
        }
        // The kept factorisations end with the step, in every run, so that a run resumed
        // from the checkpoint below repeats this one bit for bit.
        eq.renew(model).map_err(pd_fail)?;
        if k + 1 < factors.len() {
            let flow = obs.checkpoint(k, &mut || {
                let cp = (&*model, &front, &tr, &history, first_break, &eq);
                resume::checkpoint(k + 1, cp, None)
            });
            if flow.is_break() {
                return Err(CouplingError::Interrupted { step: k });
            }
        }
    }
    let last = history.steps.len().saturating_sub(1);
    history.snapshots.extend(snapshots(model, last));
    obs.event("solver", eq.work());
    let counts = &eq.counts;
    if counts.newton > 0 {
        history.notes.push(format!(
            "{} equilibria found by Newton after the chord iteration failed",
            counts.newton
        ));
    }
    if counts.loose > 0 {
        history.notes.push(format!(
            "{} equilibria accepted with a displacement-change measure below {LOOSE_MEASURE:e} (nodes that lost all bonds)",
            counts.loose
        ));
    }
    if counts.adr > 0 {
        history.notes.push(format!(
            "{} equilibria found by ADR after Newton failed",
            counts.adr
        ));
    }
    if let Some(f) = first_break {
        history.notes.push(format!("first bond broke at load {f}"));
    }
    if history.initiation_load.is_none() {
        history.notes.push(super::verdict::no_initiation_note(
            history.failure_load,
            factors.last().copied().unwrap_or(first),
        ));
    }
    for (p, t) in history.paths.iter_mut().zip(&front.tips) {
        p.ended = t.ended.clone();
    }
    Ok(history)
}

/// The failure [`FullPdParams::fail_tries`] injects into try `i` of step `k` (else Ok).
fn injected_failure(p: &FullPdParams, k: usize, i: usize) -> Result<(), CouplingError> {
    match p.fail_tries {
        Some((step, n)) if step == k && i < n => Err(rounds::fail(
            "no frozen-bond equilibrium (injected by the test hook fail_tries)".into(),
        )),
        _ => Ok(()),
    }
}

/// Progress message after a break round: load, broken bonds, tip positions.
fn round_message(load: f64, broken: usize, tips: &[[f64; 2]]) -> String {
    let tips: Vec<String> = tips
        .iter()
        .map(|p| format!("({:.4e}, {:.4e})", p[0], p[1]))
        .collect();
    format!(
        "load {load:.4e}, {broken} broken bonds, tips {}",
        tips.join(" ")
    )
}

/// Traces every growing tip, records paths, stops tips at obstacles; `Separated` once the
/// body has come apart.
fn track(
    front: &mut Front,
    tr: &mut Tracker,
    history: &mut GrowthHistory,
    model: &PdModel,
    params: &PathParams,
    step: usize,
    load: f64,
    obs: &mut dyn EngineObserver,
) -> Result<Tracked, CouplingError> {
    let n = model.n_real();
    let x = &model.positions()[..n];
    let phi = model.damage();
    let phi = &phi[..n];
    for t in front.active() {
        let Some(mut path) = tr.trace(front, t, (x, phi), params)? else {
            continue;
        };
        let tip = *path.last().unwrap_or(&front.tips[t].initial);
        let hit = obstacle_at(front, t, &tip, tr);
        match &hit {
            Obstacle::Outline => extend_to_outline(front, &mut path, tr),
            Obstacle::Hole(h) => {
                if let Some(poly) = front.hole_polygon(h) {
                    let chord = polyline::OUTLINE_CHORD_DX * tr.dx;
                    path = polyline::join_boundary(&path, &poly, chord).0;
                }
            }
            _ => {}
        }
        front.set_path(t, &path);
        record_path(
            &mut history.paths[t],
            &path,
            &mut tr.recorded[t],
            step,
            load,
            tr.dx,
        );
        if hit != Obstacle::None {
            front.stop(t, &hit);
            obs.event(
                "tip_end",
                json!({"step": step, "load": load, "tip": front.tips[t].name,
                       "reason": front.tips[t].ended}),
            );
        }
    }
    obs.event(
        "round",
        json!({"step": step, "load": load, "broken_bonds": model.broken_bonds(),
               "tips": front.tip_positions(), "wall_time_s": tr.start.elapsed().as_secs_f64()}),
    );
    if front.separated() {
        return Ok(Tracked::Separated);
    }
    if let Some(cut) = crack_cuts_body(x, phi, front, params, (tr.dx, tr.delta))? {
        tr.apart = true;
        let (a, b) = cut.contacts;
        history.notes.push(cut.note(step, load));
        obs.event(
            "cut",
            json!({"step": step, "load": load, "contacts": [[a.x, a.y], [b.x, b.y]],
                   "holes": cut.holes}),
        );
        return Ok(Tracked::Separated);
    }
    Ok(Tracked::Continue)
}

/// Ends the path on the outline by the rule of the PD-BEM mode
/// ([`pdbem_coupling::growth::polyline::end_on_outline`]).
fn extend_to_outline(front: &Front, path: &mut Vec<P2>, tr: &Tracker) {
    let Some(outline) = front.outline_points() else {
        return;
    };
    let chord = polyline::OUTLINE_CHORD_DX * tr.dx;
    *path = polyline::end_on_outline(path, outline, tr.delta, chord);
}
