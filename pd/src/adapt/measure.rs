//! Per-node measures of the refinement criteria and the split: damage (seed 002 Eq. 8,
//! [`crate::damage`]), the accumulated strains of seed 004 Eq. 17 and the nonlocal
//! displacement gradient that places a parent's children (the full-tensor form of seed
//! 004 Eq. 18).
//!
//! Over node $k$'s intact half-bonds with the weights $w_{kj} = \mu_{kj}\,\mathrm{vf}_{kj}
//! /|\xi|^2$ (`vf` the bond's volume factor: $j$'s partial volume in $k$'s horizon,
//! [`crate::mixed`]), $\xi = x_j - x_k$, $\eta = u_j - u_k$:
//! $$K = \sum_j w_{kj}\, \xi\otimes\xi,\qquad N = \sum_j w_{kj}\, \eta\otimes\xi .$$
//! The accumulated strains (Eq. 17, read as in [`crate::refine`]: the bond-projected
//! form, exact for every homogeneous strain on a symmetric family) are
//! $\varepsilon_{ii} = N_{ii}/K_{ii}$, and the displacement gradient is $H = N K^{-1}$,
//! exact for every homogeneous deformation (strain, shear and rotation) on any family
//! whose $K$ is regular. A child at $x_c$ of the parent $k$ takes
//! $u_c = u_k + H (x_c - x_k)$: seed 004 Eq. 18 when $H$ is diagonal; with the shear and
//! rotation terms, a parent turned rigidly places its children turned with it.
//!
//! **Damage of the criterion** (Eq. 15): seed 002 Eq. 8 with each intact bond counted by
//! its degradation, $\phi_k = 1 - \sum_j \mu_{kj} T(s^{hist}_{kj})\,\mathrm{vf}_{kj} /
//! \sum_j \mathrm{vf}_{kj}$ ($T$ the tanh law of seed 000 Eq. 12 at the bond's normalised
//! history, 1 for the other laws): the tanh law softens bonds without breaking them, so
//! the binary damage of [`crate::damage`] would not see a crack until its bonds reach
//! $s_c$.

use rayon::prelude::*;

use crate::bonds::group_sum;
use crate::geometry::P2;
use crate::material::{degradation, BondLaw};
use crate::model::PdModel;

/// The damage of Eq. 15 at every node (module docs): [`PdModel::damage`] with each
/// intact bond weighted by its degradation under the tanh law.
pub fn criterion_damage(model: &PdModel) -> Vec<f64> {
    let BondLaw::Degrading { s_m, s_c, beta } = model.law() else {
        return model.damage();
    };
    let (b, intact, hist) = (model.bonds(), model.bond_intact(), &model.s_hist[..]);
    (0..model.n_nodes())
        .into_par_iter()
        .map(|k| {
            // Group-ordered sums: mirror nodes get bitwise equal damage.
            let [all, alive] = group_sum(&b.meta, b.row(k), |e| {
                let v = b.vol_factor[e];
                let t = if intact[e] != 0 {
                    degradation(hist[e], s_m, s_c, beta).0
                } else {
                    0.0
                };
                [v, v * t]
            });
            if all > 0.0 {
                1.0 - alive / all
            } else {
                0.0
            }
        })
        .collect()
}

/// The measures of one node.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NodeMeasure {
    /// Accumulated strains `(eps_xx, eps_yy)` (seed 004 Eq. 17) in the global axes.
    pub strain: [f64; 2],
    /// Displacement gradient `H[i][j] = du_i / dx_j`; zero when the node's intact
    /// family does not span the plane.
    pub gradient: [[f64; 2]; 2],
}

/// The measures of every real node of `model`.
pub fn node_measures(model: &PdModel) -> Vec<NodeMeasure> {
    let (b, u, intact) = (model.bonds(), model.displacements(), model.bond_intact());
    (0..model.n_real())
        .into_par_iter()
        .map(|k| {
            let mut kk = [[0.0f64; 2]; 2];
            let mut nn = [[0.0f64; 2]; 2];
            for e in b.row(k) {
                if intact[e] == 0 {
                    continue;
                }
                let xi = b.xi[e];
                let w = b.vol_factor[e] * b.inv_len[e] * b.inv_len[e];
                let j = b.nbr[e] as usize;
                let eta = [u[j][0] - u[k][0], u[j][1] - u[k][1]];
                for r in 0..2 {
                    for c in 0..2 {
                        kk[r][c] += w * xi[r] * xi[c];
                        nn[r][c] += w * eta[r] * xi[c];
                    }
                }
            }
            measure_of(kk, nn)
        })
        .collect()
}

/// Eq. 17's strains and `H = N K^{-1}` from the sums (module docs).
fn measure_of(kk: [[f64; 2]; 2], nn: [[f64; 2]; 2]) -> NodeMeasure {
    let strain = [0, 1].map(|i| {
        if kk[i][i] > 0.0 {
            nn[i][i] / kk[i][i]
        } else {
            0.0
        }
    });
    let det = kk[0][0] * kk[1][1] - kk[0][1] * kk[1][0];
    let scale = kk[0][0] * kk[1][1];
    // A family on one line (or none) has no gradient across it.
    if !(scale > 0.0 && det > 1e-8 * scale) {
        return NodeMeasure {
            strain,
            gradient: [[0.0; 2]; 2],
        };
    }
    let inv = [
        [kk[1][1] / det, -kk[0][1] / det],
        [-kk[1][0] / det, kk[0][0] / det],
    ];
    let mut h = [[0.0; 2]; 2];
    for r in 0..2 {
        for c in 0..2 {
            h[r][c] = nn[r][0] * inv[0][c] + nn[r][1] * inv[1][c];
        }
    }
    NodeMeasure {
        strain,
        gradient: h,
    }
}

/// The displacement at `x` of a child of the node at `xp` with displacement `up` and
/// measure `m` (module docs).
pub fn child_displacement(xp: P2, up: P2, m: &NodeMeasure, x: P2) -> P2 {
    let d = [x[0] - xp[0], x[1] - xp[1]];
    let h = m.gradient;
    [
        up[0] + h[0][0] * d[0] + h[0][1] * d[1],
        up[1] + h[1][0] * d[0] + h[1][1] * d[1],
    ]
}
