//! Bond breaking at converged interface states, most stretched bonds first (crack growth
//! with `PdSolve::Staggered` of `pdbem-coupling`).
//!
//! Committing the history breaks every bond past its critical stretch $s_0$ at once. Under
//! load control a growing crack is overloaded ($K > K_c$ and rising), and breaking every
//! overstretched bond in one go spreads damage sideways and widens the crack band. The
//! progressive commit breaks only the bonds within a relative band `f` of the largest
//! stretch of the window,
//! $$s \ge \max\big(s_0,\ (1 - f)\, s_{max}\big),$$
//! and leaves the rest to the next equilibrium, when the load has redistributed around
//! the new crack front (a quasi-static event-by-event advance; $f = 1$ is the plain
//! commit). Just past the onset every bond past $s_0$ breaks, so nearly equal stretches
//! (the mirror images of a mode I tip) break together and the crack stays symmetric; the
//! band only bites when the crack is overloaded. Both directions of a pair have bitwise
//! equal stretches, so they break together.
//! Laws other than the brittle PMB law are committed in full.
//!
//! [`break_rounds`] repeats this with the window's interface held: break, re-equilibrate
//! the PD model (the window's kept solvers, [`FrozenSolver`](crate::solvers::frozen::FrozenSolver)), break
//! again, up to a number of rounds or until no bond is past $s_0$. The load
//! redistributes mostly inside the window, so a few PD rounds per converged interface
//! state let the crack advance by several bonds for the price of one interface
//! re-convergence.

use crate::material::BondLaw;
use crate::solvers::implicit::ImplicitParams;
use crate::{PdError, PdModel, SolveInfo};

use crate::solvers::frozen::SolverSlot;

/// Up to `rounds` progressive commits of `model`, each followed by a frozen-bond
/// equilibrium at the held boundary values; returns the bond pairs broken.
pub fn break_rounds(
    model: &mut PdModel,
    slot: &mut SolverSlot,
    fraction: f64,
    rounds: usize,
    newton: &ImplicitParams,
) -> Result<usize, PdError> {
    let mut total = 0;
    let mut info = SolveInfo::default();
    let start = model.displacements().to_vec();
    for _ in 0..rounds.max(1) {
        let broke = commit_most_stretched(model, fraction);
        if broke == 0 {
            break;
        }
        total += broke;
        slot.get(model)?
            .equilibrate(model, newton, &start, &mut info)?;
    }
    Ok(total)
}

/// Breaks the bonds of `model` as described in the module docs; returns the bond pairs
/// broken.
pub fn commit_most_stretched(model: &mut PdModel, fraction: f64) -> usize {
    let BondLaw::Brittle { s0 } = model.law() else {
        return model.commit_history().newly_broken / 2;
    };
    if fraction >= 1.0 {
        return model.commit_history().newly_broken / 2;
    }
    let stretch = stretches(model);
    let intact = model.bond_intact();
    let s_max = stretch
        .iter()
        .zip(intact)
        .filter(|(_, &f)| f == 1)
        .map(|(s, _)| *s)
        .fold(f64::NEG_INFINITY, f64::max);
    if s_max < s0 {
        return 0;
    }
    let threshold = ((1.0 - fraction.max(0.0)) * s_max).max(s0);
    let mut st = model.state();
    let mut broken = 0;
    for (b, s) in stretch.iter().enumerate() {
        if st.intact[b] == 1 && *s >= threshold {
            st.intact[b] = 0;
            broken += 1;
        }
    }
    model.restore(&st);
    broken / 2
}

/// Bonds that cannot break ([`crate::forces::NO_FAIL`]: a window's no-fail band, the
/// coarse cells of a refined window) although stretched past the brittle law's $s_0$:
/// the crack there is held by that protection, not by its toughness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeldBonds {
    /// Bond pairs past $s_0$.
    pub pairs: usize,
    /// The largest stretch among them over $s_0$.
    pub worst: f64,
    /// The midpoint of that bond (reference configuration, m).
    pub at: [f64; 2],
    /// Its end nodes (reference configuration, m).
    pub ends: [[f64; 2]; 2],
}

/// The [`HeldBonds`] of `model` that `keep` accepts, given each bond's midpoint and its two
/// end nodes (reference configuration); None without any, or under a law other than the
/// brittle one (the tanh law's protected bonds stay elastic by design). Bonds between two
/// nodes outside the body (a displacement condition's fictitious layer, a coupling
/// window's virtual nodes) are no part of what could crack and do not count (measured on
/// `growth_shear_edge_refined`: 10 such pairs up to 2.56 s0 at the window corner below
/// the end of the bottom clamp, from the clamp's layer to the window's virtual nodes).
pub fn held_bonds(
    model: &PdModel,
    keep: impl Fn([f64; 2], [[f64; 2]; 2]) -> bool,
) -> Option<HeldBonds> {
    let BondLaw::Brittle { s0 } = model.law() else {
        return None;
    };
    let stretch = stretches(model);
    let b = model.bonds();
    let pos = &model.grid().pos;
    let intact = model.bond_intact();
    let mut held: Option<HeldBonds> = None;
    let mut directed = 0_usize;
    let n_real = model.n_real();
    for i in 0..model.n_nodes() {
        for k in b.row(i) {
            if intact[k] != crate::forces::NO_FAIL || stretch[k] < s0 {
                continue;
            }
            let j = b.nbr[k] as usize;
            if i >= n_real && j >= n_real {
                continue;
            }
            let at = [0.5 * (pos[i][0] + pos[j][0]), 0.5 * (pos[i][1] + pos[j][1])];
            let ends = [pos[i], pos[j]];
            if !keep(at, ends) {
                continue;
            }
            directed += 1;
            let ratio = stretch[k] / s0;
            if held.is_none_or(|h| ratio > h.worst) {
                held = Some(HeldBonds {
                    pairs: 0,
                    worst: ratio,
                    at,
                    ends,
                });
            }
        }
    }
    held.map(|h| HeldBonds {
        pairs: directed.div_ceil(2),
        ..h
    })
}

/// Current stretch of every bond (CSR order).
fn stretches(model: &PdModel) -> Vec<f64> {
    let b = model.bonds();
    let u = model.displacements();
    let mut out = vec![0.0; b.len()];
    for i in 0..model.n_nodes() {
        for k in b.row(i) {
            let j = b.nbr[k] as usize;
            let y = [
                b.xi[k][0] + (u[j][0] - u[i][0]),
                b.xi[k][1] + (u[j][1] - u[i][1]),
            ];
            out[k] = y[0].hypot(y[1]) * b.inv_len[k] - 1.0;
            if let Some(sc) = b.s_scale.get(k) {
                // Mixed spacing: normalised by the pair's critical-stretch factor.
                out[k] /= sc;
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BoundaryCondition, Failure, Layer, PdProblem, Region, Selection};

    fn bar_problem() -> PdProblem {
        PdProblem {
            region: Region::rectangle([0.0, 0.0], [10.0, 3.0]),
            dx: 1.0,
            youngs_modulus: 1.0,
            failure: Failure::CriticalStretch { s0: 0.01 },
            ..Default::default()
        }
    }

    fn bar() -> PdModel {
        PdModel::new(&bar_problem()).unwrap()
    }

    #[test]
    fn only_the_most_stretched_bonds_break() {
        // Stretch growing along x: u_x = 0.002 x^2, so axial bonds stretch by about
        // 0.004 x; the most stretched ones sit at the right end.
        let mut m = bar();
        let u: Vec<[f64; 2]> = m
            .positions()
            .iter()
            .map(|x| [0.002 * x[0] * x[0], 0.0])
            .collect();
        m.set_displacements(&u).unwrap();
        let mut all = m.clone();
        let n_all = commit_most_stretched(&mut all, 1.0);
        let n_top = commit_most_stretched(&mut m, 0.1);
        assert!(n_top > 0 && n_top < n_all, "{n_top} of {n_all}");
        // Every bond broken by the progressive commit is broken by the full one too.
        let (a, b) = (m.bond_intact(), all.bond_intact());
        assert!(a.iter().zip(b).all(|(x, y)| *x != 0 || *y == 0));
        // Nothing is past s0 at rest.
        let mut rest = bar();
        assert_eq!(commit_most_stretched(&mut rest, 0.1), 0);
    }

    #[test]
    fn held_bonds_are_the_protected_ones_past_s0() {
        // u_x = 0.002 x^2 on the 10 x 3 bar (s0 = 1 %, nodes at the cell centres): an
        // axial bond from a to b stretches by 0.002 (a + b), past s0 from a + b = 5 on;
        // the bonds of the first column (a = 0.5, b <= 3.5) stay below it.
        let stretched = |m: &mut PdModel| {
            let u: Vec<[f64; 2]> = (m.positions().iter())
                .map(|x| [0.002 * x[0] * x[0], 0.0])
                .collect();
            m.set_displacements(&u).unwrap();
        };
        let mut free = bar();
        stretched(&mut free);
        assert_eq!(held_bonds(&free, |_, _| true), None, "nothing protected");
        let mut left = bar();
        left.protect_bonds(|x| x[0] < 1.0);
        stretched(&mut left);
        assert_eq!(
            held_bonds(&left, |_, _| true),
            None,
            "protected, but below s0"
        );
        let mut right = bar();
        right.protect_bonds(|x| x[0] > 8.0);
        stretched(&mut right);
        let h = held_bonds(&right, |_, _| true).expect("protected bonds past s0");
        // The breakable ones past s0 are not counted: after the commit, the held ones are
        // exactly the intact bonds past s0.
        let mut after = right.clone();
        commit_most_stretched(&mut after, 1.0);
        assert_eq!(held_bonds(&after, |_, _| true), Some(h));
        let past = count_intact_past(&after, 0.01);
        assert_eq!(h.pairs, past / 2);
        assert!(h.worst > 1.0 && h.at[0] > 8.0, "{h:?}");
        // Only those `keep` accepts: the protected bonds have an end at x = 8.5 or 9.5
        // and reach 3 cells, so their midpoints lie at x >= 7.
        assert_eq!(held_bonds(&right, |x, _| x[0] < 7.0), None);
        let top = held_bonds(&right, |x, _| x[1] > 2.0).expect("held in the top row");
        assert!(top.pairs < h.pairs && top.at[1] > 2.0, "{top:?}");
        // The largest stretch: the axial bond from 8.5 to 9.5, 0.002 (8.5 + 9.5) = 0.036,
        // first met in the bottom row.
        assert!((h.worst * 0.01 - 0.036).abs() < 1e-12, "{h:?}");
        assert_eq!(h.at, [9.0, 0.5], "{h:?}");
        assert_eq!(h.ends, [[8.5, 0.5], [9.5, 0.5]], "{h:?}");
        // With a fictitious layer beyond x = 10 (u_y held, u_x free): the most stretched
        // protected bond from a real node, 9.5 to 12.5, 0.002 (9.5 + 12.5) = 0.044,
        // counts; the layer's own bonds, up to 0.002 (11.5 + 12.5) = 0.048, do not.
        let mut layered = PdModel::new(&PdProblem {
            boundary: vec![BoundaryCondition::Displacement {
                on: Selection::Box {
                    min: [10.0, -5.0],
                    max: [15.0, 8.0],
                },
                ux: None,
                uy: Some(0.0),
                layer: Layer::Fictitious,
            }],
            ..bar_problem()
        })
        .unwrap();
        assert!(layered.n_nodes() > layered.n_real());
        layered.protect_bonds(|x| x[0] > 8.0);
        stretched(&mut layered);
        let h = held_bonds(&layered, |_, _| true).expect("held");
        assert!((h.worst * 0.01 - 0.044).abs() < 1e-12, "{h:?}");
        assert_eq!(h.at[0], 11.0, "{h:?}");
    }

    /// Directed intact bonds of `m` past stretch `s0`.
    fn count_intact_past(m: &PdModel, s0: f64) -> usize {
        let s = stretches(m);
        (s.iter().zip(m.bond_intact()))
            .filter(|(s, &f)| f != 0 && **s >= s0)
            .count()
    }
}
