//! Bodies that nothing holds against the resultant of their loads are refused
//! (issue 17): `pdbem check` and every mode of `pdbem run` fail with the resultant
//! (Fx, Fy, M about the outline centroid), while balanced free bodies and supported
//! unbalanced ones run. Before the check, the SENT plate pulled on its right edge only ran
//! with exit 0 and K_I -50 % (the bordered solver solves some other, balanced load).

mod common_scene;

use common_scene::case;
use pdbem::cli::{execute, Command};
use pdbem::scene::Scene;

/// The seed-002 SENT plate (20 x 10 m, a = 5 m from the top) with the given conditions.
fn plate(boundary: &str) -> String {
    format!(
        r#"(name: "unbalanced", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 20, height: 10)),
        cracks: [(name: "crack", start: (10, 10), angle_deg: -90, length: 5)],
        boundary: [{boundary}],
        bem: (element_size: 0.25), outputs: (plots: false, csv: false))"#
    )
}

fn temp(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("pdbem-balance-{}-{name}", std::process::id()))
}

/// The right edge pulled at 0.5 Pa over its 10 m: Fx = 5 N/m on the centroid's line.
const PULLED: &str = r#"(on: "right", x: Traction(0.5))"#;

fn assert_names_the_resultant(msg: &str) {
    assert!(
        msg.contains("boundary: the prescribed tractions (on right)"),
        "{msg}"
    );
    assert!(
        msg.contains("Fx = 5.000000e0 N/m, Fy = 0.000000e0 N/m"),
        "{msg}"
    );
    assert!(msg.contains("about (10.000000, 5.000000) m"), "{msg}");
    assert!(msg.contains("balance the loads or add a support"), "{msg}");
}

#[test]
fn an_unbalanced_free_plate_is_refused_by_check_and_run() {
    let file = temp("pulled.ron");
    std::fs::write(&file, plate(PULLED)).unwrap();
    let check = execute(Command::Check {
        scene: file.clone(),
        plot: None,
        max_memory: None,
    })
    .expect_err("check refuses");
    let msg = format!("{check:#}");
    assert!(
        msg.contains(&format!("{}: boundary", file.display())),
        "{msg}"
    );
    assert_names_the_resultant(&msg);
    let out = temp("pulled-run");
    let run = pdbem::runner::run_scene(&Scene::load(&file).unwrap(), &out, true)
        .expect_err("run refuses");
    assert_names_the_resultant(&format!("{run:#}"));
    assert!(!out.exists(), "{} left behind", out.display());
    let _ = std::fs::remove_file(&file);
}

#[test]
fn a_couple_is_reported_as_a_moment() {
    // Shear up on the right edge and down on the left: F = 0, M = 2 x 10 m x 0.5 Pa x 10 m.
    let text = plate(r#"(on: "right", y: Traction(0.5)), (on: "left", y: Traction(-0.5))"#);
    let scene = Scene::from_ron_str(&text, "couple.ron").unwrap();
    let msg = format!(
        "{:#}",
        pdbem::run_bem::solve(&scene).err().expect("refused")
    );
    assert!(msg.contains("M = 1.000000e2 N m/m"), "{msg}");
}

#[test]
fn a_balanced_free_plate_and_a_supported_unbalanced_one_run() {
    let balanced = plate(r#"(on: "left", x: Traction(-0.5)), (on: "right", x: Traction(0.5))"#);
    let scene = Scene::from_ron_str(&balanced, "balanced.ron").unwrap();
    let (s, _) = pdbem::run_bem::solve(&scene).expect("balanced plate runs");
    assert!(s.tips[0].k1 > 0.0);
    // Clamped on the left and pulled on the right: the clamp carries the resultant.
    let supported = plate(&format!(
        r#"(on: "left", x: Displacement(0), y: Displacement(0)), {PULLED}"#
    ));
    let scene = Scene::from_ron_str(&supported, "supported.ron").unwrap();
    let (s, _) = pdbem::run_bem::solve(&scene).expect("supported plate runs");
    assert!(s.tips[0].k1 > 0.0);
    // A roller on the bottom holds y and rotation but not x: still refused.
    let roller = plate(&format!(r#"(on: "bottom", y: Displacement(0)), {PULLED}"#));
    let scene = Scene::from_ron_str(&roller, "roller.ron").unwrap();
    let msg = format!(
        "{:#}",
        pdbem::run_bem::solve(&scene).err().expect("refused")
    );
    assert!(
        msg.contains("the displacement conditions leave 1 rigid motion(s) of the body free"),
        "{msg}"
    );
}

#[test]
fn coupled_and_growth_modes_refuse_an_unbalanced_body() {
    let coupled = case("coupled_sent_a5", &[("boundary.0.x.Traction", "0")]);
    let msg = format!(
        "{:#}",
        pdbem::setup::coupled::prepare(&coupled)
            .err()
            .expect("refused")
    );
    assert!(
        msg.contains("are out of balance") && msg.contains("Fx = 5.000000e0"),
        "{msg}"
    );
    let growth = case("growth_center_crack", &[("boundary.1.y.Traction", "0")]);
    let msg = format!(
        "{:#}",
        pdbem::setup::growth::input(&growth)
            .err()
            .expect("PD-BEM growth refused")
    );
    assert!(msg.contains("are out of balance"), "{msg}");
    let bem_only =
        pdbem::cli::with_growth_mode(&growth, pdbem::scene::GrowthMode::BemOnly).unwrap();
    let msg = format!(
        "{:#}",
        pdbem::setup::growth::bem_only_input(&bem_only)
            .err()
            .expect("BEM-only growth refused")
    );
    assert!(msg.contains("are out of balance"), "{msg}");
}

#[test]
fn stand_alone_pd_refuses_loads_out_of_balance_along_a_free_motion() {
    // The PD edge-crack plate (50 x 50 mm, pulled by 1 MPa on top and bottom) with its
    // bottom load turned: both edges pull up, Fy = 2 x 1 MPa x 50 mm. The quasi-static
    // solvers pin a pure-traction body at two nodes, which would carry the resultant
    // (before the check: exit 0, the pins' reaction 1e5 N/m); refused by check and run.
    let up = case("pd_edge_crack", &[("boundary.1.y.Traction", "1e6")]);
    let msg = format!(
        "{:#}",
        pdbem::setup::footprint::of(&up).expect_err("check refuses")
    );
    assert!(
        msg.contains("are out of balance") && msg.contains("Fy = 1.000000e5 N/m"),
        "{msg}"
    );
    let msg = format!("{:#}", pdbem::run_pd::solve(&up).expect_err("run refuses"));
    assert!(msg.contains("are out of balance"), "{msg}");
    // The scene's `bem` section is not what PD runs: the balance mesh takes the default
    // sizes (with the scene's 1e-9 m elements the mesher refused the body, and the
    // unbalanced loads ran unchecked).
    let mut tiny = up.clone();
    tiny.bem.element_size = Some(1e-9);
    let msg = format!(
        "{:#}",
        pdbem::setup::footprint::of(&tiny).expect_err("check refuses")
    );
    assert!(msg.contains("are out of balance"), "{msg}");
    // A couple: shear right on top, left at the bottom: M = -1 MPa x 50 mm x 50 mm
    // (clockwise).
    let text = std::fs::read_to_string("cases/pd_edge_crack.ron").unwrap();
    let sheared = text
        .replace(
            r#"(on: "top", y: Traction(1e6))"#,
            r#"(on: "top", x: Traction(1e6))"#,
        )
        .replace(
            r#"(on: "bottom", y: Traction(-1e6))"#,
            r#"(on: "bottom", x: Traction(-1e6))"#,
        );
    assert_ne!(sheared, text);
    let couple = Scene::from_ron_str(&sheared, "couple.ron").unwrap();
    let msg = format!(
        "{:#}",
        pdbem::setup::footprint::of(&couple).expect_err("refused")
    );
    assert!(msg.contains("M = -2.500000e3 N m/m"), "{msg}");
    // On a roller (the bottom held in y) and pulled right as well: x is free and Fx =
    // 1 MPa x 50 mm. Before the check: Newton "did not converge in 77 iterations",
    // ADR in its 100 000, with no reason given.
    let rolled = text.replace(
        r#"(on: "bottom", y: Traction(-1e6))"#,
        r#"(on: "bottom", y: Displacement(0)), (on: "right", x: Traction(1e6))"#,
    );
    let roller = Scene::from_ron_str(&rolled, "roller.ron").unwrap();
    let msg = format!(
        "{:#}",
        pdbem::setup::footprint::of(&roller).expect_err("refused")
    );
    assert!(
        msg.contains("leave 1 rigid motion(s) of the body free")
            && msg.contains("Fx = 5.000000e4 N/m"),
        "{msg}"
    );
    // Explicit dynamics drops the pins: the same unbalanced load accelerates the free
    // branching plate, which check accepts.
    let flying = case(
        "seed004_branching_case1",
        &[("boundary.1.y.Traction", "1e6")],
    );
    pdbem::setup::footprint::of(&flying).expect("dynamics takes an unbalanced load");
    // The shipped, balanced plate runs.
    pdbem::setup::footprint::of(&case("pd_edge_crack", &[])).unwrap();
}
