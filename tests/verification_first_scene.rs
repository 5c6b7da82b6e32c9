//! The walkthrough scene of docs/scene.md (`cases/first_scene.ron`): an inclined central
//! crack (beta = 60 degrees) in a 1 m x 0.5 m plate against the infinite-plate closed
//! form K_I = sigma sqrt(pi a) sin^2 beta, K_II = sigma sqrt(pi a) sin beta cos beta.

mod common_scene;

use common_scene::{case, pct, solve_bem};

#[test]
fn first_scene_k_against_the_inclined_crack_closed_form() {
    let s = solve_bem(&case("first_scene", &[]));
    assert_eq!(s.tips.len(), 2);
    let (sigma, a, beta) = (100e6, 0.05, 60f64.to_radians());
    let k0 = sigma * (std::f64::consts::PI * a).sqrt();
    let (k1, k2) = (k0 * beta.sin().powi(2), k0 * beta.sin() * beta.cos());
    for t in &s.tips {
        // Measured: K_I +4.743 %, K_II +2.394 % (the plate is five crack lengths tall);
        // the docs quote these numbers.
        let (e1, e2) = (pct(t.k1, k1), pct(t.k2, k2));
        assert!((e1 - 4.74).abs() < 0.05, "{}: K_I {e1:+.3} %", t.name);
        assert!((e2 - 2.39).abs() < 0.05, "{}: K_II {e2:+.3} %", t.name);
    }
}

#[test]
fn first_scene_difference_is_the_finite_plate() {
    // The same crack in a plate ten times larger: measured K_I +0.043 %, K_II within
    // 0.1 % of the closed form.
    let big = case(
        "first_scene",
        &[
            ("body.outline.width", "10"),
            ("body.outline.height", "5"),
            ("cracks.0.center", "(5, 2.5)"),
        ],
    );
    let s = solve_bem(&big);
    for t in &s.tips {
        let e1 = 100.0 * t.k1_err.expect("reference");
        let e2 = 100.0 * t.k2_err.expect("reference");
        assert!(e1.abs() < 0.1, "{}: K_I {e1:+.3} %", t.name);
        assert!(e2.abs() < 0.2, "{}: K_II {e2:+.3} %", t.name);
    }
}
