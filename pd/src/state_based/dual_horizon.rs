//! Dual-horizon state-based PD on particles of different sizes (seed 004 section 2.2,
//! Eqs. 13-14; Ren, Zhang & Rabczuk's DH-PD).
//!
//! Particle $k$ has its own spacing $\Delta_k$, volume $V_k = \Delta_k^2 h$ and horizon
//! $\delta_k = m\Delta_k$; its family is $H_k = \{j : |x_j - x_k| \le \delta_k\}$ and its
//! dual horizon $H'_k = \{j : k \in H_j\}$, which differ once sizes differ. The energy is
//! $\Pi = \sum_k V_k W_k$ with the state-based $W_k$ of [`super`] over $H_k$ alone
//! ($V'_{kj} = v_{kj} V_j$, $v_{kj}$ the partial volume of $j$'s cell in $\delta_k$), so
//! the force on $n$,
//! $$F_n = -\frac{\partial \Pi}{\partial u_n} = \sum_{j\in H_n} V_n V'_{nj}\,\tau_{nj}\,e_{nj} +
//!   \sum_{k\in H'_n} V_k V'_{kn}\,\tau_{kn}\,e_{nk},$$
//! is seed 004 Eq. 13: the direct forces of $n$'s own bonds with $n$'s constants, and the
//! reactions of the bonds of $n$'s dual horizon with their owners' constants. Forces
//! balance exactly (translation invariance of $\Pi$) whatever the sizes.
//!
//! Constants: every particle is calibrated on its own family (sizes and partial volumes as
//! they are), $\omega_{kj} = n^T B_k n$ with $\sum_j \omega\, n n^T V' = I$ and
//! $\beta_{kj} = \sum_p c_{k,p} n_x^{4-p} n_y^p$ with the isotropic fourth moment
//! $\sum_j \beta\, n^{\otimes 4}|\xi| V' = \mu\,(\delta\delta + \delta\delta + \delta\delta)$,
//! and $a = (\kappa - 2\mu)/2$: the energy density of every particle equals the classical
//! one for every homogeneous strain, at the size jump and at the edges alike.
//!
//! Patch test (`tests/verification_dual_horizon_patch.rs`, spacings 1 and 0.5): a
//! homogeneous strain is an exact equilibrium (spurious force 1e-10 of
//! $E|\varepsilon|\Delta h$) wherever the particles within two horizons share one size;
//! within two coarse horizons of the jump the spurious force is 0.26 $E|\varepsilon|\Delta h$
//! and the solved field is 0.97 % (of the largest displacement; 41 % of the strain,
//! locally) off. Dual horizons give balanced, energy-consistent forces across sizes, not
//! a passed patch test: the odd moments of a family or dual horizon that mixes sizes do
//! not vanish.
//!
//! Bonds carry a flag (`intact`: cut by a pre-crack or broken); a particle whose fitted
//! weights are not all positive (a corner, a crack mouth) takes the scalar weights of its
//! own sums ($\omega = 2/S_0$, $\beta = 8\mu/S_1$) so that the energy stays positive.
//!
//! Scope: forces, energy, the patch test and [`crate::refine`] (linear solves, adaptive
//! refinement); the particles are not a [`crate::PdModel`] (not in the ADR, Newton or
//! switching solvers, no bond breaking during a solve).

use rayon::prelude::*;

use super::{bulk_moments, deviatoric_weights, dilatation_tensor, moments};
use crate::bonds::{partial_volume, Bonds};
use crate::geometry::P2;
use crate::problem::Plane;

/// A dual-horizon state-based body of particles of different sizes.
#[derive(Clone, Debug)]
pub struct DualHorizon {
    /// Reference positions (m).
    pub pos: Vec<P2>,
    /// Volumes `V_k` (m^3).
    pub volume: Vec<f64>,
    /// Horizons `delta_k` (m).
    pub delta: Vec<f64>,
    /// Families `H_k` in CSR (`vol_factor` holds `V'_kj = v_kj V_j`).
    pub bonds: Bonds,
    /// Dual horizons: for node `n`, the bonds `k -> n` of the families containing it.
    pub dual_offsets: Vec<usize>,
    /// Bond indices of the dual horizons.
    pub dual: Vec<u32>,
    /// Owner of each bond of `dual` (the `k` of `dual[i] = k -> n`).
    pub dual_owner: Vec<u32>,
    /// Dilatation weights `omega_b`.
    pub omega: Vec<f64>,
    /// Deviatoric weights `beta_b`.
    pub beta: Vec<f64>,
    /// Dilatational coefficient `a_k` of every particle (Pa): `(kappa - 2 mu) / 2` times
    /// the intact fraction of its family.
    pub a: Vec<f64>,
    /// Bond flags: 1 intact, 0 cut or broken (seed 004 Eq. 10's `mu_kj`).
    pub intact: Vec<u8>,
}

/// Constants of a previous body to keep ([`DualHorizon::from_families`]): `same[k]` is
/// the particle of `old` whose family (members in the same order, sizes, flags) particle
/// `k` has unchanged, if any.
#[derive(Clone, Copy)]
pub struct Reuse<'a> {
    /// The previous body.
    pub old: &'a DualHorizon,
    /// Per new particle, its unchanged counterpart in `old`.
    pub same: &'a [Option<usize>],
}

impl DualHorizon {
    /// Particles at `pos` with spacings `dx` (m), thickness `h`, horizon factor `m`, and
    /// the moduli of `E`, `nu` in `plane`. Returns `None` when a particle's family does
    /// not determine its constants (fewer than three independent directions).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        pos: &[P2],
        dx: &[f64],
        h: f64,
        m: f64,
        plane: Plane,
        youngs_modulus: f64,
        nu: f64,
    ) -> Option<Self> {
        let volume: Vec<f64> = dx.iter().map(|d| d * d * h).collect();
        let delta: Vec<f64> = dx.iter().map(|d| m * d).collect();
        let bonds = families(pos, dx, &volume, &delta);
        let intact = vec![1u8; bonds.len()];
        let moduli = super::moduli(plane, youngs_modulus, nu);
        let bulk = vec![None; pos.len()];
        Self::from_families(pos, volume, delta, bonds, intact, moduli, &bulk, None)
    }

    /// The body of the given families (`bonds`, `vol_factor` = `V'_kj`) and bond flags
    /// (`intact[b] = 0`: cut by a pre-crack or broken) for the 2-D moduli
    /// `(kappa, mu)`. A particle with `bulk[k] = Some(dx)` (a fictitious layer's: its
    /// family is cut by the layer's outer edge, which is no surface of the body) takes the
    /// constants of the full lattice family of spacing `dx` and its horizon, as the
    /// uniform model's fictitious nodes do. The deviatoric weights are fitted on the whole
    /// family (the outline's truncation corrected, cut bonds dropping out of the energy as in
    /// [`super::StateBased`] without crack-face correction), the dilatation weights on the
    /// intact bonds (exact dilatation of every homogeneous strain over them), and
    /// $a_k = a\,S_{0,k}^{intact}/S_{0,k}$. Particles `reuse` maps to an unchanged family
    /// copy their constants instead. `None` when a family does not determine its
    /// constants.
    #[allow(clippy::too_many_arguments)]
    pub fn from_families(
        pos: &[P2],
        volume: Vec<f64>,
        delta: Vec<f64>,
        bonds: Bonds,
        intact: Vec<u8>,
        (kappa, mu): (f64, f64),
        bulk: &[Option<f64>],
        reuse: Option<Reuse<'_>>,
    ) -> Option<Self> {
        let n = pos.len();
        let nb = bonds.len();
        let (mut omega, mut beta) = (vec![0.0; nb], vec![0.0; nb]);
        let mut a = vec![0.0; n];
        let target = [3.0 * mu, 0.0, mu, 0.0, 3.0 * mu];
        let mut lattice: Vec<((f64, f64), super::Moments)> = Vec::new();
        for k in 0..n {
            if let Some((old, o)) = reuse.and_then(|r| Some((r.old, r.same[k]?))) {
                // The same family as particle `o` of `old`: the same constants.
                let (row, old_row) = (bonds.row(k), old.bonds.row(o));
                debug_assert_eq!(row.len(), old_row.len());
                a[k] = old.a[o];
                omega[row.clone()].copy_from_slice(&old.omega[old_row.clone()]);
                beta[row].copy_from_slice(&old.beta[old_row]);
                continue;
            }
            let (mo, kept) = match bulk.get(k).copied().flatten() {
                Some(dx) => {
                    let key = (dx, delta[k]);
                    let i = lattice
                        .iter()
                        .position(|(q, _)| *q == key)
                        .unwrap_or_else(|| {
                            lattice.push((key, bulk_moments(dx, delta[k], 1.0)));
                            lattice.len() - 1
                        });
                    let scaled = lattice[i].1.scaled(volume[k]);
                    (scaled.clone(), scaled)
                }
                None => (
                    moments(&bonds, k, 1.0, (1.0, 0.0), |_| true),
                    moments(&bonds, k, 1.0, (1.0, 0.0), |b| intact[b] != 0),
                ),
            };
            let c = deviatoric_weights(mo.h, target)?;
            let bt = dilatation_tensor(kept.m).or_else(|| dilatation_tensor(mo.m))?;
            a[k] = 0.5 * (kappa - 2.0 * mu) * kept.s0 / mo.s0;
            for b in bonds.row(k) {
                let l = 1.0 / bonds.inv_len[b];
                let (nx, ny) = (bonds.xi[b][0] / l, bonds.xi[b][1] / l);
                omega[b] = bt[0] * nx * nx + 2.0 * bt[1] * nx * ny + bt[2] * ny * ny;
                beta[b] = (0..5)
                    .map(|p| c[p] * nx.powi(4 - p as i32) * ny.powi(p as i32))
                    .sum();
            }
            // A family too lopsided for positive weights (a corner, a crack mouth) takes
            // the scalar ones of its own sums, which keep the energy positive:
            // omega = 2 / S_0 (intact), beta = 8 mu / S_1.
            let row = bonds.row(k);
            if beta[row.clone()].iter().any(|&w| w <= 0.0) {
                let s1 = mo.f[0] + 2.0 * mo.f[2] + mo.f[4];
                beta[row.clone()].fill(8.0 * mu / s1);
            }
            if omega[row.clone()].iter().any(|&w| w <= 0.0) && kept.s0 > 0.0 {
                omega[row].fill(2.0 / kept.s0);
            }
        }
        let mut count = vec![0usize; n + 1];
        for &j in &bonds.nbr {
            count[j as usize + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut dual = vec![0u32; nb];
        let mut dual_owner = vec![0u32; nb];
        for k in 0..n {
            for b in bonds.row(k) {
                let j = bonds.nbr[b] as usize;
                dual[fill[j]] = b as u32;
                dual_owner[fill[j]] = k as u32;
                fill[j] += 1;
            }
        }
        Some(DualHorizon {
            pos: pos.to_vec(),
            volume,
            delta,
            bonds,
            dual_offsets: count,
            dual,
            dual_owner,
            omega,
            beta,
            a,
            intact,
        })
    }

    /// Failure factor of bond `b` (1 intact, 0 cut).
    #[inline]
    fn t(&self, b: usize) -> f64 {
        f64::from(self.intact[b])
    }

    /// The owner of every bond (the `k` of `k -> j`).
    pub fn owners(&self) -> Vec<u32> {
        let mut o = vec![0u32; self.bonds.len()];
        for k in 0..self.pos.len() {
            for b in self.bonds.row(k) {
                o[b] = k as u32;
            }
        }
        o
    }

    /// Stretch, current length and deformed vector of bond `b` of owner `k`. The length
    /// is $\sqrt{y_x^2 + y_y^2}$, not `hypot` (a library call that guards against an
    /// overflow a bond vector cannot reach, and the largest cost of the explicit force
    /// pass); [`crate::refine::dynamics::forces_breaking`] computes it the same way.
    fn stretch(&self, u: &[P2], k: usize, b: usize) -> (f64, f64, P2) {
        let j = self.bonds.nbr[b] as usize;
        let y = [
            self.bonds.xi[b][0] + u[j][0] - u[k][0],
            self.bonds.xi[b][1] + u[j][1] - u[k][1],
        ];
        let l = (y[0] * y[0] + y[1] * y[1]).sqrt();
        (l * self.bonds.inv_len[b] - 1.0, l, y)
    }

    /// Dilatation of every particle.
    pub fn dilatation(&self, u: &[P2]) -> Vec<f64> {
        (0..self.pos.len())
            .into_par_iter()
            .map(|k| {
                self.bonds
                    .row(k)
                    .map(|b| {
                        self.t(b)
                            * self.omega[b]
                            * self.stretch(u, k, b).0
                            * self.bonds.vol_factor[b]
                    })
                    .sum()
            })
            .collect()
    }

    /// Force (N) on every particle (seed 004 Eq. 13).
    pub fn forces(&self, u: &[P2]) -> Vec<P2> {
        let theta = self.dilatation(u);
        let owner = self.owners();
        // tau_b V_k V'_b / l per bond: the force of bond b on its owner is this times y.
        let coef: Vec<f64> = (0..self.bonds.len())
            .into_par_iter()
            .map(|b| {
                let k = owner[b] as usize;
                let (s, l, _) = self.stretch(u, k, b);
                let tau = self.t(b)
                    * (2.0 * self.a[k] * self.omega[b] * theta[k] * self.bonds.inv_len[b]
                        + self.beta[b] * s);
                tau * self.volume[k] * self.bonds.vol_factor[b] / l
            })
            .collect();
        (0..self.pos.len())
            .into_par_iter()
            .map(|n| {
                let mut f = [0.0; 2];
                for b in self.bonds.row(n) {
                    let (_, _, y) = self.stretch(u, n, b);
                    f[0] += coef[b] * y[0];
                    f[1] += coef[b] * y[1];
                }
                for &b in &self.dual[self.dual_offsets[n]..self.dual_offsets[n + 1]] {
                    let b = b as usize;
                    let (_, _, y) = self.stretch(u, owner[b] as usize, b);
                    f[0] -= coef[b] * y[0];
                    f[1] -= coef[b] * y[1];
                }
                f
            })
            .collect()
    }

    /// Strain energy $\Pi = \sum_k V_k W_k$ (J).
    pub fn energy(&self, u: &[P2]) -> f64 {
        (0..self.pos.len())
            .into_par_iter()
            .map(|k| {
                let (mut th, mut dev) = (0.0, 0.0);
                for b in self.bonds.row(k) {
                    let (s, _, _) = self.stretch(u, k, b);
                    let v = self.t(b) * self.bonds.vol_factor[b];
                    th += self.omega[b] * s * v;
                    dev += self.beta[b] * s * s / self.bonds.inv_len[b] * v;
                }
                self.volume[k] * (self.a[k] * th * th + 0.5 * dev)
            })
            .sum()
    }
}

/// Families `H_k = {j : |x_j - x_k| <= delta_k}` by a cell list of cell size max delta,
/// with `vol_factor = v_kj V_j` (partial volume of `j`'s cell of side `dx_j`, seed 002
/// Eq. 16 with `j`'s spacing and `k`'s horizon).
pub fn families(pos: &[P2], dx: &[f64], volume: &[f64], delta: &[f64]) -> Bonds {
    bonds_from_rows(pos, dx, volume, delta, &family_rows(pos, delta))
}

/// The neighbour lists of [`families`] (sorted): every particle within `delta[k]` of `k`.
pub fn family_rows(pos: &[P2], delta: &[f64]) -> Vec<Vec<u32>> {
    use std::collections::HashMap;
    let cell = delta.iter().fold(0.0f64, |a, &b| a.max(b));
    let key = |p: P2| ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
    for (i, &p) in pos.iter().enumerate() {
        grid.entry(key(p)).or_default().push(i as u32);
    }
    (0..pos.len())
        .into_par_iter()
        .map(|k| {
            let (cx, cy) = key(pos[k]);
            let r2 = (delta[k] * (1.0 + 1e-9)).powi(2);
            let mut row = Vec::new();
            for gx in cx - 1..=cx + 1 {
                for gy in cy - 1..=cy + 1 {
                    for &j in grid.get(&(gx, gy)).map_or(&[][..], |v| v.as_slice()) {
                        let d = [
                            pos[j as usize][0] - pos[k][0],
                            pos[j as usize][1] - pos[k][1],
                        ];
                        if j as usize != k && d[0] * d[0] + d[1] * d[1] <= r2 {
                            row.push(j);
                        }
                    }
                }
            }
            row.sort_unstable();
            row
        })
        .collect()
}

/// The CSR families of the neighbour lists `rows` (sorted), with `vol_factor = v_kj V_j`
/// (partial volume of `j`'s cell of side `dx_j` in `k`'s horizon).
pub fn bonds_from_rows(
    pos: &[P2],
    dx: &[f64],
    volume: &[f64],
    delta: &[f64],
    rows: &[Vec<u32>],
) -> Bonds {
    let mut b = open_bonds(rows.len(), rows.iter().map(Vec::len).sum());
    for (k, row) in rows.iter().enumerate() {
        for &j in row {
            push_bond(&mut b, pos, dx, volume, delta, k, j as usize);
        }
        b.offsets.push(b.nbr.len());
    }
    finish_bonds(&mut b);
    b
}

/// Empty families for `rows` rows and `n` bonds, the first row open: fill each row with
/// [`push_bond`], push its end to `offsets`, then [`finish_bonds`].
pub(crate) fn open_bonds(rows: usize, n: usize) -> Bonds {
    let mut b = Bonds {
        offsets: Vec::with_capacity(rows + 1),
        nbr: Vec::with_capacity(n),
        xi: Vec::with_capacity(n),
        inv_len: Vec::with_capacity(n),
        vol_factor: Vec::with_capacity(n),
        meta: Vec::with_capacity(n),
        ..Default::default()
    };
    b.offsets.push(0);
    b
}

/// Append the bond of owner `k` to `j` to the open row of `b` ([`bonds_from_rows`]).
pub(crate) fn push_bond(
    b: &mut Bonds,
    pos: &[P2],
    dx: &[f64],
    volume: &[f64],
    delta: &[f64],
    k: usize,
    j: usize,
) {
    let xi = [pos[j][0] - pos[k][0], pos[j][1] - pos[k][1]];
    let l = xi[0].hypot(xi[1]);
    b.nbr.push(j as u32);
    b.xi.push(xi);
    b.inv_len.push(1.0 / l);
    b.vol_factor
        .push(partial_volume(l, delta[k], dx[j]) * volume[j]);
    b.meta.push(crate::bonds::GROUP_END);
}

/// The per-bond arrays a dual-horizon body does not use: unit surface factors, no
/// bond constants.
pub(crate) fn finish_bonds(b: &mut Bonds) {
    b.surface = vec![1.0; b.nbr.len()];
    b.k = vec![0.0; b.nbr.len()];
}
