//! Internal bond forces, gathered per node in parallel (no atomics).
//!
//! Force density on node $i$ (seed 000 Eq. 13, seed 002 Eqs. 3-4, 16):
//! $$F_i = \sum_j c\, v_j V_j G_{ij}\, T(s_{ij})\, s_{ij}\, \frac{\xi+\eta}{|\xi+\eta|},\qquad
//!   s = \frac{|\xi+\eta|-|\xi|}{|\xi|}$$
//! with the fully nonlinear stretch. `T` is 1 (elastic or intact brittle)
//! or the tanh degradation evaluated at `max(s, s_hist)` (irreversible).
//! Each bond is stored in both directions, so row `i` alone determines
//! `F_i`; the two directions see bitwise identical stretches, hence they
//! break together. The bond energy (for tests) is
//! $\Pi = \sum_{i\to j} \tfrac14 V k |\xi| s^2$ for elastic bonds.

use rayon::prelude::*;

use crate::bonds::Bonds;
use crate::geometry::P2;
use crate::material::{degradation, BondLaw};

/// Whether a force pass may change the bond history.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum History {
    /// Read only: implicit iterations (history committed after convergence).
    Frozen,
    /// Update `s_hist` and break bonds (explicit ADR, or committing a state).
    Update,
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
}

impl ForceStats {
    fn merge(a: Self, b: Self) -> Self {
        ForceStats {
            max_stretch: a.max_stretch.max(b.max_stretch),
            growing: a.growing + b.growing,
            newly_broken: a.newly_broken + b.newly_broken,
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
        .with_min_len(64)
        .map(|(i, f)| {
            let ip = intact;
            let hp = s_hist;
            // SAFETY: node i touches only the bond slots of its own row.
            unsafe { node_force(bonds, law, ip.0, hp.0, u, i, f, history) }
        })
        .reduce(ForceStats::default, ForceStats::merge)
}

/// Force on one node; `intact` and `s_hist` are written only in row `i`.
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
    let r = bonds.row(i);
    let nbr = &bonds.nbr[r.clone()];
    let xi = &bonds.xi[r.clone()];
    let inv = &bonds.inv_len[r.clone()];
    let k = &bonds.k[r.clone()];
    let base = r.start;
    let ui = u[i];
    let (mut fx, mut fy) = (0.0, 0.0);
    let mut st = ForceStats::default();
    for m in 0..nbr.len() {
        let b = base + m;
        if *intact.add(b) == 0 {
            continue;
        }
        let uj = u[nbr[m] as usize];
        let yx = xi[m][0] + (uj[0] - ui[0]);
        let yy = xi[m][1] + (uj[1] - ui[1]);
        let l = (yx * yx + yy * yy).sqrt();
        let s = l * inv[m] - 1.0;
        let t = match law {
            BondLaw::Elastic => 1.0,
            BondLaw::Brittle { s0 } => {
                if s >= s0 {
                    st.growing += 1;
                    if history == History::Update {
                        *intact.add(b) = 0;
                        st.newly_broken += 1;
                        continue;
                    }
                }
                1.0
            }
            BondLaw::Degrading { s_m, s_c, beta } => {
                let h = &mut *s_hist.add(b);
                if s > s_m && s > *h {
                    st.growing += 1;
                    if history == History::Update {
                        *h = s;
                        if s >= s_c {
                            *intact.add(b) = 0;
                            st.newly_broken += 1;
                            continue;
                        }
                    }
                }
                degradation(s.max(*h), s_m, s_c, beta).0
            }
        };
        st.max_stretch = st.max_stretch.max(s);
        let f = k[m] * t * s / l;
        fx += f * yx;
        fy += f * yy;
    }
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

/// The 2x2 tangent block `B = dF_i/du_j` of one bond (seed 000 Eqs. 8, 14):
/// $B = k[g'(s)/L\, e e^T + g(s)/l\,(I - e e^T)]$ with $g = s\,T$,
/// $g' = T + s T'$ while the bond is loading past its history, else $T(s_{hist})$.
#[inline]
pub fn bond_tangent(law: BondLaw, k: f64, inv_len: f64, y: P2, s_hist: f64) -> [[f64; 2]; 2] {
    let l = y[0].hypot(y[1]);
    let s = l * inv_len - 1.0;
    let (g, gp) = match law {
        BondLaw::Elastic | BondLaw::Brittle { .. } => (s, 1.0),
        BondLaw::Degrading { s_m, s_c, beta } => {
            if s > s_hist {
                let (t, dt) = degradation(s, s_m, s_c, beta);
                (s * t, t + s * dt)
            } else {
                let t = degradation(s_hist, s_m, s_c, beta).0;
                (s * t, t)
            }
        }
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
