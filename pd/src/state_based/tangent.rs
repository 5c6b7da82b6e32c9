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
//!
//! Every row needs $\theta_n$ and $w_n$ of its own family and of each neighbour's, so an
//! assembly computes them once for every node ([`Families`]) and the rows read them: a
//! row costs its pairwise bonds plus the two-hop products, not a family sum per
//! neighbour (the per-row sums made 58 % of the time of the displacement-controlled
//! cells case, `seed004_edge_crack_initiation_displacement_cells`, 44 s of assembly; 6.5
//! s with the families). A symmetric assembly fills only the blocks right of the
//! diagonal ([`Part::Upper`]).

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

/// The families of every node at one state, for the rows of [`row_blocks`]: the
/// dilatation $\theta_n$, the diagonal entry $w_n[n]$ and, per directed bond `k` of `n`
/// (`n -> m`), the gradient entry $w_n[m]$ (zero on a broken bond). Computed once per
/// assembly ([`Families::new`]); a row then reads its neighbours' families instead of
/// summing them again.
pub struct Families {
    theta: Vec<f64>,
    diag: Vec<[f64; 2]>,
    w: Vec<[f64; 2]>,
}

impl Families {
    /// The families of every node of `r` (in parallel over the nodes).
    pub fn new(r: &RowInput) -> Self {
        use rayon::prelude::*;
        let b = r.bonds;
        let n = b.offsets.len() - 1;
        let mut w = vec![[0.0; 2]; b.nbr.len()];
        let mut rows: Vec<&mut [[f64; 2]]> = Vec::with_capacity(n);
        let mut rest = w.as_mut_slice();
        for i in 0..n {
            let (row, tail) = rest.split_at_mut(b.offsets[i + 1] - b.offsets[i]);
            rows.push(row);
            rest = tail;
        }
        let (theta, diag): (Vec<f64>, Vec<[f64; 2]>) = rows
            .into_par_iter()
            .enumerate()
            .with_min_len(64)
            .map(|(i, row)| family(r, i, row))
            .unzip();
        Self { theta, diag, w }
    }
}

/// Dilatation of node `n` and its gradient entries $w_n[m]$ per bond (written to `w`,
/// the row of `n`'s bonds; broken bonds left zero); returns `(theta_n, w_n[n])`.
fn family(r: &RowInput, n: usize, w: &mut [[f64; 2]]) -> (f64, [f64; 2]) {
    let b = r.bonds;
    let (mut sum, mut diag) = (0.0, [0.0; 2]);
    for (slot, k) in w.iter_mut().zip(b.row(n)) {
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
        *slot = g;
    }
    (sum, diag)
}

/// Scratch of one row: the stencil position of every node (`NOT_IN` outside the row's
/// stencil).
#[derive(Default)]
pub struct RowScratch {
    pos: Vec<u32>,
}

const NOT_IN: u32 = u32::MAX;

/// Which blocks of a row [`row_blocks`] fills.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Every block of the row.
    Full,
    /// The blocks `K[i][m]` with `m >= i` (all a symmetric assembly reads).
    Upper,
}

/// Adds `f` to the block of node `m` of the row (skipped below the diagonal for
/// [`Part::Upper`]).
#[inline]
fn add(
    blocks: &mut [Block],
    pos: &[u32],
    (i, part): (u32, Part),
    m: u32,
    f: impl Fn(usize, usize) -> f64,
) {
    if part == Part::Upper && m < i {
        return;
    }
    let k = pos[m as usize];
    debug_assert!(k != NOT_IN, "node in the stencil");
    let blk = &mut blocks[k as usize];
    for (p, row) in blk.iter_mut().enumerate() {
        for (q, v) in row.iter_mut().enumerate() {
            *v += f(p, q);
        }
    }
}

/// Row `i` of the tangent: `blocks[k] += K[i][stencil[k]]` (the blocks `part` asks for),
/// with the families `fam` of the same state.
pub fn row_blocks(
    r: &RowInput,
    fam: &Families,
    (i, part): (usize, Part),
    stencil: &[u32],
    sc: &mut RowScratch,
    blocks: &mut [Block],
) {
    let n_nodes = r.bonds.offsets.len() - 1;
    if sc.pos.len() < n_nodes {
        sc.pos.resize(n_nodes, NOT_IN);
    }
    for (k, &m) in stencil.iter().enumerate() {
        sc.pos[m as usize] = k as u32;
    }
    fill_row(r, fam, (i, part), &sc.pos, blocks);
    for &m in stencil {
        sc.pos[m as usize] = NOT_IN;
    }
}

/// [`row_blocks`] with the stencil positions `pos` set.
fn fill_row(
    r: &RowInput,
    fam: &Families,
    (i, part): (usize, Part),
    pos: &[u32],
    blocks: &mut [Block],
) {
    let b = r.bonds;
    let sb = r.sb;
    let at = (i as u32, part);
    let th_i = fam.theta[i];
    // Pairwise blocks.
    for k in b.row(i) {
        let (s, l, y) = stretch(b, r.u, i, k);
        let Some((t, dt)) = bond_factor(r, k, s) else {
            continue;
        };
        let j = b.nbr[k] as usize;
        let inv = b.inv_len[k];
        let th_j = fam.theta[j];
        let (phi, dphi, v) = if b.s_scale.is_empty() {
            let base = super::forces::pair_base(sb, b, i, k, s, th_i, th_j);
            let dphi = dt * base + t * (sb.beta[k] + sb.beta[sb.rev[k] as usize]);
            (t * base, dphi, b.vol_factor[k] * r.volume)
        } else {
            // Mixed spacing: the partial volumes are inside the pair scalar.
            let base = super::forces::pair_mixed(sb, b, i, k, s, th_i, th_j);
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
        add(blocks, pos, at, i as u32, blk);
        add(blocks, pos, at, j as u32, |p, q| -blk(p, q));
    }
    // Dilatation blocks: sum over n in {i} and the neighbours of i of 2 a_n w_n[i] w_n^T,
    // w_n[i] the entry of the bond n -> i (the reverse of i -> n).
    let own = std::iter::once((i, fam.diag[i]));
    let nbrs = b
        .row(i)
        .filter(|&k| r.intact[k] != 0 && r.intact[sb.rev[k] as usize] != 0)
        .map(|k| (b.nbr[k] as usize, fam.w[sb.rev[k] as usize]));
    for (n, wi) in own.chain(nbrs) {
        if sb.a[n] == 0.0 {
            continue;
        }
        let two_a = 2.0 * sb.a[n];
        let wnn = fam.diag[n];
        add(blocks, pos, at, n as u32, |p, q| two_a * wi[p] * wnn[q]);
        for k in b.row(n).filter(|&k| r.intact[k] != 0) {
            let wm = fam.w[k];
            add(blocks, pos, at, b.nbr[k], |p, q| two_a * wi[p] * wm[q]);
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
    let fam = Families::new(r);
    t.assemble_rows(RowScratch::default, |sc, i, st, blocks| {
        row_blocks(r, &fam, (i, Part::Upper), st, sc, blocks);
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
    let fam = Families::new(r);
    let mut sc = RowScratch::default();
    for i in 0..n {
        let st = &nodes[offsets[i]..offsets[i + 1]];
        let mut blocks = vec![[[0.0; 2]; 2]; st.len()];
        row_blocks(r, &fam, (i, Part::Full), st, &mut sc, &mut blocks);
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
    let fam = Families::new(r);
    (0..r.u.len())
        .into_par_iter()
        .map_init(RowScratch::default, |sc, i| {
            let st = &nodes[offsets[i]..offsets[i + 1]];
            let mut blocks = vec![[[0.0; 2]; 2]; st.len()];
            row_blocks(r, &fam, (i, Part::Full), st, sc, &mut blocks);
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
