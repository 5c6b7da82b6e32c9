//! The state-based force gather in two parallel passes over the nodes (no atomics):
//!
//! 1. per node $k$: each bond's stretch and failure factor $T$ (the same decisions as the
//!    PMB pass [`crate::forces::internal_forces`]: break at `s0` or `s_c` in
//!    [`History::Update`], `T(max(s, s_hist))`, `T(s_hist)` in [`History::Secant`]),
//!    written in row $k$ only, and the dilatation $\theta_k = \sum_j \omega_{kj} T s V'_j$;
//!    then, with $\theta_k$ known, the half force of each bond of the row on its owner,
//!    $h_{kj} = \tau_{kj}\, V'_{kj}\, e_{kj}$ with
//!    $\tau_{kj} = T(2a_k\omega_{kj}\theta_k/|\xi| + \beta_{kj} s)$ (module docs of
//!    [`super`]; on a mixed grid $V'_{kj}$ is the half's own partial volume,
//!    [`crate::mixed`]);
//! 2. per node $k$: $F_k = \sum_j (h_{kj} - h_{jk})$, since $e_{jk} = -e_{kj}$, summed
//!    group by group in the mirror-symmetric order of [`crate::bonds`].
//!
//! Both directions of a bond see bitwise identical stretches and lengths (the reverse
//! bond's $\xi$ and displacement difference are exact negations), so they take the same
//! decision and the same $T$, and the pair's terms in step 2 at its two ends are exact
//! negations of each other (action and reaction; the forces of a free body sum to zero
//! to round-off). Each bond's length is computed once per pass (kept for the half
//! force: one square root and one division per bond) and the reverse half is one load.
//! This replaced a second pass that formed $\tau_{kj} + \tau_{jk}$ per bond from both
//! ends' constants (2026-11-29): the pass on the branching plate of seed 004 (107 k
//! bonds) went from 600 to 377 us, the same forces to round-off (test
//! `the_force_pass_is_the_sum_of_pair_forces_and_conserves_momentum`).

use rayon::prelude::*;

use super::StateBased;
use crate::bonds::{group_sum, Bonds};
use crate::forces::{BondState, ForceStats, History, RowPtr, NO_FAIL};
use crate::geometry::P2;
use crate::material::{degradation, BondLaw};

/// Stretch, current length and deformed bond vector of bond `b` of node `i`. The length
/// is $\sqrt{y_x^2 + y_y^2}$, not `hypot` (a library call guarding against an overflow a
/// bond vector cannot reach, and more than a quarter of this pass's time).
#[inline(always)]
pub(super) fn stretch(bonds: &Bonds, u: &[P2], i: usize, b: usize) -> (f64, f64, P2) {
    let j = bonds.nbr[b] as usize;
    let y = [
        bonds.xi[b][0] + (u[j][0] - u[i][0]),
        bonds.xi[b][1] + (u[j][1] - u[i][1]),
    ];
    let l = (y[0] * y[0] + y[1] * y[1]).sqrt();
    (l * bonds.inv_len[b] - 1.0, l, y)
}

/// Failure factor `T` of an intact bond of stretch `s` (updating its flags and history
/// in [`History::Update`]), as in the PMB pass.
#[inline(always)]
fn factor(law: BondLaw, h: History, s: f64, ip: &mut u8, hp: &mut f64, st: &mut ForceStats) -> f64 {
    match law {
        BondLaw::Elastic => 1.0,
        BondLaw::Brittle { s0 } => {
            if s >= s0 && *ip != NO_FAIL {
                st.growing += 1;
                if h == History::Update {
                    *ip = 0;
                    st.newly_broken += 1;
                    return 0.0;
                }
            }
            1.0
        }
        BondLaw::Degrading { s_m, s_c, beta } => {
            crate::forces::degrading(st, h, (s_m, s_c, beta), s, ip, hp).0
        }
    }
}

/// Force density of every node into `out` (pass 1 fills `sb.theta`, `sb.tfac` and
/// `sb.half`).
pub fn internal_forces(
    sb: &mut StateBased,
    bonds: &Bonds,
    law: BondLaw,
    state: BondState<'_>,
    u: &[P2],
    out: &mut [P2],
    history: History,
    volume: f64,
) -> ForceStats {
    let intact = RowPtr(state.intact.as_mut_ptr());
    let s_hist = RowPtr(state.s_hist.as_mut_ptr());
    let tfac = RowPtr(sb.tfac.as_mut_ptr());
    let half = RowPtr(sb.half.as_mut_ptr());
    let lengths = RowPtr(sb.length.as_mut_ptr());
    let (a, omega, beta) = (&sb.a, &sb.omega, &sb.beta);
    let scale = &bonds.s_scale;
    let stats = sb
        .theta
        .par_iter_mut()
        .enumerate()
        .with_min_len(crate::forces::PAR_MIN_NODES)
        .map(|(k, th)| {
            let (ip, hp, tp, fp, lp) = (&intact, &s_hist, &tfac, &half, &lengths);
            let row = bonds.row(k);
            // SAFETY: node k touches only the bond slots of its own row, and rows are
            // disjoint.
            let (flags, hist, t, h, lens) = unsafe {
                (
                    std::slice::from_raw_parts_mut(ip.0.add(row.start), row.len()),
                    std::slice::from_raw_parts_mut(hp.0.add(row.start), row.len()),
                    std::slice::from_raw_parts_mut(tp.0.add(row.start), row.len()),
                    std::slice::from_raw_parts_mut(fp.0.add(row.start), row.len()),
                    std::slice::from_raw_parts_mut(lp.0.add(row.start), row.len()),
                )
            };
            let mut st = ForceStats::default();
            let mut smax = f64::NEG_INFINITY;
            let mut sum = 0.0;
            let (nbr, xi, inv_len) = (
                &bonds.nbr[row.clone()],
                &bonds.xi[row.clone()],
                &bonds.inv_len[row.clone()],
            );
            let (vf, om, be) = (
                &bonds.vol_factor[row.clone()],
                &omega[row.clone()],
                &beta[row.clone()],
            );
            let uk = u[k];
            for i in 0..row.len() {
                t[i] = 0.0;
                if flags[i] == 0 {
                    continue;
                }
                let j = nbr[i] as usize;
                let y = [xi[i][0] + (u[j][0] - uk[0]), xi[i][1] + (u[j][1] - uk[1])];
                let l = (y[0] * y[0] + y[1] * y[1]).sqrt();
                let s = l * inv_len[i] - 1.0;
                // Mixed spacing: the pair's own critical stretch (crate::mixed).
                let sn = scale.get(row.start + i).map_or(s, |c| s / c);
                let f = factor(law, history, sn, &mut flags[i], &mut hist[i], &mut st);
                if f != 0.0 || flags[i] != 0 {
                    smax = smax.max(sn);
                }
                t[i] = f;
                sum += om[i] * f * s * vf[i];
                h[i] = y;
                lens[i] = l;
            }
            let theta = sum * volume;
            *th = theta;
            let ak = 2.0 * a[k] * theta;
            for i in 0..row.len() {
                h[i] = if t[i] == 0.0 {
                    [0.0; 2]
                } else {
                    let (y, l) = (h[i], lens[i]);
                    let s = l * inv_len[i] - 1.0;
                    let tau = ak * om[i] * inv_len[i] + be[i] * s;
                    let c = t[i] * volume * vf[i] * tau / l;
                    [c * y[0], c * y[1]]
                };
            }
            st.max_stretch = smax.max(0.0);
            st
        })
        .reduce(ForceStats::default, merge);
    let (half, rev) = (&sb.half, &sb.rev);
    out.par_iter_mut()
        .enumerate()
        .with_min_len(crate::forces::PAR_MIN_NODES)
        .for_each(|(k, f)| {
            *f = group_sum(&bonds.meta, bonds.row(k), |b| {
                let (hb, hr) = (half[b], half[rev[b] as usize]);
                [hb[0] - hr[0], hb[1] - hr[1]]
            });
        });
    stats
}

/// $\tau_{kj} + \tau_{jk}$ per unit factor $T$ with the dilatations `th_k`, `th_j`:
/// $2(a_k\omega_{kj}\theta_k + a_j\omega_{jk}\theta_j)/|\xi| + (\beta_{kj} + \beta_{jk}) s$.
#[inline(always)]
pub(super) fn pair_base(
    sb: &StateBased,
    bonds: &Bonds,
    k: usize,
    b: usize,
    s: f64,
    th_k: f64,
    th_j: f64,
) -> f64 {
    let j = bonds.nbr[b] as usize;
    let r = sb.rev[b] as usize;
    2.0 * (sb.a[k] * sb.omega[b] * th_k + sb.a[j] * sb.omega[r] * th_j) * bonds.inv_len[b]
        + (sb.beta[b] + sb.beta[r]) * s
}

/// Mixed spacing ([`crate::mixed`]; `a` and `beta` hold the owner's relative volume):
/// each half of the pair with its own partial volume, seed 004 Eq. 13,
/// $\mathrm{vf}_{kj}(2a_k\omega_{kj}\theta_k/|\xi| + \beta_{kj}s) +
/// \mathrm{vf}_{jk}(2a_j\omega_{jk}\theta_j/|\xi| + \beta_{jk}s)$ per unit factor `T`.
#[inline(always)]
pub(super) fn pair_mixed(
    sb: &StateBased,
    bonds: &Bonds,
    k: usize,
    b: usize,
    s: f64,
    th_k: f64,
    th_j: f64,
) -> f64 {
    let j = bonds.nbr[b] as usize;
    let r = sb.rev[b] as usize;
    let (vb, vr) = (bonds.vol_factor[b], bonds.vol_factor[r]);
    vb * (2.0 * sb.a[k] * sb.omega[b] * th_k * bonds.inv_len[b] + sb.beta[b] * s)
        + vr * (2.0 * sb.a[j] * sb.omega[r] * th_j * bonds.inv_len[b] + sb.beta[r] * s)
}

/// `d/ds` of [`pair_mixed`] at fixed dilatations.
#[inline(always)]
pub(super) fn pair_mixed_ds(sb: &StateBased, bonds: &Bonds, b: usize) -> f64 {
    let r = sb.rev[b] as usize;
    bonds.vol_factor[b] * sb.beta[b] + bonds.vol_factor[r] * sb.beta[r]
}

fn merge(a: ForceStats, b: ForceStats) -> ForceStats {
    ForceStats {
        max_stretch: a.max_stretch.max(b.max_stretch),
        growing: a.growing + b.growing,
        newly_broken: a.newly_broken + b.newly_broken,
        max_growth: a.max_growth.max(b.max_growth),
    }
}

/// Failure factor of bond `b` of stretch `s` with the history frozen
/// (`T(max(s / scale, s_hist))`, the law acting on the normalised stretch on mixed spacing,
/// [`crate::forces::stretch_scale`]; 1 for elastic, brittle and no-fail bonds; 0 if
/// broken).
#[inline]
pub(super) fn frozen_factor(
    law: BondLaw,
    bonds: &Bonds,
    b: usize,
    (intact, s_hist): (&[u8], &[f64]),
    s: f64,
) -> f64 {
    if intact[b] == 0 {
        return 0.0;
    }
    match law {
        BondLaw::Degrading { s_m, s_c, beta } if intact[b] != NO_FAIL => {
            let sn = s / crate::forces::stretch_scale(bonds, b);
            degradation(sn.max(s_hist[b]), s_m, s_c, beta).0
        }
        _ => 1.0,
    }
}

/// Dilatation of node `k` with the history frozen.
pub(super) fn dilatation_at(
    sb: &StateBased,
    bonds: &Bonds,
    law: BondLaw,
    intact: &[u8],
    s_hist: &[f64],
    u: &[P2],
    k: usize,
    volume: f64,
) -> f64 {
    let mut sum = 0.0;
    for b in bonds.row(k) {
        if intact[b] == 0 {
            continue;
        }
        let (s, _, _) = stretch(bonds, u, k, b);
        sum += sb.omega[b]
            * frozen_factor(law, bonds, b, (intact, s_hist), s)
            * s
            * bonds.vol_factor[b];
    }
    sum * volume
}

/// Force density (N/m^3) on node `i` from the pair of bond `b` ($i \to j$):
/// $(t_{ij} - t_{ji}) V'_j$, history frozen, dilatations computed afresh at `u`. The
/// coupling's interface forces read it bond by bond.
#[allow(clippy::too_many_arguments)]
pub fn pair_force(
    sb: &StateBased,
    bonds: &Bonds,
    law: BondLaw,
    intact: &[u8],
    s_hist: &[f64],
    u: &[P2],
    i: usize,
    b: usize,
    volume: f64,
) -> P2 {
    let (s, l, y) = stretch(bonds, u, i, b);
    let t = frozen_factor(law, bonds, b, (intact, s_hist), s);
    if t == 0.0 {
        return [0.0; 2];
    }
    let j = bonds.nbr[b] as usize;
    let th_i = dilatation_at(sb, bonds, law, intact, s_hist, u, i, volume);
    let th_j = dilatation_at(sb, bonds, law, intact, s_hist, u, j, volume);
    let c = if bonds.s_scale.is_empty() {
        let phi = pair_base(sb, bonds, i, b, s, th_i, th_j);
        t * phi * bonds.vol_factor[b] * volume / l
    } else {
        t * pair_mixed(sb, bonds, i, b, s, th_i, th_j) * volume / l
    };
    [c * y[0], c * y[1]]
}

/// Strain energy (J) $\sum_k V W_k$ at `u` with the history frozen (the elastic energy
/// for frozen factors $T$).
pub fn elastic_energy(
    sb: &StateBased,
    bonds: &Bonds,
    law: BondLaw,
    intact: &[u8],
    s_hist: &[f64],
    u: &[P2],
    volume: f64,
) -> f64 {
    (0..u.len())
        .into_par_iter()
        .map(|k| {
            let (mut sum_th, mut sum_dev) = (0.0, 0.0);
            for b in bonds.row(k) {
                if intact[b] == 0 {
                    continue;
                }
                let (s, _, _) = stretch(bonds, u, k, b);
                let t = frozen_factor(law, bonds, b, (intact, s_hist), s);
                let v = bonds.vol_factor[b] * volume;
                sum_th += sb.omega[b] * t * s * v;
                sum_dev += sb.beta[b] * t * s * s / bonds.inv_len[b] * v;
            }
            volume * (sb.a[k] * sum_th * sum_th + 0.5 * sum_dev)
        })
        .sum()
}
