//! The fracture-mechanics record along the path, in every growth mode (`sif_path.csv`):
//! for each step and tip, and along the path within a step, the crack length, K_I, K_II,
//! the maximum-circumferential-stress K_eq and kink angle ([`super::criterion`]),
//! $G = (K_I^2 + K_{II}^2)/E'$, the load factor and the CMOD.
//!
//! How K is obtained, the same way in the three modes: **K is that of the path geometry**,
//! the linear-elastic crack that the run grew, solved by BEM with the local-feature mesh
//! of the static BEM runs (tip elements L/80 over 1 L, [`super::bem_only::sizing`]) and
//! the crack-opening fit over the straight run behind the tip.
//! - BEM-only: the geometries the engine solves anyway, one row per load step and one per
//!   increment ([`SifRow::rows`], called by [`super::bem_only::run`]).
//! - PD-BEM and full PD: after the run, from the recorded paths ([`replay`]): stations
//!   every `spacing` of crack advance and at the end of every load step; at each station
//!   the paths up to where the tips were then, simplified to within `smooth` (the PD
//!   trace zig-zags on the grid), are solved at unit load and scaled by the station's load.
//!   A PD mode's own estimates were not used: the window-tip interaction integral
//!   (`crate::post::window_tip_sif`) needs a contour around the whole window clear of the
//!   boundary, which does not fit once the ligament is shorter than about 1.7 window
//!   sides (a/W > 0.7 on the seed plate), and a J from the PD field is a bond-scale
//!   average of a damage band, not the K of a sharp crack. The record therefore says what
//!   the grown path means in LEFM terms: the load at which a Griffith crack of that shape
//!   would grow, comparable across the modes and with handbook solutions.
//!   Points within `clear` (the horizon) of the outline or a hole are left out: there the
//!   ligament is shorter than a bond and a sharp-crack K means nothing at the PD scale.

use pdbem_geometry::P2;

use super::bem_only::sizing::{simplify, tip_scales};
use super::bem_only::solve::{Checked, Engine};
use super::bem_only::BemOnlyBody;
use super::criterion::TipSif;
use super::front::Front;
use super::history::{GrowthHistory, SifRow, TipPath};
use super::records::Scenario;
use crate::error::CouplingError;

/// Settings of [`replay`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplayParams {
    /// Crack advance between stations within a step (m).
    pub spacing: f64,
    /// Simplification tolerance of the recorded paths (m).
    pub smooth: f64,
    /// Path points closer than this to the outline or a hole are left out (m).
    pub clear: f64,
}

/// One event of the merged timeline: tip `tip` reached its path point `idx` in `step`.
struct Event {
    step: usize,
    frac: f64,
    tip: usize,
    idx: usize,
}

/// The record of a PD mode's `history`, replayed on the LEFM body (module docs).
/// `front0` is the initial crack front; paths are matched to its tips by name. Returns
/// the rows and a note on the stations left out: a tip within `clear` of another crack
/// or a boundary, a geometry that could not be meshed or solved, or one whose faces
/// overlap (K_I < 0 or CMOD < 0 after refinement).
pub fn replay(
    body: &BemOnlyBody,
    scenario: &dyn Scenario,
    front0: &Front,
    history: &GrowthHistory,
    p: &ReplayParams,
) -> Result<(Vec<SifRow>, Vec<String>), CouplingError> {
    let matched: Vec<&TipPath> = history
        .paths
        .iter()
        .filter(|hp| front0.tips.iter().any(|t| t.name == hp.name))
        .collect();
    let paths: Vec<(usize, Vec<P2>)> = matched
        .iter()
        .map(|hp| {
            let t = front0.tips.iter().position(|t| t.name == hp.name);
            (t.unwrap_or(0), clear_part(front0, hp, p.clear))
        })
        .collect();
    let events = timeline(&matched, &paths);
    let arcs: Vec<Vec<f64>> = paths.iter().map(|(_, pts)| cumulative(pts)).collect();
    let mut engine = Engine::new(body, scenario);
    let sizes = engine.sizes(front0, Some(p.spacing))?;
    let e_prime = body.material.e_prime();
    let mut idx = vec![0usize; paths.len()];
    let mut last_station: Option<Vec<usize>> = None;
    let mut last_solve: Option<(Front, Vec<TipSif>, Option<f64>)> = None;
    let (mut out, mut notes) = (Vec::new(), Vec::new());
    let mut next = 0;
    for rec in &history.steps {
        let mut station_arc: Vec<f64> = (0..paths.len()).map(|i| arcs[i][idx[i]]).collect();
        while next < events.len() && events[next].step <= rec.step {
            let e = &events[next];
            next += 1;
            idx[e.tip] = idx[e.tip].max(e.idx);
            let adv = (0..paths.len())
                .map(|i| arcs[i][idx[i]] - station_arc[i])
                .fold(0.0, f64::max);
            let step_end = events.get(next).is_none_or(|n| n.step > rec.step);
            if adv >= p.spacing && !step_end {
                station_arc = (0..paths.len()).map(|i| arcs[i][idx[i]]).collect();
                let load = matched[e.tip].points[e.idx].load;
                let state = (&idx, (rec.step, load));
                solve_station(
                    &mut engine,
                    &sizes,
                    front0,
                    &paths,
                    state,
                    p,
                    &mut last_solve,
                )
                .map(|r| record(&mut out, &mut notes, r))?;
                last_station = Some(idx.clone());
            }
        }
        let state = (&idx, (rec.step, rec.load));
        if last_station.as_ref() != Some(&idx) || last_solve.is_none() {
            solve_station(
                &mut engine,
                &sizes,
                front0,
                &paths,
                state,
                p,
                &mut last_solve,
            )
            .map(|r| record(&mut out, &mut notes, r))?;
            last_station = Some(idx.clone());
        } else if let Some((front, sifs, cmod1)) = &last_solve {
            out.extend(SifRow::rows(
                front,
                sifs,
                *cmod1,
                (rec.step, rec.load),
                e_prime,
            ));
        }
    }
    let notes = match notes.first() {
        Some(first) => vec![format!(
            "sif_path: {} state(s) of the path could not be solved as a growth state and \
             were left out; the first: {first}",
            notes.len()
        )],
        None => Vec::new(),
    };
    Ok((out, notes))
}

/// What one station gave: rows, or a note why it gave none.
type Station = Result<Vec<SifRow>, String>;

fn record(out: &mut Vec<SifRow>, notes: &mut Vec<String>, r: Station) {
    match r {
        Ok(rows) => out.extend(rows),
        Err(n) => notes.push(n),
    }
}

/// Solves the geometry with every tip at its path point `idx[i]` at unit load and returns
/// its rows at `(step, load)`; keeps the solve in `last` for steps without growth.
fn solve_station(
    engine: &mut Engine<'_>,
    sizes: &super::bem_only::solve::Sizes,
    front0: &Front,
    paths: &[(usize, Vec<P2>)],
    (idx, (step, load)): (&Vec<usize>, (usize, f64)),
    p: &ReplayParams,
    last: &mut Option<(Front, Vec<TipSif>, Option<f64>)>,
) -> Result<Station, CouplingError> {
    let mut front = front0.clone();
    for (i, (t, pts)) in paths.iter().enumerate() {
        if idx[i] > 0 {
            let part = simplify(&pts[..=idx[i]], p.smooth);
            front.set_path(*t, &part);
        }
    }
    let grown = idx.iter().any(|&i| i > 0);
    let e_prime = engine.body.material.e_prime();
    // Tips closer than `clear` to another crack or a boundary (cracks about to join):
    // the ligament is shorter than a bond, and the mesh would need elements of L/80.
    let body = engine.body;
    let scales = tip_scales(&front, &body.loops, body.fit_fraction, grown);
    if let Some(s) = scales.iter().find(|s| s.scale < p.clear) {
        return Ok(Err(format!(
            "step {step} (load {load}): tip {}: its length scale {:.3e} m (the crack's \
             length, or the distance to another crack or a boundary) is under a horizon",
            front.tips[s.tip].name, s.scale
        )));
    }
    let checked = match engine.solve_checked(&front, sizes, grown) {
        Ok(c) => c,
        Err(e) => return Ok(Err(format!("step {step} (load {load}): {e}"))),
    };
    match checked {
        Checked::Ok(s) => {
            let r = SifRow::rows(&front, &s.sifs, s.cmod, (step, load), e_prime);
            *last = Some((front, s.sifs, s.cmod));
            Ok(Ok(r))
        }
        Checked::Overlap(why) | Checked::Unsettled(why) => {
            Ok(Err(format!("step {step} (load {load}): {why}")))
        }
    }
}

/// The path of `hp` up to its first point within `clear` of the outline or a hole (the
/// initial point always).
fn clear_part(front: &Front, hp: &TipPath, clear: f64) -> Vec<P2> {
    let pts: Vec<P2> = hp.points.iter().map(|q| P2::new(q.x, q.y)).collect();
    let n = pts
        .iter()
        .skip(1)
        .position(|q| front.outline_distance(q) <= clear || front.hole_within(q, clear).is_some())
        .map_or(pts.len(), |k| k + 1);
    pts[..n].to_vec()
}

/// Cumulative arc length at every point of a polyline.
fn cumulative(pts: &[P2]) -> Vec<f64> {
    let mut acc = vec![0.0];
    for w in pts.windows(2) {
        let last = acc[acc.len() - 1];
        acc.push(last + (w[1] - w[0]).norm());
    }
    acc
}

/// The path points of all tips in one order of time: by step, then by the fraction of
/// the tip's points of that step reached (tips that grow together in a step advance
/// together), then by tip.
fn timeline(history: &[&TipPath], paths: &[(usize, Vec<P2>)]) -> Vec<Event> {
    let mut events = Vec::new();
    for (i, (_, pts)) in paths.iter().enumerate() {
        let hp = &history[i];
        let kept = pts.len();
        for (j, q) in hp.points.iter().enumerate().take(kept).skip(1) {
            let same: Vec<usize> = (1..kept).filter(|&m| hp.points[m].step == q.step).collect();
            let rank = same.iter().position(|&m| m == j).unwrap_or(0) + 1;
            events.push(Event {
                step: q.step,
                frac: rank as f64 / same.len() as f64,
                tip: i,
                idx: j,
            });
        }
    }
    events.sort_by(|a, b| {
        (a.step, a.frac, a.tip)
            .partial_cmp(&(b.step, b.frac, b.tip))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    events
}
