//! Bad coupled scenes get a clear error (issue 4): window outside the body, over a hole,
//! fewer than 2 delta of real nodes per side, rotated window crossing the boundary.

use pdbem::scene::Scene;

fn scene(holes: &str, coupling: &str) -> String {
    format!(
        r#"(
    name: "bad",
    material: (E: 1e11, nu: 0.3333333333333333, plane: Stress),
    body: (outline: Rectangle(x0: 0, y0: 0, width: 0.5, height: 0.5), holes: [{holes}]),
    boundary: [(on: "left", x: Displacement(0)), (on: "bottom", y: Displacement(0)),
               (on: "right", x: Traction(1e8))],
    bem: (element_size: 0.01),
    pd: (failure: Elastic),
    coupling: ({coupling}),
)"#
    )
}

/// The error message of loading + preparing, which must exist.
fn error_of(text: &str) -> String {
    match Scene::from_ron_str(text, "bad.ron") {
        Err(e) => e.to_string(),
        Ok(s) => match pdbem::setup::coupled::prepare(&s) {
            Err(e) => format!("{e:#}"),
            Ok(_) => panic!("scene accepted"),
        },
    }
}

#[test]
fn window_outside_the_body() {
    let e = error_of(&scene(
        "",
        "side: 0.1, n: 20, placement: Centered(center: (0.47, 0.25))",
    ));
    assert!(e.contains("outside the body"), "{e}");
}

#[test]
fn window_over_a_hole() {
    let e = error_of(&scene(
        "Circle(center: (0.25, 0.25), radius: 0.02)",
        "side: 0.1, n: 20, placement: Centered(center: (0.25, 0.25))",
    ));
    assert!(e.contains("overlaps hole 0"), "{e}");
}

#[test]
fn fewer_than_two_horizons_per_side() {
    let e = error_of(&scene(
        "",
        "side: 0.1, n: 6, placement: Centered(center: (0.25, 0.25))",
    ));
    // Validation catches it now (the coupling crate's TooFewNodes rule, n >= 2 m).
    assert!(
        e.contains("bad.ron: coupling.n = 6")
            && e.contains("at least 7: a window must be at least 2 horizons wide"),
        "{e}"
    );
}

#[test]
fn rotated_window_crossing_the_boundary() {
    let e = error_of(&scene(
        "",
        "side: 0.1, n: 20, placement: Centered(center: (0.06, 0.25), angle_deg: 45)",
    ));
    assert!(e.contains("outside the body"), "{e}");
}
