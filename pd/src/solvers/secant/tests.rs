//! Unit tests of the secant solver: the secant tangent against finite
//! differences, the Woodbury solve against a fresh factorisation, the chord
//! iteration against Newton.

use super::*;
use crate::forces::bond_tangent_scaled;
use crate::problem::{BoundaryCondition, Failure, Layer, PdProblem, Region, Selection};

/// 10 x 6 strip, degrading bonds, left end clamped, right end pulled.
fn strip() -> PdModel {
    let fixed = |min: [f64; 2], max: [f64; 2], ux: f64| BoundaryCondition::Displacement {
        on: Selection::Box { min, max },
        ux: Some(ux),
        uy: Some(0.0),
        layer: Layer::Fictitious,
    };
    PdModel::new(&PdProblem {
        region: Region::rectangle([0.0, 0.0], [0.01, 0.006]),
        dx: 0.001,
        youngs_modulus: 200e9,
        thickness: 0.001,
        failure: Failure::Degradation {
            s_m: 0.015,
            s_c: 0.02,
            beta: 3.0,
        },
        boundary: vec![
            fixed([-1.0, -1.0], [0.0, 1.0], 0.0),
            fixed([0.01, -1.0], [1.0, 1.0], 1e-4),
        ],
        ..Default::default()
    })
    .unwrap()
}

/// Degrade about one bond pair in 13 (both directions) and break about
/// one in 31, as committed histories.
fn damage_some(m: &mut PdModel, s_hist: f64) {
    for i in 0..m.n_nodes() {
        for b in m.bonds.row(i) {
            let j = m.bonds.nbr[b] as usize;
            let (lo, hi) = (i.min(j), i.max(j));
            if (lo + 3 * hi) % 13 == 0 {
                m.s_hist[b] = s_hist;
            }
            if (lo + 7 * hi) % 31 == 0 {
                m.intact[b] = 0;
            }
        }
    }
}

/// Dense free-DOF tangent of `kind` (force densities), from the bond blocks.
fn dense(m: &PdModel, t: &Tangent, kind: TangentKind) -> Vec<Vec<f64>> {
    let mut k = vec![vec![0.0; t.n_free]; t.n_free];
    for i in 0..m.n_nodes() {
        for b in m.bonds.row(i) {
            if m.intact[b] == 0 {
                continue;
            }
            let j = m.bonds.nbr[b] as usize;
            let y = [
                m.bonds.xi[b][0] + (m.u[j][0] - m.u[i][0]),
                m.bonds.xi[b][1] + (m.u[j][1] - m.u[i][1]),
            ];
            let blk = bond_tangent_scaled(
                m.law,
                m.bonds.k[b],
                m.bonds.inv_len[b],
                y,
                m.s_hist[b],
                kind,
                1.0,
            );
            for p in 0..2 {
                let r = t.dof[2 * i + p];
                if r == FIXED {
                    continue;
                }
                for q in 0..2 {
                    if t.dof[2 * i + q] != FIXED {
                        k[r][t.dof[2 * i + q]] += blk[p][q];
                    }
                    if t.dof[2 * j + q] != FIXED {
                        k[r][t.dof[2 * j + q]] -= blk[p][q];
                    }
                }
            }
        }
    }
    k
}

fn matvec(k: &[Vec<f64>], x: &[f64]) -> Vec<f64> {
    k.iter()
        .map(|row| row.iter().zip(x).map(|(a, b)| a * b).sum())
        .collect()
}

#[test]
fn secant_tangent_matches_finite_differences_of_the_secant_forces() {
    let mut m = strip();
    m.set_load_factor(1.0);
    let x = m.positions().to_vec();
    for (u, p) in m.u.iter_mut().zip(&x) {
        // Stretch 1 % along x plus a shear, so bonds load past their
        // (degraded) history and the secant law differs from Eq. 13.
        *u = [0.01 * p[0] + 0.002 * p[1], 0.001 * p[0]];
    }
    m.apply_prescribed();
    damage_some(&mut m, 0.017);
    let t = Tangent::new(&m.bonds, &m.bc.fixed).unwrap();
    let k = dense(&m, &t, TangentKind::Secant);
    let (h, mut err, mut kmax) = (1e-9, 0.0f64, 0.0f64);
    let u0 = m.u.clone();
    for node in 0..m.n_nodes() {
        for c in 0..2 {
            let col = t.dof[2 * node + c];
            if col == FIXED {
                continue;
            }
            let mut f = [Vec::new(), Vec::new()];
            for (s, sign) in [(0, 1.0), (1, -1.0)] {
                m.u.clone_from(&u0);
                m.u[node][c] += sign * h;
                m.compute_forces(History::Secant);
                f[s] = m.force.clone();
            }
            for i in 0..m.n_nodes() {
                for r in 0..2 {
                    let row = t.dof[2 * i + r];
                    if row != FIXED {
                        let fd = -(f[0][i][r] - f[1][i][r]) / (2.0 * h);
                        kmax = kmax.max(k[row][col].abs());
                        err = err.max((fd - k[row][col]).abs());
                    }
                }
            }
        }
    }
    eprintln!("secant tangent FD error / max |K| = {:e}", err / kmax);
    // Measured 9.7e-11 relative to max |K| (finite-difference round-off).
    assert!(err < 1e-6 * kmax, "FD error {err:e} vs max |K| {kmax:e}");
}

#[test]
fn woodbury_solve_equals_a_fresh_factorisation_after_damage() {
    // At u = 0 every bond keeps its reference direction and has zero
    // stretch, so the low-rank update is exact: M = K_secant.
    let mut m = strip();
    let mut t = Tangent::new(&m.bonds, &m.bc.fixed).unwrap();
    let mut info = SolveInfo::default();
    let mut sec = SecantSolver::new(&m, t.n_free, 256, 0);
    sec.refactor(&m, &mut t, &mut info).unwrap();
    damage_some(&mut m, 0.018);
    sec.track_changes(&m, &mut t, &mut info).unwrap();
    assert!(
        sec.low_rank.len() > 20 && sec.factorizations == 1,
        "{} columns",
        sec.low_rank.len()
    );
    let k = dense(&m, &t, TangentKind::Secant);
    let r: Vec<f64> = (0..t.n_free)
        .map(|i| ((i * 37) % 11) as f64 - 5.0)
        .collect();
    sec.rhs.clone_from(&r);
    sec.apply_inverse(&mut t, &mut info).unwrap();
    let back = matvec(&k, &sec.rhs);
    let (e, n) = back
        .iter()
        .zip(&r)
        .fold((0.0f64, 0.0f64), |(e, n), (a, b)| {
            (e.max((a - b).abs()), n.max(b.abs()))
        });
    eprintln!(
        "{} columns: |K M^-1 r - r| / max |r| = {:e}",
        sec.low_rank.len(),
        e / n
    );
    // Measured 4.9e-10 of max |r| with 90 columns (round-off of the
    // solves with a tangent of condition number about 1e5).
    assert!(
        e < 1e-8 * n,
        "K M^-1 r differs from r by {e:e} (max |r| {n})"
    );
}

/// The chord iteration's parameters on the strip: tolerances near round-off, 8 low-rank
/// columns, Anderson depth 3, the given refactorisation rule.
fn tight_chord(refactor_contraction: f64, max_refactors: Option<usize>) -> SecantParams {
    SecantParams {
        convergence: Convergence::Displacement { e0: 1e-12 },
        residual_tol: 1e-13,
        max_iters: 50,
        max_columns: 8,
        anderson_depth: 3,
        refactor_contraction,
        max_refactors,
    }
}

/// The strip at load 1 with a fresh tangent and chord solver for `params`.
fn strip_chord(params: &SecantParams) -> (PdModel, Tangent, SecantSolver) {
    let mut m = strip();
    let t = Tangent::new(&m.bonds, &m.bc.fixed).unwrap();
    let sec = SecantSolver::new(&m, t.n_free, params.max_columns, params.anderson_depth);
    m.set_load_factor(1.0);
    (m, t, sec)
}

#[test]
fn chord_iteration_reaches_the_newton_equilibrium() {
    let params = tight_chord(super::CONTRACTION_REFACTOR, None);
    // Newton (consistent tangent) on the elastic response at load 1.
    let mut newton_model = strip();
    let ip = crate::solvers::implicit::ImplicitParams {
        convergence: Convergence::Displacement { e0: 1e-12 },
        residual_tol: 1e-13,
        ..Default::default()
    };
    crate::solvers::implicit::solve(&mut newton_model, &ip).unwrap();
    // Secant chord iterations from the factor taken at u = 0 (no bond
    // reaches the damage onset, so the secant law is the elastic one).
    let (mut m, mut t, mut sec) = strip_chord(&params);
    let mut info = SolveInfo::default();
    let (it, _) = sec.equilibrate(&mut m, &mut t, &params, &mut info).unwrap();
    let (mut d, mut n) = (0.0f64, 0.0f64);
    for (a, b) in m.u.iter().zip(&newton_model.u) {
        for c in 0..2 {
            d = d.max((a[c] - b[c]).abs());
            n = n.max(b[c].abs());
        }
    }
    eprintln!(
        "{it} chord iterations, {} factorisations, difference / max |u| = {:e}",
        sec.factorizations,
        d / n
    );
    // Measured: 9 iterations on one factor (the 1 % strain's geometric
    // terms set the contraction), difference 2.4e-14 of max |u|.
    assert!(it <= 15, "{it} chord iterations");
    assert!(
        d < 1e-10 * n,
        "chord and Newton differ by {d:e} (max |u| {n:e})"
    );
}

#[test]
fn a_chord_iteration_out_of_refactorisations_gives_up_to_a_fallback() {
    // A threshold no contraction meets asks for a refactorisation at every iteration
    // after the first; with at most 2 allowed the third request ends the iteration.
    let params = tight_chord(1e-30, Some(2));
    let (mut m, mut t, mut sec) = strip_chord(&params);
    let mut info = SolveInfo::default();
    match sec.equilibrate(&mut m, &mut t, &params, &mut info) {
        Err(PdError::NoConvergence { iterations, .. }) => assert_eq!(iterations, 4),
        other => panic!("expected NoConvergence after 4 iterations, got {other:?}"),
    }
    // The first factor and the two refactorisations allowed.
    assert_eq!(sec.factorizations, 3);
    // Without the limit the same iteration converges (refactorising every time).
    let unlimited = tight_chord(1e-30, None);
    let (mut m, mut t, mut sec) = strip_chord(&unlimited);
    let (it, _) = sec
        .equilibrate(&mut m, &mut t, &unlimited, &mut info)
        .unwrap();
    assert!(
        it >= 4 && sec.factorizations > 3,
        "{it} iterations, {} factorisations",
        sec.factorizations
    );
}
