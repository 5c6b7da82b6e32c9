//! J and G next to K (issue 19): every tip of a run carries the contour J-integral of the
//! solved field (`j`, no auxiliary field) and G = (K_I^2 + K_II^2) / E' of its reported K
//! (`g`), in `summary.json` and `tips.csv`. In linear elastic fracture mechanics both
//! equal the analytic G_ref = (K_I,ref^2 + K_II,ref^2) / E' of the scene's reference.
mod common_scene;

use common_scene::*;

/// Runs `name` through the runner (which sets `g`) and checks J and G of every tip
/// against G_ref within `tol_pct` per cent, and J against G within `tol_pct`.
fn check(name: &str, tol_pct: f64) {
    let scene = case(name, &[]);
    let dir = std::env::temp_dir().join(format!("pdbem-jg-{name}-{}", std::process::id()));
    let s = pdbem::runner::run_scene(&scene, &dir, true).unwrap();
    let e_prime = scene.material.e_prime();
    assert!(!s.tips.is_empty());
    for t in &s.tips {
        let (j, g) = (t.j.unwrap(), t.g.unwrap());
        let g_ref = (t.k1_ref.unwrap().powi(2) + t.k2_ref.unwrap().powi(2)) / e_prime;
        println!(
            "{name} {}: J {j:.5e}, G {g:.5e}, G_ref {g_ref:.5e} J/m^2 (J {:+.3} %, G {:+.3} %)",
            t.name,
            pct(j, g_ref),
            pct(g, g_ref)
        );
        assert!(pct(j, g_ref).abs() < tol_pct, "{name} {}: J", t.name);
        assert!(pct(g, g_ref).abs() < tol_pct, "{name} {}: G", t.name);
        assert!(pct(j, g).abs() < tol_pct, "{name} {}: J - G", t.name);
    }
    let csv = std::fs::read_to_string(dir.join("tips.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert!(header.contains(&"j") && header.contains(&"g"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Inclined crack in an infinite plate (mixed mode, K_I = K_II). Measured: J +0.29 %,
/// G -0.01 % against G_ref.
#[test]
fn inclined_crack_j_and_g_equal_the_mixed_mode_energy_release_rate() {
    check("inclined_crack_45", 1.0);
}

/// SENT a/W = 0.5 against Tada's K (0.5 % accurate at this a/W, so 1 % in G): measured
/// J -0.68 %, G -0.38 % against G_ref, J - G -0.30 % of G.
#[test]
fn sent_j_and_g_equal_the_energy_release_rate() {
    check("sent_bem_a5", 1.5);
}
