//! Several PD windows in one BEM body (issue 4): the inclined central crack of
//! `cases/coupled_inclined_crack_two_windows.ron` with one window per tip. Both windows
//! share one BEM system (one factorization) and are solved in parallel each iteration.
//! Checks: K_I, K_II and the kink angle at both tips against the BEM-only solve of the
//! same plate, and the point symmetry of the problem (both tips alike). The same plate
//! with refined state-based windows (`cases/coupled_inclined_crack_refined.ron`): the
//! zone turns with the window.

use pdbem::scene::Scene;

/// The BEM-only solve of `scene` (its `pd` and `coupling` removed).
fn bem_alone(scene: &Scene) -> pdbem::runner::summary::RunSummary {
    let mut plain = scene.clone();
    plain.pd = None;
    plain.coupling = None;
    pdbem::run_bem::solve(&plain).unwrap().0
}

/// Solve `scene` coupled and alone; assert one window per tip, convergence in at most
/// `max_iter` IQN-ILS iterations, K_I and K_II within `tol` (relative) of BEM alone at
/// both tips and within each tip's own error estimates, the kink within `kink_deg`, and
/// both tips alike (the point symmetry).
fn against_bem_alone(scene: &Scene, tol: f64, kink_deg: f64, max_iter: usize) {
    let setup = pdbem::setup::coupled::prepare(scene).unwrap();
    assert_eq!(setup.problem.windows.len(), 2, "one window per tip");
    let (coupled, out) = pdbem::run_coupled::solve(scene).unwrap();
    assert!(out.info.converged);
    let bem = bem_alone(scene);
    for t in &coupled.tips {
        let b = bem.tips.iter().find(|b| b.name == t.name).unwrap();
        let (e1, e2) = (t.k1 / b.k1 - 1.0, t.k2 / b.k2 - 1.0);
        println!(
            "{}: K_I {:.5} (BEM {:.5}, {e1:+.4}), K_II {:.5} (BEM {:.5}, {e2:+.4}), kink {:.2} (BEM {:.2})",
            t.name, t.k1, b.k1, t.k2, b.k2, t.kink_deg, b.kink_deg
        );
        assert!(e1.abs() < tol && e2.abs() < tol, "{}: {e1} {e2}", t.name);
        let (est1, est2) = (t.k1_err_est.unwrap(), t.k2_err_est.unwrap());
        assert!(
            (t.k1 - b.k1).abs() <= est1 && (t.k2 - b.k2).abs() <= est2,
            "{}: beyond its estimates {est1} {est2}",
            t.name
        );
        assert!((t.kink_deg - b.kink_deg).abs() < kink_deg, "{}", t.name);
    }
    let (a, b) = (&coupled.tips[0], &coupled.tips[1]);
    assert!((a.k1 - b.k1).abs() < 1e-6 * a.k1 && (a.k2 - b.k2).abs() < 1e-6 * a.k2);
    assert!(out.info.iterations <= max_iter, "{}", out.info.iterations);
}

#[test]
fn two_tip_windows_match_bem_alone_at_both_tips() {
    // Measured: K_I +0.20 %, K_II +0.36 %, kink 0.03 degrees from BEM alone at both
    // tips (640 BEM-only elements; 1120 elements change BEM alone by 2e-5). Before the
    // crack-face correction took its directions in the window's lattice frame (along the
    // crack) instead of the global one, +0.25 % and +0.04 %: a frame-dependent result
    // (`tests/verification_invariance.rs`); without the correction +0.33 % and +0.94 %. The two tips
    // agree to 1e-12; 10 IQN-ILS iterations (12 before the QR2 filter). Both are +5.1 %
    // (K_I) above the infinite-plate value: the finite plate (2a/W = 0.2).
    let scene = Scene::load("cases/coupled_inclined_crack_two_windows.ron").unwrap();
    against_bem_alone(&scene, 0.01, 0.5, 12);
}

#[test]
fn refined_windows_on_an_inclined_crack_match_bem_alone() {
    // Measured: K_I +0.04 %, K_II -0.04 %, kink 0.01 degrees from BEM alone at both tips,
    // 12 iterations, 1752 PD nodes. Uniform 0.1 m windows of the same size: +0.06 % and
    // +0.29 %. With the zone square in the global frame (before) this scene was refused:
    // the turned zone reached 0.46 m from the tip instead of 0.35 m.
    let scene = Scene::load("cases/coupled_inclined_crack_refined.ron").unwrap();
    against_bem_alone(&scene, 0.002, 0.1, 14);
}
