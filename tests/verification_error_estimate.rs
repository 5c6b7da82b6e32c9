//! The error estimate of every K (issue 17): |K(h) - K(2h)| ([`pdbem::refine`]) must be
//! honest: never below a third of the true error and not above ten times it, wherever the
//! reference can resolve the true error. SENT (H = 2W) at a/W = 0.1 to 0.95, DENT, a
//! centre-cracked plate (CCT) and Griffith's crack in an infinite plate, each at a coarse
//! and a fine element size.
//!
//! References and their uncertainty u (relative): SENT a/W <= 0.8 the FEM table
//! (u = 1e-5); SENT beyond, Tada (u = 5e-3); Griffith exact (u = 0); CCT and DENT the
//! converged BEM value itself, Richardson 2 K(h/4) - K(h/2) of the fine scene (u = the
//! difference K(h/4) - K(h/2), which bounds it), checked against Tada's CCT formula
//! within its 0.1 % (the DENT formula is 1.5 % above the converged BEM and not asserted).
//! The bounds tested: est >= (|err| - u) / 3 everywhere; est <= 10 (|err| + u) where the
//! error exceeds 1e-3, and est <= 2e-3 below (the floor 2e-4 and the O(h) term
//! over-estimate errors of a few 1e-5 by up to 50 times: Griffith and CCT).

use pdbem::refine::RESOLUTION_FLOOR;
use pdbem::run_bem::solve;
use pdbem::scene::Scene;
use pdbem_bem::analytic::{sent_f_fem, sent_f_tada};
use std::f64::consts::PI;

fn scene(src: &str) -> Scene {
    Scene::from_ron_str(src, "cases/estimate.ron").expect("valid scene")
}

/// SENT strip W = 1, H = 2W each side, crack from the left edge; tension 1 on top and bottom.
fn sent(a: f64, h: f64) -> Scene {
    scene(&format!(
        r#"(name: "sent", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 1, height: 4)),
        cracks: [(name: "c", start: (0, 2), angle_deg: 0, length: {a})],
        boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
        bem: (element_size: {h}), outputs: (plots: false))"#
    ))
}

/// Centre crack 2a in a plate of width 1 and height 4, tension 1.
fn cct(a: f64, h: f64) -> Scene {
    scene(&format!(
        r#"(name: "cct", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: -0.5, y0: -2, width: 1, height: 4)),
        cracks: [(name: "c", center: (0, 0), angle_deg: 0, length: {})],
        boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
        bem: (element_size: {h}), outputs: (plots: false))"#,
        2.0 * a
    ))
}

/// Two edge cracks of depth a in a plate of width 1 and height 4, tension 1.
fn dent(a: f64, h: f64) -> Scene {
    scene(&format!(
        r#"(name: "dent", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: -0.5, y0: -2, width: 1, height: 4)),
        cracks: [(name: "l", start: (-0.5, 0), angle_deg: 0, length: {a}),
                 (name: "r", start: (0.5, 0), angle_deg: 180, length: {a})],
        boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
        bem: (element_size: {h}), outputs: (plots: false))"#
    ))
}

/// Griffith: crack of half-length 1 in an infinite plate, remote tension 1.
fn griffith(h: f64) -> Scene {
    scene(&format!(
        r#"(name: "griffith", material: (E: 1e4, nu: 0.3, plane: Strain),
        body: (outline: Infinite(syy: 1.0)),
        cracks: [(name: "c", center: (0, 0), angle_deg: 0, length: 2)],
        bem: (element_size: {h}), outputs: (plots: false))"#
    ))
}

/// (K_I, its estimate) of the first tip.
fn k_and_estimate(s: &Scene) -> (f64, f64) {
    let (sum, _) = solve(s).expect("solves");
    let t = &sum.tips[0];
    (t.k1, t.k1_err_est.expect("an estimate"))
}

/// Checks the bounds; returns the ratio estimate / true error for the table.
fn honest(label: &str, k: f64, est: f64, reference: f64, u: f64) -> f64 {
    let err = (k - reference).abs() / reference;
    let e = est / reference;
    println!(
        "{label:28} K {k:.6e} ref {reference:.6e} err {:+.4} % est {:.4} % (u {:.4} %) ratio {:.2}",
        100.0 * (k / reference - 1.0),
        100.0 * e,
        100.0 * u,
        e / err
    );
    assert!(
        e >= (err - u) / 3.0,
        "{label}: estimate {e:.3e} below a third of the error {err:.3e}"
    );
    // Errors far below the estimate's floor (2e-4) cannot be matched within ten times:
    // there the estimate must only stay small in absolute terms (<= 2e-3).
    let upper = if err > 5.0 * RESOLUTION_FLOOR {
        10.0 * (err + u)
    } else {
        2e-3
    };
    assert!(
        e <= upper,
        "{label}: estimate {e:.3e} over {upper:.3e} (error {err:.3e})"
    );
    e / err
}

#[test]
fn sent_estimates_are_honest_from_shallow_to_deep() {
    for x in [0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95] {
        for h in [0.05, 0.02] {
            let (k, est) = k_and_estimate(&sent(x, h));
            let (f, u) = match sent_f_fem(x) {
                Some(f) => (f, 1e-5),
                None => (sent_f_tada(x), 5e-3),
            };
            honest(
                &format!("SENT a/W {x} h {h}"),
                k,
                est,
                (PI * x).sqrt() * f,
                u,
            );
        }
    }
}

#[test]
fn griffith_estimates_are_honest() {
    for h in [0.1, 0.025] {
        let (k, est) = k_and_estimate(&griffith(h));
        honest(&format!("Griffith h {h}"), k, est, PI.sqrt(), 0.0);
    }
}

/// A scene at element size h.
type Maker<'a> = dyn Fn(f64) -> Scene + 'a;

/// The converged K of a scene built by `make(h)`: Richardson of h/2 and h/4, with the
/// difference of the two as its uncertainty.
fn converged(make: &Maker<'_>, h: f64) -> (f64, f64) {
    let (k2, _) = k_and_estimate(&make(0.5 * h));
    let (k4, _) = k_and_estimate(&make(0.25 * h));
    let k = 2.0 * k4 - k2;
    (k, ((k4 - k2) / k).abs())
}

#[test]
fn cct_and_dent_estimates_are_honest() {
    // Tada: CCT F = (1 - 0.025 l^2 + 0.06 l^4) sqrt(sec(pi l / 2)), l = 2a/W (0.1 %);
    // DENT F = (1.122 - 0.561 l - 0.205 l^2 + 0.471 l^3 - 0.190 l^4) / sqrt(1 - l),
    // l = 2a/W (0.5 %).
    let a: f64 = 0.2;
    let l = 2.0 * a;
    let f_cct = (1.0 - 0.025 * l * l + 0.06 * l.powi(4)) * (1.0 / (PI * l / 2.0).cos()).sqrt();
    let f_dent = (1.122 - 0.561 * l - 0.205 * l * l + 0.471 * l.powi(3) - 0.190 * l.powi(4))
        / (1.0 - l).sqrt();
    let cases: [(&str, &Maker<'_>, f64, f64); 2] = [
        ("CCT", &|h| cct(a, h), f_cct, 1e-3),
        // Not asserted: the converged BEM DENT K is 1.5 % below this formula, more than
        // its stated 0.5 % (an open question, see the issue notes).
        ("DENT", &|h| dent(a, h), f_dent, f64::INFINITY),
    ];
    for (name, make, f, u_handbook) in cases {
        let (truth, u) = converged(make, 0.02);
        let handbook = (PI * a).sqrt() * f;
        println!("{name}: converged K {truth:.6e} (u {u:.1e}), handbook {handbook:.6e}");
        assert!(
            (truth / handbook - 1.0).abs() < u_handbook + u,
            "{name}: converged K off the handbook"
        );
        for h in [0.05, 0.02] {
            let (k, est) = k_and_estimate(&make(h));
            honest(&format!("{name} a/W {l} h {h}"), k, est, truth, u);
        }
    }
}
