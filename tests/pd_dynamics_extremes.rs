//! Explicit dynamics (`pd.solver: Explicit`) at odd settings: `pdbem check` refuses what
//! the run would (the grid's own stable step, a step past the end time, a velocity box
//! without a node), the automatic step ends the run on `end_time`, and a free body whose
//! loads do not balance is noted and moves as Newton's second law says.
//!
//! The plate: 20 x 10 mm, state-based, dx = 0.5 mm (800 nodes), a 5 mm edge crack at
//! mid-height, 4 MPa held on the top and bottom edges, seed 004's Table 4 concrete.

use std::path::Path;

use pdbem::runner::run_scene;
use pdbem::scene::Scene;

const PLATE: &str = r#"(
    name: "dyn_plate",
    material: (E: 32e9, nu: 0.2, plane: Stress, thickness: 0.001, density: 2450, fracture: (g_c: 3)),
    body: (outline: Rectangle(x0: 0, y0: 0, width: 0.02, height: 0.01)),
    cracks: [(name: "crack", start: (0, 0.005), angle_deg: 0, length: 0.005)],
    boundary: [
        (on: "top", y: Traction(4e6)),
        (on: "bottom", y: Traction(-4e6)),
    ],
    pd: (dx: 0.0005, model: StateBased, failure: FromGc, solver: SOLVER),
)"#;

fn plate(solver: &str) -> Scene {
    let text = PLATE.replace("SOLVER", solver);
    Scene::from_ron_str(&text, Path::new("dyn.ron")).unwrap_or_else(|e| panic!("{e}"))
}

fn temp(tag: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("pdbem_dyn_extreme_{tag}_{}", std::process::id()))
}

/// The check's error (patch bound and work, then the grid the run builds) or `None`.
fn check_error(scene: &Scene) -> Option<String> {
    pdbem::setup::estimate::check(scene)
        .and_then(|_| pdbem::setup::footprint::of(scene).map(|_| ()))
        .err()
        .map(|e| format!("{e:#}"))
}

/// The run's error, no run folder left behind.
fn run_error(scene: &Scene, tag: &str) -> String {
    let dir = temp(tag);
    let e = run_scene(scene, &dir, true).expect_err("refused");
    assert!(!dir.exists(), "{tag}: no half-written run folder");
    format!("{e:#}")
}

/// Before, each passed `check` and failed (or ran wrongly) at run time. The stable step of
/// this grid is 1.78996e-7 s (the nodes by the crack tip and the corners bound it), the
/// patch of 8 horizons that `check` sized the run with gives 1.7914e-7 s: a step between
/// them passed `check` and was refused by the run. A step longer than `end_time` ran one
/// step past it (end_time 1e-12 s: 1e-8 s simulated); the scene is refused now. A box of
/// `velocities` between the nodes (or between adaptive dynamics' particles) was refused
/// only when the run started.
#[test]
fn check_refuses_what_the_run_refuses() {
    let between = plate("Explicit(end_time: 5e-6, dt: Some(1.7905e-7))");
    pdbem::setup::estimate::check(&between).expect("below the patch's bound");
    let e = check_error(&between).expect("above the grid's bound");
    assert!(
        e.contains("pd.solver: invalid input `dt`: time step 1.7905e-7 s exceeds the stable step dt_c = 1.7900e-7 s"),
        "{e}"
    );
    assert_eq!(run_error(&between, "between"), e);

    let past = PLATE.replace("SOLVER", "Explicit(end_time: 1e-12, dt: Some(1e-8))");
    let e = format!(
        "{}",
        Scene::from_ron_str(&past, Path::new("dyn.ron")).expect_err("a step past the end")
    );
    assert!(
        e.contains("pd.solver.dt = 0.00000001: the time step exceeds end_time = 0.000000000001"),
        "{e}"
    );

    // Nodes sit at (i + 1/2) dx: the box lies between four of them.
    let empty = plate(
        "Explicit(end_time: 5e-6, dt: Some(1e-8), velocities: [(min: (0.0101, 0.0051), max: (0.0102, 0.0052), velocity: (1, 0))])",
    );
    let e = check_error(&empty).expect("an empty box");
    assert!(
        e.contains("invalid input `velocities[0].region`: holds no node of the body"),
        "{e}"
    );
    assert_eq!(run_error(&empty, "empty"), e);
    // The same box with adaptive refinement: its particles at the start.
    let text = PLATE
        .replace(
            "failure: FromGc,",
            "failure: FromGc, refinement: (critical_damage: 0.4, strain_factor: 0.5),",
        )
        .replace(
            "SOLVER",
            "Explicit(end_time: 5e-6, dt: Some(1e-8), velocities: [(min: (0.0101, 0.0051), max: (0.0102, 0.0052), velocity: (1, 0))])",
        );
    let refined = Scene::from_ron_str(&text, Path::new("dyn.ron")).unwrap();
    let e = check_error(&refined).expect("an empty box among the particles");
    assert!(
        e.contains("adaptive dynamics: invalid input `velocities[0].region`: holds no node"),
        "{e}"
    );
    assert_eq!(run_error(&refined, "empty_refined"), e);

    assert_eq!(
        check_error(&plate("Explicit(end_time: 5e-6, dt: Some(1.7899e-7))")),
        None,
        "at the grid's bound"
    );
}

/// Without `dt` the step is the largest of at most 0.8 dt_c that divides `end_time`:
/// 3.3 us is 23.04 steps of 0.8 dt_c, so 24 steps of 1.375e-7 s end on it (before: 24
/// steps of 0.8 dt_c ended at 3.44 us). A density of 1e12 kg/m^3 (dt_c = 3.6 ms) against
/// 5 us: one step of 5 us (before: one step of 2.9 ms, 580 times the time asked for).
#[test]
fn the_automatic_step_ends_the_run_on_end_time() {
    for (solver, heavy, end, steps) in [
        ("Explicit(end_time: 3.3e-6)", false, 3.3e-6, 24),
        ("Explicit(end_time: 5e-6)", true, 5e-6, 1),
    ] {
        let mut scene = plate(solver);
        if heavy {
            scene.material.density = Some(1e12);
        }
        let dir = temp(&format!("auto{steps}"));
        let s = run_scene(&scene, &dir, true).unwrap_or_else(|e| panic!("{e:#}"));
        let _ = std::fs::remove_dir_all(&dir);
        let d = &s.extra["dynamics"];
        let f = |k: &str| d[k].as_f64().unwrap();
        assert_eq!(d["steps"].as_u64(), Some(steps), "{d}");
        assert!((f("end_time_s") - end).abs() < 1e-12 * end, "{d}");
        assert!(f("dt_s") <= 0.8 * f("dt_c_s"), "{d}");
    }
}

/// The plate loaded on its top edge only, nothing holding it: the loads' resultant 4 MPa x
/// 20 mm = 8e4 N/m accelerates its 0.49 kg/m at 1.633e5 m/s^2. Before, `check` said nothing
/// and the run ended with "the body is cut apart: ... 1 of its 1 pieces". Now `check` and the
/// summary give the resultant, the acceleration and the rigid displacement a T^2 / 2 by the
/// end, and the run's end note says the body moves as a whole. Velocity Verlet conserves
/// the discrete momentum (the bond forces cancel in pairs, broken or not), so the nodes'
/// mean displacement is exactly F T^2 / (2 m): asserted to 1e-9. The balanced plate gets
/// no such note.
#[test]
fn a_free_body_under_unbalanced_loads_is_noted_and_moves_as_newton_says() {
    let solver = "Explicit(end_time: 5e-6, dt: Some(1e-8))";
    let balanced = pdbem::setup::footprint::of(&plate(solver)).expect("footprint");
    assert!(
        !balanced.notes.iter().any(|n| n.contains("out of balance")),
        "{:?}",
        balanced.notes
    );
    let text = PLATE
        .replace("SOLVER", solver)
        .replace(r#"(on: "bottom", y: Traction(-4e6)),"#, "");
    let scene = Scene::from_ron_str(&text, Path::new("dyn.ron")).unwrap();
    let notes = pdbem::setup::footprint::of(&scene)
        .expect("a note, not an error")
        .notes;
    let note = notes
        .iter()
        .find(|n| n.starts_with("boundary: the prescribed tractions (on top) are out of balance"))
        .unwrap_or_else(|| panic!("{notes:?}"));
    for part in [
        "Fy = 8.000000e4 N/m",
        "at up to 1.633e5 m/s^2, a rigid displacement of up to 2.041e-6 m by end_time",
        "Explicit dynamics runs the body as it is",
    ] {
        assert!(note.contains(part), "{part}: {note}");
    }
    let dir = temp("free");
    let s = run_scene(&scene, &dir, true).unwrap_or_else(|e| panic!("{e:#}"));
    let nodes = std::fs::read_to_string(dir.join("nodes.csv")).expect("nodes.csv");
    let _ = std::fs::remove_dir_all(&dir);
    assert!(s.notes.contains(note), "{:?}", s.notes);
    assert!(
        s.notes.iter().any(|n| n
            .starts_with("the loads on the body do not balance: at the end it carries 100.0 %")),
        "{:?}",
        s.notes
    );
    assert!(
        !s.notes.iter().any(|n| n.contains("cut apart")),
        "{:?}",
        s.notes
    );
    let uy: Vec<f64> = nodes
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(3).unwrap().parse().unwrap())
        .collect();
    assert_eq!(uy.len(), 800);
    let mean = uy.iter().sum::<f64>() / uy.len() as f64;
    let (force, mass, t) = (4e6 * 0.02, 2450.0 * 0.02 * 0.01, 5e-6);
    let expected = force * t * t / (2.0 * mass);
    assert!(
        ((mean - expected) / expected).abs() < 1e-9,
        "mean u_y {mean:.9e} m, F T^2 / 2m {expected:.9e} m"
    );
}
