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
    // 40 x 40 points (seed Table 5 case 3), 1640 elements. Measured: error 0.0068 in 17
    // IQN-ILS iterations (about 3 s, see `pdbem bench coupling`); BEM only on the same
    // element size 0.0063; seed 002 Table 5: 4.03 % in 862 s.
    let (ec, eb, it, _) = compare(8);
    assert!(ec < 0.0403, "{ec}");
    assert!(ec < eb + 0.01, "{ec} vs BEM {eb}");
    assert!(it <= 17, "{it}");
}

#[test]
fn aitken_within_the_seeds_fifteen_iterations_at_psi_1e_3() {
    // Seed 002 bounds its iterations by 15 with Psi = 1e-2 m absolute (larger than the
    // CMOD itself here); at our default psi = 1e-4 relative Aitken needs 19 / 16 and does
    // not converge in 50 at a/W = 0.8, IQN-ILS 12 / 11 / 17. At psi = 1e-3 relative,
    // measured: Aitken 15 / 12 (a/W = 0.8: 40, the bound is NOT met there),
    // IQN-ILS 10 / 9 / 15; the CMOD moves by 8e-5 / 2e-5 from the psi = 1e-4 value.
    for a in [2, 5] {
        let scene = Scene::load(format!("cases/coupled_sent_a{a}.ron")).unwrap();
        let (tight, _) = pdbem::run_coupled::solve(&scene).unwrap();
        let mut setup = pdbem::run_coupled::prepare(&scene).unwrap();
        setup.params.psi = 1e-3;
        setup.params.acceleration = pdbem_coupling::Acceleration::Aitken(0.3);
        let out = pdbem::run_coupled::solve_setup(setup).unwrap();
        let loose = pdbem::run_coupled::summarize(&scene, &out).unwrap();
        let (c0, c1) = (tight.cracks[0].cmod.unwrap(), loose.cracks[0].cmod.unwrap());
        println!(
            "a = {a}: aitken {} iterations, CMOD change {:.2e}",
            out.info.iterations,
            c1 / c0 - 1.0
        );
        assert!(
            out.info.iterations <= 15,
            "a = {a}: {}",
            out.info.iterations
        );
        assert!((c1 / c0 - 1.0).abs() < 1e-3, "a = {a}: {c0} {c1}");
    }
}
