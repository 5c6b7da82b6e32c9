//! Thin ligaments along grown paths: the check of [`crate::setup::thin_ligament`] (a
//! crack flank running close along another boundary, a strip more than
//! [`SLENDERNESS_LIMIT`] times as long as it is thick, which the BEM crack faces do not
//! resolve and whose error the estimates do not see) on the crack geometry at the end of
//! every load step of a growth run, not only on the scene's initial cracks.
//!
//! The geometry of step $k$ is each crack of the scene with its tips' path points of steps
//! up to $k$ put on its ends (the path of `<crack>.start` before its first point, that of
//! `<crack>.end` after its last). A ligament counts as grown unless the initial geometry has
//! one of the same crack and other boundary at most [`TURN_ALLOWANCE`] less slender (those
//! are the run's ordinary notes, [`crate::runner::plausibility::thin_ligaments`]). The note names the
//! first step with a grown ligament and the most slender one of the run: from that step
//! on, K along the path (`sif_path.csv`), and in BEM-only growth the kinks and critical
//! loads K decides, may be off by more than their estimates.

use pdbem_coupling::growth::history::TipPath;

use super::GrowthHistory;
use crate::geometry::P2;
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;
use crate::setup::thin_ligament::{
    find, resolved, Ligament, RESOLVED_SLENDERNESS, RESOLVING_FRACTION, SLENDERNESS_LIMIT,
};

/// A ligament of the initial geometry gets no grown note while it is at most this much
/// more slender than at the start: where the path turns away from the other boundary, the
/// run of gaps within [`crate::setup::thin_ligament::RUN_RATIO`] (2) reaches up to a
/// thickness further along the path.
pub const TURN_ALLOWANCE: f64 = 2.0;

/// The grown ligaments of a run at one step.
struct Found {
    step: usize,
    load: f64,
    ligament: Ligament,
}

/// The note on the thin ligaments the run's paths formed (module docs); none when every
/// step's geometry is free of grown ones.
pub fn notes(scene: &Scene, h: &GrowthHistory) -> Vec<String> {
    let geo0 = SceneGeometry::of(scene);
    if geo0.cracks.is_empty() || h.paths.iter().all(|p| p.points.len() < 2) {
        return Vec::new();
    }
    let loops = crate::setup::bem::loops(scene, &geo0, 1.0);
    let slender = |geo: &SceneGeometry| -> Vec<Ligament> {
        find(geo, &loops)
            .into_iter()
            .filter(|l| l.slenderness() > SLENDERNESS_LIMIT && !resolved(scene, l))
            .collect()
    };
    let initial = slender(&geo0);
    let grown = |l: &Ligament| {
        !initial.iter().any(|i| {
            i.crack == l.crack
                && i.other == l.other
                && l.slenderness() <= i.slenderness() + TURN_ALLOWANCE
        })
    };
    let mut found: Vec<Found> = Vec::new();
    for step in growth_steps(h) {
        let geo = geometry_at(&geo0, &h.paths, step);
        let load = load_of(h, step);
        found.extend(
            slender(&geo)
                .into_iter()
                .filter(|l| grown(l))
                .map(|ligament| Found {
                    step,
                    load,
                    ligament,
                }),
        );
    }
    let Some(first) = found.first() else {
        return Vec::new();
    };
    let most = found
        .iter()
        .max_by(|a, b| {
            a.ligament
                .slenderness()
                .total_cmp(&b.ligament.slenderness())
        })
        .unwrap_or(first);
    vec![note(scene, h, first, most)]
}

/// The steps at which some tip reached a path point past its first, in order.
fn growth_steps(h: &GrowthHistory) -> Vec<usize> {
    let mut steps: Vec<usize> = h
        .paths
        .iter()
        .flat_map(|p| p.points.iter().skip(1).map(|q| q.step))
        .collect();
    steps.sort_unstable();
    steps.dedup();
    steps
}

/// The load factor of `step`: its step record's, else that of a path point of the step.
fn load_of(h: &GrowthHistory, step: usize) -> f64 {
    h.steps
        .iter()
        .find(|s| s.step == step)
        .map(|s| s.load)
        .or_else(|| {
            h.paths
                .iter()
                .flat_map(|p| p.points.iter())
                .find(|q| q.step == step)
                .map(|q| q.load)
        })
        .unwrap_or(f64::NAN)
}

/// The scene geometry with every crack grown by its tips' path points of steps up to
/// `step` (module docs).
pub fn geometry_at(geo0: &SceneGeometry, paths: &[TipPath], step: usize) -> SceneGeometry {
    let mut geo = geo0.clone();
    for crack in &mut geo.cracks {
        let grown = |end: &str| -> Vec<P2> {
            let name = format!("{}.{end}", crack.name);
            paths
                .iter()
                .find(|p| p.name == name)
                .map(|p| {
                    p.points
                        .iter()
                        .skip(1)
                        .filter(|q| q.step <= step)
                        .map(|q| P2::new(q.x, q.y))
                        .collect()
                })
                .unwrap_or_default()
        };
        let (start, end) = (grown("start"), grown("end"));
        let mut points: Vec<P2> = start.into_iter().rev().collect();
        points.extend(crack.points.iter().copied());
        points.extend(end);
        crack.points = points;
    }
    geo
}

/// The note of the first grown ligament and the most slender one.
fn note(scene: &Scene, h: &GrowthHistory, first: &Found, most: &Found) -> String {
    let name = |l: &Ligament| scene.cracks[l.crack].name.clone();
    let describe = |f: &Found| {
        format!(
            "at step {} (load {}) {}, a strip {:.0} times as long as it is thick",
            f.step,
            f.load,
            f.ligament.describe(scene),
            f.ligament.slenderness()
        )
    };
    let most_text = if std::ptr::eq(first, most) {
        String::new()
    } else {
        format!("; the most slender: {}", describe(most))
    };
    let decided = if h.mode == "bem-only" {
        ", and the kinks and critical loads K decides,"
    } else {
        ""
    };
    let most_l = &most.ligament;
    let remedy = if most_l.slenderness() <= RESOLVED_SLENDERNESS {
        format!(
            "crack elements of 1/64 of the thickness (bem.group_sizes.{}: {:.3e}) bring it \
             within its estimates",
            name(most_l),
            RESOLVING_FRACTION * most_l.width,
        )
    } else {
        format!(
            "no mesh is known to resolve a strip more than {RESOLVED_SLENDERNESS} times as \
             long as it is thick: take K along this part of the path as unknown"
        )
    };
    format!(
        "thin ligament along the grown path (a strip more than {SLENDERNESS_LIMIT} times as \
         long as it is thick): {}{most_text}. BEM crack faces resolve such a strip only with \
         elements far below its thickness, and the error estimates do not see it (an edge \
         crack 0.03 m under a free edge over 0.5 m: CMOD more than 92 % low with an estimate \
         of 6 %); from step {} on, K along the path (sif_path.csv){decided} may be off by \
         more than its estimates: {remedy}",
        describe(first),
        first.step,
    )
}

#[cfg(test)]
#[path = "ligaments_tests.rs"]
mod tests;
