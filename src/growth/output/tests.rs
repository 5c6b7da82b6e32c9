//! Tests of the growth outputs: tables, plots and snapshots.
use super::*;
use crate::growth::{PathPoint, StepRecord};

/// An empty field snapshot of `label` at `step`.
fn snap(label: &str, step: usize) -> FieldSnapshot {
    FieldSnapshot {
        step,
        label: label.into(),
        points: Vec::new(),
        values: Vec::new(),
        tips: Vec::new(),
        groups: Vec::new(),
    }
}

#[test]
fn snapshot_titles_use_the_file_names_step_numbers() {
    assert_eq!(
        snapshot_title(&snap("damage_window0_step001_reloc007", 1)),
        "damage in PD window 0, load step 1, before window relocation 7"
    );
    assert_eq!(snapshot_title(&snap("displacement", 0)), "|u|, load step 0");
}

/// The displacement field of the failure step is titled as the collapse; other steps,
/// damage fields and runs without failure are not; the load-CMOD plot starts at the
/// unloaded body and draws the failure load.
#[test]
fn the_failure_step_is_shown_as_the_collapse() {
    let step = |k: usize, cmod: Option<f64>| StepRecord {
        step: k,
        load: 3.3 + 0.05 * k as f64,
        cmod,
        ..Default::default()
    };
    let mut h = GrowthHistory {
        mode: "pd-bem".into(),
        steps: vec![step(0, Some(0.048)), step(1, None)],
        failure: true,
        failure_load: Some(3.35),
        ..Default::default()
    };
    assert!(collapse_field(&h, &snap("displacement", 1)));
    assert!(!collapse_field(&h, &snap("displacement", 0)));
    assert!(!collapse_field(&h, &snap("damage_window0_step001", 1)));
    let scene = Scene::load(format!(
        "{}/cases/growth_tension_edge.ron",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let p = load_cmod_plot(&scene, &h).expect("a step has a CMOD");
    assert_eq!(p.series[0].points, vec![(0.0, 0.0), (0.048, 3.3)]);
    assert_eq!(p.series[1].points, vec![(0.0, 3.35), (0.048, 3.35)]);
    h.failure = false;
    assert!(!collapse_field(&h, &snap("displacement", 1)));
    assert_eq!(load_cmod_plot(&scene, &h).unwrap().series.len(), 1);
}

fn pp(x: f64, y: f64, step: usize, load: f64) -> PathPoint {
    PathPoint { x, y, step, load }
}

#[test]
fn tables_have_the_documented_columns() {
    let h = GrowthHistory {
        mode: "bem-only".into(),
        paths: vec![TipPath {
            name: "c.end".into(),
            points: vec![pp(0.0, 0.0, 0, 1.0), pp(3.0, 4.0, 2, 1.2)],
            ended: Some("outline".into()),
        }],
        steps: vec![StepRecord {
            step: 0,
            load: 1.0,
            cmod: Some(1e-6),
            tips: vec![[0.0, 0.0]],
            ..Default::default()
        }],
        ..Default::default()
    };
    let p = path_table(&h.paths[0]).to_csv();
    assert!(p.starts_with("x,y,step,load\n0,0,0,1\n3,4,2,1.2\n"), "{p}");
    let s = steps_table(&h).to_csv();
    assert!(s.starts_with(
        "step,load,cmod,coupling_iterations,coupling_residual,broken_bonds,wall_time_s,c.end.x,c.end.y\n"
    ), "{s}");
    assert!((extension(&h.paths[0]) - 5.0).abs() < 1e-15);
    assert_eq!(path_file("c.end"), "path_c.end.csv");
    assert_eq!(engineering_scale([2e-5, -1e-6].into_iter()), (-6, 1e6));
    assert_eq!(engineering_scale([0.0].into_iter()), (0, 1.0));
}

#[test]
fn the_overstrain_reaches_the_summary_and_the_path_plot() {
    let scene = Scene::load(format!(
        "{}/cases/growth_shear_edge.ron",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let o = crate::growth::Overstrain {
        step: 6,
        load: 0.2,
        position: [10.05, 0.15],
        strain: 0.0219,
        onset: 0.02,
    };
    let mut h = GrowthHistory {
        mode: "pd-bem".into(),
        overstrain: Some(o),
        ..Default::default()
    };
    let summary = growth_summary(&scene, &h);
    assert_eq!(summary.extra["bem_overstrain"]["load"], 0.2);
    assert_eq!(summary.extra["bem_overstrain"]["position"][0], 10.05);
    let plot = paths_plot(&scene, &h);
    assert_eq!(plot.marks.len(), 1);
    assert_eq!(plot.marks[0].1, (10.05, 0.15));
    assert!(plot.marks[0].0.contains("load 0.2"), "{}", plot.marks[0].0);
    h.overstrain = None;
    let none = growth_summary(&scene, &h);
    assert_eq!(none.extra.get("bem_overstrain"), Some(&Value::Null));
    h.mode = "full-pd".into();
    assert!(!growth_summary(&scene, &h)
        .extra
        .contains_key("bem_overstrain"));
}

#[test]
fn snapshots_show_the_path_as_far_as_it_had_grown() {
    let pt = |y: f64, step| PathPoint {
        x: 0.0,
        y,
        step,
        load: 1.0,
    };
    let h = GrowthHistory {
        paths: vec![TipPath {
            name: "c.end".into(),
            points: vec![pt(0.0, 0), pt(1.0, 1), pt(2.0, 1), pt(3.0, 2)],
            ended: None,
        }],
        ..Default::default()
    };
    let mut s = FieldSnapshot {
        step: 1,
        label: "damage_window0_step1".into(),
        ..Default::default()
    };
    // End of step 1: the points reached by step 1, the tip at the last.
    let (paths, marks) = path_so_far(&h, &s);
    assert_eq!(paths, vec![vec![(0.0, 0.0), (0.0, 1.0), (0.0, 2.0)]]);
    assert_eq!(marks[0].0, (0.0, 2.0));
    // Before a relocation in step 1 with the tip at y = 1.1: cut at the nearest point.
    s.tips = vec![[0.0, 1.1]];
    let (paths, marks) = path_so_far(&h, &s);
    assert_eq!(paths, vec![vec![(0.0, 0.0), (0.0, 1.0), (0.0, 1.1)]]);
    assert_eq!(marks[0].0, (0.0, 1.1));
}

/// A crack that grows, or a body that fails, in the first load step gets a note: that
/// load is an upper bound. A later initiation gets none.
#[test]
fn growth_in_the_first_load_step_is_noted_as_an_upper_bound() {
    let step = |k: usize| StepRecord {
        step: k,
        load: 10.0 + 0.1 * k as f64,
        ..Default::default()
    };
    let mut h = GrowthHistory {
        mode: "bem-only".into(),
        steps: vec![step(0), step(1), step(2)],
        initiation_load: Some(10.1),
        failure: true,
        failure_load: Some(10.2),
        ..Default::default()
    };
    assert!(first_step_bounds(&h).is_empty());
    h.initiation_load = Some(10.0);
    let n = first_step_bounds(&h);
    assert_eq!(n.len(), 1, "{n:?}");
    assert!(
        n[0].starts_with("the crack grew in the first load step (load factor 10)")
            && n[0].contains("the initiation load is only an upper bound"),
        "{}",
        n[0]
    );
    h.failure_load = Some(10.0);
    let n = first_step_bounds(&h);
    assert!(
        n[0].starts_with("the crack grew and the body failed in the first load step")
            && n[0].contains("the initiation and failure loads are each only an upper bound"),
        "{}",
        n[0]
    );
    // The summary carries the note.
    let scene = Scene::load(format!(
        "{}/cases/growth_tension_edge.ron",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let s = growth_summary(&scene, &h);
    assert!(
        s.notes.iter().any(|m| m.contains("upper bound")),
        "{:?}",
        s.notes
    );
}
