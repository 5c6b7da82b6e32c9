//! The refined body's force pass with bond breaking and its stable time step (module
//! docs of [`super::dynamics`]; seed 004 Eq. 13 forces, the Gershgorin bound of
//! [`crate::dynamics`]).

use rayon::prelude::*;

use super::Body;
use crate::geometry::P2;
use crate::state_based::dual_horizon::DualHorizon;

/// The Gershgorin stable step $\min_k\sqrt{4\rho V_k/R_k}$ of `body` (module docs) over
/// the particles with a free component (s); infinite when none moves.
///
/// $R_k$ bounds the absolute row sums of the linearised stiffness
/// ([`super::linear::apply`]): every bond's deviatoric bar $c_b\,n n^T$,
/// $c_b = V_k\beta_b V'_b/|\xi_b|$, adds $2c_b|n_p|(|n_x| + |n_y|)$ to the rows of both
/// ends, and every particle's dilatation term $2a_kV_k\,g_k g_k^T$ ($\theta_k = g_k\cdot v$)
/// adds $2|a_k|V_k|g_{k,ip}|\,\|g_k\|_1$ to row $(i, p)$.
pub fn critical_time_step(body: &Body, density: f64) -> f64 {
    let dh = &body.dh;
    let bonds = &dh.bonds;
    let n = body.len();
    let mut r = vec![[0.0f64; 2]; n];
    for k in 0..n {
        let vk = dh.volume[k];
        let mut gk = [0.0; 2];
        let mut l1 = 0.0;
        for b in bonds.row(k).filter(|&b| dh.intact[b] != 0) {
            let j = bonds.nbr[b] as usize;
            let il = bonds.inv_len[b];
            let nb = [bonds.xi[b][0] * il, bonds.xi[b][1] * il];
            let c = vk * dh.beta[b].abs() * bonds.vol_factor[b] * il;
            let spread = nb[0].abs() + nb[1].abs();
            let w = dh.omega[b] * bonds.vol_factor[b] * il;
            for p in 0..2 {
                let dev = 2.0 * c * nb[p].abs() * spread;
                r[k][p] += dev;
                r[j][p] += dev;
                gk[p] -= w * nb[p];
            }
            l1 += w.abs() * spread;
        }
        l1 += gk[0].abs() + gk[1].abs();
        let f = 2.0 * dh.a[k].abs() * vk * l1;
        for p in 0..2 {
            r[k][p] += f * gk[p].abs();
        }
        for b in bonds.row(k).filter(|&b| dh.intact[b] != 0) {
            let j = bonds.nbr[b] as usize;
            let il = bonds.inv_len[b];
            let w = (dh.omega[b] * bonds.vol_factor[b] * il).abs();
            for p in 0..2 {
                r[j][p] += f * w * (bonds.xi[b][p] * il).abs();
            }
        }
    }
    (0..n)
        .filter(|&k| !(body.fixed[k][0] && body.fixed[k][1]))
        .map(|k| r[k][0].max(r[k][1]))
        .zip(&dh.volume)
        .filter(|(rk, _)| *rk > 0.0)
        .map(|(rk, v)| (4.0 * density * v / rk).sqrt())
        .fold(f64::INFINITY, f64::min)
}

/// Forces (N) of seed 004 Eq. 13 at `u` after breaking every intact bond whose stretch
/// passes its owner's critical stretch `sc` (`None`: no breaking); returns the forces and
/// the directed bonds broken. Equals [`DualHorizon::forces`] of the updated flags.
pub fn forces_breaking(
    dh: &mut DualHorizon,
    owner: &[u32],
    u: &[P2],
    sc: Option<&[f64]>,
) -> (Vec<P2>, usize) {
    let bonds = &dh.bonds;
    let y = |b: usize| {
        let (k, j) = (owner[b] as usize, bonds.nbr[b] as usize);
        [
            bonds.xi[b][0] + u[j][0] - u[k][0],
            bonds.xi[b][1] + u[j][1] - u[k][1],
        ]
    };
    let stretch: Vec<f64> = (0..bonds.len())
        .into_par_iter()
        .map(|b| {
            let yb = y(b);
            yb[0].hypot(yb[1]) * bonds.inv_len[b] - 1.0
        })
        .collect();
    let broken = match sc {
        Some(sc) => dh
            .intact
            .par_iter_mut()
            .enumerate()
            .map(|(b, f)| {
                if *f != 0 && stretch[b] > sc[owner[b] as usize] {
                    *f = 0;
                    1
                } else {
                    0
                }
            })
            .sum(),
        None => 0,
    };
    let dh = &*dh;
    let theta: Vec<f64> = (0..dh.pos.len())
        .into_par_iter()
        .map(|k| {
            bonds
                .row(k)
                .map(|b| f64::from(dh.intact[b]) * dh.omega[b] * stretch[b] * bonds.vol_factor[b])
                .sum()
        })
        .collect();
    let coef: Vec<f64> = (0..bonds.len())
        .into_par_iter()
        .map(|b| {
            let k = owner[b] as usize;
            let l = (1.0 + stretch[b]) / bonds.inv_len[b];
            let tau = f64::from(dh.intact[b])
                * (2.0 * dh.a[k] * dh.omega[b] * theta[k] * bonds.inv_len[b]
                    + dh.beta[b] * stretch[b]);
            tau * dh.volume[k] * bonds.vol_factor[b] / l
        })
        .collect();
    let f = (0..dh.pos.len())
        .into_par_iter()
        .map(|n| {
            let mut f = [0.0; 2];
            for b in bonds.row(n) {
                let yb = y(b);
                f[0] += coef[b] * yb[0];
                f[1] += coef[b] * yb[1];
            }
            for &b in &dh.dual[dh.dual_offsets[n]..dh.dual_offsets[n + 1]] {
                let b = b as usize;
                let yb = y(b);
                f[0] -= coef[b] * yb[0];
                f[1] -= coef[b] * yb[1];
            }
            f
        })
        .collect();
    (f, broken)
}
