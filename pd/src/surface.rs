//! Surface correction by the energy method (Madenci & Oterkus, Peridynamic
//! Theory and Its Applications, 2014, section 4.2).
//!
//! Under a uniform strain $\varepsilon$ along direction $d$ the PD strain
//! energy density of node $i$ is
//! $W_i^{PD} = \tfrac14 \sum_j c\,s_{ij}^2 |\xi_{ij}| v_j V_j$ with the linear
//! stretch $s = \varepsilon n_d^2$; the classical value is
//! $W^{CM} = \tfrac12 E'\varepsilon^2$ with $E' = 9E/8$ (plane stress,
//! $\nu = 1/3$) or $6E/5$ (plane strain, $\nu = 1/4$). The node factor is
//! $g_{d,i} = W^{CM}/W^{PD}_{d,i}$, the bond factor
//! $G_d = (g_{d,i} + g_{d,j})/2$, combined over directions as the ellipse
//! $G = [(n_x/G_x)^2 + (n_y/G_y)^2]^{-1/2}$. In the bulk $g \approx 1$ up to
//! the discretisation error of the horizon sum, which it also removes.

use rayon::prelude::*;

use crate::bonds::Bonds;
use crate::problem::Plane;

/// Fill `bonds.surface` with the correction factors (before pre-cracks are
/// cut, so crack faces are not stiffened).
pub fn apply_surface_correction(bonds: &mut Bonds, c: f64, volume: f64, youngs: f64, plane: Plane) {
    let n = bonds.offsets.len() - 1;
    let e_eff = match plane {
        Plane::Stress => 9.0 / 8.0 * youngs,
        Plane::Strain => 6.0 / 5.0 * youngs,
    };
    let w_cm = 0.5 * e_eff; // for unit strain
    let g: Vec<[f64; 2]> = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut w = [0.0; 2];
            for b in bonds.row(i) {
                let len = 1.0 / bonds.inv_len[b];
                let nx = bonds.xi[b][0] * bonds.inv_len[b];
                let ny = bonds.xi[b][1] * bonds.inv_len[b];
                let f = 0.25 * c * len * bonds.vol_factor[b] * volume;
                w[0] += f * nx.powi(4);
                w[1] += f * ny.powi(4);
            }
            [w_cm / w[0], w_cm / w[1]]
        })
        .collect();
    let mut out = vec![0.0; bonds.len()];
    for i in 0..n {
        for b in bonds.row(i) {
            let j = bonds.nbr[b] as usize;
            let gx = 0.5 * (g[i][0] + g[j][0]);
            let gy = 0.5 * (g[i][1] + g[j][1]);
            let nx = bonds.xi[b][0] * bonds.inv_len[b];
            let ny = bonds.xi[b][1] * bonds.inv_len[b];
            out[b] = 1.0 / ((nx / gx).powi(2) + (ny / gy).powi(2)).sqrt();
        }
    }
    bonds.surface = out;
}
