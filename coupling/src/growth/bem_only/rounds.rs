//! The pieces of one BEM-only growth round: a tip's increment ([`grow_tip`]), whether an
//! obstacle shortens it ([`shortens`]), the notes and failure reasons of the rounds, and
//! the checkpoint inside a load step ([`within_step`]).

use pdbem_geometry::rotate;
use serde_json::json;

use super::solve::Sizes;
use super::{increment, point, TipSif, LIGAMENT_MARGIN, MIN_INCREMENT};
use crate::growth::checkpoint::{BemOnlyCheckpoint, BemOnlyWithin};
use crate::growth::events::EngineObserver;
use crate::growth::front::{Front, Obstacle};
use crate::growth::history::GrowthHistory;

/// Whether tip `t`'s next increment is shortened by an obstacle ahead ([`increment`]).
pub(super) fn shortens(front: &Front, t: &TipSif, sizes: &Sizes) -> bool {
    let dir = rotate(&front.tip_direction(t.tip), t.theta);
    let da = sizes.da[front.tips[t.tip].crack];
    increment(front.room_ahead(t.tip, dir), da) < da
}

/// The note of a round of shortened increments taken again with the full `da`: load
/// step, load and geometry, the tips that were shortened, why the geometry was refused.
pub(super) fn full_increment_note(
    (step, load, geometry): (usize, f64, usize),
    shortened: &[String],
    why: &str,
) -> String {
    format!(
        "step {step} (load {load}): after the shortened increments of {} towards the \
         boundary, geometry {geometry} was not a growth state ({why}); the increments were \
         taken with the full growth.da instead, which takes a tip within 2.5 growth.da of \
         the outline or a hole onto it",
        shortened.join(", ")
    )
}

/// Why the body came apart: a tip reached the outline, or cracks joined across it.
pub(super) fn failure_reason(front: &Front) -> String {
    match front
        .tips
        .iter()
        .find(|t| t.ended.as_deref() == Some("outline"))
    {
        Some(t) => format!(
            "tip reached the outline ({} was taken onto it when its increments, shortened \
             towards it, would fall under {MIN_INCREMENT} growth.da, or left a geometry that \
             is not a growth state)",
            t.name
        ),
        None => match front.holes_reached().first() {
            Some(h) => format!(
                "cracks joined to hole {h} cut the body apart (a chain of cracks through the \
                 holes links the outline to itself)"
            ),
            None => "a crack cut the body through".into(),
        },
    }
}

/// One increment of one tip: direction by MCS, `Front::step_ahead`, path point and events.
/// The increment is [`increment`]'s, or with `snap` the full `da` (which takes a tip near
/// the outline or a hole onto it). Returns whether the increment was shortened.
pub(super) fn grow_tip(
    front: &mut Front,
    history: &mut GrowthHistory,
    observer: &mut dyn EngineObserver,
    t: &TipSif,
    sizes: &Sizes,
    (f, step, k_c): (f64, usize, f64),
    snap: bool,
) -> bool {
    let tip = t.tip;
    let from = front.tip_position(tip);
    let dir = rotate(&front.tip_direction(tip), t.theta);
    let full = sizes.da[front.tips[tip].crack];
    let da = if snap {
        full
    } else {
        increment(front.room_ahead(tip, dir), full)
    };
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
    da < full
}

/// The checkpoint inside load step `step` after `increments` growth rounds, the geometry
/// solved: the run as it stands and the state the step started from (`start`: front,
/// history with its snapshots, geometries), to which a step that breaks returns.
pub(super) fn within_step(
    (step, increments): (usize, usize),
    (front, history, geometry): (&Front, &GrowthHistory, usize),
    start: &(Front, GrowthHistory, usize),
) -> BemOnlyCheckpoint {
    BemOnlyCheckpoint {
        next_step: step,
        front: front.state(),
        history: history.clone(),
        snapshots: history.snapshots.clone(),
        geometry,
        within: Some(Box::new(BemOnlyWithin {
            increments,
            front: start.0.state(),
            history: start.1.clone(),
            snapshots: start.1.snapshots.clone(),
            geometry: start.2,
        })),
    }
}
