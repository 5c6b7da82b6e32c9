//! `pd.solver: Explicit` from a scene: validation (density, coupling, the stable time
//! step and the work bound) and a short end-to-end run of seed 004's branching plate on
//! a coarse grid with its outputs.

use std::path::{Path, PathBuf};

use pdbem::runner::run_scene;
use pdbem::scene::Scene;

fn case_text(name: &str) -> String {
    let f = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name);
    std::fs::read_to_string(f).expect("case file")
}

fn parse(text: &str) -> Result<Scene, String> {
    Scene::from_ron_str(text, Path::new("dyn.ron")).map_err(|e| format!("{e}"))
}

#[test]
fn missing_density_is_refused() {
    let text = case_text("seed004_branching_case1.ron").replace(" density: 2450,", "");
    let e = parse(&text).expect_err("no density");
    assert!(e.contains("material.density"), "{e}");
}

#[test]
fn explicit_with_coupling_is_refused() {
    let text = case_text("coupled_sent_a5_state_based.ron").replace(
        "pd: (model: StateBased,",
        "pd: (solver: Explicit(end_time: 1e-6), model: StateBased,",
    );
    let text = text.replace("plane: Stress)", "plane: Stress, density: 7800)");
    let e = parse(&text).expect_err("coupled dynamics");
    assert!(e.contains("pd.solver") && e.contains("stand-alone"), "{e}");
}

#[test]
fn a_step_above_the_stable_step_is_refused_at_check() {
    let ok = parse(&case_text("seed004_branching_case1.ron")).expect("valid case");
    pdbem::setup::estimate::check(&ok).expect("dt = 1e-8 s is stable at dx = 1 mm");
    let text = case_text("seed004_branching_case1.ron").replace("dt: Some(1e-8)", "dt: Some(1e-6)");
    let scene = parse(&text).expect("valid at the scene level");
    let e = format!(
        "{:#}",
        pdbem::setup::estimate::check(&scene).expect_err("unstable")
    );
    assert!(e.contains("pd.solver.dt") && e.contains("dt_c"), "{e}");
    let long = case_text("seed004_branching_case1.ron").replace("end_time: 8e-5", "end_time: 10");
    let e = format!(
        "{:#}",
        pdbem::setup::estimate::check(&parse(&long).unwrap()).unwrap_err()
    );
    assert!(e.contains("pd.solver.end_time"), "{e}");
}

/// An impact velocity strains the body by |v| / c (c = sqrt(E / rho), 4873 m/s for the
/// Kalthoff steel): from strain 1 on it is refused like a load, naming the velocity.
#[test]
fn an_impact_beyond_small_strain_is_refused() {
    let case = case_text("seed004_kalthoff_coarse.ron");
    parse(&case).expect("16.5 m/s");
    let fast = case.replace("velocity: (16.5, 0)", "velocity: (0, -5000)");
    let e = parse(&fast).expect_err("5000 m/s");
    assert!(
        e.contains("pd.solver.velocities.0.velocity = (0.0, -5000.0)")
            && e.contains("strains the body by about 1.026e0"),
        "{e}"
    );
    parse(&case.replace("velocity: (16.5, 0)", "velocity: (4800, 0)")).expect("below c");
}

/// Adaptive dynamics whose `check_every` exceeds the run's steps would never check its
/// criteria: refused at check; a short run that checks them once passes.
#[test]
fn refinement_checks_beyond_the_runs_end_are_refused_at_check() {
    let short = case_text("seed004_branching_case1_adaptive.ron")
        .replace("end_time: 8e-5", "end_time: 2e-6")
        .replace("snapshots: [2e-5, 3.5e-5, 5e-5, 8e-5]", "snapshots: []");
    let rare = short.replace("check_every: 10", "check_every: 201");
    let e = format!(
        "{:#}",
        pdbem::setup::estimate::check(&parse(&rare).expect("valid at the scene level"))
            .expect_err("never checked")
    );
    assert!(
        e.contains("pd.refinement.check_every = 201 exceeds the run's 200 time steps"),
        "{e}"
    );
    let once = short.replace("check_every: 10", "check_every: 200");
    pdbem::setup::estimate::check(&parse(&once).unwrap()).expect("checked at the last step");
}

/// The branching plate at dx = 2 mm for 30 us (automatic dt): the run writes
/// dynamics.csv with rising fracture energy, a snapshot plot, the energy plot and the
/// summary entry; the crack has started by 30 us.
#[test]
fn coarse_branching_plate_runs_from_a_scene() {
    let text = case_text("seed004_branching_case1.ron")
        .replace("dx: 0.001", "dx: 0.002")
        .replace(
            "Explicit(end_time: 8e-5, dt: Some(1e-8), output_every: Some(5e-7), snapshots: [2e-5, 3.5e-5, 5e-5, 8e-5])",
            "Explicit(end_time: 3e-5, output_every: Some(1e-6), snapshots: [2e-5])",
        );
    let scene = parse(&text).expect("valid");
    let dir = std::env::temp_dir().join(format!("pdbem_dyn_scene_{}", std::process::id()));
    let s = run_scene(&scene, &dir, true).unwrap_or_else(|e| panic!("{e:#}"));
    let d = &s.extra["dynamics"];
    assert!(d["dt_s"].as_f64().unwrap() <= d["dt_c_s"].as_f64().unwrap());
    assert!(d["steps"].as_u64().unwrap() > 10);
    let csv = std::fs::read_to_string(dir.join("dynamics.csv")).expect("dynamics.csv");
    let rows: Vec<&str> = csv.lines().collect();
    assert!(rows[0].starts_with("step,time,kinetic,strain"));
    assert!(rows.len() > 25, "{} rows", rows.len());
    assert!(d["final"]["fracture_J"].as_f64().unwrap() > 0.0);
    assert!(!d["final"]["tip"].is_null(), "the crack started");
    for f in [
        "energy.png",
        "energy_balance.png",
        "damage_t20us.png",
        "damage.png",
        "nodes.csv",
    ] {
        assert!(dir.join(f).exists(), "{f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The coarse branching plate (dx = 2 mm, surface-corrected, 20 us, dt 1e-8 s) with the
/// fracture energy `g_c` (the seed's: 3 J/m^2): its summary's notes and deflection angles.
fn run_with_g_c(g_c: &str, tag: &str) -> (Vec<String>, serde_json::Value) {
    let scene = plate_with_g_c(g_c);
    let dir = std::env::temp_dir().join(format!("pdbem_dyn_{tag}_{}", std::process::id()));
    let s = run_scene(&scene, &dir, false).unwrap_or_else(|e| panic!("{e:#}"));
    let _ = std::fs::remove_dir_all(&dir);
    (s.notes.clone(), s.extra["deflection_deg"].clone())
}

/// The scene of [`run_with_g_c`].
fn plate_with_g_c(g_c: &str) -> Scene {
    let text = case_text("seed004_branching_case1.ron")
        .replace("dx: 0.001", "dx: 0.002")
        .replace("g_c: 3)", &format!("g_c: {g_c})"))
        .replace("failure: FromGc,", "failure: FromGc,\n        surface_correction: true,")
        .replace(
            "Explicit(end_time: 8e-5, dt: Some(1e-8), output_every: Some(5e-7), snapshots: [2e-5, 3.5e-5, 5e-5, 8e-5])",
            "Explicit(end_time: 2e-5, dt: Some(1e-8), output_every: Some(1e-6))",
        );
    parse(&text).expect("valid")
}

/// `pdbem check` notes a step load past the bonds' critical stretch (|t| / E = 3.1e-5
/// against s0 = 1.4e-5 at 1/100 of the seed's G_c), not one below it (0.69 s0 at 1/10,
/// whose run cuts the plate in two, and the seed's G_c).
#[test]
fn check_notes_a_step_load_past_the_critical_stretch() {
    let notes = |g_c: &str| {
        pdbem::setup::footprint::of(&plate_with_g_c(g_c))
            .expect("footprint")
            .notes
    };
    let over = notes("0.03");
    assert!(
        over.iter().any(|n| n.starts_with(
            "pd.solver: the step load's nominal strain |t| / E = 3.125e-5 is 2.182 times"
        )),
        "{over:?}"
    );
    for g_c in ["0.3", "3"] {
        let n = notes(g_c);
        assert!(
            !n.iter().any(|n| n.contains("nominal strain")),
            "{g_c}: {n:?}"
        );
    }
}

/// A fracture energy 100 times too small for the 1 MPa step load (s0 = 1.4e-5 against
/// |t| / E = 3.1e-5): the loaded rows tear off in the first waves and fly away with the
/// whole load, the crack never grows, and the run said nothing and gave a deflection of
/// -81 degrees (the torn rows' damage in its annulus). Now the note names the torn layers
/// and the strain against s0, and the deflection is left out. At 10 times too small the
/// crack cuts the plate in two by 7 us: the pieces' note, the deflection kept. At the
/// seed's G_c, over the same 20 us: no such note.
#[test]
fn loads_the_body_cannot_hold_are_noted() {
    let (notes, angles) = run_with_g_c("0.03", "torn");
    // The check's note comes first, as the run logged it before it started.
    assert!(
        notes[0].starts_with("pd.solver: the step load's nominal strain |t| / E = 3.125e-5"),
        "{notes:?}"
    );
    let torn: Vec<&String> = notes
        .iter()
        .filter(|n| n.starts_with("the loads tore off the layers"))
        .collect();
    assert_eq!(torn.len(), 1, "{notes:?}");
    assert!(
        torn[0].contains("2 piece(s) of 100 node(s)") && torn[0].contains("carry 100.0 %"),
        "{}",
        torn[0]
    );
    assert!(
        torn[0].contains("is 2.182 times the bonds' critical stretch"),
        "{}",
        torn[0]
    );
    assert!(
        angles.as_array().unwrap().iter().all(|a| a.is_null()),
        "{angles}"
    );

    let (notes, angles) = run_with_g_c("0.3", "cut");
    assert!(
        notes.iter().any(|n| n.starts_with("the body is cut apart")),
        "{notes:?}"
    );
    assert!(
        !notes.iter().any(|n| n.starts_with("the loads tore off")),
        "{notes:?}"
    );
    assert!(angles[0].is_f64(), "{angles}");

    let (notes, _) = run_with_g_c("3", "seed");
    assert!(
        !notes
            .iter()
            .any(|n| n.contains("tore off") || n.contains("cut apart")),
        "{notes:?}"
    );
}
