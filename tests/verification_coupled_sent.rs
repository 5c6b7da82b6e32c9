//! Seed 002 section 3.2.1, Tables 3-5: the SENT plate (20 m x 10 m, E = 1e4 Pa,
//! nu = 1/3, 0.5 Pa) with a 2 m PD window on the tip, CMOD against the Tada formula and
//! against the BEM-only solve of the same mesh size (sent_bem_a*.ron).

use std::time::Instant;

use pdbem::runner::reference::cmod_reference;
use pdbem::scene::Scene;

fn cmod_error(scene: &Scene, cmod: f64) -> f64 {
    let (_, r) = cmod_reference(scene).unwrap();
    (cmod - r).abs() / r
}

/// (coupled CMOD error, BEM-only CMOD error, coupled iterations, coupled wall time).
fn compare(a: usize) -> (f64, f64, usize, f64) {
    let coupled = Scene::load(format!("cases/coupled_sent_a{a}.ron")).unwrap();
    let t0 = Instant::now();
    let (s, out) = pdbem::run_coupled::solve(&coupled).unwrap();
    let wall = t0.elapsed().as_secs_f64();
    let ec = cmod_error(&coupled, s.cracks[0].cmod.unwrap());
    let bem = Scene::load(format!("cases/sent_bem_a{a}.ron")).unwrap();
    let (sb, _) = pdbem::run_bem::solve(&bem).unwrap();
    let eb = cmod_error(&bem, sb.cracks[0].cmod.unwrap());
    println!(
        "a = {a}: coupled {ec:.4} ({} iterations, {wall:.2} s), BEM only {eb:.4}",
        out.info.iterations
    );
    (ec, eb, out.info.iterations, wall)
}

#[test]
fn seed002_table3_cmod_a2_a5() {
    // Measured CMOD errors, coupled / BEM only: a = 2: 0.0174 / 0.0179; a = 5: 0.0102 /
    // 0.0048 (12 and 11 IQN-ILS iterations). The issue: at most 1 percentage point above
    // BEM only. Before the PD pre-crack ends were made open and its faces corrected
    // (pdbem_pd::geometry::segment_crosses_crack, pdbem_pd::surface), 0.0433 and 0.0292.
    // Wall time is measured by `pdbem bench coupling`, not here.
    let (ec, eb, it, _) = compare(2);
    assert!(ec < eb + 0.01 && ec < 0.02 && it <= 12, "{ec} {eb} {it}");
    let (ec, eb, it, _) = compare(5);
    assert!(ec < eb + 0.01 && ec < 0.012 && it <= 11, "{ec} {eb} {it}");
}

#[test]
fn seed002_table5_cmod_a8_beats_the_seed() {
    // 40 x 40 points (seed Table 5 case 3), 1640 elements. Measured: error 0.0068 in 12
    // IQN-ILS iterations (17 before the QR2 filter and the relaxed quasi-Newton step of
    // pdbem_coupling::relaxation; about 3 s, see `pdbem bench coupling`); BEM only on the
    // same element size 0.0063; seed 002 Table 5: 4.03 % in 862 s. The count is
    // deterministic; 12 is the bound (the Krylov bound is 10, see the docs of
    // pdbem_coupling::relaxation).
    let (ec, eb, it, _) = compare(8);
    assert!(ec < 0.0403, "{ec}");
    assert!(ec < eb + 0.01, "{ec} vs BEM {eb}");
    assert!(it <= 12, "{it}");
}

/// Aitken at psi = 1e-3 on `coupled_sent_a{a}`: (iterations, CMOD change against the
/// scene's own psi = 1e-4 IQN-ILS solve).
fn aitken_at_psi_1e_3(a: usize) -> (usize, f64) {
    let scene = Scene::load(format!("cases/coupled_sent_a{a}.ron")).unwrap();
    let (tight, _) = pdbem::run_coupled::solve(&scene).unwrap();
    let mut setup = pdbem::setup::coupled::prepare(&scene).unwrap();
    setup.params.psi = 1e-3;
    setup.params.acceleration = pdbem_coupling::Acceleration::Aitken(0.3);
    let out = pdbem::run_coupled::solve_setup(setup).unwrap();
    let loose = pdbem::run_coupled::summarize(&scene, &out).unwrap();
    let (c0, c1) = (tight.cracks[0].cmod.unwrap(), loose.cracks[0].cmod.unwrap());
    let change = c1 / c0 - 1.0;
    println!(
        "a = {a}: aitken {} iterations, CMOD change {change:.2e}",
        out.info.iterations
    );
    (out.info.iterations, change)
}

#[test]
fn aitken_within_the_seeds_fifteen_iterations_at_psi_1e_3() {
    // Seed 002 bounds its iterations by 15 with Psi = 1e-2 m absolute (larger than the
    // CMOD itself here); at our default psi = 1e-4 relative Aitken needs 19 / 16 / 12 (a8:
    // handed over to IQN-ILS; 35 before the safeguard), IQN-ILS 12 / 11 / 12. At psi =
    // 1e-3 relative, measured: Aitken 15 / 12, IQN-ILS 10 / 8 / 12; the CMOD moves by
    // 4.9e-5 / 2.3e-5 from the psi = 1e-4 value.
    for a in [2, 5] {
        let (it, change) = aitken_at_psi_1e_3(a);
        assert!(it <= 15, "a = {a}: {it}");
        assert!(change.abs() < 1e-3, "a = {a}: {change}");
    }
}

#[test]
fn aitken_at_a8_is_bounded_by_the_interface_spectrum() {
    // The 15-iteration bound does not hold at a/W = 0.8 for any single-weight
    // relaxation: the interface operator has Ritz values -38.4 and -19.5 (the BEM body
    // hinging on its 1 m ligament under the window is 40 times softer than the PD window
    // in that mode) above a bulk in [-5.4, 0], against [-3.4, 0] for the plate window.
    // The best constant weight then contracts by 0.95 per iteration (135 iterations
    // for 1e-3); Aitken's secant weights alone took 25 (38 with the weight clamped at
    // 1e-3 instead of kept); safeguarded, its first step jumps tenfold and IQN-ILS takes
    // over: 12 (see pdbem_coupling::relaxation). Seed 002 itself reports 36 steps
    // (Table 3) and 44 / 59 (Table 5) with constant w = 0.1 / 0.06 for this plate.
    let scene = Scene::load("cases/coupled_sent_a8.ron").unwrap();
    let mut setup = pdbem::setup::coupled::prepare(&scene).unwrap();
    let bem = pdbem_coupling::PreparedBem::new(&mut setup.problem).unwrap();
    let ritz =
        pdbem_coupling::spectrum::ritz_values(&mut setup.problem, &bem, &setup.params, 40).unwrap();
    println!("a = 8 Ritz values: {:?}", &ritz[..6]);
    assert!(
        ritz.iter().all(|r| r.0 < 0.05 && r.1.abs() < 0.05),
        "{ritz:?}"
    );
    assert!(ritz[0].0 < -30.0 && ritz[1].0 < -15.0, "{ritz:?}");
    let lambda: Vec<f64> = ritz.iter().map(|r| r.0).collect();
    let (_, factor) = pdbem_coupling::spectrum::best_constant_weight(&lambda).unwrap();
    let constant_iterations = (1e-3f64).ln() / factor.ln();
    assert!(
        constant_iterations > 100.0,
        "{factor} {constant_iterations}"
    );
    let (it, change) = aitken_at_psi_1e_3(8);
    assert!(it <= 12, "{it}");
    assert!(change.abs() < 1e-3, "{change}");
}

#[test]
fn plate_window_spectrum_allows_fast_relaxation() {
    // The contrast case: a window in an intact plate sees a bulk of Ritz values in
    // [-3.4, 0] (measured -3.357 first), so one weight serves every mode.
    let scene = Scene::load("cases/coupled_plate_window_center.ron").unwrap();
    let mut setup = pdbem::setup::coupled::prepare(&scene).unwrap();
    let bem = pdbem_coupling::PreparedBem::new(&mut setup.problem).unwrap();
    let ritz =
        pdbem_coupling::spectrum::ritz_values(&mut setup.problem, &bem, &setup.params, 30).unwrap();
    println!("plate Ritz values: {:?}", &ritz[..4]);
    assert!(ritz[0].0 > -4.0 && ritz[0].0 < -2.5, "{ritz:?}");
    assert!(ritz.iter().all(|r| r.0 < 0.05), "{ritz:?}");
}

/// `coupled_sent_a8` at its psi = 1e-4 with `acceleration`: (K_I at the tip, iterations,
/// the solve's notes). Panics when the solve does not converge within `max_iter`.
fn a8_with(acceleration: pdbem_coupling::Acceleration) -> (f64, usize, Vec<String>) {
    let scene = Scene::load("cases/coupled_sent_a8.ron").unwrap();
    let mut setup = pdbem::setup::coupled::prepare(&scene).unwrap();
    setup.params.acceleration = acceleration;
    let out = pdbem::run_coupled::solve_setup(setup).unwrap();
    let summary = pdbem::run_coupled::summarize(&scene, &out).unwrap();
    println!(
        "{acceleration:?}: {} iterations, K_I {:.7e}, notes {:?}",
        out.info.iterations, summary.tips[0].k1, summary.notes
    );
    assert_eq!(summary.notes, out.info.notes, "notes reach the summary");
    (summary.tips[0].k1, out.info.iterations, out.info.notes)
}

#[test]
fn aitken_safeguard_converges_at_a8_from_small_and_unit_weights() {
    // Before the safeguard (restart on a jump, hand-over to IQN-ILS) Aitken from w0 = 0.05
    // and 1 did not converge in 50 iterations (residual 4.2e-2 / 3.3e-4 at 50). Measured
    // with it: 21 iterations from 0.05 (restart after iteration 8, hand-over after 12),
    // 12 from 1 (its first step jumps 39-fold, hand-over after 2); K_I 2.2e-5 / 4.5e-5
    // from IQN-ILS's (scene w0 = 0.5), within psi = 1e-4.
    use pdbem_coupling::Acceleration;
    let (k_ref, _, _) = a8_with(Acceleration::IqnIls(0.5));
    for (w0, bound) in [(0.05, 21), (1.0, 12)] {
        let (k, it, notes) = a8_with(Acceleration::Aitken(w0));
        assert!(it <= bound, "w0 {w0}: {it} iterations");
        assert!(
            (k / k_ref - 1.0).abs() < 1e-4,
            "w0 {w0}: K_I {k} vs {k_ref}"
        );
        assert!(
            notes
                .last()
                .is_some_and(|n| n.contains("handed over to IQN-ILS")),
            "w0 {w0}: {notes:?}"
        );
    }
}

#[test]
fn coupled_k_and_cmod_carry_an_estimate_that_bounds_their_error() {
    // The coupled K and CMOD of coupled_sent_a5 against an independent, finer BEM solve of
    // the same plate: all element sizes / 4 (3210 elements; its own estimate from the
    // level below, 5.5e-4 relative, widens the bound). Measured: coupled K_I 0.43 % off
    // with an estimate of 0.69 %. An estimate without its BEM-alone term would be the
    // floor (0.02 %) and fail here.
    let coupled = Scene::load("cases/coupled_sent_a5.ron").unwrap();
    let (s, _) = pdbem::run_coupled::solve(&coupled).unwrap();
    let bem = Scene::load("cases/sent_bem_a5.ron").unwrap();
    let fine = pdbem::run_bem::level::solve_level(&bem, 1.0, 4.0).unwrap();
    let below = pdbem::run_bem::level::solve_level(&bem, 1.0, 2.0).unwrap();
    let (t, r, r2) = (&s.tips[0], &fine.tips[0], &below.tips[0]);
    let est = t.k1_err_est.expect("coupled K_I estimate");
    let err = (t.k1 - r.k1).abs();
    let slack = (r.k1 - r2.k1).abs();
    println!(
        "K_I {:.6} finer BEM {:.6} ({} elements): error {:.3e}, estimate {:.3e} (slack {:.3e})",
        t.k1,
        r.k1,
        fine.setup.mesh.len(),
        err,
        est,
        slack
    );
    assert!(
        err <= est + slack,
        "K_I error {err} over the estimate {est}"
    );
    assert!(est >= err / 3.0 && est <= 0.01 * t.k1, "estimate {est}");
    let (v, rv) = (s.cracks[0].cmod.unwrap(), fine.cracks[0].cmod.unwrap());
    let rv2 = below.cracks[0].cmod.unwrap();
    let est = s.cracks[0].cmod_err_est.expect("coupled CMOD estimate");
    println!("CMOD {v:.6e} finer BEM {rv:.6e}: estimate {est:.3e}");
    assert!((v - rv).abs() <= est + (rv - rv2).abs());
    assert!(est <= 0.01 * v);
}
