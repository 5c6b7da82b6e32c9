//! Internal bond forces, gathered per node in parallel (no atomics).
//!
//! Force density on node $i$ (seed 000 Eq. 13, seed 002 Eqs. 3-4, 16):
//! $$F_i = \sum_j c\, v_j V_j G_{ij}\, T(s_{ij})\, s_{ij}\, \frac{\xi+\eta}{|\xi+\eta|},\qquad
//!   s = \frac{|\xi+\eta|-|\xi|}{|\xi|}$$
//! with the fully nonlinear stretch. `T` is 1 (elastic or intact brittle)
//! or the tanh degradation evaluated at `max(s, s_hist)` (irreversible;
//! at `s_hist` alone in the [`History::Secant`] pass of the ADR re-commit
//! loop).
//! Each bond is stored in both directions, so row `i` alone determines
//! `F_i`; the two directions see bitwise identical stretches, hence they
//! break together. Row sums run group by group in the mirror-symmetric
//! order of [`crate::bonds`], so mirror-image nodes get bitwise mirrored
//! forces. The loop is monomorphised per bond law (no per-bond `match`),
//! reads 38 bytes per bond (neighbour `u32`, `xi`, `1/|xi|`, `k`, group
//! byte, intact byte; plus `s_hist` for degrading bonds) and skips bounds
//! checks; rayon splits the nodes with a minimum chunk of 64. The bond
//! energy (for tests) is
//! $\Pi = \sum_{i\to j} \tfrac14 V k |\xi| s^2$ for elastic bonds.

use rayon::prelude::*;

use crate::bonds::{Bonds, GROUP_END};
use crate::geometry::P2;
use crate::material::{degradation, BondLaw};

/// Intact flag of a bond that may not fail (a no-fail zone, e.g. next to a coupling
/// interface, [`crate::PdModel::protect_bonds`]): it stays elastic and intact.
pub const NO_FAIL: u8 = 2;

/// Whether a force pass may change the bond history.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum History {
    /// Read only: implicit iterations (history committed after convergence).
    Frozen,
    /// Update `s_hist` and break bonds (explicit ADR, or committing a state).
    Update,
    /// Read only, and every bond acts with its committed secant factor
    /// `T(s_hist)` (no softening inside the pass): an equilibrium search in
    /// this mode has a unique, stable solution; committing it and repeating
    /// reaches the softening equilibrium as a monotone fixed point.
    Secant,
}

/// Per-pass statistics, reduced over all bonds (directed counts).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ForceStats {
    /// Largest stretch over intact bonds.
    pub max_stretch: f64,
    /// Directed bonds whose damage grows: stretch past both the onset
    /// (`s0` or `s_m`) and the bond's history.
    pub growing: usize,
    /// Directed bonds newly broken in this pass (`Update` only).
    pub newly_broken: usize,
    /// Largest stretch increase past the damage onset and the history,
    /// `max(s - max(s_hist, s_m))` over growing bonds (0 if none).
    pub max_growth: f64,
}

impl ForceStats {
    fn merge(a: Self, b: Self) -> Self {
        ForceStats {
            max_stretch: a.max_stretch.max(b.max_stretch),
            growing: a.growing + b.growing,
            newly_broken: a.newly_broken + b.newly_broken,
            max_growth: a.max_growth.max(b.max_growth),
        }
    }
}

/// Raw pointer that may be shared across rayon tasks writing disjoint rows.
#[derive(Clone, Copy)]
pub(crate) struct RowPtr<T>(pub *mut T);
// SAFETY: used only to write disjoint CSR rows from different tasks.
unsafe impl<T: Send> Send for RowPtr<T> {}
// SAFETY: as above; no two tasks touch the same index.
unsafe impl<T: Send> Sync for RowPtr<T> {}

/// Mutable bond history.
pub struct BondState<'a> {
    /// 1 for an intact bond, 0 once broken or cut.
    pub intact: &'a mut [u8],
    /// Largest stretch reached (history for the degradation law).
    pub s_hist: &'a mut [f64],
}

/// Nodes per parallel chunk of a force pass. A PD-BEM window (20 x 20 nodes and their
/// layers, about 540 nodes and 15 000 bonds, 50-80 us a pass) then runs its passes on the
/// calling thread instead of waking the other one for half of each (futex and scheduler
/// time), and a growth run makes tens of thousands of them. On `growth_tension_edge`
/// (PD-BEM, the same binary with 64 and 1024 nodes per chunk, five alternated pairs):
/// user CPU 5.7-6.8 s against 6.1-7.4 s, system CPU 0.35-0.50 s against 0.72-0.81 s,
/// wall time 4.5-5.7 s against 4.5-5.6 s (no difference beyond the machine's scatter),
/// forces unchanged bit for bit. Whole-body models (full PD, tens of thousands of nodes)
/// still split into many chunks.
pub(crate) const PAR_MIN_NODES: usize = 1024;

/// Compute the internal force density of every node into `out` and return
/// statistics. `u` has one displacement per node.
pub fn internal_forces(
    bonds: &Bonds,
    law: BondLaw,
    state: BondState<'_>,
    u: &[P2],
    out: &mut [P2],
    history: History,
) -> ForceStats {
    let intact = RowPtr(state.intact.as_mut_ptr());
    let s_hist = RowPtr(state.s_hist.as_mut_ptr());
    out.par_iter_mut()
        .enumerate()
        .with_min_len(PAR_MIN_NODES)
        .map(|(i, f)| {
            let ip = intact;
            let hp = s_hist;
            // SAFETY: node i touches only the bond slots of its own row.
            unsafe { node_force(bonds, law, ip.0, hp.0, u, i, f, history) }
        })
        .reduce(ForceStats::default, ForceStats::merge)
}

/// Force on one node; `intact` and `s_hist` are written only in row `i`.
/// The bond sum is taken group by group in the mirror-symmetric order of
/// [`crate::bonds`] (`((t0 + t1) + (t2 + t3))` per group).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn node_force(
    bonds: &Bonds,
    law: BondLaw,
    intact: *mut u8,
    s_hist: *mut f64,
    u: &[P2],
    i: usize,
    out: &mut P2,
    history: History,
) -> ForceStats {
    match (law, history) {
        (BondLaw::Elastic, _) => {
            row_force(bonds, intact, s_hist, u, i, out, |_, s, _, _, _| (1.0, s))
        }
        (BondLaw::Brittle { s0 }, h) if !bonds.s_scale.is_empty() => {
            // Mixed spacing: the pair's own critical stretch; the normalised stretch is
            // reported (crate::mixed).
            let scale = &bonds.s_scale;
            row_force(bonds, intact, s_hist, u, i, out, |st, s, b, ip, _| {
                let s = s / *scale.get_unchecked(b);
                if s >= s0 && *ip != NO_FAIL {
                    st.growing += 1;
                    if h == History::Update {
                        *ip = 0;
                        st.newly_broken += 1;
                        return (0.0, s);
                    }
                }
                (1.0, s)
            })
        }
        (BondLaw::Brittle { s0 }, h) => {
            row_force(bonds, intact, s_hist, u, i, out, |st, s, _, ip, _| {
                if s >= s0 && *ip != NO_FAIL {
                    st.growing += 1;
                    if h == History::Update {
                        *ip = 0;
                        st.newly_broken += 1;
                        return (0.0, s);
                    }
                }
                (1.0, s)
            })
        }
        (BondLaw::Degrading { s_m, s_c, beta }, h) if !bonds.s_scale.is_empty() => {
            // Mixed spacing: the law acts on the normalised stretch, which `s_hist` holds
            // (crate::mixed).
            let scale = &bonds.s_scale;
            row_force(bonds, intact, s_hist, u, i, out, |st, s, b, ip, hp| {
                let s = s / *scale.get_unchecked(b);
                degrading(st, h, (s_m, s_c, beta), s, ip, hp)
            })
        }
        (BondLaw::Degrading { s_m, s_c, beta }, h) => {
            row_force(bonds, intact, s_hist, u, i, out, |st, s, _, ip, hp| {
                degrading(st, h, (s_m, s_c, beta), s, ip, hp)
            })
        }
    }
}

/// The tanh law's factor `T` of an intact bond of (normalised) stretch `s` and the
/// stretch to report, updating its flags and history `hp` in [`History::Update`]; the
/// PMB and state-based passes share it.
#[inline(always)]
pub(crate) fn degrading(
    st: &mut ForceStats,
    h: History,
    (s_m, s_c, beta): (f64, f64, f64),
    s: f64,
    ip: &mut u8,
    hp: &mut f64,
) -> (f64, f64) {
    if *ip == NO_FAIL {
        return (1.0, s);
    }
    let hv = *hp;
    if s > s_m && s > hv {
        st.growing += 1;
        st.max_growth = st.max_growth.max(s - hv.max(s_m));
        if h == History::Update {
            *hp = s;
            if s >= s_c {
                *ip = 0;
                st.newly_broken += 1;
                return (0.0, s);
            }
        }
    }
    let arg = if h == History::Secant { hv } else { s.max(hv) };
    (degradation(arg, s_m, s_c, beta).0, s)
}

/// The bond loop of [`node_force`], monomorphised per bond law. `law`
/// returns the factor `T` for bond `b` of stretch `s` (0 once it breaks) and the stretch
/// to report (`s`, or `s` over the bond's scale on a mixed grid).
#[inline(always)]
unsafe fn row_force(
    bonds: &Bonds,
    intact: *mut u8,
    s_hist: *mut f64,
    u: &[P2],
    i: usize,
    out: &mut P2,
    mut law: impl FnMut(&mut ForceStats, f64, usize, &mut u8, &mut f64) -> (f64, f64),
) -> ForceStats {
    let r = bonds.offsets[i]..bonds.offsets[i + 1];
    let nbr = &bonds.nbr[r.clone()];
    let xi = &bonds.xi[r.clone()];
    let inv = &bonds.inv_len[r.clone()];
    let k = &bonds.k[r.clone()];
    let meta = &bonds.meta[r.clone()];
    let base = r.start;
    let ui = u[i];
    let mut st = ForceStats::default();
    let mut g = [[0.0f64; 2]; 4];
    let (mut fx, mut fy) = (0.0, 0.0);
    let mut smax = f64::NEG_INFINITY;
    for m in 0..nbr.len() {
        let b = base + m;
        let mt = *meta.get_unchecked(m);
        let ip = &mut *intact.add(b);
        if *ip != 0 {
            let uj = *u.get_unchecked(*nbr.get_unchecked(m) as usize);
            let x = *xi.get_unchecked(m);
            let yx = x[0] + (uj[0] - ui[0]);
            let yy = x[1] + (uj[1] - ui[1]);
            let l = (yx * yx + yy * yy).sqrt();
            let s = l * *inv.get_unchecked(m) - 1.0;
            let (t, sr) = law(&mut st, s, b, ip, &mut *s_hist.add(b));
            if t != 0.0 || *ip != 0 {
                smax = smax.max(sr);
            }
            let f = *k.get_unchecked(m) * t * s / l;
            let sl = (mt & 3) as usize;
            g[sl][0] += f * yx;
            g[sl][1] += f * yy;
        }
        if mt & GROUP_END != 0 {
            fx += (g[0][0] + g[1][0]) + (g[2][0] + g[3][0]);
            fy += (g[0][1] + g[1][1]) + (g[2][1] + g[3][1]);
            g = [[0.0; 2]; 4];
        }
    }
    st.max_stretch = smax.max(0.0);
    *out = [fx, fy];
    st
}

/// Elastic bond energy $\Pi$ (J) for the current displacements, counting
/// intact bonds only (valid for the elastic law and intact brittle bonds).
pub fn elastic_energy(bonds: &Bonds, intact: &[u8], u: &[P2], volume: f64) -> f64 {
    (0..u.len())
        .into_par_iter()
        .map(|i| {
            let mut e = 0.0;
            for b in bonds.row(i) {
                if intact[b] == 0 {
                    continue;
                }
                let j = bonds.nbr[b] as usize;
                let yx = bonds.xi[b][0] + (u[j][0] - u[i][0]);
                let yy = bonds.xi[b][1] + (u[j][1] - u[i][1]);
                let l = yx.hypot(yy);
                let s = l * bonds.inv_len[b] - 1.0;
                e += 0.25 * volume * bonds.k[b] * s * s / bonds.inv_len[b];
            }
            e
        })
        .sum()
}

/// Which tangent a bond block is taken of.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TangentKind {
    /// Of the [`History::Frozen`] force pass (seed 000 Eqs. 14-15): the
    /// degradation acts at `max(s, s_hist)` and a bond loading past its
    /// history gets the softening slope.
    Consistent,
    /// Of the [`History::Secant`] force pass: every bond keeps its
    /// committed factor `T(s_hist)`, so $g' = T(s_{hist})$ (no softening).
    Secant,
    /// [`TangentKind::Secant`] with the transverse (geometric) term taken as
    /// $\max(g, 0)$: a compressed bond would make it negative, and a
    /// compressed bond left on its own (a fragment cut free by the crack)
    /// makes the secant matrix indefinite. Positive semi-definite bond by
    /// bond; iterations with it contract by the ratio of the dropped
    /// geometric stiffness to the stiffness of the softest mode (about 0.3
    /// measured on the three-point bend, whose compressed top chord
    /// carries a bending mode).
    SecantPositive,
}

/// The 2x2 tangent block `B = dF_i/du_j` of one bond (seed 000 Eqs. 8, 14):
/// $B = k[g'(s)/L\, e e^T + g(s)/l\,(I - e e^T)]$ with $g = s\,T$,
/// $g' = T + s T'$ while the bond is loading past its history, else $T(s_{hist})$.
/// The tangent of the force pass with [`History::Frozen`] on a uniform grid; see
/// [`bond_tangent_scaled`] for the other kinds and mixed spacing.
#[inline]
pub fn bond_tangent(law: BondLaw, k: f64, inv_len: f64, y: P2, s_hist: f64) -> [[f64; 2]; 2] {
    bond_tangent_scaled(law, k, inv_len, y, s_hist, TangentKind::Consistent, 1.0)
}

/// The factor of bond `b`'s stretch that its failure law sees: `bonds.s_scale[b]` on
/// mixed spacing ([`crate::mixed`]: the law acts on `s / s_scale`), else 1.
#[inline]
pub fn stretch_scale(bonds: &Bonds, b: usize) -> f64 {
    bonds.s_scale.get(b).copied().unwrap_or(1.0)
}

/// [`bond_tangent`] of the given [`TangentKind`], for a bond whose law acts on the
/// normalised stretch `s / scale` (`s_hist` normalised too; [`stretch_scale`]; 1 on a
/// uniform grid): the tanh law's slope is $dT/ds = T'(s/\sigma)/\sigma$.
#[inline]
pub fn bond_tangent_scaled(
    law: BondLaw,
    k: f64,
    inv_len: f64,
    y: P2,
    s_hist: f64,
    kind: TangentKind,
    scale: f64,
) -> [[f64; 2]; 2] {
    let l = y[0].hypot(y[1]);
    let s = l * inv_len - 1.0;
    let (g, gp) = match law {
        BondLaw::Elastic | BondLaw::Brittle { .. } => (s, 1.0),
        BondLaw::Degrading { s_m, s_c, beta } => {
            let sn = s / scale;
            if sn > s_hist && kind == TangentKind::Consistent {
                let (t, dt) = degradation(sn, s_m, s_c, beta);
                (s * t, t + s * (dt / scale))
            } else {
                let t = degradation(s_hist, s_m, s_c, beta).0;
                (s * t, t)
            }
        }
    };
    let g = if kind == TangentKind::SecantPositive {
        g.max(0.0)
    } else {
        g
    };
    let e = [y[0] / l, y[1] / l];
    let a = gp * inv_len;
    let bb = g / l;
    let mut m = [[0.0; 2]; 2];
    for p in 0..2 {
        for q in 0..2 {
            let ee = e[p] * e[q];
            let id = if p == q { 1.0 } else { 0.0 };
            m[p][q] = k * (a * ee + bb * (id - ee));
        }
    }
    m
}
