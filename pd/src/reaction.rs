//! Resultants of the boundary conditions: the load-displacement record of a PD solve.
//!
//! A node whose component c is prescribed is in equilibrium with the support:
//! $R_{i,c} + V\,(f_{i,c} + b_{i,c}) = 0$, with $f_i$ the peridynamic force density on
//! node i from all its intact bonds (seed 002 Eq. 6, surface corrections included),
//! $b_i$ its body force density and V the node volume (thickness included). The
//! reaction of a displacement condition is the sum of $R_{i,c}$ over its nodes and
//! prescribed components (a component prescribed twice counts for the first condition); the force of a load is $\lambda \sum_i V b_i$ over its layer
//! (seed 000 section 2.3), $\lambda$ the load factor. The displacement of either is the
//! mean displacement of its nodes, weighted by their volumes on a mixed grid
//! ([`crate::mixed`]). In equilibrium the reactions and the loads sum to
//! zero (up to the solver's residual): [`BcResultant`] lets a caller check it.

use serde::Serialize;

use crate::geometry::P2;
use crate::model::PdModel;

/// What a boundary condition does to the body.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BcKind {
    /// Prescribed displacement: the force is the support's reaction.
    Support,
    /// Applied load: the force is the load.
    Load,
}

/// Force and displacement of one boundary condition at the model's state.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BcResultant {
    /// Support or load.
    pub kind: BcKind,
    /// Force on the body (N): the reaction of a support, the load of a load.
    pub force: P2,
    /// Mean displacement of the condition's nodes (m).
    pub displacement: P2,
    /// Number of nodes.
    pub nodes: usize,
}

impl PdModel {
    /// The resultant of every boundary condition of the problem, in its order
    /// (see the module docs). Costs one pass over the bonds.
    pub fn bc_resultants(&mut self) -> Vec<BcResultant> {
        let f = self.internal_forces();
        let (u, lam, v) = (self.displacements(), self.load_factor(), self.grid().volume);
        let grid = self.grid();
        // Volume weights: all 1 on a uniform grid (then `u / n` to the bit).
        let weight = |i: usize| {
            let r = grid.node_dx(i) / grid.dx;
            r * r
        };
        let bc = self.boundary();
        bc.groups
            .iter()
            .map(|g| {
                let n = g.nodes.len().max(1) as f64;
                let total = match g.nodes.iter().map(|&i| weight(i)).sum::<f64>() {
                    t if t > 0.0 => t,
                    _ => 1.0,
                };
                let mut disp = [0.0; 2];
                for &i in &g.nodes {
                    let w = weight(i);
                    disp[0] += u[i][0] * w / total;
                    disp[1] += u[i][1] * w / total;
                }
                let support = g.fixed != [false; 2];
                let mut force = [0.0; 2];
                if support {
                    for (&i, claim) in g.nodes.iter().zip(&g.claimed) {
                        for c in 0..2 {
                            if claim[c] {
                                force[c] -= f[i][c] + v * lam * bc.body[i][c];
                            }
                        }
                    }
                } else {
                    force = [lam * v * n * g.body[0], lam * v * n * g.body[1]];
                }
                BcResultant {
                    kind: if support {
                        BcKind::Support
                    } else {
                        BcKind::Load
                    },
                    force,
                    displacement: disp,
                    nodes: g.nodes.len(),
                }
            })
            .collect()
    }
}

/// |sum of all forces| / (largest |force|): zero in exact equilibrium.
pub fn imbalance(r: &[BcResultant]) -> f64 {
    let (mut s, mut m) = ([0.0f64; 2], 0.0f64);
    for x in r {
        s[0] += x.force[0];
        s[1] += x.force[1];
        m = m.max(x.force[0].hypot(x.force[1]));
    }
    if m == 0.0 {
        0.0
    } else {
        s[0].hypot(s[1]) / m
    }
}
