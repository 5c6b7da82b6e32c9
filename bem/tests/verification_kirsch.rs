//! Kirsch: circular hole in an infinite plate under remote uniaxial tension.
mod common;

use common::*;
use pdbem_bem::post::{Background, FieldEvaluator};
use pdbem_bem::{BemSystem, SolveParams, V2};

#[test]
fn kirsch_hole_peak_stress() {
    let mat = steel();
    let sigma = 1.0;
    let mesh = build(vec![circle_loop(V2::zeros(), 1.0, 256, true)], vec![]);
    let remote = [sigma, 0.0, 0.0];
    let bcs = traction_from_stress(&mesh, remote, -1.0);
    let params = SolveParams {
        infinite: true,
        ..Default::default()
    };
    let sys = BemSystem::new(&mesh, &mat, &bcs, &params).unwrap();
    let sol = sys.solve().unwrap();
    let ev = FieldEvaluator::new(&mesh, &mat, &sol, Background { stress: remote });
    let hoop = ev.boundary_hoop_stress(0);
    let mut worst: f64 = 0.0;
    let mut peak: f64 = 0.0;
    for (p, s) in &hoop {
        let th = p.y.atan2(p.x);
        let exact = sigma * (1.0 - 2.0 * (2.0 * th).cos());
        worst = worst.max((s - exact).abs());
        peak = peak.max(*s);
    }
    println!(
        "peak hoop {peak:.5} (exact 3), max abs error {worst:.3e}, cond {:.1}",
        sys.info().condition
    );
    // Issue bound: 1 %. Measured: peak 2.99999, worst 5.9e-4 (2.9984 and 4.8e-3 with plain
    // constant elements on the circle).
    assert!((peak - 3.0).abs() < 3e-3);
    assert!(worst < 2e-3);
    assert!(sys.info().condition < 1e3);
    // Interior point check: sigma_xx at (0, 2) = sigma (1 + a^2/(2r^2) + 3a^4/(2r^4)) = 1.21875.
    let s = ev.stress(V2::new(0.0, 2.0));
    println!("sigma_xx(0,2) = {:.6}", s[0]);
    // Measured 1.218768 (1.5e-5 off).
    assert!((s[0] - 1.21875).abs() < 1e-4);
}
