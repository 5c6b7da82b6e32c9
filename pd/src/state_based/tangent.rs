//! The state-based tangent $K = -\partial F/\partial u$, row by row.
//!
//! With the pair scalar
//! $\varphi_{ij} = T\,[2(a_i\omega_{ij}\theta_i + a_j\omega_{ji}\theta_j)/|\xi| + (\beta_{ij}+\beta_{ji})s]$
//! and the dilatation gradient
//! $w_n[m] = \partial\theta_n/\partial u_m = \omega_{nm}\, g'_{nm} V'_m\, e_{nm}/|\xi_{nm}|$
//! ($m \in H_n$), $w_n[n] = -\sum_m w_n[m]$, $g' = d(Ts)/ds$:
//! $$K = \sum_{\text{bonds}} V'\Big[\frac{\partial_s\varphi}{|\xi|}\, e e^T +
//!   \frac{\varphi}{l}(I - e e^T)\Big]_{\pm} + \sum_n 2a_n\, w_n w_n^T,
//!   \qquad$$
//! the first sum the pairwise blocks (as [`crate::forces::bond_tangent`], entering
//! $K_{ii}$ with $+$ and $K_{ij}$ with $-$), $\partial_s\varphi$ at fixed dilatations. The
//! second sum couples node $i$ to the families of its neighbours, so row $i$ spans the
//! two-hop stencil. It is exact (the Hessian of $\sum_k V W_k$) while no bond softens;
//! a softening bond ($T' \ne 0$, [`TangentKind::Consistent`]) puts $g' = T + sT'$ on both
//! sides of $w_n w_n^T$ where the exact tangent has $T$ on one side, which keeps it
//! symmetric for the Cholesky factorisation (Newton then converges linearly in the
//! softening steps). The secant kinds take $T(s_{hist})$ and $T' = 0$, as the PMB ones.

use super::forces::stretch;
use super::StateBased;
use crate::bonds::Bonds;
use crate::forces::{stretch_scale, TangentKind, NO_FAIL};
use crate::geometry::P2;
use crate::material::{degradation, BondLaw};
use crate::tangent::{Block, Tangent};

/// The inputs of a tangent row: model constants, bonds and state.
#[derive(Clone, Copy)]
pub struct RowInput<'a> {
    /// Constants.
    pub sb: &'a StateBased,
    /// Bonds.
    pub bonds: &'a Bonds,
    /// Failure law.
    pub law: BondLaw,
    /// Bond flags.
    pub intact: &'a [u8],
    /// Bond history.
    pub s_hist: &'a [f64],
    /// Displacements.
    pub u: &'a [P2],
    /// Node volume (m^3).
    pub volume: f64,
    /// Which tangent.
    pub kind: TangentKind,
}

/// `(T, dT/ds)` of intact bond `k` of stretch `s` for the tangent of `r.kind`; `None` if
/// broken. On mixed spacing the law acts on `s / scale` ([`stretch_scale`]), so
/// $dT/ds = T'(s/\sigma)/\sigma$.
#[inline]
fn bond_factor(r: &RowInput, k: usize, s: f64) -> Option<(f64, f64)> {
    let (intact, s_hist) = (r.intact[k], r.s_hist[k]);
    if intact == 0 {
        return None;
    }
    Some(match r.law {
        BondLaw::Degrading { s_m, s_c, beta } if intact != NO_FAIL => {
            let scale = stretch_scale(r.bonds, k);
            let sn = s / scale;
            if r.kind == TangentKind::Consistent && sn > s_hist {
                let (t, dt) = degradation(sn, s_m, s_c, beta);
                (t, dt / scale)
            } else {
                (degradation(s_hist, s_m, s_c, beta).0, 0.0)
            }
        }
        _ => (1.0, 0.0),
    })
}

/// Dilatation of node `n` and its gradient entries `(m, w_n[m])` over its bonds
/// (appended to `w`); returns `(theta_n, w_n[n])`.
fn family(r: &RowInput, n: usize, w: &mut Vec<(u32, [f64; 2])>) -> (f64, [f64; 2]) {
    let b = r.bonds;
    let (mut sum, mut diag) = (0.0, [0.0; 2]);
    for k in b.row(n) {
        let (s, l, y) = stretch(b, r.u, n, k);
        let Some((t, dt)) = bond_factor(r, k, s) else {
            continue;
        };
        let v = b.vol_factor[k] * r.volume;
        let om = r.sb.omega[k];
        sum += om * t * s * v;
        let c = om * (t + s * dt) * v * b.inv_len[k] / l;
        let g = [c * y[0], c * y[1]];
        diag[0] -= g[0];
        diag[1] -= g[1];
        w.push((b.nbr[k], g));
    }
    (sum, diag)
}

/// Scratch of one row.
#[derive(Default)]
pub struct RowScratch {
    w: Vec<(u32, [f64; 2])>,
    theta: Vec<f64>,
}

#[inline]
fn add(blocks: &mut [Block], stencil: &[u32], m: u32, f: impl Fn(usize, usize) -> f64) {
    let k = stencil.binary_search(&m).expect("node in the stencil");
    for p in 0..2 {
        for q in 0..2 {
            blocks[k][p][q] += f(p, q);
        }
    }
}

/// Row `i` of the tangent: `blocks[k] = K[i][stencil[k]]` (added to `blocks`).
pub fn row_blocks(
    r: &RowInput,
    i: usize,
    stencil: &[u32],
    sc: &mut RowScratch,
    blocks: &mut [Block],
) {
    let b = r.bonds;
    let sb = r.sb;
    // Dilatations of i and its neighbours (frozen-history factors of `kind`).
    sc.w.clear();
    let (th_i, _) = family(r, i, &mut sc.w);
    sc.theta.clear();
    for k in b.row(i) {
        let j = b.nbr[k] as usize;
        sc.w.clear();
        sc.theta.push(family(r, j, &mut sc.w).0);
    }
    // Pairwise blocks.
    for (m, k) in b.row(i).enumerate() {
        let (s, l, y) = stretch(b, r.u, i, k);
        let Some((t, dt)) = bond_factor(r, k, s) else {
            continue;
        };
        let j = b.nbr[k] as usize;
        let inv = b.inv_len[k];
        let (phi, dphi, v) = if b.s_scale.is_empty() {
            let base = super::forces::pair_base(sb, b, i, k, s, th_i, sc.theta[m]);
            let dphi = dt * base + t * (sb.beta[k] + sb.beta[sb.rev[k] as usize]);
            (t * base, dphi, b.vol_factor[k] * r.volume)
        } else {
            // Mixed spacing: the partial volumes are inside the pair scalar.
            let base = super::forces::pair_mixed(sb, b, i, k, s, th_i, sc.theta[m]);
            let dphi = dt * base + t * super::forces::pair_mixed_ds(sb, b, k);
            (t * base, dphi, r.volume)
        };
        let phi_g = if r.kind == TangentKind::SecantPositive {
            phi.max(0.0)
        } else {
            phi
        };
        let e = [y[0] / l, y[1] / l];
        let (ca, cb) = (v * dphi * inv, v * phi_g / l);
        let blk = |p: usize, q: usize| {
            let ee = e[p] * e[q];
            ca * ee + cb * (if p == q { 1.0 } else { 0.0 } - ee)
        };
        add(blocks, stencil, i as u32, blk);
        add(blocks, stencil, j as u32, |p, q| -blk(p, q));
    }
    // Dilatation blocks: sum over n in {i} and the neighbours of i of 2 a_n w_n[i] w_n^T.
    let nodes = std::iter::once(i).chain(
        b.row(i)
            .filter(|&k| r.intact[k] != 0)
            .map(|k| b.nbr[k] as usize),
    );
    for n in nodes {
        if sb.a[n] == 0.0 {
            continue;
        }
        let two_a = 2.0 * sb.a[n];
        sc.w.clear();
        let (_, wnn) = family(r, n, &mut sc.w);
        let wi = if n == i {
            wnn
        } else {
            match sc.w.iter().find(|e| e.0 as usize == i) {
                Some(e) => e.1,
                None => continue,
            }
        };
        add(blocks, stencil, n as u32, |p, q| two_a * wi[p] * wnn[q]);
        for &(m, wm) in &sc.w {
            add(blocks, stencil, m, |p, q| two_a * wi[p] * wm[q]);
        }
    }
}

/// The two-hop stencil of every node (itself, its neighbours and theirs, sorted), as CSR
/// `(offsets, nodes)`; broken bonds included so the pattern stays fixed.
pub fn stencil(bonds: &Bonds) -> (Vec<usize>, Vec<u32>) {
    use rayon::prelude::*;
    let n = bonds.offsets.len() - 1;
    let rows: Vec<Vec<u32>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut v = vec![i as u32];
            for k in bonds.row(i) {
                let j = bonds.nbr[k] as usize;
                v.push(j as u32);
                v.extend(bonds.row(j).map(|kk| bonds.nbr[kk]));
            }
            v.sort_unstable();
            v.dedup();
            v
        })
        .collect();
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0);
    for r in &rows {
        offsets.push(offsets.last().unwrap() + r.len());
    }
    (offsets, rows.concat())
}

/// Fill a [`Tangent::from_stencil`] pattern of [`stencil`] at the state of `r`, with the
/// PMB assembly's diagonal shift (1e-10 of the node's pair stiffness).
pub fn assemble(t: &mut Tangent, r: &RowInput) {
    t.assemble_rows(RowScratch::default, |sc, i, st, blocks| {
        row_blocks(r, i, st, sc, blocks);
        let kref: f64 = r
            .bonds
            .row(i)
            .map(|k| r.bonds.k[k] * r.bonds.inv_len[k])
            .sum();
        let d = st.binary_search(&(i as u32)).expect("node in its stencil");
        blocks[d][0][0] += 1e-10 * kref;
        blocks[d][1][1] += 1e-10 * kref;
    });
}

/// Dense tangent over all `2n` DOFs (a testing aid for small models).
pub fn dense_tangent(r: &RowInput) -> Vec<Vec<f64>> {
    let n = r.u.len();
    let (offsets, nodes) = stencil(r.bonds);
    let mut k = vec![vec![0.0; 2 * n]; 2 * n];
    let mut sc = RowScratch::default();
    for i in 0..n {
        let st = &nodes[offsets[i]..offsets[i + 1]];
        let mut blocks = vec![[[0.0; 2]; 2]; st.len()];
        row_blocks(r, i, st, &mut sc, &mut blocks);
        for (m, blk) in st.iter().zip(&blocks) {
            for p in 0..2 {
                for q in 0..2 {
                    k[2 * i + p][2 * *m as usize + q] = blk[p][q];
                }
            }
        }
    }
    k
}

/// Absolute row sums of the tangent per DOF, $\sum_m \sum_q |K_{(i,p),(m,q)}|$ (the
/// Gershgorin bound ADR's fictitious density needs).
pub fn row_sums(r: &RowInput) -> Vec<[f64; 2]> {
    use rayon::prelude::*;
    let (offsets, nodes) = stencil(r.bonds);
    (0..r.u.len())
        .into_par_iter()
        .map_init(RowScratch::default, |sc, i| {
            let st = &nodes[offsets[i]..offsets[i + 1]];
            let mut blocks = vec![[[0.0; 2]; 2]; st.len()];
            row_blocks(r, i, st, sc, &mut blocks);
            let mut s = [0.0; 2];
            for blk in &blocks {
                for p in 0..2 {
                    s[p] += blk[p][0].abs() + blk[p][1].abs();
                }
            }
            s
        })
        .collect()
}
