//! Invariants and the uniform-stress patch test on a square plate.
mod common;

use common::*;
use pdbem_bem::{Bc, BemSystem, SolveParams, V2};

#[test]
fn rigid_translation_gives_zero_traction() {
    let mesh = build(vec![rect_loop(0.0, 0.0, 1.0, 1.0, 0.05)], vec![]);
    let bcs = vec![[Bc::Displacement(1e-3), Bc::Displacement(-2e-3)]; mesh.len()];
    let sys = BemSystem::new(&mesh, &steel(), &bcs, &SolveParams::default()).unwrap();
    let sol = sys.solve().unwrap();
    // Traction scale of a strain 1e-3 in E = 1e4: 10 Pa.
    let tmax = sol.t.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(tmax / 10.0 < 1e-10, "max traction {tmax}");
}

/// Fits u_x = a x + c (u_y likewise) over the boundary nodes and returns the slope errors.
fn patch_errors(h: f64) -> (f64, f64, f64) {
    let mat = steel();
    let sigma = 0.5;
    let mesh = build(vec![rect_loop(0.0, 0.0, 1.0, 1.0, h)], vec![]);
    let bcs = traction_from_stress(&mesh, [sigma, 0.0, 0.0], 1.0);
    let sys = BemSystem::new(&mesh, &mat, &bcs, &SolveParams::default()).unwrap();
    let sol = sys.solve().unwrap();
    let exact = |p: V2| [sigma * p.x / mat.e, -mat.nu * sigma * p.y / mat.e];
    // Compare displacement differences (gauge free) against the exact field.
    let (p0, u0) = (mesh.elements[0].mid, sol.u[0]);
    let e0 = exact(p0);
    let mut err: f64 = 0.0;
    for (e, u) in mesh.elements.iter().zip(&sol.u) {
        let ex = exact(e.mid);
        let d = [(u[0] - u0[0]) - (ex[0] - e0[0]), (u[1] - u0[1]) - (ex[1] - e0[1])];
        err = err.max(d[0].hypot(d[1]));
    }
    (err / (sigma / mat.e), sys.info().condition, sys.info().rigid_modes as f64)
}

#[test]
fn uniform_tension_patch_converges_at_order_one_and_is_well_conditioned() {
    let hs = [0.1, 0.05, 0.025];
    let res: Vec<(f64, f64, f64)> = hs.iter().map(|&h| patch_errors(h)).collect();
    for (h, (e, c, r)) in hs.iter().zip(&res) {
        println!("h = {h}: relative displacement error {e:.3e}, cond1 {c:.1}, rigid modes {r}");
        assert!(*c < 1e3, "condition {c}");
        assert_eq!(*r, 3.0);
    }
    let rate = (res[1].0 / res[2].0).ln() / 2f64.ln();
    let rate0 = (res[0].0 / res[1].0).ln() / 2f64.ln();
    println!("observed rates {rate0:.3}, {rate:.3}");
    assert!(rate > 0.8 && rate < 1.5, "rate {rate}");
    assert!(res[2].0 < 0.05);
}

#[test]
fn wrong_beta_sign_degrades_conditioning() {
    let mesh = build(vec![rect_loop(0.0, 0.0, 1.0, 1.0, 0.05)], vec![]);
    let bcs = traction_from_stress(&mesh, [1.0, 0.0, 0.0], 1.0);
    let good = BemSystem::new(&mesh, &steel(), &bcs, &SolveParams::default()).unwrap();
    let bad_params = SolveParams {
        beta_factor: 1.0,
        ..Default::default()
    };
    let bad = BemSystem::new(&mesh, &steel(), &bcs, &bad_params).unwrap();
    println!("cond good {:.1} bad {:.1}", good.info().condition, bad.info().condition);
    assert!(bad.info().condition > 10.0 * good.info().condition);
}
