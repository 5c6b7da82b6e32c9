//! A pre-crack whose ligament the PD grid cannot resolve is refused by `pdbem check` and
//! `pdbem run` with the ligament named (`setup::ligament`); a ligament the grid resolves
//! but the horizon spans is noted. Before, an edge crack 1 mm short of the far edge of a
//! 50 mm plate at dx = 2 mm failed with "implicit did not converge in 62 iterations" and
//! no reason, at any load.

use pdbem::cli::{execute, Command};
use pdbem::scene::Scene;
use pdbem_pd::solvers::implicit::{solve, ImplicitParams};
use pdbem_pd::PdModel;

/// A state-based edge-crack plate (50 x 100 mm, grid spacing `dx`) under 10 MPa, with an
/// edge crack of `length` from the middle of the left edge and `extra` scene text in `pd`.
fn plate(length: f64, dx: f64, extra: &str) -> String {
    format!(
        r#"(name: "ligament", material: (E: 200e9, nu: 0.3, plane: Stress, thickness: 0.001),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 0.05, height: 0.1)),
        cracks: [(name: "crack", start: (0, 0.05), angle_deg: 0, length: {length})],
        boundary: [(on: "top", y: Traction(10e6)), (on: "bottom", y: Traction(-10e6))],
        pd: (model: StateBased, dx: {dx}, solver: Implicit(), failure: Elastic{extra}),
        outputs: (plots: false, csv: false))"#
    )
}

fn temp(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("pdbem-ligament-{}-{name}", std::process::id()))
}

fn check(text: &str, name: &str) -> anyhow::Result<()> {
    let file = temp(name);
    std::fs::write(&file, text).unwrap();
    let r = execute(Command::Check {
        scene: file.clone(),
        plot: None,
        max_memory: None,
    });
    let _ = std::fs::remove_file(&file);
    r
}

fn scene(text: &str) -> Scene {
    Scene::from_ron_str(text, "ligament.ron").expect("valid scene")
}

/// The top edge's opening per unit load factor of the plate with its crack ending at
/// `end` on a grid of spacing `dx`, at a 1 kPa load (linear), or the solve's error.
fn opening(dx: f64, end: f64) -> Result<f64, pdbem_pd::PdError> {
    let mut problem =
        pdbem::setup::pd::problem_from_scene(&scene(&plate(0.04, dx, ""))).expect("problem");
    let tip = problem.cracks[0].len() - 1;
    problem.cracks[0][tip][0] = end;
    let mut model = PdModel::new(&problem).expect("model");
    let load = 1e-4;
    let params = ImplicitParams {
        target_load: load,
        ..Default::default()
    };
    solve(&mut model, &params)?;
    let top = model
        .displacements()
        .iter()
        .zip(model.positions())
        .filter(|(_, x)| x[1] > 0.1 - dx && x[1] < 0.1)
        .map(|(u, _)| u[1])
        .fold(f64::NEG_INFINITY, f64::max);
    Ok(top / load)
}

/// Why the rule holds: on a 2 mm grid a 1.5 mm ligament (0.75 spacings) opens more than
/// 4 times as much as on a 1 mm grid (5.6 measured), and a 1.0 mm one (0.5 spacings) has
/// no equilibrium at all, even at 1 kPa.
#[test]
fn a_ligament_under_two_grid_spacings_is_a_hinge_on_the_grid() {
    let coarse = opening(0.002, 0.0485).expect("solved");
    let fine = opening(0.001, 0.0485).expect("solved");
    assert!(coarse > 4.0 * fine, "{coarse} vs {fine}");
    let err = opening(0.002, 0.049).expect_err("a 1 mm ligament has no equilibrium");
    assert!(format!("{err}").contains("did not converge"), "{err}");
}

/// `check` and `run` refuse the 1.5 mm ligament on the 2 mm grid naming the crack, the
/// tip, the edge, the width in spacings and the spacing that resolves it; a refine zone
/// over the tip (0.5 mm there) lets it run, and dx = 0.75 mm pass `check`, each with a
/// note (3 and 2 spacings, under the horizon).
#[test]
fn an_unresolved_ligament_is_refused_and_a_resolved_one_under_the_horizon_noted() {
    let text = plate(0.0485, 0.002, "");
    for msg in [
        format!(
            "{:#}",
            check(&text, "short.ron").expect_err("check refuses")
        ),
        format!(
            "{:#}",
            pdbem::runner::run_scene(&scene(&text), &temp("short-run"), true)
                .expect_err("run refuses")
        ),
    ] {
        for part in [
            "cracks.0: the ligament between tip crack.end at (0.048500, 0.050000) m and the outline (edge 'right') is 1.5000e-3 m wide, 0.75 PD grid spacings (2.0000e-3 m there)",
            "use pd.dx of at most 7.5000e-4 m",
        ] {
            assert!(msg.contains(part), "{part} not in {msg}");
        }
    }
    assert!(!temp("short-run").exists());
    let note = |spacings: f64| {
        format!(
            "cracks.0: the ligament between tip crack.end and the outline (edge 'right') is 1.5000e-3 m wide, {spacings:.2} grid spacings, under the horizon"
        )
    };
    let zone = ", refine_zones: [(centre: (0.048, 0.05), half_size: 0.004, levels: 2)]";
    let text = plate(0.0485, 0.002, zone);
    check(&text, "zone.ron").expect("check accepts");
    let out = temp("zone-run");
    let summary = pdbem::runner::run_scene(&scene(&text), &out, true).expect("runs");
    assert!(
        summary.notes.iter().any(|n| n.starts_with(&note(3.0))),
        "{} not in {:?}",
        note(3.0),
        summary.notes
    );
    let _ = std::fs::remove_dir_all(&out);
    let fine = pdbem::setup::pd::problem_from_scene(&scene(&plate(0.0485, 0.00075, "")))
        .expect("two spacings are resolved");
    let notes = pdbem::setup::ligament::notes(&scene(&plate(0.0485, 0.00075, "")), fine.dx);
    assert!(notes.iter().any(|n| n.starts_with(&note(2.0))), "{notes:?}");
}

/// The other boundaries a ligament ends on: another crack (two collinear interior cracks
/// 1 mm apart) and a hole (a tip 1 mm from it); a crack from the left edge 1 mm above the
/// bottom corner leaves a 1 mm strip along the bottom edge.
#[test]
fn ligaments_to_cracks_holes_and_a_corner_are_measured() {
    let base = plate(0.01, 0.002, "");
    let two = base.replace(
        r#"cracks: [(name: "crack", start: (0, 0.05), angle_deg: 0, length: 0.01)]"#,
        r#"cracks: [(name: "a", start: (0.01, 0.05), angle_deg: 0, length: 0.014),
                    (name: "b", start: (0.025, 0.05), angle_deg: 0, length: 0.014)]"#,
    );
    let msg = format!("{:#}", check(&two, "two.ron").expect_err("refused"));
    assert!(
        msg.contains("cracks.0: the ligament between tip a.end at (0.024000, 0.050000) m and cracks.1 ('b') is 1.0000e-3 m wide"),
        "{msg}"
    );
    let hole = base.replace(
        "width: 0.05, height: 0.1)",
        r#"width: 0.05, height: 0.1), holes: [Circle(center: (0.02, 0.05), radius: 0.009, name: "hole")]"#,
    );
    let msg = format!("{:#}", check(&hole, "hole.ron").expect_err("refused"));
    assert!(
        msg.contains("and body.holes.0 ('hole') is 1.0000e-3 m wide"),
        "{msg}"
    );
    let corner = base.replace("start: (0, 0.05)", "start: (0, 0.001)");
    let msg = format!("{:#}", check(&corner, "corner.ron").expect_err("refused"));
    assert!(
        msg.contains("and the outline (edge 'bottom') is 1.0000e-3 m wide"),
        "{msg}"
    );
    check(&base, "base.ron").expect("a 40 mm ligament is accepted");
}

/// Full-PD growth builds its grid at the windows' spacing: the rule names
/// `coupling.side / coupling.n` (no refine zones there). The tension plate's crack moved
/// to 0.15 m from its held left edge at dx = 0.1 m.
#[test]
fn full_pd_growth_names_the_windows_spacing() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/growth_tension_edge.ron"),
    )
    .unwrap()
    .replace("start: (10, 10)", "start: (0.15, 10)")
    .replace("mode: PdBem", "mode: FullPd")
    // A crack 0.15 m from the strip's end is not Tada's (its reference is refused).
    .replace("    reference: SentTada(width: 10, sigma: 1),\n", "");
    let msg = format!("{:#}", check(&text, "full.ron").expect_err("refused"));
    for part in [
        "and the outline (edge 'left') is 1.5000e-1 m wide, 1.50 PD grid spacings",
        "use coupling.side / coupling.n of at most 7.5000e-2 m, or a crack",
    ] {
        assert!(msg.contains(part), "{part} not in {msg}");
    }
}

/// Seed 001's two parallel cracks on a 10 x 10 grid: both crack lines run through node
/// rows, so 4 nodes lose every bond. The transfer-function tractions reach a horizon (15
/// mm) into the body and load them (404 N each at load factor 1): refused by `check` and
/// `run`, where the solve stalled with no reason. The body-force layer loads only the edge
/// rows: accepted.
#[test]
fn loaded_nodes_a_crack_cuts_off_are_refused() {
    let text = |traction: &str| {
        format!(
            r#"(name: "loose", material: (E: 30e9, nu: 0.3333333333333333, plane: Stress, fracture: (g_c: 110)),
            body: (outline: Rectangle(x0: 0, y0: 0, width: 0.05, height: 0.05)),
            cracks: [(name: "lower", center: (0.025, 0.0125), angle_deg: 0, length: 0.01),
                     (name: "upper", center: (0.025, 0.0375), angle_deg: 0, length: 0.01)],
            boundary: [(on: "top", y: Traction(1e6)), (on: "bottom", y: Traction(-1e6))],
            load: (initial: 4, step: 0.2, count: 100),
            pd: (nx: 10, solver: Implicit(), failure: FromGc, traction: {traction}),
            outputs: (plots: false, csv: false))"#
        )
    };
    let tf = text("TransferFunction");
    let want = "pd: 4 loaded node(s) in 4 piece(s) have no intact bond to the body (the first at (0.022500, 0.012500) m, on crack 'lower'; a pre-crack through a row of nodes cuts every bond of the nodes on it), and nothing holds the 1.617e3 N";
    let msg = format!("{:#}", check(&tf, "loose.ron").expect_err("check refuses"));
    assert!(msg.contains(want), "{msg}");
    let run =
        pdbem::runner::run_scene(&scene(&tf), &temp("loose-run"), true).expect_err("run refuses");
    assert!(format!("{run:#}").contains(want), "{run:#}");
    check(&text("BodyForceLayer"), "layer.ron").expect("unloaded loose nodes are left");
}

/// Seed 001's 50 mm square with a 10 mm edge crack under 1 MPa (elastic bonds, surface
/// correction) on `nx` nodes across, horizon factor `m`; without `pd` the BEM alone.
fn edge_crack_square(pd: &str) -> Scene {
    scene(&format!(
        r#"(name: "square", material: (E: 30e9, nu: 0.3333333333333333, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 0.05, height: 0.05)),
        cracks: [(name: "crack", start: (0, 0.025), angle_deg: 0, length: 0.01)],
        boundary: [(on: "top", y: Traction(1e6)), (on: "bottom", y: Traction(-1e6))],
        {pd}
        outputs: (plots: false, csv: false))"#
    ))
}

/// Opening between the loaded edges (their mean y displacements) and the run's notes.
fn edge_opening(s: &Scene, name: &str) -> (f64, Vec<String>) {
    let out = temp(name);
    let summary = pdbem::runner::run_scene(s, &out, true).expect("runs");
    let _ = std::fs::remove_dir_all(&out);
    let groups = summary.extra["load_displacement"]["groups"]
        .as_array()
        .expect("groups")
        .clone();
    let uy = |g: &str| {
        groups.iter().find(|x| x["group"] == g).expect("group")["displacement"][1]
            .as_f64()
            .unwrap()
    };
    (uy("top") - uy("bottom"), summary.notes)
}

/// A cracked body only a few horizons across answers with PD's nonlocal stiffness: the
/// square at 13 nodes and horizon factor 6 (the horizon 0.46 of its side) opens 19.6 %
/// more than the BEM body and gets a note (`setup::horizon_scale`); at 50 nodes and
/// factor 3.015 (0.06) it opens within 2.2 % of it and gets none. A refinement zone counts
/// at its finest level; full-PD growth at the windows' spacing.
#[test]
fn a_cracked_body_a_few_horizons_across_is_noted() {
    let (elastic, _) = edge_opening(&edge_crack_square(""), "bem");
    let wide = edge_crack_square(
        "pd: (nx: 13, horizon_factor: 6, failure: Elastic, surface_correction: true),",
    );
    let (o, notes) = edge_opening(&wide, "wide");
    println!("BEM {elastic:.5e}, horizon 0.46 of the side {o:.5e}");
    assert!(o / elastic - 1.0 > 0.15, "{o} against {elastic}");
    let noted: Vec<_> = notes
        .iter()
        .filter(|n| n.starts_with("pd: the horizon"))
        .collect();
    assert_eq!(noted.len(), 1, "{notes:?}");
    assert!(
        noted[0].contains("is 0.46 of the body's smaller side"),
        "{}",
        noted[0]
    );
    let fine = edge_crack_square("pd: (nx: 50, failure: Elastic, surface_correction: true),");
    let (o, notes) = edge_opening(&fine, "fine");
    println!("horizon 0.06 of the side {o:.5e}");
    assert!((o / elastic - 1.0).abs() < 0.03, "{o} against {elastic}");
    assert!(
        notes.iter().all(|n| !n.starts_with("pd: the horizon")),
        "{notes:?}"
    );
    let refined = edge_crack_square(
        "pd: (nx: 13, horizon_factor: 6, failure: Elastic, refine_zones: [(centre: (0.015, 0.025), half_size: 0.008, levels: 2)]),",
    );
    assert!(pdbem::setup::horizon_scale::note(&refined).is_none());
    // Full-PD growth runs the whole body at the windows' spacing: 0.004 m / 4.
    let full_pd = |n: usize| {
        scene(&format!(
            r#"(name: "square", material: (E: 30e9, nu: 0.3333333333333333, plane: Stress, fracture: (g_c: 110)),
            body: (outline: Rectangle(x0: 0, y0: 0, width: 0.05, height: 0.05)),
            cracks: [(name: "crack", start: (0, 0.025), angle_deg: 0, length: 0.01)],
            boundary: [(on: "top", y: Traction(1e6)), (on: "bottom", y: Traction(-1e6))],
            load: (initial: 4, step: 0.25, count: 4),
            pd: (failure: FromGc, horizon_factor: 6),
            coupling: (side: 0.004, n: {n}),
            growth: (mode: FullPd),
            outputs: (plots: false, csv: false))"#
        ))
    };
    let note = pdbem::setup::horizon_scale::note(&full_pd(2)).expect("noted");
    assert!(
        note.contains("is 0.24 of the body's smaller side"),
        "{note}"
    );
    assert!(pdbem::setup::horizon_scale::note(&full_pd(8)).is_none());
}
