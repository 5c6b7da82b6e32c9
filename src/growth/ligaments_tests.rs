//! Tests of the thin-ligament note on grown paths.
use std::path::Path;

use super::*;
use crate::growth::{PathPoint, StepRecord};

/// A 2 m x 1 m plate with an edge crack `c` from the left edge at height `y`, `length`
/// long, along x.
fn plate(y: f64, length: f64) -> Scene {
    let text = format!(
        r#"(
    name: "strip",
    description: "a crack grown along the top edge",
    material: (E: 1e4, nu: 0.3, plane: Stress, fracture: (g_c: 1)),
    body: (outline: Rectangle(x0: 0, y0: 0, width: 2, height: 1)),
    cracks: [(name: "c", start: (0, {y}), angle_deg: 0, length: {length})],
    boundary: [
        (on: "top", y: Traction(1)),
        (on: "bottom", y: Traction(-1)),
    ],
    load: (initial: 1, step: 1, count: 20),
    growth: (mode: BemOnly, da: 0.05),
)"#
    );
    Scene::parse(&text, Path::new("strip.ron")).expect("parses")
}

/// A history whose tip `c.end` reaches `points[k]` in step k + 1 (load k + 2).
fn history(points: &[(f64, f64)], start: (f64, f64)) -> GrowthHistory {
    let pp = |(x, y): (f64, f64), step: usize| PathPoint {
        x,
        y,
        step,
        load: step as f64 + 1.0,
    };
    let mut path = vec![pp(start, 0)];
    path.extend(points.iter().enumerate().map(|(k, &p)| pp(p, k + 1)));
    GrowthHistory {
        mode: "bem-only".into(),
        paths: vec![TipPath {
            name: "c.end".into(),
            points: path,
            ended: None,
        }],
        steps: (0..=points.len())
            .map(|k| StepRecord {
                step: k,
                load: k as f64 + 1.0,
                ..Default::default()
            })
            .collect(),
        ..Default::default()
    }
}

/// The crack 0.03 m under the top edge grows along it by 0.05 m a step: at 0.15 m
/// (step 2) it is 5 times as long as the strip is thick, past the limit of 4; at 0.55 m
/// (step 10) 18 times. The note names both; the BEM-only note names the kinks.
#[test]
fn a_crack_grown_along_an_edge_gets_the_note_from_the_step_it_is_slender() {
    let scene = plate(0.97, 0.05);
    let pts: Vec<(f64, f64)> = (1..=10).map(|k| (0.05 + 0.05 * k as f64, 0.97)).collect();
    let h = history(&pts, (0.05, 0.97));
    let found = notes(&scene, &h);
    assert_eq!(found.len(), 1, "{found:?}");
    let n = &found[0];
    assert!(
        n.contains("at step 2 (load 3) cracks.0 ('c') runs 1.500e-1 m"),
        "{n}"
    );
    assert!(n.contains("'top' at 3.000e-2 m"), "{n}");
    assert!(n.contains("a strip 5 times"), "{n}");
    assert!(n.contains("the most slender: at step 10 (load 11)"), "{n}");
    assert!(n.contains("a strip 18 times"), "{n}");
    assert!(n.contains("from step 2 on"), "{n}");
    assert!(n.contains("kinks and critical loads"), "{n}");
    assert!(
        n.contains("take K along this part of the path as unknown"),
        "{n}"
    );
    // Up to step 1 the strip is 0.10 / 0.03 = 3.3 times as long as thick: no note.
    let h1 = history(&pts[..1], (0.05, 0.97));
    assert!(notes(&scene, &h1).is_empty());
    // Up to step 4, 8.3 times: elements of 1/64 of the thickness resolve it.
    let h4 = notes(&scene, &history(&pts[..4], (0.05, 0.97)));
    assert!(h4[0].contains("a strip 8 times"), "{}", h4[0]);
    assert!(h4[0].contains("bem.group_sizes.c: 4.688e-4"), "{}", h4[0]);
}

/// A crack that grows away from the edge forms no strip; one already slender at the
/// start (the run's ordinary note) is not noted again while it gets no more slender than
/// the turn allowance.
#[test]
fn paths_away_from_boundaries_and_initial_ligaments_get_no_grown_note() {
    let down: Vec<(f64, f64)> = (1..=10).map(|k| (0.5, 0.97 - 0.05 * k as f64)).collect();
    let start = (0.5, 0.97);
    let long = plate(0.97, 0.5);
    assert!(!crate::runner::plausibility::thin_ligaments(&long).is_empty());
    assert!(notes(&long, &history(&down, start)).is_empty());
    let deep = plate(0.5, 0.5);
    let away: Vec<(f64, f64)> = (1..=10).map(|k| (0.5 + 0.05 * k as f64, 0.5)).collect();
    assert!(notes(&deep, &history(&away, start)).is_empty());
    // The long crack (16.7 times as long as thick) growing on along the edge: 18.3 times
    // at step 1, within the allowance; 20 at step 2, past it.
    let on: Vec<(f64, f64)> = (1..=4).map(|k| (0.5 + 0.05 * k as f64, 0.97)).collect();
    let n = notes(&long, &history(&on, start));
    assert_eq!(n.len(), 1, "{n:?}");
    assert!(n[0].contains("at step 2 (load 3)"), "{}", n[0]);
}

/// The geometry of a step puts the path points of steps up to it on the crack's ends.
#[test]
fn the_geometry_of_a_step_holds_the_path_so_far() {
    let scene = plate(0.5, 0.5);
    let geo0 = SceneGeometry::of(&scene);
    let pts = [(0.6, 0.5), (0.7, 0.52)];
    let h = history(&pts, (0.5, 0.5));
    let at = |k| geometry_at(&geo0, &h.paths, k).cracks[0].points.clone();
    assert_eq!(at(0), geo0.cracks[0].points);
    assert_eq!(at(1).last(), Some(&P2::new(0.6, 0.5)));
    assert_eq!(at(2).len(), geo0.cracks[0].points.len() + 2);
    assert_eq!(at(2).last(), Some(&P2::new(0.7, 0.52)));
}
