//! Single-edge-cracked strip (`cases/sent_tall.ron`, H = 2W) against Tada's K_I and CMOD
//! formulas and the converged FEM table of REFERENCES.md, with default settings.
mod common_scene;

use common_scene::*;
use pdbem_bem::analytic::{sent_cmod, sent_f_fem, sent_f_tada};
use std::f64::consts::PI;

const W: f64 = 10.0;
const SIGMA: f64 = 0.5;
const E: f64 = 1e4;

/// K_I by both methods at every a/W of the FEM table. Issue bounds against Tada: 1 % up to
/// a/W = 0.5, 3 % beyond. Measured (crack-opening fit): -0.63, +0.01, +0.28, +0.15, -0.21,
/// -0.41, -0.50, -0.43 %; the interaction integral agrees with it within 0.1 %. Against the
/// FEM table (better than Tada's 0.3-0.55 %): -0.08, -0.03, +0.01, +0.00, -0.12, -0.14,
/// -0.15, -0.10 %.
#[test]
fn sent_tada_k1_all_depths_both_methods() {
    for k in 1..=8 {
        let a = k as f64;
        let x = a / W;
        let scene = case("sent_tall", &[("cracks.0.length", &a.to_string())]);
        let s = solve_bem(&scene);
        let t = &s.tips[0];
        let tada = SIGMA * (PI * a).sqrt() * sent_f_tada(x);
        let fem = SIGMA * (PI * a).sqrt() * sent_f_fem(x).unwrap();
        let (ec, ej) = (pct(t.k1_cod.unwrap(), tada), pct(t.k1_j.unwrap(), tada));
        println!(
            "a/W {x:.1}: {} elements, K_I cod {ec:+.3} % j {ej:+.3} % vs Tada; cod {:+.3} % vs FEM; K_II {:.1e}",
            s.elements.unwrap(),
            pct(t.k1_cod.unwrap(), fem),
            t.k2
        );
        let bound = if x <= 0.5 { 1.0 } else { 3.0 };
        assert!(ec.abs() < bound && ej.abs() < bound, "a/W {x}: {ec} {ej}");
        assert!((t.k1_cod.unwrap() / t.k1_j.unwrap() - 1.0).abs() < 0.005);
        if x >= 0.2 {
            assert!(pct(t.k1_cod.unwrap(), fem).abs() < 0.5, "a/W {x} vs FEM");
        }
        assert!(t.k2.abs() < 1e-6 * t.k1, "mode I only");
    }
}

/// Richardson over h and h/2 at a/W = 0.8 (issue: within 2 %). Measured -0.38 % vs Tada
/// (1650 + 3290 elements); without it -0.43 %: with the linear reconstruction the error is no
/// longer O(h), so the extrapolation changes little (plain constant elements: -7.6 / -4.5 %
/// at h = 0.1 / 0.05, extrapolated -1.4 %).
#[test]
fn sent_tada_richardson_deep_crack() {
    let scene = case(
        "sent_tall",
        &[("cracks.0.length", "8"), ("bem.richardson", "true")],
    );
    let s = solve_bem(&scene);
    let t = &s.tips[0];
    let tada = SIGMA * (PI * 8.0).sqrt() * sent_f_tada(0.8);
    let e = pct(t.k1, tada);
    println!(
        "a/W 0.8 Richardson: {} elements (fine level), K_I {e:+.3} %",
        s.elements.unwrap()
    );
    assert!(e.abs() < 2.0);
    assert!(s.extra.contains_key("richardson"));
}

/// CMOD against Tada's V(a/W) formula. Measured +0.74, +1.72, +1.79, +1.20, +0.35 % for
/// a/W = 0.1 to 0.5. The issue asks for 1 %; the formula itself is the limit at 0.2-0.4:
/// it is +0.62 % above the exact half-plane value 4 (1.4541) sigma a / E' already at
/// a/W = 0.02 (where this solver is 0.21 % below the formula), the same K_I agrees with the
/// FEM table within 0.3 %, and H/W = 4 gives the same CMOD as H/W = 2 to 0.01 %. So the
/// bound is 1 % at a/W = 0.1 and 0.5 and 2 % in between (see the closing note of issue 2).
#[test]
fn sent_tada_cmod_shallow_to_half() {
    for (k, bound) in [(1, 1.0), (2, 2.0), (3, 2.0), (4, 2.0), (5, 1.0)] {
        let a = k as f64;
        let scene = case("sent_tall", &[("cracks.0.length", &a.to_string())]);
        let s = solve_bem(&scene);
        let c = s.cracks[0].cmod.unwrap();
        let e = pct(c, sent_cmod(SIGMA, a, W, E));
        println!("a/W {:.1}: CMOD {e:+.3} % vs formula", a / W);
        assert!(e.abs() < bound, "a/W {}: {e}", a / W);
    }
}
