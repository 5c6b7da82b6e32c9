//! Infinite-plate scenes by superposition: `inclined_crack_45` (K_I = K_II =
//! sigma sqrt(pi a)/2, kink -53.13 deg) and `kirsch_hole` (peak hoop stress 3 sigma).
mod common_scene;

use common_scene::*;
use std::f64::consts::PI;

/// Issue bounds 0.5 % and 0.2 deg. Measured -0.004 % (both), kink -53.13.
#[test]
fn inclined_crack_45_infinite_plate() {
    let s = solve_bem(&case("inclined_crack_45", &[]));
    let k = (PI * 1.0_f64).sqrt() / 2.0;
    assert_eq!(s.tips.len(), 2);
    for t in &s.tips {
        println!(
            "{}: K_I {:+.4} % K_II {:+.4} % kink {:.3}",
            t.name,
            pct(t.k1, k),
            pct(t.k2.abs(), k),
            t.kink_deg
        );
        assert!(pct(t.k1, k).abs() < 0.5 && pct(t.k2.abs(), k).abs() < 0.5);
        assert!(pct(t.k1_j.unwrap(), k).abs() < 0.5 && pct(t.k2_j.unwrap().abs(), k).abs() < 0.5);
        assert!((t.kink_deg.abs() - 53.130).abs() < 0.2);
    }
}

/// Issue bound 1 %. Measured peak 3.00009 sigma with 256 elements.
#[test]
fn kirsch_hole_peak_hoop_stress() {
    let scene = case("kirsch_hole", &[]);
    let ctxdir = std::env::temp_dir().join(format!("pdbem-kirsch-{}", std::process::id()));
    let s = pdbem::runner::run_scene(&scene, &ctxdir, true).unwrap();
    let peak = s.extra["hoop_peak"].as_f64().unwrap();
    println!("peak hoop stress {peak:.5}");
    assert!((peak - 3.0).abs() < 0.03);
    assert!(ctxdir.join("hoop_hole.csv").exists() && ctxdir.join("summary.json").exists());
    let _ = std::fs::remove_dir_all(&ctxdir);
}
