//! Loads of the stand-alone PD crack-initiation ramps ([`crate::run_pd`] on a grid,
//! [`crate::run_refined`] on refined particles): the ramp's parameters from the scene,
//! and the units of the reports (loads in Pa, the load factor times the largest applied
//! traction; load factors to 12 significant digits).

use pdbem_pd::measure::{crack_tips, RampParams, Tip};
use pdbem_pd::PdProblem;
use serde_json::{json, Map, Value};

use crate::runner::context::RunContext;
use crate::scene::shapes::SceneGeometry;
use crate::scene::{Component, Scene};

/// The pre-crack tips of the scene, where the ramps measure the crack's extension (an
/// edge crack: its inner end only).
pub fn scene_tips(scene: &Scene) -> Vec<Tip> {
    SceneGeometry::of(scene)
        .cracks
        .iter()
        .flat_map(|c| {
            crack_tips(
                &c.points.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(),
                c.mouth,
            )
        })
        .collect()
}

/// The initiation ramp of `scene`: from `load.initial` by `load.step` (5 % of the
/// initial load when the scene gives none) to the last load factor; the crack has run at
/// two horizons `delta` (m) of extension and grows on to five for the kink angle; at most
/// `max_rounds` break-and-re-solve rounds per load.
pub fn initiation_ramp(scene: &Scene, delta: f64, max_rounds: usize) -> RampParams {
    let last = scene.load.factors().last().copied().unwrap_or(1.0);
    RampParams {
        start: scene.load.initial,
        step: if scene.load.step > 0.0 {
            scene.load.step
        } else {
            0.05 * scene.load.initial
        },
        max_load: last,
        run_length: 2.0 * delta,
        grow_to: 5.0 * delta,
        max_rounds,
    }
}

/// `v` to 12 significant digits: a ramp's `start + k step` (14.999999999999993) written
/// as the load it means (15).
pub fn round12(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

/// Largest applied traction magnitude (Pa) at load factor 1.
pub fn traction_scale(scene: &Scene) -> Option<f64> {
    scene
        .boundary
        .iter()
        .flat_map(|b| [b.x, b.y])
        .filter_map(|c| match c {
            Component::Traction(v) => Some(v.abs()),
            _ => None,
        })
        .chain(
            scene
                .boundary
                .iter()
                .flat_map(|b| [b.normal, b.shear])
                .flatten()
                .map(f64::abs),
        )
        .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))))
}

/// The unit of the reported loads: `Pa` when the scene applies tractions (the factor
/// times [`traction_scale`]), `-` when the loads are load factors.
pub fn load_unit(scene: &Scene) -> &'static str {
    if traction_scale(scene).is_some() {
        "Pa"
    } else {
        "-"
    }
}

/// What an initiation ramp found, into `extra` (docs/outputs.md): `first_break_load` and
/// `initiation_load` in [`load_unit`], `initiation_load_factor`, `unstable_growth`,
/// `kink_deg` (the first tip with one) and `kink_deg_per_tip`; the loads are factors.
pub fn report_initiation(
    scene: &Scene,
    first_break: Option<f64>,
    initiation: Option<f64>,
    unstable: bool,
    kinks: &[Option<f64>],
    extra: &mut Map<String, Value>,
) {
    let scale = traction_scale(scene).unwrap_or(1.0);
    let load = |f: Option<f64>| f.map(|f| round12(f * scale));
    extra.insert("first_break_load".into(), json!(load(first_break)));
    extra.insert("initiation_load".into(), json!(load(initiation)));
    extra.insert(
        "initiation_load_factor".into(),
        json!(initiation.map(round12)),
    );
    extra.insert("unstable_growth".into(), json!(unstable));
    extra.insert(
        "kink_deg".into(),
        json!(kinks.iter().flatten().copied().next()),
    );
    extra.insert("kink_deg_per_tip".into(), json!(kinks));
}

/// The note of a PD load ramp whose first load (factor `first`) already broke bonds: its
/// first-break load, and the initiation load if the crack ran there too, are then only
/// upper bounds. Every PD ramp reports through it: the crack-initiation ramps
/// ([`initiation_notes`]) and the ramps to the final load (`crate::run_pd`).
pub fn first_load_note(
    first: f64,
    first_break: Option<f64>,
    initiation: Option<f64>,
) -> Option<String> {
    let at_first = |f: f64| round12(f) <= round12(first);
    if !first_break.is_some_and(at_first) {
        return None;
    }
    let what = if initiation.is_some_and(at_first) {
        "the first-break and initiation loads are upper bounds, the true ones lie"
    } else {
        "the first-break load is an upper bound, the true one lies"
    };
    Some(format!(
        "bonds already broke at the ramp's first load factor {}: {what} below it; start the \
         ramp lower (load.initial)",
        round12(first)
    ))
}

/// The notes of an initiation ramp that ended short of a full answer: bonds broke at the
/// ramp's first load (`first_break`, a factor, equal to `load.initial`), so the first-break
/// and initiation loads are only upper bounds; the crack did not run by the last load
/// factor (`extension`, m, at the end); or loads (factors) used up their
/// break-and-re-solve rounds before the bonds settled.
pub fn initiation_notes(
    scene: &Scene,
    first_break: Option<f64>,
    initiation: Option<f64>,
    extension: f64,
    unsettled: &[f64],
    notes: &mut Vec<String>,
) {
    notes.extend(first_load_note(scene.load.initial, first_break, initiation));
    if initiation.is_none() {
        let last = round12(scene.load.factors().last().copied().unwrap_or(1.0));
        notes.push(format!(
            "the crack did not run by the last load factor {last} (extension {extension:.4e} m): no initiation load"
        ));
    }
    if let Some(first) = unsettled.first() {
        notes.push(format!(
            "{} load step(s) used up their break-and-re-solve rounds with bonds still breaking \
             or a refinement not yet solved (first at load factor {}): the ramp went on from \
             a state that was not an equilibrium there",
            unsettled.len(),
            round12(*first)
        ));
    }
}

/// Damage past which a node counts in [`damaged_throughout_note`].
pub const THROUGHOUT_DAMAGE: f64 = 0.4;
/// Share of the body's volume past [`THROUGHOUT_DAMAGE`] from which an initiation ramp's
/// damage is no crack from its tips but the body broken throughout. A crack across the
/// body damages about two node rows of it (0.1 % of the nodes of `pd_edge_crack`'s 200 x
/// 200 plate at its initiation); a load far past the bonds' strength, 99.7 % (its 50 x 50
/// plate at G_c = 1e-6 J/m^2).
pub const THROUGHOUT_SHARE: f64 = 0.25;

/// The note of an initiation ramp that broke the body throughout: more than
/// [`THROUGHOUT_SHARE`] of its volume (per node, `volume`) past [`THROUGHOUT_DAMAGE`] at the
/// end (`phi`). The kink angles then measure scattered damage and are left out (the caller
/// drops them when this returns a note).
pub fn damaged_throughout_note(phi: &[f64], volume: impl Fn(usize) -> f64) -> Option<String> {
    let (mut all, mut damaged) = (0.0, 0.0);
    for (k, &d) in phi.iter().enumerate() {
        let v = volume(k);
        all += v;
        if d > THROUGHOUT_DAMAGE {
            damaged += v;
        }
    }
    let share = damaged / all;
    (share > THROUGHOUT_SHARE).then(|| {
        format!(
            "{:.1} % of the body's volume is past damage {THROUGHOUT_DAMAGE} at the end: the bonds broke throughout the body, not along a crack from its tips, so the initiation load is that of the body's breaking everywhere and the kink angles are left out; the loads far exceed the bonds' strength: start the ramp lower (load.initial), and check material.fracture.g_c or the failure law and the loads' units (Pa)",
            100.0 * share
        )
    })
}

/// The note of a stand-alone PD scene whose loads pass the bonds' strength: a step load
/// of explicit dynamics past the critical stretch
/// ([`crate::dynamic_notes::overload_note`]), a quasi-static ramp's final load far past
/// the damage onset ([`ramp_overload_note`]).
pub(crate) fn overload_notes(scene: &Scene, problem: &PdProblem, dynamic: bool) -> Vec<String> {
    let onset = problem.bond_law().damage_onset();
    if dynamic {
        let load = scene.load.factors().last().copied().unwrap_or(1.0);
        let mut notes: Vec<String> = crate::dynamic_notes::overload_note(problem, onset, load)
            .into_iter()
            .collect();
        notes.extend(free_flight_note(scene, problem));
        notes
    } else {
        ramp_overload_note(scene, onset).into_iter().collect()
    }
}

/// The note of an explicit run whose loads the free body does not balance
/// ([`crate::setup::balance::dynamic_note`]; the quasi-static runs refuse such a scene).
fn free_flight_note(scene: &Scene, problem: &PdProblem) -> Option<String> {
    let crate::scene::PdSolver::Explicit(p) = &scene.pd.as_ref()?.solver else {
        return None;
    };
    let density = scene.material.density?;
    let (mesh, bcs) = crate::setup::bem::whole_body_where_meshable(scene)?;
    let area = pdbem_pd::traction::region_area(problem);
    crate::setup::balance::dynamic_note(scene, (&mesh, &bcs), area, density, p.end_time)
        .map(|n| format!("boundary: {n}"))
}

/// Ratio of the final load's nominal strain to the bonds' damage onset from which
/// [`ramp_overload_note`] speaks: a uniform field that far past the onset breaks or
/// softens every bond along the load many times over. The shipped quasi-static PD cases
/// stay at 1.78 or below (`pd_notched_bar_adaptive`; `pd_three_point_bend` 1.01, the
/// other ramps 0.30-0.52).
pub(crate) const RAMP_OVERLOAD: f64 = 10.0;

/// `pdbem check`'s note on a stand-alone quasi-static PD scene with breaking or softening
/// bonds whose final load's nominal strain (`crate::scene::validate::strain`) is at least
/// [`RAMP_OVERLOAD`] times the bonds' damage onset `onset` (s0, or s_m of the tanh law):
/// the body then breaks or softens throughout long before that load, and ADR, which a
/// softened body's solves fall back on, crawls there (`pd_three_point_bend` with s_m =
/// 1e-5: 1617 times, not ended after 5 minutes against 81 s).
fn ramp_overload_note(scene: &Scene, onset: f64) -> Option<String> {
    let (strain, path) = crate::scene::validate::strain::nominal_strain(scene)?;
    let last = scene
        .load
        .factors()
        .into_iter()
        .map(f64::abs)
        .fold(0.0, f64::max);
    let final_strain = strain * last;
    let ratio = final_strain / onset;
    (onset.is_finite() && onset > 0.0 && ratio >= RAMP_OVERLOAD).then(|| {
        format!(
            "{path}: the final load's nominal strain {final_strain:.3e} (|load| / E, or a displacement's spread over the body's size, at load factor {last}) is {ratio:.0} times the bonds' damage onset {onset:.3e}: the body breaks or softens throughout long before that load, and the solves of a softened body crawl (ADR); lower the final load (load.step, load.count) or check the failure law (material.fracture.g_c, s_m, s_c) and the units (Pa, m)"
        )
    })
}

/// The notes on a stand-alone PD scene before it runs: [`overload_notes`] and the
/// ligaments narrower than the horizon ([`crate::setup::ligament::notes`]). `pdbem check`
/// prints them; the runs log them and keep them in `summary.json` ([`early_notes`]).
pub(crate) fn set_up_notes(scene: &Scene, problem: &PdProblem, dynamic: bool) -> Vec<String> {
    let mut notes = overload_notes(scene, problem, dynamic);
    notes.extend(crate::setup::ligament::notes(scene, problem.dx));
    notes
}

/// The notes a stand-alone PD run logs before it starts ([`set_up_notes`] of its
/// `problem`), for its summary.
pub(crate) fn early_notes(
    scene: &Scene,
    problem: &PdProblem,
    dynamic: bool,
    ctx: &RunContext,
) -> Vec<String> {
    let notes = set_up_notes(scene, problem, dynamic);
    for n in &notes {
        ctx.log(&format!("  note: {n}"));
    }
    notes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two rows of four damaged (a crack's band) in a body of eight rows: no note; six of
    /// eight: 75 % noted; weighted by volume, two damaged quarter-size children of a
    /// refined cell count as half a node.
    #[test]
    fn damage_throughout_the_body_is_noted() {
        let band: Vec<f64> = (0..32).map(|k| if k < 8 { 0.5 } else { 0.1 }).collect();
        assert!(damaged_throughout_note(&band, |_| 1.0).is_none());
        let most: Vec<f64> = (0..32).map(|k| if k < 24 { 0.9 } else { 0.0 }).collect();
        let note = damaged_throughout_note(&most, |_| 1.0).expect("a note");
        assert!(note.starts_with("75.0 % of the body's volume"), "{note}");
        // 3 coarse nodes (one damaged) and 8 children of a quarter (all damaged): 3 of 5.
        let phi = [0.9, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5];
        let note =
            damaged_throughout_note(&phi, |k| if k < 3 { 1.0 } else { 0.25 }).expect("a note");
        assert!(note.starts_with("60.0 %"), "{note}");
        assert!(damaged_throughout_note(&phi, |_| 1.0).is_some());
        assert!(damaged_throughout_note(&[0.41, 0.0, 0.0, 0.0], |_| 1.0).is_none());
    }

    /// A ramp to the final load (no initiation): a first break in the first load step
    /// makes the first-break load a bound, noted; a later first break is a result.
    #[test]
    fn a_first_break_at_the_first_load_is_noted() {
        let note = first_load_note(0.05, Some(0.05), None).expect("a note");
        assert!(
            note.contains("first load factor 0.05:")
                && note.contains("the first-break load is an upper bound"),
            "{note}"
        );
        assert!(first_load_note(0.05, Some(0.1), None).is_none());
        assert!(first_load_note(0.05, None, None).is_none());
    }

    #[test]
    fn initiation_notes_name_the_last_load_and_the_unsettled_ones() {
        let scene = Scene::load(format!(
            "{}/cases/seed004_edge_crack_initiation_displacement_cells.ron",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap();
        let mut notes = Vec::new();
        initiation_notes(&scene, Some(6.9), Some(8.1), 0.03, &[], &mut notes);
        assert!(notes.is_empty(), "{notes:?}");
        initiation_notes(&scene, Some(6.9), None, 1e-3, &[8.1, 8.2], &mut notes);
        assert_eq!(notes.len(), 2, "{notes:?}");
        // The case's ramp: 80 steps of 0.1 from 3.
        assert!(notes[0].contains("last load factor 10.9"), "{}", notes[0]);
        assert!(
            notes[1].starts_with("2 load step(s)") && notes[1].contains("load factor 8.1)"),
            "{}",
            notes[1]
        );
        // Bonds broke at the ramp's first load, 3 (a ramp start of 3 + 0 steps).
        let mut notes = Vec::new();
        initiation_notes(&scene, Some(3.0), Some(3.0), 0.03, &[], &mut notes);
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(
            notes[0].contains("first load factor 3:")
                && notes[0].contains("first-break and initiation loads are upper bounds"),
            "{}",
            notes[0]
        );
        let mut notes = Vec::new();
        initiation_notes(&scene, Some(3.0), Some(3.5), 0.03, &[], &mut notes);
        assert!(
            notes[0].contains("the first-break load is an upper bound, the true one lies below"),
            "{notes:?}"
        );
    }
}
