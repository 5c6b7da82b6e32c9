//! The state of a model carried onto its refined grid (module docs of [`super`]):
//! displacements by seed 004 Eq. 18 (full-tensor form, [`super::measure`]), bond flags
//! and the tanh law's history from the ancestors' bonds.

use std::collections::HashMap;

use super::measure::{child_displacement, node_measures};
use super::Cell;
use crate::error::PdError;
use crate::forces::stretch_scale;
use crate::geometry::{rotate, P2};
use crate::grid::Lattice;
use crate::material::BondLaw;
use crate::model::PdModel;
use crate::problem::PdProblem;

/// Where a node of the refined grid comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// The same node (same position) of the old grid.
    Kept(usize),
    /// A child of this old node (its cell holds the child).
    Child(usize),
    /// A child of a cell the old grid had no node in (a hole or a slanted side cut it):
    /// placed from the nearest old real node, bonds new.
    Orphan(usize),
}

impl Origin {
    /// The old node the state comes from.
    pub fn source(self) -> usize {
        match self {
            Origin::Kept(o) | Origin::Child(o) | Origin::Orphan(o) => o,
        }
    }

    /// The ancestor whose bonds this node inherits, if any.
    fn ancestor(self) -> Option<usize> {
        match self {
            Origin::Kept(o) | Origin::Child(o) => Some(o),
            Origin::Orphan(_) => None,
        }
    }
}

/// Positions on the lattice of `dx/8` (every node of a mixed grid lies on it).
struct Keys {
    lattice: Lattice,
}

impl Keys {
    fn of(&self, x: P2) -> (i64, i64) {
        let q = rotate(x, -self.lattice.angle);
        let h = self.lattice.dx / 8.0;
        (
            ((q[0] - self.lattice.origin[0]) / h).round() as i64,
            ((q[1] - self.lattice.origin[1]) / h).round() as i64,
        )
    }
}

/// The origin of every node of `new` in `old` (both built from problems on one lattice).
pub fn origins(old: &PdModel, new: &PdModel, problem: &PdProblem) -> Vec<Origin> {
    let lattice = Lattice::of(problem);
    let keys = Keys { lattice };
    let index: HashMap<(i64, i64), usize> = old
        .positions()
        .iter()
        .enumerate()
        .map(|(i, &x)| (keys.of(x), i))
        .collect();
    let mut cells: HashMap<Cell, Vec<usize>> = HashMap::new();
    for (i, &x) in old.positions()[..old.n_real()].iter().enumerate() {
        cells.entry(lattice.cell_of(x)).or_default().push(i);
    }
    let g = old.grid();
    new.positions()
        .iter()
        .map(|&x| {
            if let Some(&o) = index.get(&keys.of(x)) {
                return Origin::Kept(o);
            }
            let (i, j) = lattice.cell_of(x);
            let centre = lattice.centre(i, j);
            let q = rotate([x[0] - centre[0], x[1] - centre[1]], -lattice.angle);
            for level in 0..=crate::refine_zone::MAX_LEVELS {
                let n = 1i64 << level;
                let h = g.dx / n as f64;
                let sub = |v: f64| ((v + 0.5 * g.dx) / h).floor().clamp(0.0, (n - 1) as f64);
                let o = [
                    (sub(q[0]) + 0.5) * h - 0.5 * g.dx,
                    (sub(q[1]) + 0.5) * h - 0.5 * g.dx,
                ];
                let r = rotate(o, lattice.angle);
                let p = [centre[0] + r[0], centre[1] + r[1]];
                if let Some(&o) = index.get(&keys.of(p)) {
                    if o < old.n_real() && (g.node_dx(o) - h).abs() <= 1e-9 * h {
                        return Origin::Child(o);
                    }
                }
            }
            Origin::Orphan(nearest(&cells, (i, j), old.positions(), x))
        })
        .collect()
}

/// The old real node nearest to `x` among the cells around `c` (and further out if
/// those are empty).
fn nearest(cells: &HashMap<Cell, Vec<usize>>, c: Cell, pos: &[P2], x: P2) -> usize {
    let mut best = (f64::INFINITY, 0usize);
    for reach in 1..=64i64 {
        for i in c.0 - reach..=c.0 + reach {
            for j in c.1 - reach..=c.1 + reach {
                for &o in cells.get(&(i, j)).map_or(&[][..], |v| v.as_slice()) {
                    let d = (pos[o][0] - x[0]).hypot(pos[o][1] - x[1]);
                    if d < best.0 {
                        best = (d, o);
                    }
                }
            }
        }
        if best.0.is_finite() {
            break;
        }
    }
    best.1
}

/// The model of the refined `problem` with `old`'s state carried over (module docs of
/// [`super`]): displacements, load factor, bond flags and history.
pub fn refined_model(old: &PdModel, problem: &PdProblem) -> Result<PdModel, PdError> {
    let mut new = PdModel::new(problem)?;
    let from = origins(old, &new, problem);
    let measures = node_measures(old);
    let (xo, uo) = (old.positions(), old.displacements());
    let u: Vec<P2> = from
        .iter()
        .zip(new.positions())
        .map(|(&f, &x)| match f {
            Origin::Kept(o) => uo[o],
            Origin::Child(o) | Origin::Orphan(o) => {
                child_displacement(xo[o], uo[o], &measures[o], x)
            }
        })
        .collect();
    new.set_displacements(&u)?;
    new.set_load_factor(old.load_factor());
    new.apply_prescribed();
    inherit_bonds(old, &mut new, &from);
    Ok(new)
}

/// Bond flags and history of `new` from `old` (module docs of [`super`]).
fn inherit_bonds(old: &PdModel, new: &mut PdModel, from: &[Origin]) {
    let breaking = match new.law() {
        BondLaw::Brittle { s0 } => Some(s0),
        _ => None,
    };
    let ob = old.bonds();
    for k in 0..new.n_nodes() {
        for e in new.bonds.row(k) {
            if new.intact[e] == 0 {
                continue; // cut by a pre-crack
            }
            let j = new.bonds.nbr[e] as usize;
            let inherited = match (from[k].ancestor(), from[j].ancestor()) {
                (Some(a), Some(b)) if a == b => Some((1, 0.0)),
                (Some(a), Some(b)) => ob
                    .row(a)
                    .find(|&f| ob.nbr[f] as usize == b)
                    .map(|f| (old.intact[f], old.s_hist[f])),
                _ => None,
            };
            match inherited {
                Some((intact, hist)) => {
                    new.intact[e] = intact;
                    new.s_hist[e] = hist;
                }
                None => {
                    if let Some(s0) = breaking {
                        if bond_stretch(new, e, k, j) / stretch_scale(&new.bonds, e) >= s0 {
                            new.intact[e] = 0;
                        }
                    }
                }
            }
        }
    }
}

/// The stretch of bond `e` from `k` to `j` at the model's displacements.
pub(super) fn bond_stretch(m: &PdModel, e: usize, k: usize, j: usize) -> f64 {
    let xi = m.bonds.xi[e];
    let (uk, uj) = (m.u[k], m.u[j]);
    let y = [xi[0] + uj[0] - uk[0], xi[1] + uj[1] - uk[1]];
    y[0].hypot(y[1]) * m.bonds.inv_len[e] - 1.0
}
