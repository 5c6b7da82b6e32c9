//! Several PD windows in one BEM body (issue 4): the inclined central crack of
//! `cases/coupled_inclined_crack_two_windows.ron` with one window per tip. Both windows
//! share one BEM system (one factorization) and are solved in parallel each iteration.
//! Checks: K_I, K_II and the kink angle at both tips against the BEM-only solve of the
//! same plate, and the point symmetry of the problem (both tips alike).

use pdbem::scene::Scene;

#[test]
fn two_tip_windows_match_bem_alone_at_both_tips() {
    let scene = Scene::load("cases/coupled_inclined_crack_two_windows.ron").unwrap();
    let setup = pdbem::setup::coupled::prepare(&scene).unwrap();
    assert_eq!(setup.problem.windows.len(), 2, "one window per tip");
    let (coupled, out) = pdbem::run_coupled::solve(&scene).unwrap();
    assert!(out.info.converged);
    let mut plain = scene.clone();
    plain.pd = None;
    plain.coupling = None;
    let (bem, _) = pdbem::run_bem::solve(&plain).unwrap();
    // Measured: K_I +0.20 %, K_II +0.36 %, kink 0.03 degrees from BEM alone at both
    // tips (640 BEM-only elements; 1120 elements change BEM alone by 2e-5). Before the
    // crack-face correction took its directions in the window's lattice frame (along the
    // crack) instead of the global one, +0.25 % and +0.04 %: a frame-dependent result
    // (`tests/verification_invariance.rs`); without the correction +0.33 % and +0.94 %. The two tips
    // agree to 1e-12; 10 IQN-ILS iterations (12 before the QR2 filter). Both are +5.1 %
    // (K_I) above the infinite-plate value: the finite plate (2a/W = 0.2).
    for t in &coupled.tips {
        let b = bem.tips.iter().find(|b| b.name == t.name).unwrap();
        let (e1, e2) = (t.k1 / b.k1 - 1.0, t.k2 / b.k2 - 1.0);
        println!(
            "{}: K_I {:.5} (BEM {:.5}, {e1:+.4}), K_II {:.5} (BEM {:.5}, {e2:+.4}), kink {:.2} (BEM {:.2})",
            t.name, t.k1, b.k1, t.k2, b.k2, t.kink_deg, b.kink_deg
        );
        assert!(e1.abs() < 0.01 && e2.abs() < 0.01, "{}: {e1} {e2}", t.name);
        assert!((t.kink_deg - b.kink_deg).abs() < 0.5, "{}", t.name);
    }
    let (a, b) = (&coupled.tips[0], &coupled.tips[1]);
    assert!((a.k1 - b.k1).abs() < 1e-6 * a.k1 && (a.k2 - b.k2).abs() < 1e-6 * a.k2);
    assert!(out.info.iterations <= 12, "{}", out.info.iterations);
}
