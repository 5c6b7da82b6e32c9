//! BEM-only growth decides whether a tip reaches the boundary by K, not by `growth.da`
//! (`pdbem_coupling::growth::bem_only::increment`): near an obstacle the increments
//! shrink (room / 3, down to da / 8) before the tip is taken onto it. Before, a tip whose
//! next increment would leave less than 1.5 da of ligament was taken onto the outline: on
//! the seed 002 shear plate (`growth_shear_edge`, BEM-only), whose crack arrests 0.32 m
//! from the clamped bottom edge with da = 0.05 and 0.1 m (no failure up to load 0.46),
//! da = 0.2, 0.5 and 1 m reported failure at loads 0.40, 0.26 and 0.16, exit code 0.

mod common_scene;

use common_scene::case;
use pdbem::runner::{run_scene, RunSummary};
use pdbem_coupling::growth::bem_only::{increment, LIGAMENT_MARGIN, MIN_INCREMENT};

fn run(da: &str) -> RunSummary {
    let mut scene = case("growth_shear_edge", &[("growth.mode", "\"BemOnly\"")]);
    scene.growth.as_mut().unwrap().da = Some(da.parse().unwrap());
    let dir = std::env::temp_dir().join(format!("pdbem-increment-{}-{da}", std::process::id()));
    let s = run_scene(&scene, &dir, true).unwrap_or_else(|e| panic!("da {da}: {e:#}"));
    let _ = std::fs::remove_dir_all(&dir);
    s
}

#[test]
fn the_increment_shrinks_near_an_obstacle_and_then_stops() {
    let da = 0.5;
    assert_eq!(increment(None, da), da);
    assert_eq!(increment(Some(10.0), da), da);
    // The full step leaves exactly the margin: shortened.
    let edge = (1.0 + LIGAMENT_MARGIN) * da;
    assert!((increment(Some(edge), da) - edge / 3.0).abs() < 1e-15);
    assert_eq!(increment(Some(edge * 1.000001), da), da);
    // Shortened increments leave two of their own, more than the margin.
    let a = increment(Some(0.6), da);
    assert!((0.6 - a) > LIGAMENT_MARGIN * a && a < da);
    // Under the smallest increment: the full da, which takes the tip onto the obstacle.
    assert_eq!(increment(Some(0.99 * 3.0 * MIN_INCREMENT * da), da), da);
    assert!((increment(Some(3.0 * MIN_INCREMENT * da), da) - MIN_INCREMENT * da).abs() < 1e-15);
}

#[test]
fn a_coarse_increment_does_not_fail_an_arrested_crack() {
    // da = 0.5 and 1 m against the arrest with fine increments: no failure within the load
    // budget, the tip still inside the plate above the clamped edge. Measured: tips at
    // (8.426, 0.243) and (8.401, 0.251); da = 0.1: (8.394, 0.324).
    for da in ["0.5", "1"] {
        let s = run(da);
        let e = &s.extra;
        assert_eq!(
            e["end_state"], "load_budget_spent",
            "da {da}: {:?}",
            s.notes
        );
        assert_eq!(e["failure"], false, "da {da}");
        assert_eq!(e["final_load"], 0.46, "da {da}");
        let tip = &e["tips_final"][0];
        assert!(tip["ended"].is_null(), "da {da}: {tip}");
        let (x, y) = (
            tip["position"][0].as_f64().unwrap(),
            tip["position"][1].as_f64().unwrap(),
        );
        // Within 0.15 m of the da = 0.1 m arrest point (8.394, 0.324).
        assert!(
            (x - 8.394).hypot(y - 0.324) < 0.15,
            "da {da}: tip at ({x}, {y})"
        );
    }
}

#[test]
fn an_approach_that_leaves_no_growth_state_takes_the_full_increment() {
    // growth_hole_edge, BEM-only: the crack passes the hole and runs to the top edge at
    // load 539. The shortened increments bring the tip to 0.37 mm (0.74 da) of the edge,
    // where the linear solution has K_I < 0 (not a growth state); the round is taken again
    // with the full da, which takes the tip onto the edge: failure at 539, as with the
    // fixed increment, and a note that says so (without the fallback: no failure, and the
    // run ended at that geometry).
    let scene = case("growth_hole_edge", &[("growth.mode", "\"BemOnly\"")]);
    let dir = std::env::temp_dir().join(format!("pdbem-increment-{}-hole", std::process::id()));
    let s = run_scene(&scene, &dir, true).unwrap_or_else(|e| panic!("{e:#}"));
    let _ = std::fs::remove_dir_all(&dir);
    let e = &s.extra;
    assert_eq!(e["end_state"], "failure", "{:?}", s.notes);
    assert_eq!(e["failure_load"], 539.0);
    assert_eq!(e["tips_final"][0]["ended"], "outline");
    assert!(
        s.notes.iter().any(
            |n| n.contains("after the shortened increments of crack.end")
                && n.contains("was not a growth state")
                && n.contains("taken with the full growth.da")
        ),
        "{:?}",
        s.notes
    );
}

#[test]
fn check_refuses_a_bem_only_scene_whose_loads_close_the_crack() {
    // The tension plate pushed instead of pulled: the run refused it at its first solve
    // (K_I < 0), exit 1, while `pdbem check` passed it.
    let shipped = format!(
        "{}/cases/growth_tension_edge.ron",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(shipped)
        .unwrap()
        .replace("mode: PdBem", "mode: BemOnly");
    let text: String = text
        .lines()
        .filter(|l| !l.contains("reference: SentTada"))
        .collect::<Vec<_>>()
        .join("\n");
    assert!(text.contains("x: Traction(1))"));
    let check = |text: &str, tag: &str| {
        let file =
            std::env::temp_dir().join(format!("pdbem-increment-{}-{tag}.ron", std::process::id()));
        std::fs::write(&file, text).unwrap();
        let r = pdbem::cli::execute(pdbem::cli::Command::Check {
            scene: file.clone(),
            plot: None,
            max_memory: None,
        });
        let _ = std::fs::remove_file(&file);
        r
    };
    check(&text, "pulled").expect("the pulled plate passes");
    // What check prints on the run's cost: the first solve, and one crossing of the 20 m x
    // 10 m plate's diagonal by its one tip in increments of the crack elements' 0.1 m.
    let scene = pdbem::scene::Scene::parse(&text, std::path::Path::new("pulled.ron")).unwrap();
    let first = pdbem::growth::bem_only::check(&scene).expect("solves");
    assert!((first.da - 0.1).abs() < 1e-12, "{first:?}");
    assert!(
        (first.increments_across - 500f64.sqrt() / 0.1).abs() < 1e-9,
        "{first:?}"
    );
    assert!(first.elements > 500 && first.seconds > 0.0, "{first:?}");
    let pushed = text.replace("x: Traction(1))", "x: Traction(-1))");
    let msg = format!("{:#}", check(&pushed, "pushed").expect_err("check refuses"));
    assert!(
        msg.contains("geometry 0: K_I = ") && msg.contains("the crack faces overlap"),
        "{msg}"
    );
}

/// BEM-only growth in an infinite plate under a constant remote stress: once critical,
/// the crack's K rises with its length and it never arrests. Before, the run hit the
/// increment cap, rolled its path back, ended with "increase growth.da" (exit 3) and noted
/// that no tip reached K_c, although the log held every increment; now the plate fails at
/// that load, with the grown paths and the initiation load.
#[test]
fn an_infinite_plate_fails_by_unstable_growth() {
    let text = r#"(
    name: "griffith_growth",
    description: "unstable growth under a constant remote stress",
    material: (E: 1e4, nu: 0.3, plane: Stress, fracture: (k_c: 5)),
    body: (outline: Infinite(syy: 1)),
    cracks: [(name: "c", center: (0, 0), angle_deg: 20, length: 2)],
    boundary: [],
    load: (initial: 3, step: 0.5, count: 3),
    growth: (mode: BemOnly, da: 0.5),
    bem: (element_size: 0.5),
    outputs: (plots: false),
)"#;
    let scene = pdbem::scene::Scene::parse(text, std::path::Path::new("griffith.ron")).unwrap();
    let dir = std::env::temp_dir().join(format!("pdbem-increment-{}-inf", std::process::id()));
    let s = run_scene(&scene, &dir, true).unwrap_or_else(|e| panic!("{e:#}"));
    let _ = std::fs::remove_dir_all(&dir);
    let e = &s.extra;
    // K_eq at load 3 (about 3 sqrt(pi) cos^2(20 deg) > 5): critical at the first load.
    assert_eq!(e["end_state"], "failure", "{:?}", s.notes);
    assert_eq!(e["failure_load"], 3.0);
    assert_eq!(e["initiation_load"], 3.0);
    assert_eq!(e["complete"], true);
    for tip in e["tips_final"].as_array().unwrap() {
        assert!(tip["extension"].as_f64().unwrap() > 2.0, "{tip}");
    }
    assert!(
        s.notes
            .iter()
            .any(|n| n.contains("unstable growth in the infinite plate")),
        "{:?}",
        s.notes
    );
    assert!(!s.notes.iter().any(|n| n.contains("no tip reached K_c")));
}
