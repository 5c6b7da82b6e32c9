//! Seed 000 section 3.2: cantilever 0.5 m x 0.05 m, 100 x 10 grid, 125 N
//! tip load. Implicit Newton and ADR must agree on the undamaged solution,
//! and the tip deflection must match the Timoshenko beam solution.

use pdbem_pd::cases::{cantilever, CANTILEVER_LOAD};
use pdbem_pd::solvers::{adr, implicit};
use pdbem_pd::{Convergence, PdModel};

/// Timoshenko tip deflection P L^3/(3EI) + P L/(kappa G A), plane stress
/// with nu = 1/3 (bond-based PD), kappa = 5/6, span L measured from the
/// clamp (x = 0) to the loaded node column (x = 0.5 - dx/2).
fn timoshenko(dx: f64) -> f64 {
    let (e, nu, w, t): (f64, f64, f64, f64) = (200e9, 1.0 / 3.0, 0.05, dx);
    let l: f64 = 0.5 - 0.5 * dx;
    let i = t * w.powi(3) / 12.0;
    let g = e / (2.0 * (1.0 + nu));
    CANTILEVER_LOAD * l.powi(3) / (3.0 * e * i) + CANTILEVER_LOAD * l / (5.0 / 6.0 * g * w * t)
}

fn tip_deflection(m: &PdModel) -> f64 {
    // Mean uy of the last node column.
    let x = m.positions();
    let u = m.displacements();
    let xmax = x[..m.n_real()].iter().fold(f64::MIN, |a, p| a.max(p[0]));
    let col: Vec<f64> = (0..m.n_real())
        .filter(|&i| (x[i][0] - xmax).abs() < 1e-9)
        .map(|i| u[i][1])
        .collect();
    -col.iter().sum::<f64>() / col.len() as f64
}

#[test]
fn implicit_and_adr_agree_and_match_timoshenko() {
    let case = cantilever(100, 10, true);
    let dx = case.problem.dx;
    let mut mi = PdModel::new(&case.problem).unwrap();
    let info = implicit::solve(&mut mi, &implicit::ImplicitParams::default()).unwrap();
    let wi = tip_deflection(&mi);
    let wb = timoshenko(dx);
    eprintln!(
        "implicit: {} Newton iterations, tip {wi:.6e} m, Timoshenko {wb:.6e} m, ratio {:.4}",
        info.iterations,
        wi / wb
    );

    let mut ma = PdModel::new(&case.problem).unwrap();
    let p = adr::AdrParams {
        convergence: Convergence::Residual { tol: 1e-10 },
        ..Default::default()
    };
    let info_a = adr::solve(&mut ma, &p).unwrap();
    let ua = ma.displacements();
    let ui = mi.displacements();
    let (mut d2, mut n2) = (0.0, 0.0);
    for k in 0..ua.len() {
        for c in 0..2 {
            d2 += (ua[k][c] - ui[k][c]).powi(2);
            n2 += ui[k][c].powi(2);
        }
    }
    let rel = (d2 / n2).sqrt();
    eprintln!(
        "adr: {} iterations, {:.2} s; relative difference to implicit {rel:.3e}",
        info_a.iterations, info_a.wall_time_s
    );
    // Measured 6.2e-9 (ADR to a 1e-10 relative residual, 22207 steps).
    assert!(rel < 1e-6);
    // Measured ratio 1.0010 with the surface correction (1.3975 without).
    assert!((wi / wb - 1.0).abs() < 0.05);
}

#[test]
fn surface_effect_without_correction_is_reported() {
    // Without the surface correction the boundary layers are too soft.
    let case = cantilever(100, 10, false);
    let mut m = PdModel::new(&case.problem).unwrap();
    implicit::solve(&mut m, &implicit::ImplicitParams::default()).unwrap();
    let ratio = tip_deflection(&m) / timoshenko(case.problem.dx);
    eprintln!("uncorrected tip / Timoshenko = {ratio:.4}");
    // Measured 1.3975: the correction is what brings the 5 % within reach.
    assert!(ratio > 1.2);
}
