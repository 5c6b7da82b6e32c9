//! Splitting parents into four children (seed 004 Eqs. 18-19, 30) and the neighbour
//! lists of the refined body from the old ones (Eqs. 20-23), see [`super`].

use std::collections::{HashMap, HashSet};

use rayon::prelude::*;

use super::Body;
use crate::bonds::Bonds;
use crate::error::PdError;
use crate::geometry::{segment_crosses_crack, P2};
use crate::state_based::dual_horizon::{
    family_rows, finish_bonds, open_bonds, push_bond, DualHorizon, Reuse,
};

/// Bytes a refined body holds per particle (geometry, state, constants, flags, the
/// dynamics' velocities and criteria, with room for the vectors' slack).
pub const PARTICLE_BYTES: f64 = 256.0;
/// Bytes a refined body holds per directed bond: the family (`Bonds`, 53), the
/// dual-horizon data (flags, weights, dual lists, 25) and the force pass's buffers (24),
/// rounded up.
pub const BOND_BYTES: f64 = 112.0;

/// Quadrant signs `(xi, eta)` of the four children.
const SIGNS: [[f64; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [-1.0, 1.0], [1.0, 1.0]];

/// Where every old particle went: kept at a new index, or split into four.
enum Fate {
    Kept(u32),
    Split(u32),
}

impl Body {
    /// Split the particles `parents` (old indices; repeats ignored) into four children
    /// each. The particles keep their old order, each parent's four children taking its
    /// place (quadrants in the order of `SIGNS`), so that a particle's neighbours stay
    /// near it in the arrays (the force pass's memory locality). The children and the
    /// kept particles whose family changed (a member split, a child within reach) get
    /// constants fitted to their new family and its current bond flags; every other
    /// particle keeps its constants, as the uniform model keeps them while bonds break.
    /// Returns the number of particles split.
    pub fn split(&mut self, parents: &[usize]) -> Result<usize, PdError> {
        let n = self.len();
        let mut is_parent = vec![false; n];
        let mut order = Vec::new();
        for &k in parents {
            if k < n && !is_parent[k] {
                is_parent[k] = true;
                order.push(k);
            }
        }
        if order.is_empty() {
            return Ok(0);
        }
        // New indices in the old order, a parent's four children in its place (memory
        // locality: a particle's neighbours stay near it in the arrays).
        let n_new = n + 3 * order.len();
        let mut fate: Vec<Fate> = Vec::with_capacity(n);
        let mut ancestor: Vec<usize> = Vec::with_capacity(n_new);
        let mut pos: Vec<P2> = Vec::with_capacity(n_new);
        let mut size: Vec<f64> = Vec::with_capacity(n_new);
        let mut u: Vec<P2> = Vec::with_capacity(n_new);
        for k in 0..n {
            let next = ancestor.len() as u32;
            if !is_parent[k] {
                fate.push(Fate::Kept(next));
                ancestor.push(k);
                pos.push(self.dh.pos[k]);
                size.push(self.size[k]);
                u.push(self.u[k]);
                continue;
            }
            fate.push(Fate::Split(next));
            let (x, d, e) = (self.dh.pos[k], self.size[k], self.accumulated_strain_of(k));
            for s in SIGNS {
                ancestor.push(k);
                pos.push([x[0] + 0.25 * d * s[0], x[1] + 0.25 * d * s[1]]);
                size.push(0.5 * d);
                // Eqs. 18-19: y_c - x_c = u_k + eps_ii * offset_i.
                u.push([
                    self.u[k][0] + e[0] * 0.25 * d * s[0],
                    self.u[k][1] + e[1] * 0.25 * d * s[1],
                ]);
            }
        }
        // Whether each new particle is a child.
        let child: Vec<bool> = ancestor.iter().map(|&a| is_parent[a]).collect();
        let volume: Vec<f64> = size.iter().map(|d| d * d * self.thickness).collect();
        let delta: Vec<f64> = if self.keep_horizon {
            ancestor.iter().map(|&a| self.dh.delta[a]).collect()
        } else {
            size.iter().map(|d| self.m * d).collect()
        };
        // Children with their parent's horizon reach beyond the parent's family: a fresh
        // search then (Eqs. 20-22 hold for the halved horizon).
        let rows: Vec<Option<Vec<u32>>> = if self.keep_horizon {
            family_rows(&pos, &delta).into_iter().map(Some).collect()
        } else {
            self.new_rows(&child, &order, &fate, &ancestor, &pos, &delta)
        };
        self.within_budget(&rows, &ancestor, order.len())?;
        let same = self.unchanged(&rows, &ancestor, &child, &fate);
        let bonds = self.splice_bonds(&rows, &ancestor, &fate, (&pos, &size, &volume, &delta));
        let intact = self.new_flags(&bonds, &ancestor, &pos, &size, &same);
        let layer: Vec<bool> = ancestor.iter().map(|&a| self.layer[a]).collect();
        let bulk: Vec<Option<f64>> = layer
            .iter()
            .zip(&size)
            .map(|(&l, &d)| l.then_some(d))
            .collect();
        let reuse = Reuse {
            old: &self.dh,
            same: &same,
        };
        let dh = DualHorizon::from_families(
            &pos,
            volume,
            delta,
            bonds,
            intact,
            self.moduli,
            &bulk,
            Some(reuse),
        )
        .ok_or_else(|| {
            PdError::invalid(
                "refinement",
                "a refined particle's family does not determine its constants",
            )
        })?;
        self.fixed = ancestor.iter().map(|&a| self.fixed[a]).collect();
        self.layer = layer;
        self.base = ancestor.iter().map(|&a| self.base[a]).collect();
        self.body = ancestor.iter().map(|&a| self.body[a]).collect();
        self.level = ancestor
            .iter()
            .enumerate()
            .map(|(i, &a)| self.level[a] + u8::from(child[i]))
            .collect();
        for (i, ui) in u.iter_mut().enumerate() {
            for c in 0..2 {
                if self.fixed[i][c] {
                    ui[c] = self.base[i][c];
                }
            }
        }
        self.u = u;
        self.size = size;
        self.dh = dh;
        Ok(order.len())
    }

    /// [`PdError::TooLarge`] when the refined body of `rows` (beside this one, which lives
    /// until the split is done) would pass [`Body::budget`] (default the memory budget,
    /// [`crate::tangent::factor_budget`]): checked before its bonds are allocated, so a
    /// refinement too deep or too wide for the machine is refused instead of aborting on
    /// allocation.
    fn within_budget(
        &self,
        rows: &[Option<Vec<u32>>],
        ancestor: &[usize],
        parents: usize,
    ) -> Result<(), PdError> {
        let old = &self.dh.bonds;
        let bonds = self.bond_count(rows, ancestor);
        let bytes = |particles: usize, bonds: usize| {
            particles as f64 * PARTICLE_BYTES + bonds as f64 * BOND_BYTES
        };
        crate::tangent::check_budget(
            &format!(
                "pd.refinement: splitting {parents} particles makes a body of {} particles and {bonds} directed bonds, which beside the body it splits",
                rows.len()
            ),
            bytes(rows.len(), bonds) + bytes(self.len(), old.len()),
            self.budget.unwrap_or_else(crate::tangent::factor_budget),
        )
    }

    /// Directed bonds of the refined body's `rows` (a row `None` keeps its ancestor's).
    fn bond_count(&self, rows: &[Option<Vec<u32>>], ancestor: &[usize]) -> usize {
        let old = &self.dh.bonds;
        rows.iter()
            .zip(ancestor)
            .map(|(r, &a)| r.as_ref().map_or(old.row(a).len(), Vec::len))
            .sum()
    }

    /// The CSR families of the refined body's `rows`: a row `None` (an unchanged family)
    /// is its ancestor's old row at the new indices with its old bond data; the others are
    /// built as [`crate::state_based::dual_horizon::bonds_from_rows`] builds them. `geo`
    /// is (positions, spacings, volumes, horizons) of the new particles.
    fn splice_bonds(
        &self,
        rows: &[Option<Vec<u32>>],
        ancestor: &[usize],
        fate: &[Fate],
        geo: (&[P2], &[f64], &[f64], &[f64]),
    ) -> Bonds {
        let (pos, size, volume, delta) = geo;
        let old = &self.dh.bonds;
        let mut b = open_bonds(rows.len(), self.bond_count(rows, ancestor));
        for (i, row) in rows.iter().enumerate() {
            match row {
                Some(row) => {
                    for &j in row {
                        push_bond(&mut b, pos, size, volume, delta, i, j as usize);
                    }
                }
                None => {
                    let r = old.row(ancestor[i]);
                    b.nbr
                        .extend(old.nbr[r.clone()].iter().map(|&j| match fate[j as usize] {
                            Fate::Kept(jn) => jn,
                            Fate::Split(_) => {
                                unreachable!("an unchanged family has no split member")
                            }
                        }));
                    b.xi.extend_from_slice(&old.xi[r.clone()]);
                    b.inv_len.extend_from_slice(&old.inv_len[r.clone()]);
                    b.vol_factor.extend_from_slice(&old.vol_factor[r.clone()]);
                    b.meta.extend_from_slice(&old.meta[r]);
                }
            }
            b.offsets.push(b.nbr.len());
        }
        finish_bonds(&mut b);
        b
    }

    /// Neighbour lists of the refined body (new indices, sorted), from the old families
    /// (Eqs. 20-23, module docs of [`super`]); `None` for a kept particle no child can
    /// reach and whose family lost no member: its family is unchanged.
    fn new_rows(
        &self,
        child: &[bool],
        order: &[usize],
        fate: &[Fate],
        ancestor: &[usize],
        pos: &[P2],
        delta: &[f64],
    ) -> Vec<Option<Vec<u32>>> {
        let old = &self.dh;
        // Split parents by cell, cell size the largest reach delta + Delta / sqrt 2.
        let reach_max = delta.iter().fold(0.0f64, |a, &b| a.max(b))
            + order.iter().map(|&k| self.size[k]).fold(0.0, f64::max) / 2f64.sqrt();
        let key = |p: P2| {
            (
                (p[0] / reach_max).floor() as i64,
                (p[1] / reach_max).floor() as i64,
            )
        };
        let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for &k in order {
            cells.entry(key(old.pos[k])).or_default().push(k);
        }
        // Cells with a split parent in their 3 x 3 block: only their particles can reach
        // a child.
        let near_split: HashSet<(i64, i64)> = cells
            .keys()
            .flat_map(|&(cx, cy)| {
                (cx - 1..=cx + 1).flat_map(move |gx| (cy - 1..=cy + 1).map(move |gy| (gx, gy)))
            })
            .collect();
        (0..pos.len())
            .into_par_iter()
            .map(|i| {
                let a = ancestor[i];
                let x = pos[i];
                // A kept particle no child can reach and whose family lost no member
                // keeps its family (its members keep their positions and horizons).
                if !child[i]
                    && !near_split.contains(&key(x))
                    && old
                        .bonds
                        .row(a)
                        .all(|b| matches!(fate[old.bonds.nbr[b] as usize], Fate::Kept(_)))
                {
                    return None;
                }
                let r2 = (delta[i] * (1.0 + 1e-9)).powi(2);
                let near = |q: P2| {
                    let d = [q[0] - x[0], q[1] - x[1]];
                    d[0] * d[0] + d[1] * d[1] <= r2
                };
                let mut row = Vec::new();
                // Kept members of the ancestor's family (Eqs. 20, 22 for a child).
                for b in old.bonds.row(a) {
                    let j = old.bonds.nbr[b] as usize;
                    if let Fate::Kept(jn) = fate[j] {
                        if jn as usize != i && near(pos[jn as usize]) {
                            row.push(jn);
                        }
                    }
                }
                // Children of split parents within reach (siblings included).
                let (cx, cy) = key(x);
                for gx in cx - 1..=cx + 1 {
                    for gy in cy - 1..=cy + 1 {
                        for &k in cells.get(&(gx, gy)).map_or(&[][..], |v| v.as_slice()) {
                            let Fate::Split(first) = fate[k] else {
                                continue;
                            };
                            for c in first..first + 4 {
                                if c as usize != i && near(pos[c as usize]) {
                                    row.push(c);
                                }
                            }
                        }
                    }
                }
                row.sort_unstable();
                row.dedup();
                Some(row)
            })
            .collect()
    }

    /// The old particle whose family each new particle has unchanged: a kept particle
    /// whose new row lists its old members, none split, in the same order (the first
    /// body's rows need not be sorted by index). Its bonds, flags and constants are then
    /// the old ones.
    fn unchanged(
        &self,
        rows: &[Option<Vec<u32>>],
        ancestor: &[usize],
        child: &[bool],
        fate: &[Fate],
    ) -> Vec<Option<usize>> {
        let old = &self.dh.bonds;
        (0..rows.len())
            .into_par_iter()
            .map(|i| {
                let a = ancestor[i];
                let same = !child[i]
                    && rows[i].as_ref().is_none_or(|row| {
                        row.len() == old.row(a).len()
                            && old.row(a).zip(row).all(|(b, &jn)| {
                                matches!(fate[old.nbr[b] as usize], Fate::Kept(k) if k == jn)
                            })
                    });
                same.then_some(a)
            })
            .collect()
    }

    /// Flags of the new bonds: cut where a bond crosses a pre-crack or where the old bond
    /// between the two ancestors was broken; an unchanged family's (`same`) are its old
    /// flags.
    fn new_flags(
        &self,
        bonds: &crate::bonds::Bonds,
        anc: &[usize],
        pos: &[P2],
        size: &[f64],
        same: &[Option<usize>],
    ) -> Vec<u8> {
        let old = &self.dh;
        let mut flags = vec![1u8; bonds.len()];
        for (i, s) in same.iter().enumerate() {
            if let Some(a) = *s {
                flags[bonds.row(i)].copy_from_slice(&old.intact[old.bonds.row(a)]);
            }
        }
        let owner_of: Vec<usize> = {
            let mut o = vec![0usize; bonds.len()];
            for i in 0..pos.len() {
                for b in bonds.row(i) {
                    o[b] = i;
                }
            }
            o
        };
        flags.par_iter_mut().enumerate().for_each(|(b, f)| {
            let i = owner_of[b];
            if same[i].is_some() {
                return;
            }
            let j = bonds.nbr[b] as usize;
            let tol = 1e-6 * size[i].min(size[j]);
            if self
                .cracks
                .iter()
                .any(|c| segment_crosses_crack(pos[i], pos[j], c, tol))
            {
                *f = 0;
                return;
            }
            let (ai, aj) = (anc[i], anc[j]);
            if ai != aj {
                if let Some(ob) = old
                    .bonds
                    .row(ai)
                    .find(|&ob| old.bonds.nbr[ob] as usize == aj)
                {
                    *f = old.intact[ob];
                }
            }
        });
        flags
    }
}

#[cfg(test)]
#[path = "budget_tests.rs"]
mod budget_tests;
