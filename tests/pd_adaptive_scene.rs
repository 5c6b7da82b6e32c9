//! `pd.refinement` with `pd.solver: Explicit` from a scene (adaptive dynamics,
//! `pdbem::run_adaptive`): the refused combinations name their field, and a short run of
//! seed 004's case-2 plate on a 2 mm grid refines where the damage is, records finite
//! energies and starts from the library driver's stable step.

use std::path::{Path, PathBuf};

use pdbem::runner::run_scene;
use pdbem::scene::Scene;
use pdbem_pd::cases::{branching_plate, SEED004_DENSITY};
use pdbem_pd::dynamics::ExplicitParams;
use pdbem_pd::refine::{run_dynamic, Refinement};

fn case_text(name: &str) -> String {
    let f = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name);
    std::fs::read_to_string(f).expect("case file")
}

fn parse(text: &str) -> Result<Scene, String> {
    Scene::from_ron_str(text, Path::new("adyn.ron")).map_err(|e| format!("{e}"))
}

const REFINE: &str = "refinement: (critical_damage: 0.4, strain_factor: 0.5, check_every: 10)";

/// Every adaptive case parses; the combinations that cannot run are refused with the
/// field named: a tanh law, children keeping their horizon, no check interval, alpha
/// outside (0, 1), alpha without a breaking law, and (without Explicit) a breaking law or
/// alpha on the elastic refined solve.
#[test]
fn refused_combinations_name_the_field() {
    let text = case_text("seed004_branching_case2_adaptive.ron");
    parse(&text).expect("valid");
    parse(&case_text("seed004_branching_case1_adaptive.ron")).expect("valid");
    let refused = |from: &str, to: &str, field: &str| {
        assert!(text.contains(from), "{from}");
        let e = parse(&text.replace(from, to)).expect_err(to);
        assert!(e.contains(field), "{to}: {e}");
    };
    refused(
        "failure: FromGc",
        "failure: Degradation(s_m: 1e-4, s_c: 2e-4, beta: 3)",
        "pd.failure",
    );
    refused(
        "check_every: 10)",
        "check_every: 10, keep_horizon: true)",
        "pd.refinement.keep_horizon",
    );
    refused(
        "check_every: 10",
        "check_every: 0",
        "pd.refinement.check_every",
    );
    refused(
        "strain_factor: 0.5",
        "strain_factor: 1.5",
        "pd.refinement.strain_factor",
    );
    refused(
        "failure: FromGc",
        "failure: Elastic",
        "pd.refinement.strain_factor",
    );
    let solver = "solver: Explicit(end_time: 8e-5, dt: Some(1e-8), output_every: Some(5e-7), snapshots: [2e-5, 3.5e-5, 5e-5, 8e-5]),";
    refused(solver, "", "pd.refinement");
    let e = parse(
        &text
            .replace(solver, "")
            .replace("failure: FromGc", "failure: Elastic"),
    )
    .expect_err("alpha on the elastic solve");
    assert!(e.contains("pd.refinement.strain_factor"), "{e}");
    let e = parse(&text.replace(solver, "").replace(", strain_factor: 0.5", ""))
        .expect_err("breaking law on the elastic solve");
    assert!(e.contains("pd.refinement") && e.contains("Elastic"), "{e}");
}

/// `pdbem check` bounds dt by the refined particles' stable step: the unrefined
/// particles' Gershgorin bound (2.77e-7 s at dx = 1 mm, below the uniform grid's
/// 3.58e-7 s) halved for `max_level: 1`, so dt = 2e-7 s, stable on the uniform grid, is
/// refused for the adaptive case, and the seed's 1e-8 s passes.
#[test]
fn check_bounds_dt_by_the_finest_particles() {
    let text = case_text("seed004_branching_case1_adaptive.ron");
    pdbem::setup::estimate::check(&parse(&text).unwrap()).expect("dt = 1e-8 s");
    let uniform =
        case_text("seed004_branching_case1.ron").replace("dt: Some(1e-8)", "dt: Some(2e-7)");
    pdbem::setup::estimate::check(&parse(&uniform).unwrap()).expect("stable on the grid");
    let text = text.replace("dt: Some(1e-8)", "dt: Some(2e-7)");
    let e = format!(
        "{:#}",
        pdbem::setup::estimate::check(&parse(&text).unwrap()).expect_err("too large")
    );
    assert!(
        e.contains("pd.solver.dt") && e.contains("dt_c = 1.38"),
        "{e}"
    );
}

/// Case 2 (sigma_B = 2 MPa) at dx = 2 mm for 20 us with the automatic dt: the particle
/// count grows during the run and every child particle (off the 2 mm lattice) lies within
/// one coarse horizon of a particle past phi_c = 0.4; the energy records are finite and
/// the crack dissipates; the run's stable step equals the library driver's on the same
/// plate (the scene gives the library's problem: loads, density, pre-crack, no pins),
/// and `pdbem check`'s patch bound does not refuse it.
#[test]
fn short_adaptive_run_refines_where_the_damage_is() {
    let text = case_text("seed004_branching_case2_adaptive.ron")
        .replace("dx: 0.001", "dx: 0.002")
        .replace(
            "Explicit(end_time: 8e-5, dt: Some(1e-8), output_every: Some(5e-7), snapshots: [2e-5, 3.5e-5, 5e-5, 8e-5])",
            "Explicit(end_time: 2e-5, output_every: Some(1e-6), snapshots: [2e-5])",
        );
    assert!(text.contains(REFINE));
    let scene = parse(&text).expect("valid");
    pdbem::setup::estimate::check(&scene).expect("check passes");
    let dir = std::env::temp_dir().join(format!("pdbem_adyn_scene_{}", std::process::id()));
    let s = run_scene(&scene, &dir, true).unwrap_or_else(|e| panic!("{e:#}"));
    let d = &s.extra["dynamics"];
    let p = &s.extra["particles"];
    let (start, max) = (p["start"].as_u64().unwrap(), p["max"].as_u64().unwrap());
    assert!(start >= 1000 && max > start, "{p}");
    assert!(d["final"]["fracture_J"].as_f64().unwrap() > 0.0, "{d}");
    let csv = std::fs::read_to_string(dir.join("dynamics.csv")).expect("dynamics.csv");
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect()
        })
        .collect();
    assert!(csv.lines().next().unwrap().ends_with(",particles"));
    assert!(rows.len() > 15);
    for r in &rows {
        assert!(r[1..6].iter().all(|v| v.is_finite()), "{r:?}");
    }
    let n: Vec<f64> = rows.iter().map(|r| r[10]).collect();
    assert!(
        n.windows(2).all(|w| w[1] >= w[0]) && n[n.len() - 1] as u64 == max,
        "{n:?}"
    );
    assert!(dir.join("refinements.csv").exists() && dir.join("particles.svg").exists());
    let nodes = std::fs::read_to_string(dir.join("nodes.csv")).expect("nodes.csv");
    let pts: Vec<[f64; 3]> = nodes
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[4]]
        })
        .collect();
    let dx = 0.002;
    let child = |x: f64| ((x / dx - 0.5) - (x / dx - 0.5).round()).abs() > 0.1;
    let damaged: Vec<&[f64; 3]> = pts.iter().filter(|p| p[2] > 0.4).collect();
    let children: Vec<&[f64; 3]> = pts.iter().filter(|p| child(p[0]) || child(p[1])).collect();
    assert_eq!(children.len() as u64, 4 * (pts.len() as u64 - 1000) / 3);
    for c in &children {
        let near = damaged
            .iter()
            .any(|q| (q[0] - c[0]).hypot(q[1] - c[1]) <= 3.015 * dx);
        assert!(near, "child at {c:?} far from the damage");
    }
    let case = branching_plate(dx, 2e6);
    let ex = ExplicitParams {
        density: SEED004_DENSITY,
        end_time: 1e-7,
        ..Default::default()
    };
    let refinement = Refinement {
        strain_factor: Some(0.5),
        ..Default::default()
    };
    let (_, info) = run_dynamic(&case.problem, &ex, &refinement, 10, &mut ()).unwrap();
    let dt_c = d["dt_c_s"].as_f64().unwrap();
    assert!(
        (dt_c - info.dynamics.dt_c).abs() <= 1e-12 * dt_c,
        "{dt_c} {}",
        info.dynamics.dt_c
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Case 1 with adaptive refinement at dx = 2 mm, surface-corrected, for 20 us with a
/// fracture energy 100 times the seed's too small for its 1 MPa step load: the loaded
/// layers split and tear off (400 particles, the whole load), and the summary notes it
/// and leaves the deflection angles out, as the uniform grid's run does
/// (`tests/pd_dynamics_scene.rs`).
#[test]
fn torn_loaded_layers_of_refined_particles_are_noted() {
    let text = case_text("seed004_branching_case1_adaptive.ron")
        .replace("dx: 0.001", "dx: 0.002")
        .replace("g_c: 3)", "g_c: 0.03)")
        .replace("failure: FromGc,", "failure: FromGc,\n        surface_correction: true,")
        .replace(
            "Explicit(end_time: 8e-5, dt: Some(1e-8), output_every: Some(5e-7), snapshots: [2e-5, 3.5e-5, 5e-5, 8e-5])",
            "Explicit(end_time: 2e-5, dt: Some(1e-8), output_every: Some(1e-6))",
        );
    let scene = parse(&text).expect("valid");
    let dir = std::env::temp_dir().join(format!("pdbem_adyn_torn_{}", std::process::id()));
    let s = run_scene(&scene, &dir, false).unwrap_or_else(|e| panic!("{e:#}"));
    let _ = std::fs::remove_dir_all(&dir);
    let torn: Vec<&String> = s
        .notes
        .iter()
        .filter(|n| n.starts_with("the loads tore off the layers"))
        .collect();
    assert_eq!(torn.len(), 1, "{:?}", s.notes);
    assert!(torn[0].contains("carry 100.0 %"), "{}", torn[0]);
    let angles = s.extra["deflection_deg"].as_array().unwrap();
    assert!(angles.iter().all(|a| a.is_null()), "{angles:?}");
}
