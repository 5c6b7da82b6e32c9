//! Tractions on the crack faces (`bem/src/post/face_traction.rs`): the interaction
//! integral and J take the faces inside the contour into account. Before, a Griffith crack
//! under unit face pressure had an interaction-integral K_I 45 % low (0.975 against
//! sqrt(pi a) = 1.772), J 84 % low, an error estimate of 45 % that no refinement could
//! lower, and a note advising to refine the crack mesh.
mod common_scene;

use std::path::Path;

use common_scene::*;
use pdbem::runner::RunSummary;
use pdbem::scene::Scene;

/// A crack of half-length 1 m at `angle` degrees in `outline`, loaded by `boundary`
/// (RON list entries), with `bem` settings.
fn crack(outline: &str, center: &str, angle: f64, boundary: &str, bem: &str) -> Scene {
    let text = format!(
        r#"(
    name: "faces",
    description: "crack-face tractions",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (outline: {outline}),
    cracks: [(name: "c", center: {center}, angle_deg: {angle}, length: 2)],
    boundary: [{boundary}],
    bem: ({bem}),
)"#
    );
    Scene::parse(&text, Path::new("faces.ron")).expect("parses")
}

/// Solved with the run's plausibility notes.
fn solve(scene: &Scene) -> RunSummary {
    let mut s = solve_bem(scene);
    pdbem::runner::plausibility::review(scene, &mut s);
    s
}

/// Unit pressure on both faces of a crack in an infinite plate: K_I = sqrt(pi a) by both
/// extractions, J = K_I^2 / E', an estimate of a fraction of a per cent, and no note.
/// Measured: K_I +0.024 % (integral) and -0.0043 % (opening fit), J +0.30 %, estimate
/// 0.085 %.
#[test]
fn a_pressurised_griffith_crack_gives_the_same_k_by_both_extractions() {
    let s = solve(&crack(
        "Infinite()",
        "(0, 0)",
        0.0,
        r#"(on: "c", normal: -1)"#,
        "",
    ));
    let exact = std::f64::consts::PI.sqrt();
    for t in &s.tips {
        let (k, kj) = (t.k1, t.k1_j.unwrap());
        println!(
            "{}: K_I {:+.4} %, integral {:+.4} %, J vs K^2/E' {:+.3} %, estimate {:.4} %",
            t.name,
            pct(k, exact),
            pct(kj, exact),
            pct(t.j.unwrap(), exact * exact / 1e4),
            100.0 * t.k1_err_est.unwrap() / k
        );
        assert!(pct(k, exact).abs() < 0.1);
        assert!(pct(kj, exact).abs() < 0.1);
        assert!(pct(t.j.unwrap(), exact * exact / 1e4).abs() < 1.0);
        assert!(t.k1_err_est.unwrap() < 5e-3 * k);
        assert!(t.k2.abs() < 1e-9 && t.k2_j.unwrap().abs() < 1e-9);
    }
    assert!(s.notes.is_empty(), "{:?}", s.notes);
}

/// Unit shear on the faces of an inclined crack: K_II = sqrt(pi a) by both.
/// Measured: integral +0.044 %, opening fit -0.0043 %.
#[test]
fn a_sheared_griffith_crack_gives_the_same_k_ii_by_both_extractions() {
    let s = solve(&crack(
        "Infinite()",
        "(0, 0)",
        30.0,
        r#"(on: "c", shear: 1)"#,
        "",
    ));
    let exact = std::f64::consts::PI.sqrt();
    for t in &s.tips {
        println!(
            "{}: K_II {:+.4} %, integral {:+.4} %",
            t.name,
            pct(t.k2, exact),
            pct(t.k2_j.unwrap(), exact)
        );
        assert!(pct(t.k2, exact).abs() < 0.1);
        assert!(pct(t.k2_j.unwrap(), exact).abs() < 0.1);
        assert!(t.k1.abs() < 1e-9 && t.k1_j.unwrap().abs() < 1e-9);
    }
    assert!(s.notes.is_empty(), "{:?}", s.notes);
}

/// Superposition: a crack in a finite plate opened by face pressure p has the K of the
/// same plate pulled by p at its ends (the uncracked plate's uniform stress carries the
/// rest). Measured on the 10 m square plate: the integrals within 0.0052 %, the opening
/// fits equal to 1e-7, the face pressure's integral 0.028 % above the plate's opening fit.
#[test]
fn face_pressure_and_remote_tension_give_the_same_k() {
    let plate = "Rectangle(x0: 0, y0: 0, width: 10, height: 10)";
    let pressure = solve(&crack(plate, "(5, 5)", 0.0, r#"(on: "c", normal: -1)"#, ""));
    let tension = solve(&crack(
        plate,
        "(5, 5)",
        0.0,
        r#"(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))"#,
        "",
    ));
    for (p, t) in pressure.tips.iter().zip(&tension.tips) {
        let (kp, kt) = (p.k1_j.unwrap(), t.k1_j.unwrap());
        println!(
            "{}: integral {kp:.6} (pressure) against {kt:.6} (tension): {:+.4} %; \
             opening fit {:.6} / {:.6}",
            p.name,
            pct(kp, kt),
            p.k1,
            t.k1
        );
        assert!(pct(kp, kt).abs() < 0.05);
        assert!(pct(kp, t.k1).abs() < 0.1);
        assert!(pct(p.k1, t.k1).abs() < 0.1);
    }
}

/// A traction on one face only: the interaction integral is path independent (the same
/// K within 0.2 % on contours of 0.25, 0.5 and 0.8 a; without the face terms it fell
/// with the radius). Its K_II differs from the opening fit's (0.199 against 0.162 at
/// every refinement): one loaded face adds a term linear in r to the tangential opening,
/// which the fit's polynomial in r does not hold; so the reported K is the integral's,
/// with a note that says so and the fit kept as `k1_cod`, `k2_cod`.
#[test]
fn a_one_face_load_gives_a_path_independent_integral() {
    let plate = "Rectangle(x0: 0, y0: 0, width: 10, height: 10)";
    let load = r#"(on: "c.upper", y: Traction(1)), (on: "bottom", y: Traction(-0.2))"#;
    let at = |r: f64| {
        let s = solve(&crack(
            plate,
            "(5, 5)",
            0.0,
            load,
            &format!("j_contour: (radius_fraction: {r})"),
        ));
        let t = s.tips[1].clone();
        (t.k1_j.unwrap(), t.k2_j.unwrap(), t, s.notes)
    };
    let (k1, k2, tip, notes) = at(0.25);
    for r in [0.5, 0.8] {
        let (k1r, k2r, _, _) = at(r);
        println!("radius {r} a: K_I {k1r:.5} ({k1:.5}), K_II {k2r:.5} ({k2:.5})");
        assert!(pct(k1r, k1).abs() < 0.2);
        assert!(pct(k2r, k2).abs() < 0.2);
    }
    println!(
        "reported K_II {:.5} (estimate {:.5}), opening fit {:.5}",
        tip.k2,
        tip.k2_err_est.unwrap(),
        tip.k2_cod.unwrap()
    );
    assert_eq!((tip.k1, tip.k2), (k1, k2));
    assert_eq!(tip.k_source.as_deref(), Some("interaction_integral"));
    assert!(pct(tip.k2_cod.unwrap(), k2) < -10.0);
    assert!(
        notes
            .iter()
            .any(|n| n.contains("k1, k2 are the interaction-integral values")
                && n.contains("one face of the crack")),
        "{notes:?}"
    );
    assert!(!notes.iter().any(|n| n.contains("differ by")), "{notes:?}");
}

/// A Griffith crack (half-length a = 1 m) in an infinite plate with unit pressure on its
/// upper face only: half the pressure's K_I, p sqrt(pi a) / 2, and a K_II from the
/// faces' unequal loads, (kappa - 1) / (kappa + 1) p sqrt(a / pi) (the one-face point
/// force of Tada's handbook integrated over the crack), of opposite signs at the two tips.
/// Measured: K_I +0.024 %, K_II -0.13 % (plane stress and strain, nu = 0.3 and 0), within
/// their estimates; the opening fit's K_II was 19 % low. No balance note: the infinite
/// plate carries the net force at infinity.
#[test]
fn a_griffith_crack_pressed_on_one_face_matches_the_analytic_k() {
    for (nu, plane) in [(0.3, "Stress"), (0.3, "Strain"), (0.0, "Stress")] {
        let text = format!(
            r#"(
    name: "one_face",
    description: "one face pressed",
    material: (E: 1e4, nu: {nu}, plane: {plane}),
    body: (outline: Infinite()),
    cracks: [(name: "c", center: (0, 0), angle_deg: 0, length: 2)],
    boundary: [(on: "c.upper", normal: -1)],
)"#
        );
        let scene = Scene::parse(&text, Path::new("one_face.ron")).expect("parses");
        let out = std::env::temp_dir().join(format!(
            "pdbem-one-face-{}-{nu}-{plane}",
            std::process::id()
        ));
        let s = pdbem::runner::run_scene(&scene, &out, true).expect("runs");
        let _ = std::fs::remove_dir_all(&out);
        let kappa = if plane == "Stress" {
            (3.0 - nu) / (1.0 + nu)
        } else {
            3.0 - 4.0 * nu
        };
        let k1 = std::f64::consts::PI.sqrt() / 2.0;
        let k2 = (kappa - 1.0) / (kappa + 1.0) / std::f64::consts::PI.sqrt();
        for t in &s.tips {
            let sign = if t.name == "c.end" { -1.0 } else { 1.0 };
            println!(
                "{nu} {plane} {}: K_I {:+.3} %, K_II {:+.3} % (estimates {:.3} %, {:.3} %), fit K_II {:+.1} %",
                t.name,
                pct(t.k1, k1),
                pct(sign * t.k2, k2),
                100.0 * t.k1_err_est.unwrap() / k1,
                100.0 * t.k2_err_est.unwrap() / k2,
                pct(sign * t.k2_cod.unwrap(), k2)
            );
            assert!((t.k1 - k1).abs() <= t.k1_err_est.unwrap() && pct(t.k1, k1).abs() < 0.2);
            assert!((sign * t.k2 - k2).abs() <= t.k2_err_est.unwrap());
            assert!(pct(sign * t.k2, k2).abs() < 0.5);
        }
        assert!(
            !s.notes.iter().any(|n| n.contains("do not balance")),
            "{:?}",
            s.notes
        );
    }
}

/// Remote tension and face pressure together in an infinite plate (the solution loads the
/// faces by minus the remote traction, the integral takes the whole field's): K_I =
/// (sigma + p) sqrt(pi a) by both extractions. Measured: integral +0.021 %, fit -0.0043 %.
#[test]
fn remote_tension_and_face_pressure_add_up_in_an_infinite_plate() {
    let s = solve(&crack(
        "Infinite(syy: 1)",
        "(0, 0)",
        0.0,
        r#"(on: "c", normal: -1)"#,
        "",
    ));
    let exact = 2.0 * std::f64::consts::PI.sqrt();
    for t in &s.tips {
        println!(
            "{}: K_I {:+.4} %, integral {:+.4} %",
            t.name,
            pct(t.k1, exact),
            pct(t.k1_j.unwrap(), exact)
        );
        assert!(pct(t.k1, exact).abs() < 0.1);
        assert!(pct(t.k1_j.unwrap(), exact).abs() < 0.1);
    }
    assert!(s.notes.is_empty(), "{:?}", s.notes);
}

/// BEM-only growth (and the K record of every growth mode, which solves the same body)
/// takes the interaction integral's K at a crack loaded on one face, as the static run:
/// the Griffith crack pressed on one face gives the analytic K at its initial geometry.
/// Before, the growth engine took the opening fit's K_II, 19 % low (on an edge crack of
/// `growth_tension_edge` with half its upper face pressed, a kink of 3.4 degrees against
/// the integral's 4.0).
#[test]
fn bem_only_growth_takes_the_integral_k_of_a_crack_loaded_on_one_face() {
    let text = r#"(
    name: "one_face_growth",
    description: "one face pressed, BEM-only growth",
    material: (E: 1e4, nu: 0.3, plane: Stress, fracture: (k_c: 10)),
    body: (outline: Infinite()),
    cracks: [(name: "c", center: (0, 0), angle_deg: 0, length: 2)],
    boundary: [(on: "c.upper", normal: -1)],
    load: (initial: 1, step: 1, count: 2),
    growth: (mode: BemOnly, da: 0.1),
)"#;
    let scene = Scene::parse(text, Path::new("one_face_growth.ron")).expect("parses");
    let k1 = std::f64::consts::PI.sqrt() / 2.0;
    let kappa = (3.0 - 0.3) / 1.3;
    let k2 = (kappa - 1.0) / (kappa + 1.0) / std::f64::consts::PI.sqrt();
    let tips = pdbem::growth::bem_only::critical_loads(&scene).expect("solves");
    assert_eq!(tips.len(), 2);
    for t in &tips {
        let sign = if t.tip == "c.end" { -1.0 } else { 1.0 };
        println!(
            "{}: K_I {:+.3} %, K_II {:+.3} %",
            t.tip,
            pct(t.k[0], k1),
            pct(sign * t.k[1], k2)
        );
        assert!(pct(t.k[0], k1).abs() < 0.5);
        assert!(pct(sign * t.k[1], k2).abs() < 1.0);
    }
}
