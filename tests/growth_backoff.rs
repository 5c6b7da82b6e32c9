//! The back-off of full-PD and BEM-only load steps and the honest end of a run whose step
//! no try solves (issue 18 item 2; PD-BEM's is in `growth_resume.rs`). Failures are
//! injected by the runner's test hook `fail_tries` (the first n tries of step k fail as a
//! solver failure does); the scenes are small (about a second each).

use std::path::{Path, PathBuf};

use pdbem::runner::{run_scene_with, RunOptions, RunSummary};
use pdbem::scene::Scene;
use serde_json::Value;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdbem-backoff-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn inline(src: &str) -> Scene {
    Scene::from_ron_str(src, "inline.ron").unwrap_or_else(|e| panic!("{e}"))
}

/// Edge crack 10 mm in a 40 mm square plate, full PD at dx = 1 mm, three load steps
/// below the first broken bond (5.5 MPa): linear steps, so a retry repeats the solve.
fn full_pd() -> Scene {
    inline(
        r#"(
        name: "edge_coarse",
        material: (E: 30e9, nu: 0.3333333333333333, plane: Stress, fracture: (g_c: 110)),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 0.04, height: 0.04)),
        cracks: [(name: "crack", start: (0, 0.02), angle_deg: 0, length: 0.01)],
        boundary: [(on: "top", y: Traction(1e6)), (on: "bottom", y: Traction(-1e6))],
        load: (initial: 4, step: 0.25, count: 3),
        bem: (element_size: 0.001),
        pd: (failure: FromGc),
        coupling: (side: 0.004, n: 4),
        growth: (mode: FullPd),
    )"#,
    )
}

/// SENT plate, BEM-only: no growth at 5.3 and 5.4, the crack runs through at 5.5.
fn bem_only() -> Scene {
    inline(
        r#"(
        name: "sent_growth",
        material: (E: 70e9, nu: 0.3, plane: Strain, fracture: (g_c: 1000)),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 1, height: 4)),
        cracks: [(name: "crack", start: (0, 2), angle_deg: 0, length: 0.3)],
        boundary: [(on: "top", y: Traction(1e6)), (on: "bottom", y: Traction(-1e6))],
        load: (initial: 5.3, step: 0.1, count: 4),
        bem: (element_size: 0.05),
        growth: (mode: BemOnly, da: 0.1),
    )"#,
    )
}

fn run(scene: &Scene, dir: &Path, fail_tries: Option<(usize, usize)>) -> RunSummary {
    let options = RunOptions {
        quiet: true,
        fail_tries,
        ..Default::default()
    };
    run_scene_with(scene, dir, &options).unwrap_or_else(|e| panic!("{e:#}"))
}

fn read(dir: &Path, f: &str) -> String {
    std::fs::read_to_string(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"))
}

/// The `message` of every `note` event of the run log.
fn notes(dir: &Path) -> Vec<String> {
    read(dir, "growth_log.jsonl")
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).expect("json line"))
        .filter(|e| e["event"] == "note")
        .map(|e| e["message"].as_str().unwrap_or("").to_string())
        .collect()
}

/// Columns `step,load,cmod` of `steps.csv`.
fn steps(dir: &Path) -> Vec<String> {
    read(dir, "steps.csv")
        .lines()
        .map(|l| l.split(',').take(3).collect::<Vec<_>>().join(","))
        .collect()
}

fn summary(dir: &Path) -> Value {
    serde_json::from_str(&read(dir, "summary.json")).expect("summary")
}

#[test]
fn a_full_pd_step_that_fails_is_retried_with_larger_budgets_then_half_the_increment() {
    let scene = full_pd();
    let plain = scratch("pd-plain");
    run(&scene, &plain, None);
    // One failed try: the second (5 x the budgets) solves step 1; two: the third (also
    // half the load increment, 4.125 then 4.25) does. The records are those of the run
    // without failures: a linear step, same start state, same solvers.
    for (n, label) in [
        (
            1,
            "retry 1 with 5 times the chord, Newton and ADR iteration budgets",
        ),
        (
            2,
            "retry 2 with 5 times the budgets and half the load increment",
        ),
    ] {
        let dir = scratch(&format!("pd-retry{n}"));
        let s = run(&scene, &dir, Some((1, n)));
        assert!(s.incomplete().is_none(), "{:?}", s.incomplete());
        assert_eq!(summary(&dir)["complete"], Value::Bool(true));
        let notes = notes(&dir);
        assert!(
            notes
                .iter()
                .any(|m| m.contains(&format!("step 1 (load 4.25): {label}"))),
            "{notes:?}"
        );
        assert_eq!(notes.iter().filter(|m| m.contains("retry")).count(), n);
        if n == 1 {
            assert_eq!(steps(&dir), steps(&plain));
        } else {
            // The split step ends at the same load; its CMOD agrees to solver tolerance.
            let (a, b) = (steps(&dir), steps(&plain));
            assert_eq!(a.len(), b.len());
            let cmod = |r: &str| r.split(',').nth(2).unwrap().parse::<f64>().unwrap();
            for (x, y) in a[1..].iter().zip(&b[1..]) {
                assert!((cmod(x) / cmod(y) - 1.0).abs() < 1e-6, "{x} vs {y}");
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    let _ = std::fs::remove_dir_all(&plain);
}

#[test]
fn a_full_pd_step_no_try_solves_ends_the_run_with_the_completed_steps() {
    let dir = scratch("pd-end");
    let s = run(&full_pd(), &dir, Some((1, 3)));
    let reason = s.incomplete().expect("incomplete").to_string();
    for tried in [
        "load step 1 (load factor 4.25): no equilibrium before any bond broke; tried",
        "the scene's budgets: ",
        "5 times the chord, Newton and ADR iteration budgets: ",
        "5 times the budgets and half the load increment: ",
    ] {
        assert!(reason.contains(tried), "{tried} missing: {reason}");
    }
    let sm = summary(&dir);
    assert_eq!(sm["complete"], Value::Bool(false));
    assert_eq!(sm["failure_reason"].as_str(), Some(reason.as_str()));
    assert_eq!(sm["failure"], Value::Bool(false));
    // Step 0 is kept: header and one row.
    assert_eq!(steps(&dir).len(), 2, "{:?}", steps(&dir));
    for f in [
        "growth.json",
        "growth_log.jsonl",
        "paths.png",
        "sif_path.csv",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    assert!(!dir.join(".pdbem-checkpoint.ron").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_bem_only_geometry_that_cannot_be_solved_ends_the_run_without_retry() {
    // Step 2 (load 5.5) grows the crack; its re-meshed geometry fails. Steps 0 and 1
    // stand, the front and history go back to their end.
    let dir = scratch("bem-end");
    let s = run(&bem_only(), &dir, Some((2, 1)));
    let reason = s.incomplete().expect("incomplete").to_string();
    assert!(
        reason.starts_with("step 2 (load 5.5): geometry 1 could not be meshed or solved")
            && reason.contains("no retry applies"),
        "{reason}"
    );
    let sm = summary(&dir);
    assert_eq!(sm["complete"], Value::Bool(false));
    assert_eq!(sm["failure"], Value::Bool(false));
    assert_eq!(steps(&dir).len(), 3, "{:?}", steps(&dir));
    let growth: Value = serde_json::from_str(&read(&dir, "growth.json")).expect("json");
    // The path is that of step 1: the initial tip only.
    let points = growth["paths"][0]["points"].as_array().expect("points");
    assert_eq!(points.len(), 1, "{points:?}");
    // The crack did reach K_c at 5.5: that stays its initiation load (before, it went back
    // with the path, and a note said no tip reached K_c).
    assert_eq!(sm["initiation_load"], 5.5);
    assert!(!notes(&dir).iter().any(|n| n.contains("no tip reached K_c")));
    assert!(dir.join("paths.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The seed 002 tension plate at half size (10 m x 5 m, a 1 m edge crack pulled at the
/// right edge), full PD at dx = 1/3 m with horizon factor `m`, one load step at 3.3.
fn half_tension_plate(m: f64) -> Scene {
    inline(&format!(
        r#"(
        name: "half_tension_plate",
        material: (E: 1e3, nu: 0.3333333333333333, plane: Stress, fracture: (g_c: 0.08637338761597162)),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 10, height: 5)),
        cracks: [(name: "crack", start: (5, 5), angle_deg: -90, length: 1)],
        boundary: [
            (on: "left", x: Displacement(0), y: Displacement(0)),
            (on: "right", x: Traction(1)),
        ],
        load: (initial: 3.3, step: 0.05, count: 1),
        pd: (horizon_factor: {m}, failure: CriticalStretch(0.02)),
        coupling: (side: 2, n: 6),
        growth: (mode: FullPd),
    )"#
    ))
}

#[test]
fn a_full_pd_body_torn_at_its_loaded_edge_says_so() {
    // Horizon factor 6: the rows by the pulled edge (no surface correction) break before
    // the crack moves and the body comes apart there (seed 002's plate at full size: the
    // same at load 3.3). The failure is the model's, but it is not the crack's: a note
    // names the damaged nodes by the loaded edge.
    let dir = scratch("torn");
    let s = run(&half_tension_plate(6.0), &dir, None);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        s.notes
            .iter()
            .any(|n| n.contains("lie within a horizon of the traction-loaded edges")),
        "{:?}",
        s.notes
    );
    assert!(s.notes.iter().any(|n| n.starts_with("failure at load 3.3")));
    // The default horizon factor holds the edge (and the crack, at this load): no note.
    let dir = scratch("held");
    let s = run(&half_tension_plate(3.015), &dir, None);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        !s.notes.iter().any(|n| n.contains("traction-loaded edges")),
        "{:?}",
        s.notes
    );
}
