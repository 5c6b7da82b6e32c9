//! The PD-BEM growth run as a mode-independent [`GrowthHistory`]: tip paths (from
//! [`Growth::tip_path`]), per-step records, window outlines (initial and after every
//! relocation), relocations, the initiation load (a tip advanced by more than one
//! horizon, as in full PD), the first overstrained step with its note, and damage
//! snapshots of the windows. The snapshots that need the scene's geometry (displacement
//! over the body) and the run log stay with the caller.

use pdbem_bem::V2;

use super::driver::Growth;
use super::history::{
    FieldSnapshot, GrowthHistory, Overstrain, PathPoint, Relocation, StepRecord, TipPath,
    WindowOutline, WindowStray,
};
use super::overstrain::Hotspot;
use super::params::GrowthParams;
use super::records::{GrowthResult, Scenario, StepResult};
use crate::setup::WindowModel;

/// Damage at the real nodes of every window (labels `damage_window<i>_step<kkk><tag>`, the step zero-padded to 3 digits).
pub fn damage_snapshots(step: usize, windows: &[WindowModel], tag: &str) -> Vec<FieldSnapshot> {
    windows
        .iter()
        .enumerate()
        .map(|(i, w)| {
            let n = w.model.n_real();
            FieldSnapshot {
                step,
                label: format!("damage_window{i}_step{step:03}{tag}"),
                points: w.model.positions()[..n].to_vec(),
                values: w.model.damage()[..n].to_vec(),
                tips: Vec::new(),
                groups: Vec::new(),
            }
        })
        .collect()
}

/// The window outlines of the initial geometry.
pub fn initial_windows<S: Scenario>(g: &Growth<'_, S>) -> Vec<WindowOutline> {
    g.tips()
        .iter()
        .map(|t| WindowOutline {
            step: 0,
            tip: t.spec.name.clone(),
            corners: corners(&g.problem().windows[t.window].window.corners()),
        })
        .collect()
}

/// Corner coordinates of a window outline.
fn corners(c: &[V2; 4]) -> [[f64; 2]; 4] {
    c.map(|p| [p.x, p.y])
}

/// Load factor of the first path point more than `distance` from its tip's initial
/// position, over all tips (None: no tip got that far).
pub fn grown_by(paths: &[TipPath], distance: f64) -> Option<f64> {
    paths
        .iter()
        .filter_map(|p| {
            let o = p.points.first()?;
            p.points
                .iter()
                .find(|q| (q.x - o.x).hypot(q.y - o.y) > distance)
                .map(|q| q.load)
        })
        .min_by(f64::total_cmp)
}

/// The history of the finished run `result` of `g`, with `windows` the outlines of the
/// initial geometry ([`initial_windows`], taken before the run) and no snapshots.
pub fn history_of<S: Scenario>(
    g: &Growth<'_, S>,
    result: &GrowthResult,
    windows: Vec<WindowOutline>,
) -> GrowthHistory {
    let paths: Vec<TipPath> = (0..g.tips().len())
        .map(|t| TipPath {
            name: g.tips()[t].spec.name.clone(),
            points: g
                .tip_path(t)
                .into_iter()
                .map(|(p, step, load)| PathPoint {
                    x: p.x,
                    y: p.y,
                    step,
                    load,
                })
                .collect(),
            ended: g.tips()[t].ended.as_ref().map(|e| e.to_string()),
        })
        .collect();
    let steps = result
        .steps
        .iter()
        .map(|s| StepRecord {
            step: s.step,
            load: s.load,
            cmod: s.cmod,
            tips: s.tips.iter().map(|p| [p.x, p.y]).collect(),
            coupling_iterations: s.iterations,
            coupling_residual: s.residual.is_finite().then_some(s.residual),
            broken_bonds: s.broken_bonds,
            wall_time_s: s.wall_s,
        })
        .collect();
    let mut outlines = windows;
    outlines.extend(result.relocations.iter().map(|r| WindowOutline {
        step: r.step,
        tip: r.tip.clone(),
        corners: corners(&r.corners),
    }));
    // Initiation as in full PD: a tip advanced by more than one horizon (the first bond
    // breaks at the sharp pre-crack tip well below the Griffith load: a note).
    let horizon = g
        .problem()
        .windows
        .first()
        .map_or(0.0, |w| w.window.delta());
    let initiation_load = grown_by(&paths, horizon);
    let mut notes = result.notes.clone();
    if let Some(f) = result.initiation_load {
        notes.push(format!("first bond broke at load {f}"));
    }
    for (t, p) in paths.iter().enumerate() {
        let added = g.join_length(t);
        if let (Some(end), true) = (&p.ended, added > horizon) {
            notes.push(format!(
                "tip {} ended at {end}: its path is continued by {added:.4e} m along its \
                 approach to reach it (the ligament left in its window)",
                p.name
            ));
        }
    }
    let overstrain = first_overstrain(&result.steps);
    if let Some(o) = &overstrain {
        notes.push(overstrain_note(o));
    }
    let stray = first_stray(&result.steps);
    if let Some(s) = &stray {
        notes.push(stray_note(s));
    }
    GrowthHistory {
        mode: "pd-bem".into(),
        paths,
        steps,
        windows: outlines,
        relocations: result
            .relocations
            .iter()
            .map(|r| Relocation {
                step: r.step,
                tip: r.tip.clone(),
                from: [r.from.x, r.from.y],
                to: [r.to.x, r.to.y],
                elements_added: r.elements_added,
                rebuild_s: r.rebuild_s,
            })
            .collect(),
        initiation_load,
        failure: result.failure.is_some(),
        failure_load: result.failure.as_ref().map(|f| f.load),
        overstrain,
        stray_damage: stray.as_ref().and_then(window_stray),
        notes,
        failure_reason: result.failure_reason.clone(),
        sif_path: Vec::new(),
        snapshots: Vec::new(),
    }
}

/// The first step whose BEM body reached the PD onset stretch away from the windows.
pub fn first_overstrain(steps: &[StepResult]) -> Option<Overstrain> {
    steps.iter().find_map(|s| {
        let h = s.overstrain.filter(Hotspot::breaks)?;
        Some(Overstrain {
            step: s.step,
            load: s.load,
            position: [h.position.x, h.position.y],
            strain: h.strain,
            onset: h.onset,
        })
    })
}

/// With [`GrowthParams::end_on_overstrain`], why the run ends after the last of `steps`
/// when that step is the first whose BEM body reached the PD onset stretch away from the
/// windows (None otherwise).
pub fn overstrain_end(params: &GrowthParams, steps: &[StepResult]) -> Option<String> {
    let (last, before) = steps.split_last()?;
    if !params.end_on_overstrain || first_overstrain(before).is_some() {
        return None;
    }
    let o = first_overstrain(std::slice::from_ref(last))?;
    Some(format!(
        "run ended at load {} (step {}): the BEM body is strained past the PD onset stretch \
         away from the windows (maximum principal strain {:.3e} >= {:.3e} one horizon inside \
         the boundary at ({:.3}, {:.3})); PD would break bonds there and may start a crack \
         that PD-BEM, growing cracks only in its windows, cannot model, so growth beyond \
         this load is not computed (check with --growth-mode full-pd, or set \
         growth.overstrain: Note to go on assuming the body stays elastic there)",
        o.load, o.step, o.strain, o.onset, o.position[0], o.position[1]
    ))
}

/// The first step after which a window held damage off the cracks it tracks
/// ([`StepResult::stray`]).
pub fn first_stray(steps: &[StepResult]) -> Option<StepResult> {
    steps.iter().find(|s| s.stray.is_some()).cloned()
}

/// The history's record of the stray damage of step `s`.
fn window_stray(s: &StepResult) -> Option<WindowStray> {
    let d = s.stray?;
    Some(WindowStray {
        step: s.step,
        load: s.load,
        window: d.window,
        position: [d.position.x, d.position.y],
        damage: d.damage,
        distance: d.distance,
        horizon: d.horizon,
    })
}

/// What the stray damage of step `s` is.
fn stray_account(s: &StepResult) -> String {
    let Some(d) = s.stray else {
        return String::new();
    };
    format!(
        "after step {} (load {}) PD window {} holds damage {:.2} at ({:.3}, {:.3}), {:.3e} m \
         ({:.1} horizons) from every crack it tracks: a second crack, which PD-BEM does not \
         follow (the tracker follows each crack from its tip, and a window move keeps only \
         the tracked path)",
        s.step,
        s.load,
        d.window,
        d.damage,
        d.position.x,
        d.position.y,
        d.distance,
        d.distance / d.horizon
    )
}

/// With [`GrowthParams::end_on_overstrain`], why the run ends after the last of `steps`
/// when that step is the first whose windows hold stray damage (None otherwise).
pub fn stray_end(params: &GrowthParams, steps: &[StepResult]) -> Option<String> {
    let (last, before) = steps.split_last()?;
    if !params.end_on_overstrain || first_stray(before).is_some() || last.stray.is_none() {
        return None;
    }
    Some(format!(
        "run ended at load {} (step {}): {}; growth beyond this load is not computed (check \
         with --growth-mode full-pd, or set growth.overstrain: Note to go on without it)",
        last.load,
        last.step,
        stray_account(last)
    ))
}

/// The note of the first step with stray damage.
pub fn stray_note(s: &StepResult) -> String {
    format!(
        "{}; results from this load on leave that crack out (check with --growth-mode full-pd)",
        stray_account(s)
    )
}

/// The note of the first overstrained step ([`GrowthHistory::overstrain`]).
pub fn overstrain_note(o: &Overstrain) -> String {
    format!(
        "from step {} (load {}) the BEM body is strained past the PD onset stretch away from \
         the windows: maximum principal strain {:.3e} >= {:.3e} one horizon inside the \
         boundary at ({:.3}, {:.3}). A full-PD model would break bonds there and may start \
         a crack that PD-BEM, growing cracks only in its windows, cannot model; results from \
         this load on assume the body stays elastic there (check with --growth-mode full-pd)",
        o.step, o.load, o.strain, o.onset, o.position[0], o.position[1]
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::fixtures::{plate_setup, step_result, PlateScenario};
    use crate::growth::params::LoadSteps;
    use crate::growth::records::StrayDamage;
    use crate::growth::Silent;

    /// A 10 m x 5 m plate clamped on its left edge and pulled along x (1 MPa times the
    /// load, E = 1 GPa), an edge crack from (10, 2.5) to (9, 2.5) along the load under its
    /// window (it does not open), a hole; bonds break at s0 = 2.5e-3. Load factors 0.5,
    /// 1, 1.5, 2: measured, the BEM body passes s0 beside the hole at 1.5 (2.71e-3), the
    /// window holds. `end` sets [`GrowthParams::end_on_overstrain`].
    fn run(end: bool) -> GrowthResult {
        // A hole of radius 0.5 m at (3, 2.5), far from the window: about three times the
        // remote strain at its top and bottom (Kirsch).
        let hole: Vec<V2> = (0..16)
            .map(|k| {
                let a = -(k as f64) * std::f64::consts::TAU / 16.0;
                V2::new(3.0 + 0.5 * a.cos(), 2.5 + 0.5 * a.sin())
            })
            .collect();
        let setup = plate_setup(
            (10.0, 5.0),
            vec![hole],
            vec![vec![V2::new(10.0, 2.5), V2::new(9.0, 2.5)]],
            Some(2.5e-3),
        );
        let loads = LoadSteps {
            initial: 0.5,
            step: 0.5,
            count: 4,
        };
        let mut params = GrowthParams::new(loads, 0.5);
        params.coupling.acceleration = crate::iteration::Acceleration::IqnIls(0.5);
        params.end_on_overstrain = end;
        let mut g = Growth::new(setup, &PlateScenario, params).expect("setup");
        g.run(&mut Silent).expect("run")
    }

    #[test]
    fn a_run_ends_at_the_first_step_whose_bem_body_passes_the_pd_onset() {
        let noted = run(false);
        let o = first_overstrain(&noted.steps).expect("the clamped corners overstrain");
        assert!(noted.failure_reason.is_none());
        assert!(
            noted.steps.len() > o.step + 1,
            "{} steps",
            noted.steps.len()
        );
        let ended = run(true);
        assert_eq!(ended.steps.len(), o.step + 1);
        for (a, b) in ended.steps.iter().zip(&noted.steps) {
            assert_eq!(
                (a.load, a.broken_bonds, &a.tips),
                (b.load, b.broken_bonds, &b.tips)
            );
        }
        let reason = ended.failure_reason.expect("ended");
        assert!(
            reason.starts_with(&format!("run ended at load {} (step {})", o.load, o.step)),
            "{reason}"
        );
        let params = GrowthParams::new(
            LoadSteps {
                initial: 1.0,
                step: 1.0,
                count: 4,
            },
            0.5,
        );
        // The rule itself: only with the switch, only at the first overstrained step.
        assert!(overstrain_end(&params, &ended.steps).is_none());
        let on = GrowthParams {
            end_on_overstrain: true,
            ..params
        };
        assert!(overstrain_end(&on, &ended.steps).is_some());
        assert!(overstrain_end(&on, &noted.steps).is_none());
    }

    #[test]
    fn the_run_goes_on_with_the_other_tips_after_one_ran_into_a_hole() {
        // The crack and hole of `driver::ends`' hole test in a 10 m x 8 m plate, with a
        // second edge crack from the right edge along the load at y = 7.5 m (it hardly
        // opens; at y = 6.5 m the ligament over the joined hole bends it up into its
        // window's no-fail band, 99 pairs up to 2.6 s0, and once the driver follows it
        // there it reaches the top edge in step 1). Measured: the first tip runs into the hole in step 0 and ends there; its
        // crack is joined to the hole (BEM geometry and reported path) and the run goes
        // on through every load step with the second tip on the joined body. (In the
        // 5 m high plate of the ends test the joined crack leaves a 1.2 m ligament over
        // the hole; a second crack in that ligament then broke bonds in every coupling
        // round and the step did not converge within the back-offs.)
        let hole: Vec<V2> = (0..16)
            .map(|k| {
                let a = -(k as f64) * std::f64::consts::TAU / 16.0;
                V2::new(5.0 + 0.5 * a.cos(), 3.3 + 0.5 * a.sin())
            })
            .collect();
        let hole_poly = hole.clone();
        let setup = plate_setup(
            (10.0, 8.0),
            vec![hole],
            vec![
                vec![V2::new(5.0, 0.0), V2::new(5.0, 1.5)],
                vec![V2::new(10.0, 7.5), V2::new(9.0, 7.5)],
            ],
            Some(3e-3),
        );
        let loads = LoadSteps {
            initial: 1.0,
            step: 0.25,
            count: 3,
        };
        let mut params = GrowthParams::new(loads, 0.5);
        params.coupling.acceleration = crate::iteration::Acceleration::IqnIls(0.5);
        let mut g = Growth::new(setup, &PlateScenario, params).expect("setup");
        let out = g.run(&mut Silent).expect("run");
        use crate::growth::tips::TipEnd;
        assert_eq!(
            g.tips()[0].ended,
            Some(TipEnd::Hole("hole0".into())),
            "{:#?}",
            out.notes
        );
        assert_eq!(g.tips()[1].ended, None, "{:?}", out.notes);
        assert!(out.failure.is_none() && out.failure_reason.is_none());
        assert_eq!(out.steps.len(), 3, "{:?}", out.notes);
        // The reported path of the first tip ends on the hole edge.
        let h = history_of(&g, &out, Vec::new());
        let p = h.paths[0].points.last().expect("path");
        let end = V2::new(p.x, p.y);
        assert!(
            pdbem_geometry::polygon_distance(&end, &hole_poly) < 1e-9,
            "{end:?}"
        );
        // The BEM geometry of the later steps is joined: the crack `c0.end.hole` runs
        // from the window side to that same point on the hole rim, where the hole's
        // boundary is split (a hole element ends there) and which is not a tip.
        let mesh = &g.problem().mesh;
        let joined = mesh
            .cracks
            .iter()
            .find(|c| c.name == crate::growth::driver::join_name("c0.end"))
            .expect("joining crack in the mesh");
        assert!(!joined.start_is_tip && !joined.end_is_tip);
        let rim = *joined.points.last().expect("points");
        assert!((rim - end).norm() < 1e-9, "{rim:?} vs {end:?}");
        let hole_group = mesh.group("hole0").expect("hole group");
        let faces = joined.upper.iter().chain(&joined.lower);
        let reach = faces
            .flat_map(|&e| [mesh.elements[e].a, mesh.elements[e].b])
            .map(|q| pdbem_geometry::polygon_distance(&q, &hole_poly))
            .fold(f64::INFINITY, f64::min);
        assert!(reach < 1e-9, "crack faces {reach:.3e} m from the hole rim");
        let split = mesh
            .group_elements(hole_group)
            .any(|e| (mesh.elements[e].a - rim).norm() < 1e-9);
        assert!(split, "no hole element ends at the junction");
        // No tip at the hole: the mesh's tips are c1's (and none of c0 beyond its window).
        assert!(mesh.tips().iter().all(|t| (t.2 - rim).norm() > 1e-6));
        // The joining happened before the last steps, which solved the joined body.
        assert!(
            out.notes.iter().all(|n| !n.contains("every tip ended")),
            "{:?}",
            out.notes
        );
    }

    /// The stray-damage end: only after the first step with stray damage, and only when
    /// the run ends on such findings ([`GrowthParams::end_on_overstrain`]); its reason and
    /// the note name the window, the place and the distance in horizons.
    #[test]
    fn stray_damage_ends_the_run_once_and_only_when_asked() {
        let step = |k: usize, stray: bool| StepResult {
            stray: stray.then_some(StrayDamage {
                window: 1,
                position: V2::new(10.0, 0.5),
                damage: 0.45,
                distance: 0.6,
                horizon: 0.15,
            }),
            ..step_result(k, 0.1 * (k + 1) as f64)
        };
        let loads = LoadSteps {
            initial: 0.1,
            step: 0.1,
            count: 3,
        };
        let mut params = GrowthParams::new(loads, 0.5);
        params.end_on_overstrain = true;
        assert!(stray_end(&params, &[step(0, false)]).is_none());
        let steps = [step(0, false), step(1, true)];
        let reason = stray_end(&params, &steps).expect("ends at the first stray step");
        assert!(
            reason.contains("run ended at load 0.2 (step 1)"),
            "{reason}"
        );
        assert!(
            reason.contains("PD window 1 holds damage 0.45 at (10.000, 0.500)"),
            "{reason}"
        );
        assert!(reason.contains("(4.0 horizons)"), "{reason}");
        // Only the first such step ends a run (a resumed or noted run goes on).
        assert!(stray_end(&params, &[step(0, true), step(1, true)]).is_none());
        params.end_on_overstrain = false;
        assert!(stray_end(&params, &steps).is_none());
        let first = first_stray(&steps).expect("step 1");
        assert_eq!(first.step, 1);
        let note = stray_note(&first);
        assert!(
            note.contains("second crack") && note.contains("leave that crack out"),
            "{note}"
        );
        let w = window_stray(&first).expect("a record");
        assert_eq!((w.step, w.window, w.position), (1, 1, [10.0, 0.5]));
    }
}
