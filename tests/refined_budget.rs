//! The refined ramp within a memory budget (its own test binary: the factor budget is
//! process-wide). Under a budget that holds every split of the refined body (each is
//! checked against it too) but is too small for the preconditioner's pattern or factor
//! (24 MiB: the factor needs 30.6 MiB at its first refusal; 8 MiB, this test's budget
//! before the splits were checked, refuses the body itself),
//! `cases/seed004_edge_crack_initiation_nested.ron` runs by plain conjugate gradients and
//! says so in a note; its first-break and initiation loads are the preconditioned run's
//! (measured 40 and 46 MPa on both; 11 s plain, 3.4 s preconditioned).

use std::path::PathBuf;

use pdbem::scene::Scene;

#[test]
fn refined_ramp_over_the_budget_says_it_ran_plain_conjugate_gradients() {
    let f = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("cases/seed004_edge_crack_initiation_nested.ron");
    let scene = Scene::load(&f).expect("valid case");
    let run = |budget: u64, tag: &str| {
        pdbem_pd::tangent::set_factor_budget(budget);
        let dir = std::env::temp_dir().join(format!("pdbem-budget-{tag}-{}", std::process::id()));
        let s = pdbem::runner::run_scene(&scene, &dir, true).expect("run");
        let _ = std::fs::remove_dir_all(&dir);
        s
    };
    let small = run(24 << 20, "small");
    let big = run(8 << 30, "big");
    let plain = |s: &pdbem::runner::summary::RunSummary| {
        s.notes
            .iter()
            .any(|n| n.contains("plain conjugate gradients") && n.contains("budget"))
    };
    eprintln!("{:?}", small.notes);
    assert!(plain(&small), "{:?}", small.notes);
    assert!(!plain(&big), "{:?}", big.notes);
    for key in ["first_break_load", "initiation_load"] {
        assert_eq!(small.extra[key], big.extra[key], "{key}");
    }
    assert!(small.extra["initiation_load"].as_f64().is_some());
}
