//! Seed 002 sections 3.1.1-3.1.2 (Figs. 10-17): a 1 m x 0.2 m cantilever, left half BEM,
//! right half PD (50 x 20 points), in tension and under end shear. Centre-line
//! displacements (BEM interior points on the left, PD nodes on the right, interfaces
//! included) against the beam solutions: u = sigma x / E (tension, exact) and
//! Timoshenko's v = P (L x^2 / 2 - x^3 / 6) / (E I) + P x / (kappa G A) (shear).

use pdbem::run_coupled::{solve, CoupledOutcome};
use pdbem::scene::Scene;
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::V2;

const E: f64 = 1e11;
const NU: f64 = 1.0 / 3.0;
const H: f64 = 0.2;
const L: f64 = 1.0;

/// Centre-line displacement component `c`: BEM interior points at x < 0.5, and the mean
/// of the two PD node rows next to y = H/2 at x > 0.5. Returns (x, value) pairs.
fn centre_line(out: &CoupledOutcome, c: usize) -> Vec<(f64, f64)> {
    let pb = &out.setup.problem;
    let ev = FieldEvaluator::new(
        &pb.mesh,
        &pb.material,
        &out.solution.solution,
        pb.background,
    );
    let mut pts: Vec<(f64, f64)> = (1..10)
        .map(|k| {
            let x = 0.05 * k as f64;
            (x, ev.displacement(V2::new(x, 0.5 * H))[c])
        })
        .collect();
    let m = &pb.windows[0].model;
    let (pos, u) = (m.positions(), m.displacements());
    for i in 0..m.n_real() {
        if (pos[i][1] - (0.5 * H - 0.005)).abs() < 1e-9 {
            // Partner node one row up.
            let j = (0..m.n_real())
                .find(|&j| {
                    (pos[j][0] - pos[i][0]).abs() < 1e-9
                        && (pos[j][1] - (0.5 * H + 0.005)).abs() < 1e-9
                })
                .unwrap();
            pts.push((pos[i][0], 0.5 * (u[i][c] + u[j][c])));
        }
    }
    pts
}

fn worst(pts: &[(f64, f64)], exact: impl Fn(f64) -> f64) -> f64 {
    let scale = pts.iter().map(|p| exact(p.0).abs()).fold(0.0, f64::max);
    pts.iter()
        .map(|p| (p.1 - exact(p.0)).abs() / scale)
        .fold(0.0, f64::max)
}

#[test]
fn seed002_beam_tension_centre_line() {
    let (s, out) = solve(&Scene::load("cases/coupled_beam_tension.ron").unwrap()).unwrap();
    let err = worst(&centre_line(&out, 0), |x| 1e8 * x / E);
    println!(
        "tension: {} iterations, centre-line error {err:.5}",
        out.info.iterations
    );
    // Measured 0.0126 of the end displacement with the PD surface correction on the free
    // top and bottom sides (0.0222 without it); issue: 2 %.
    assert!(err < 0.02, "{err}");
    assert_eq!(s.mode, "coupled");
}

#[test]
fn seed002_beam_shear_centre_line() {
    let (_, out) = solve(&Scene::load("cases/coupled_beam_shear.ron").unwrap()).unwrap();
    let p = 1e6 * H;
    let i = H.powi(3) / 12.0;
    let g = E / (2.0 * (1.0 + NU));
    let v =
        |x: f64| p * (L * x * x / 2.0 - x.powi(3) / 6.0) / (E * i) + p * x / (5.0 / 6.0 * g * H);
    let err = worst(&centre_line(&out, 1), v);
    println!(
        "shear: {} iterations, centre-line error {err:.5}",
        out.info.iterations
    );
    // Measured 0.0050 of the end deflection (issue: 2 %).
    assert!(err < 0.02, "{err}");
}
