//! Local damage (seed 002 Eq. 8, seed 001 Eq. 22):
//! $$\varphi_i = 1 - \frac{\sum_j \mu_{ij} v_j V_j}{\sum_j v_j V_j}$$
//! with $\mu_{ij} = 0$ for a broken or cut bond. $\varphi > 0.38$ marks a
//! macro crack (seed 002 section 2.1).

use rayon::prelude::*;

use crate::bonds::{group_sum, Bonds};

/// Damage threshold of a macro crack (seed 002 section 2.1).
pub const MACRO_CRACK_DAMAGE: f64 = 0.38;

/// Damage of every node.
pub fn damage(bonds: &Bonds, intact: &[u8]) -> Vec<f64> {
    (0..bonds.offsets.len() - 1)
        .into_par_iter()
        .map(|i| {
            // Group-ordered sum: mirror nodes get bitwise equal damage.
            let [all, alive] = group_sum(&bonds.meta, bonds.row(i), |b| {
                let v = bonds.vol_factor[b];
                [v, if intact[b] != 0 { v } else { 0.0 }]
            });
            if all > 0.0 {
                1.0 - alive / all
            } else {
                0.0
            }
        })
        .collect()
}
