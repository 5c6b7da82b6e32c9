//! Linear elastic equilibrium of a dual-horizon body by Jacobi-preconditioned conjugate
//! gradients.
//!
//! Linearised about the reference configuration, the stretch of bond $b = k\to j$ is
//! $s_b = n_b\cdot(v_j - v_k)/|\xi_b|$ and the energy of
//! [`crate::state_based::dual_horizon`],
//! $\Pi = \sum_k V_k\big(a_k\theta_k^2 + \tfrac12\sum_b T_b\beta_b|\xi_b|V'_b s_b^2\big)$,
//! $\theta_k = \sum_b T_b\omega_b V'_b s_b$, is the quadratic form $\tfrac12 v^T K v$.
//! [`apply`] returns $Kv$ (the bond of owner $k$ pushes $k$ by
//! $-T V_k V'_b(2a_k\omega_b\theta_k/|\xi_b| + \beta_b s_b)\,n_b$ and $j$ by the
//! opposite, seed 004 Eq. 13), [`diagonal`] its 2x2-block diagonals' diagonal entries.
//! [`solve`] finds $K u = f$ on the free components with the prescribed ones held, by
//! [`pcg`] with the Jacobi preconditioner ([`super::direct`] passes a Cholesky factor).
//!
//! **Convergence is checked on the true residual.** The recurrence $r \leftarrow r -
//! \alpha K p$ drifts from $f - Ku$ by round-off, and below about $10^{-11}$ the drift
//! is larger than the tolerance: on the Table 2 plate at dx = 0.5 mm a solve to
//! $10^{-12}$ ended with $|f - Ku| = 1.9\times10^{-12}|f|$. So when the recurrence
//! passes the tolerance, [`pcg`] forms $f - Ku$; if that misses it, the iteration
//! restarts from $u$ with the true residual (at most [`RESTARTS`] times, within the
//! iteration cap), and a solve whose true residual stalls above the tolerance fails with
//! that residual as its measure.

use rayon::prelude::*;

use super::Body;
use crate::error::PdError;
use crate::geometry::P2;
use crate::state_based::dual_horizon::DualHorizon;

/// Restarts of [`pcg`] from the true residual when the recurrence's has met the
/// tolerance and the true one has not (module docs).
pub const RESTARTS: usize = 3;

/// `K v` of the linearised dual-horizon energy.
pub fn apply(dh: &DualHorizon, owner: &[u32], v: &[P2]) -> Vec<P2> {
    let bonds = &dh.bonds;
    let s = |b: usize, k: usize| {
        let j = bonds.nbr[b] as usize;
        let xi = bonds.xi[b];
        let il = bonds.inv_len[b];
        ((v[j][0] - v[k][0]) * xi[0] + (v[j][1] - v[k][1]) * xi[1]) * il * il
    };
    let theta: Vec<f64> = (0..dh.pos.len())
        .into_par_iter()
        .map(|k| {
            bonds
                .row(k)
                .map(|b| f64::from(dh.intact[b]) * dh.omega[b] * bonds.vol_factor[b] * s(b, k))
                .sum()
        })
        .collect();
    // Scalar force of every bond along n_b on its owner (times -1 in K v).
    let coef: Vec<f64> = (0..bonds.len())
        .into_par_iter()
        .map(|b| {
            let k = owner[b] as usize;
            let t = f64::from(dh.intact[b]);
            let il = bonds.inv_len[b];
            t * dh.volume[k]
                * bonds.vol_factor[b]
                * (2.0 * dh.a[k] * dh.omega[b] * theta[k] * il + dh.beta[b] * s(b, k))
                * il
        })
        .collect();
    (0..dh.pos.len())
        .into_par_iter()
        .map(|n| {
            let mut f = [0.0; 2];
            for b in bonds.row(n) {
                f[0] -= coef[b] * bonds.xi[b][0];
                f[1] -= coef[b] * bonds.xi[b][1];
            }
            for &b in &dh.dual[dh.dual_offsets[n]..dh.dual_offsets[n + 1]] {
                let b = b as usize;
                f[0] += coef[b] * bonds.xi[b][0];
                f[1] += coef[b] * bonds.xi[b][1];
            }
            f
        })
        .collect()
}

/// Diagonal entries of `K` per particle and component.
pub fn diagonal(dh: &DualHorizon) -> Vec<P2> {
    let n = dh.pos.len();
    let bonds = &dh.bonds;
    let mut d = vec![[0.0; 2]; n];
    for k in 0..n {
        let mut g = [0.0; 2];
        for b in bonds.row(k) {
            let t = f64::from(dh.intact[b]);
            let il = bonds.inv_len[b];
            let nv = [bonds.xi[b][0] * il, bonds.xi[b][1] * il];
            let j = bonds.nbr[b] as usize;
            let spring = t * dh.volume[k] * dh.beta[b] * bonds.vol_factor[b] * il;
            let w = t * dh.omega[b] * bonds.vol_factor[b] * il;
            for c in 0..2 {
                let dev = spring * nv[c] * nv[c];
                d[k][c] += dev;
                d[j][c] += dev + 2.0 * dh.volume[k] * dh.a[k] * (w * nv[c]).powi(2);
                g[c] += w * nv[c];
            }
        }
        for c in 0..2 {
            d[k][c] += 2.0 * dh.volume[k] * dh.a[k] * g[c] * g[c];
        }
    }
    d
}

/// Solve `K u = f` (`f` the body forces at load factor `load` times the volumes) for the
/// free components of `body.u`, from its current value, with the prescribed components
/// at `load` times their base values, by Jacobi-preconditioned conjugate gradients.
/// Returns the iterations.
pub fn solve(body: &mut Body, load: f64, tol: f64, max_iter: usize) -> Result<usize, PdError> {
    let diag = diagonal(&body.dh);
    let jacobi = |r: &[P2]| -> Result<Vec<P2>, PdError> {
        Ok(r.iter()
            .zip(&diag)
            .map(|(x, d)| std::array::from_fn(|c| if d[c] > 0.0 { x[c] / d[c] } else { 0.0 }))
            .collect())
    };
    pcg(
        body,
        load,
        tol,
        max_iter,
        "refined body (conjugate gradients)",
        jacobi,
    )
}

/// Conjugate gradients on `K u = f` as [`solve`] sets it up, preconditioned by
/// `precond` (zero on the prescribed components); `solver` names it in the error when
/// `max_iter` iterations do not reach `tol` (relative to the load or, under prescribed
/// displacements alone, the first residual).
pub fn pcg(
    body: &mut Body,
    load: f64,
    tol: f64,
    max_iter: usize,
    solver: &'static str,
    mut precond: impl FnMut(&[P2]) -> Result<Vec<P2>, PdError>,
) -> Result<usize, PdError> {
    let dh = &body.dh;
    let owner = dh.owners();
    let n = body.len();
    let fixed = &body.fixed;
    for i in 0..n {
        for c in 0..2 {
            if fixed[i][c] {
                body.u[i][c] = load * body.base[i][c];
            }
        }
    }
    let f: Vec<P2> = (0..n)
        .map(|i| {
            std::array::from_fn(|c| {
                if fixed[i][c] {
                    0.0
                } else {
                    load * body.body[i][c] * dh.volume[i]
                }
            })
        })
        .collect();
    let mask = |v: &mut [P2]| {
        for (i, vi) in v.iter_mut().enumerate() {
            for c in 0..2 {
                if fixed[i][c] {
                    vi[c] = 0.0;
                }
            }
        }
    };
    let dot = |a: &[P2], b: &[P2]| -> f64 {
        a.par_iter()
            .zip(b)
            .map(|(x, y)| x[0] * y[0] + x[1] * y[1])
            .sum()
    };
    let true_residual = |u: &[P2]| -> Vec<P2> {
        let ku = apply(dh, &owner, u);
        let mut r: Vec<P2> = (0..n)
            .map(|i| [f[i][0] - ku[i][0], f[i][1] - ku[i][1]])
            .collect();
        mask(&mut r);
        r
    };
    let mut r = true_residual(&body.u);
    let fnorm = dot(&f, &f)
        .sqrt()
        .max(dot(&r, &r).sqrt())
        .max(f64::MIN_POSITIVE);
    let mut z = precond(&r)?;
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut restarts = 0;
    for it in 0..max_iter {
        let rnorm = dot(&r, &r).sqrt();
        if !rnorm.is_finite() {
            return Err(PdError::NonFinite {
                solver,
                iteration: it,
                load,
            });
        }
        if rnorm <= tol * fnorm {
            // The recurrence says converged: check f - K u itself (module docs).
            r = true_residual(&body.u);
            let measure = dot(&r, &r).sqrt() / fnorm;
            if measure <= tol {
                return Ok(it);
            }
            if restarts == RESTARTS {
                return Err(PdError::NoConvergence {
                    solver,
                    iterations: it,
                    load,
                    measure,
                    tolerance: tol,
                });
            }
            restarts += 1;
            z = precond(&r)?;
            p.clone_from(&z);
            rz = dot(&r, &z);
            continue;
        }
        let mut kp = apply(dh, &owner, &p);
        mask(&mut kp);
        let pkp = dot(&p, &kp);
        if pkp.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        let alpha = rz / pkp;
        for i in 0..n {
            for c in 0..2 {
                body.u[i][c] += alpha * p[i][c];
                r[i][c] -= alpha * kp[i][c];
            }
        }
        z = precond(&r)?;
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..n {
            for c in 0..2 {
                p[i][c] = z[i][c] + beta * p[i][c];
            }
        }
    }
    Err(PdError::NoConvergence {
        solver,
        iterations: max_iter,
        load,
        measure: dot(&r, &r).sqrt() / fnorm,
        tolerance: tol,
    })
}
