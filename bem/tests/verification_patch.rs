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

/// Max displacement-difference error of the uniform-tension patch (relative to sigma/E),
/// the condition estimate and the number of rigid modes removed.
fn patch_errors(h: f64, reconstruct: bool) -> (f64, f64, f64) {
    let mat = steel();
    let sigma = 0.5;
    let mesh = build(vec![rect_loop(0.0, 0.0, 1.0, 1.0, h)], vec![]);
    let bcs = traction_from_stress(&mesh, [sigma, 0.0, 0.0], 1.0);
    let params = SolveParams {
        reconstruct,
        ..Default::default()
    };
    let sys = BemSystem::new(&mesh, &mat, &bcs, &params).unwrap();
    let sol = sys.solve().unwrap();
    let exact = |p: V2| [sigma * p.x / mat.e, -mat.nu * sigma * p.y / mat.e];
    // Compare displacement differences (gauge free) against the exact field.
    let (p0, u0) = (mesh.elements[0].mid, sol.u[0]);
    let e0 = exact(p0);
    let mut err: f64 = 0.0;
    for (e, u) in mesh.elements.iter().zip(&sol.u) {
        let ex = exact(e.mid);
        let d = [
            (u[0] - u0[0]) - (ex[0] - e0[0]),
            (u[1] - u0[1]) - (ex[1] - e0[1]),
        ];
        err = err.max(d[0].hypot(d[1]));
    }
    (
        err / (sigma / mat.e),
        sys.info().condition,
        sys.info().rigid_modes as f64,
    )
}

/// Plain constant elements: O(h). Measured: 1.232e-2, 6.317e-3, 3.233e-3 (rates 0.963,
/// 0.967), condition 52, 104, 208.
#[test]
fn uniform_tension_patch_converges_at_order_one_and_is_well_conditioned() {
    let hs = [0.1, 0.05, 0.025];
    let res: Vec<(f64, f64, f64)> = hs.iter().map(|&h| patch_errors(h, false)).collect();
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

/// With the linear reconstruction on straight sides the linear patch field is reproduced to
/// round-off (measured 3.7e-13, 3.5e-14, 4.0e-14).
#[test]
fn uniform_tension_patch_is_exact_with_linear_reconstruction() {
    for h in [0.1, 0.05, 0.025] {
        let (e, c, _) = patch_errors(h, true);
        println!("h = {h}: relative error {e:.3e}, cond {c:.1}");
        assert!(e < 1e-10, "error {e}");
        assert!(c < 1e3);
    }
}

/// Measured condition estimates: 104 with beta = -h/E, 4307 with +h/E (h = 0.05).
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
    println!(
        "cond good {:.1} bad {:.1}",
        good.info().condition,
        bad.info().condition
    );
    assert!(bad.info().condition > 10.0 * good.info().condition);
}

/// A prescribed rigid rotation must give zero traction. Plain constant elements leave
/// about 0.22 mu omega at the worst element whatever h (measured 0.220, 0.218, 0.217: the
/// defect behind the slow convergence of deep edge cracks); the linear reconstruction
/// removes it (measured 3e-13).
#[test]
fn rigid_rotation_gives_zero_traction_only_with_reconstruction() {
    for (reconstruct, h) in [(false, 0.1), (false, 0.025), (true, 0.1), (true, 0.025)] {
        let mesh = build(vec![rect_loop(-0.5, -0.5, 1.0, 1.0, h)], vec![]);
        let w = 1e-3;
        let bcs: Vec<[Bc; 2]> = mesh
            .elements
            .iter()
            .map(|e| {
                [
                    Bc::Displacement(-w * e.mid.y),
                    Bc::Displacement(w * e.mid.x),
                ]
            })
            .collect();
        let params = SolveParams {
            reconstruct,
            ..Default::default()
        };
        let sys = BemSystem::new(&mesh, &steel(), &bcs, &params).unwrap();
        let sol = sys.solve().unwrap();
        let mu = steel().mu();
        let tmax = sol.t.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        let trms =
            (sol.t.iter().flatten().map(|v| v * v).sum::<f64>() / (2 * mesh.len()) as f64).sqrt();
        let rel = tmax / (mu * w);
        println!(
            "reconstruct {reconstruct} h={h}: max |t|/(mu w) = {rel:.3e}, rms {:.3e}",
            trms / (mu * w)
        );
        if reconstruct {
            assert!(rel < 1e-10);
        } else {
            assert!(rel > 0.1);
        }
    }
}

/// A further right-hand side through the kept factorization equals a fresh assembly
/// (on the benchmark SENT plate: needs the `bench` feature, which the workspace build
/// enables through the root package).
#[cfg(feature = "bench")]
#[test]
fn further_rhs_matches_fresh_assembly() {
    let (mesh, bcs, loaded) = pdbem_bem::bench::sent_plate(300).unwrap();
    let mat = steel();
    let params = SolveParams {
        variable_groups: loaded,
        ..Default::default()
    };
    let sys = BemSystem::new(&mesh, &mat, &bcs, &params).unwrap();
    let new: Vec<[Bc; 2]> = bcs
        .iter()
        .map(|b| [Bc::Traction(b[0].value() * 2.5), b[1]])
        .collect();
    let again = sys.solve_with(&new).unwrap();
    // The precomputed response gives the same solution without a substitution.
    let pre = BemSystem::new(
        &mesh,
        &mat,
        &bcs,
        &SolveParams {
            precompute_response: true,
            ..params.clone()
        },
    )
    .unwrap()
    .solve_with(&new)
    .unwrap();
    for (a, b) in pre.u.iter().zip(&again.u) {
        assert!(
            (a[0] - b[0]).abs() + (a[1] - b[1]).abs()
                < 1e-9 * (a[0].abs() + a[1].abs() + 1e-30) + 1e-18
        );
    }
    let fresh = BemSystem::new(&mesh, &mat, &new, &SolveParams::default())
        .unwrap()
        .solve()
        .unwrap();
    let c = pdbem_bem::post::sif::cmod(&mesh, &again, 0).unwrap();
    let cf = pdbem_bem::post::sif::cmod(&mesh, &fresh, 0).unwrap();
    assert!((c - cf).abs() < 1e-10 * cf.abs(), "{c} vs {cf}");
    // Changing a non-variable group must be refused.
    let mut bad = bcs.clone();
    let top = mesh.group("top").unwrap();
    let i = mesh.group_elements(top).next().unwrap();
    bad[i][1] = Bc::Traction(1.0);
    assert!(sys.solve_with(&bad).is_err());
}
