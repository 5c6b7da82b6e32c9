//! Inclined central crack in an infinite plate under uniaxial tension:
//! K_I = sigma sqrt(pi a) sin^2(beta), K_II = sigma sqrt(pi a) sin(beta) cos(beta).
mod common;

use common::*;
use pdbem_bem::mesh::FaceMode;
use pdbem_bem::post::sif::{analyze_tips, SifOptions};
use pdbem_bem::post::{Background, FieldEvaluator};
use pdbem_bem::{BemSystem, SolveParams, V2};
use std::f64::consts::PI;

fn solve(faces: FaceMode, n_per_face: usize) -> Vec<pdbem_bem::post::TipResult> {
    let mat = steel();
    let a = 1.0;
    let beta = PI / 4.0;
    let d = V2::new(beta.cos(), beta.sin());
    // Load along y; crack line at 45 degrees to it.
    let remote = [0.0, 1.0, 0.0];
    let mesh = build(
        vec![],
        vec![crack(
            "c",
            -a * d,
            a * d,
            2.0 * a / n_per_face as f64,
            faces,
        )],
    );
    let bcs = traction_from_stress(&mesh, remote, -1.0);
    let params = SolveParams {
        infinite: true,
        ..Default::default()
    };
    let sys = BemSystem::new(&mesh, &mat, &bcs, &params).unwrap();
    let sol = sys.solve().unwrap();
    println!("cond {:.1}", sys.info().condition);
    let ev = FieldEvaluator::new(&mesh, &mat, &sol, Background { stress: remote });
    analyze_tips(&mesh, &ev, &sol, &SifOptions::default()).unwrap()
}

#[test]
fn inclined_crack_45_sif_and_kink() {
    let k0 = (PI * 1.0_f64).sqrt();
    let (k1e, k2e) = (0.5 * k0, 0.5 * k0);
    for t in solve(FaceMode::Coincident, 160) {
        println!("{t:?}");
        for (k1, k2) in [(t.k1_cod, t.k2_cod), (t.k1_m, t.k2_m)] {
            assert!((k1 - k1e).abs() / k1e < 0.005, "k1 {k1} vs {k1e}");
            assert!((k2.abs() - k2e).abs() / k2e < 0.005, "k2 {k2} vs {k2e}");
        }
        assert!(
            (t.kink_deg.abs() - 53.13).abs() < 0.2,
            "kink {}",
            t.kink_deg
        );
    }
}
