//! Adaptive refinement of a PD grid's cells by seed 004's criteria (section 3), for the
//! quasi-static solvers (Newton, ADR, the explicit-implicit switch) on the mixed grid of
//! [`crate::mixed`] with either model (PMB or state-based) and every failure law,
//! the tanh degradation included.
//!
//! **Criteria** (seed 004 section 3.1), checked at every converged load step on each
//! real node $k$ below the deepest level:
//! $$\phi_k > \phi_c \quad\text{(Eq. 15)},\qquad
//!   \min(\varepsilon_{xx}, \varepsilon_{yy}) > \alpha\, s_c \sqrt{\delta/\delta_k}
//!   \quad\text{(Eq. 16)},$$
//! $\phi_k$ the damage over the node's own family (seed 002 Eq. 8, tanh-degraded bonds
//! counted by their degradation, [`measure::criterion_damage`]), $\varepsilon_{ii}$ the
//! accumulated strains of Eq. 17 ([`measure`]), $s_c$ the law's critical stretch
//! (`s0` of the brittle law, the zero-force stretch `s_c` of the tanh law) at the
//! coarse horizon $\delta$, scaled to the node's horizon $\delta_k$ as the mixed grid
//! scales it ([`crate::mixed`], $s \propto \delta^{-1/2}$). Static criteria (cells near
//! the pre-cracks, circles) refine before the first step, as do the pre-cracks' own
//! damage (the seed's set-up steps 3-5).
//!
//! **Unit of refinement: the coarse cell.** A node that fires splits its whole coarse
//! cell one level deeper: a coarse node into 4 children (seed 004's split), a child's
//! cell into 16 grandchildren (where the seed splits only the particle that fired, the
//! grid splits its three siblings with it, so every cell stays a uniform square lattice
//! and the dual-horizon bonds of [`crate::mixed`] apply unchanged). The grid is graded:
//! the cells next to a level-2 cell are split at least once, so no size jump exceeds 2.
//! Cells holding a real node with a prescribed displacement (a pin) are never split.
//!
//! **Split and transfer** ([`transfer`]): the refined grid is built afresh from the
//! problem with one zone per split cell, and the state carried over: a kept node keeps
//! its displacement; a child takes its parent's plus the parent's displacement gradient
//! times its offset ([`measure`], seed 004 Eq. 18 in full-tensor form); a bond between
//! two nodes whose ancestors were bonded inherits that bond's state (broken stays broken,
//! the tanh law's normalised history, so its degradation $T$, stays), a bond within one
//! parent starts intact, and a bond whose ancestors were not bonded starts intact unless
//! its stretch already passes its breaking stretch (as [`crate::refine`] rules).
//!
//! **Ramp** ([`ramp`]): each load step is solved, the criteria checked, and while any
//! cell splits the step is solved again on the refined grid (the seed's per-step steps
//! 3-5); the rounds end because every split deepens a cell and the levels are bounded.
//! [`initiation`] does the same within stand-alone PD's crack-initiation ramp (Newton,
//! brittle breaking until the crack runs), and with `before_breaking` also splits, before
//! a round's bonds break, the cells below the deepest level that hold an end of a bond
//! past its breaking stretch and the cells around them ([`breaking_cells`]; not a
//! criterion of the seed): bonds then break on the deepest level only. Without it a
//! coarse cell's broken bonds are inherited by its children when Eq. 15 fires after the
//! break, the coarse crack's cell-scale pattern stays in the fine grid, and a stably
//! growing crack bent by 9 degrees where the uniform fine grid's ran straight
//! (`docs/seed004.md`).

pub mod initiation;
pub mod measure;
pub mod ramp;
pub mod transfer;

#[cfg(test)]
mod initiation_tests;
#[cfg(test)]
mod tests;

use std::collections::{BTreeMap, BTreeSet};

use crate::error::PdError;
use crate::geometry::{dist_point_segment, P2};
use crate::grid::Lattice;
use crate::material::BondLaw;
use crate::model::PdModel;
use crate::problem::PdProblem;
use crate::refine_zone::{RefineZone, MAX_LEVELS};

/// A coarse cell of the grid's lattice, `(i, j)`.
pub type Cell = (i64, i64);

/// The criteria of seed 004 section 3.1 on a grid's cells (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct CellCriteria {
    /// Critical damage phi_c of Eq. 15 in (0, 1); `None`: no damage criterion.
    pub critical_damage: Option<f64>,
    /// Factor alpha of Eq. 16 in (0, 1); `None`: no strain criterion.
    pub strain_factor: Option<f64>,
    /// Deepest level, 1 or [`MAX_LEVELS`].
    pub max_level: u32,
    /// Static: cells whose centres lie within this distance (m) of a pre-crack are split
    /// to `max_level` before the first step.
    pub near_cracks: Option<f64>,
    /// Static: cells whose centres lie in a circle `(centre, radius, level)` are split
    /// to `level` before the first step.
    pub circles: Vec<(P2, f64, u32)>,
    /// The crack-initiation ramp ([`initiation`]) splits, before the bonds of a round
    /// break, every cell below `max_level` holding an end of a bond past its breaking
    /// stretch ([`breaking_cells`]), so bonds break on the deepest level only.
    pub before_breaking: bool,
}

impl CellCriteria {
    /// Checks the criteria's own values.
    pub fn validate(&self) -> Result<(), PdError> {
        for (name, v) in [
            ("critical_damage", self.critical_damage),
            ("strain_factor", self.strain_factor),
        ] {
            if let Some(v) = v {
                if !(v > 0.0 && v < 1.0) {
                    return Err(PdError::invalid(
                        name,
                        format!("must lie in (0, 1), got {v}"),
                    ));
                }
            }
        }
        if !(1..=MAX_LEVELS).contains(&self.max_level) {
            return Err(PdError::invalid(
                "max_level",
                format!(
                    "a grid's cells split 1 to {MAX_LEVELS} times, got {}",
                    self.max_level
                ),
            ));
        }
        if let Some(d) = self.near_cracks {
            if !(d.is_finite() && d > 0.0) {
                return Err(PdError::invalid(
                    "near_cracks",
                    format!("must be positive, got {d}"),
                ));
            }
        }
        for (i, &(c, r, l)) in self.circles.iter().enumerate() {
            if !(c[0].is_finite() && c[1].is_finite() && r.is_finite() && r > 0.0) {
                return Err(PdError::invalid(
                    format!("circles[{i}]"),
                    "centre must be finite and the radius positive",
                ));
            }
            if !(1..=self.max_level).contains(&l) {
                return Err(PdError::invalid(
                    format!("circles[{i}].level"),
                    format!("must be 1 to max_level = {}", self.max_level),
                ));
            }
        }
        Ok(())
    }
}

/// The split cells of an adaptive grid and the problem they refine.
#[derive(Clone, Debug)]
pub struct AdaptiveCells {
    base: PdProblem,
    levels: BTreeMap<Cell, u32>,
}

impl AdaptiveCells {
    /// No cell split yet over `base` (its own fixed zones stay).
    pub fn new(base: &PdProblem) -> Self {
        AdaptiveCells {
            base: base.clone(),
            levels: BTreeMap::new(),
        }
    }

    /// Split cells and their levels.
    pub fn levels(&self) -> &BTreeMap<Cell, u32> {
        &self.levels
    }

    /// Raises the cells' levels; returns how many rose.
    pub fn raise(&mut self, cells: &BTreeMap<Cell, u32>) -> usize {
        let mut raised = 0;
        for (&c, &l) in cells {
            let e = self.levels.entry(c).or_insert(0);
            if l > *e {
                *e = l;
                raised += 1;
            }
        }
        raised
    }

    /// The problem with one zone per split cell besides its own zones.
    pub fn problem(&self) -> PdProblem {
        let mut p = self.base.clone();
        let lattice = Lattice::of(&p);
        let half = 0.25 * p.dx;
        p.refine_zones
            .extend(self.levels.iter().map(|(&(i, j), &levels)| RefineZone {
                centre: lattice.centre(i, j),
                half_size: half,
                levels,
            }));
        p
    }
}

/// Level of node `k` (0 coarse, 1 child, 2 grandchild) from its spacing.
fn node_level(model: &PdModel, k: usize) -> u32 {
    let g = model.grid();
    (g.dx / g.node_dx(k)).log2().round().max(0.0) as u32
}

/// The current level of every cell holding a real node, and the cells that may not
/// split (they hold a real node with a prescribed component).
fn cell_levels(model: &PdModel, lattice: &Lattice) -> (BTreeMap<Cell, u32>, BTreeSet<Cell>) {
    let mut levels = BTreeMap::new();
    let mut blocked = BTreeSet::new();
    let fixed = &model.boundary().fixed;
    for (k, &x) in model.positions()[..model.n_real()].iter().enumerate() {
        let c = lattice.cell_of(x);
        let l = levels.entry(c).or_insert(0);
        *l = (*l).max(node_level(model, k));
        if fixed[k][0] || fixed[k][1] {
            blocked.insert(c);
        }
    }
    (levels, blocked)
}

/// The law's critical stretch at the coarse horizon (Eq. 16's `s_c`), if it breaks.
fn critical_stretch(law: BondLaw) -> Option<f64> {
    match law {
        BondLaw::Elastic => None,
        BondLaw::Brittle { s0 } => Some(s0),
        BondLaw::Degrading { s_c, .. } => Some(s_c),
    }
}

/// The cells Eqs. 15-16 split now, with their new levels (graded, module docs); empty
/// when no criterion fires.
pub fn flagged_cells(
    model: &PdModel,
    problem: &PdProblem,
    crit: &CellCriteria,
) -> BTreeMap<Cell, u32> {
    let lattice = Lattice::of(problem);
    let (current, blocked) = cell_levels(model, &lattice);
    let damage = crit
        .critical_damage
        .map(|_| measure::criterion_damage(model));
    let strain = match (crit.strain_factor, critical_stretch(model.law())) {
        (Some(a), Some(s_c)) => Some((a * s_c, measure::node_measures(model))),
        _ => None,
    };
    let g = model.grid();
    let mut want = BTreeMap::new();
    for k in 0..model.n_real() {
        let level = node_level(model, k);
        if level >= crit.max_level {
            continue;
        }
        let by_damage = match (&damage, crit.critical_damage) {
            (Some(d), Some(phi_c)) => d[k] > phi_c,
            _ => false,
        };
        let by_strain = strain.as_ref().is_some_and(|(limit, m)| {
            let scale = (g.dx / g.node_dx(k)).sqrt();
            m[k].strain[0].min(m[k].strain[1]) > limit * scale
        });
        if by_damage || by_strain {
            let l = want.entry(lattice.cell_of(g.pos[k])).or_insert(0);
            *l = (*l).max(level + 1);
        }
    }
    settle(want, &current, &blocked)
}

/// The cells, with their new levels (graded), that hold a real node below `max_level`
/// with an intact bond past the brittle law's breaking stretch (normalised,
/// [`crate::forces::stretch_scale`]: the bonds the next commit would break there), and
/// the 8 cells around each, one level deeper than that node. The ring keeps the size
/// jump a cell away from the breaking bonds (without it the plate of
/// [`super::initiation`]'s tests with the criteria alone initiated two load steps above
/// the finer grid, with it at the finer grid's load; docs/seed004.md). Empty unless
/// `crit.before_breaking` and the law is brittle.
pub fn breaking_cells(
    model: &PdModel,
    problem: &PdProblem,
    crit: &CellCriteria,
) -> BTreeMap<Cell, u32> {
    let (true, BondLaw::Brittle { s0 }) = (crit.before_breaking, model.law()) else {
        return BTreeMap::new();
    };
    let lattice = Lattice::of(problem);
    let (current, blocked) = cell_levels(model, &lattice);
    let g = model.grid();
    let b = model.bonds();
    let mut want = BTreeMap::new();
    for k in 0..model.n_real() {
        let level = node_level(model, k);
        if level >= crit.max_level {
            continue;
        }
        let hit = b.row(k).any(|e| {
            let j = b.nbr[e] as usize;
            // The commit's rule (crate::forces): intact, not protected, past s0.
            !matches!(model.intact[e], 0 | crate::forces::NO_FAIL)
                && transfer::bond_stretch(model, e, k, j) / crate::forces::stretch_scale(b, e) >= s0
        });
        if hit {
            let (i, j) = lattice.cell_of(g.pos[k]);
            for c in (i - 1..=i + 1).flat_map(|a| (j - 1..=j + 1).map(move |b| (a, b))) {
                if current.contains_key(&c) {
                    let l = want.entry(c).or_insert(0);
                    *l = (*l).max(level + 1);
                }
            }
        }
    }
    settle(want, &current, &blocked)
}

/// The static criteria's cells (module docs) with their levels.
pub fn static_cells(
    model: &PdModel,
    problem: &PdProblem,
    crit: &CellCriteria,
) -> BTreeMap<Cell, u32> {
    let lattice = Lattice::of(problem);
    let (current, blocked) = cell_levels(model, &lattice);
    let mut want = BTreeMap::new();
    for &c in current.keys() {
        let x = lattice.centre(c.0, c.1);
        let mut level = 0;
        if let Some(d) = crit.near_cracks {
            let near = problem.cracks.iter().any(|cr| {
                cr.windows(2)
                    .any(|s| dist_point_segment(x, s[0], s[1]) <= d)
            });
            if near {
                level = crit.max_level;
            }
        }
        for &(o, r, l) in &crit.circles {
            if (x[0] - o[0]).hypot(x[1] - o[1]) <= r {
                level = level.max(l);
            }
        }
        if level > 0 {
            want.insert(c, level);
        }
    }
    settle(want, &current, &blocked)
}

/// The wanted levels graded (a cell next to one at level `L` is at least at `L - 1`),
/// without the blocked cells, kept where they deepen a cell.
fn settle(
    mut want: BTreeMap<Cell, u32>,
    current: &BTreeMap<Cell, u32>,
    blocked: &BTreeSet<Cell>,
) -> BTreeMap<Cell, u32> {
    for c in blocked {
        want.remove(c);
    }
    for level in (2..=MAX_LEVELS).rev() {
        let deep: Vec<Cell> = current
            .iter()
            .map(|(&c, &l)| (c, want.get(&c).copied().unwrap_or(0).max(l)))
            .filter(|&(_, l)| l >= level)
            .map(|(c, _)| c)
            .collect();
        for (i, j) in deep {
            for (di, dj) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let n = (i + di, j + dj);
                if current.contains_key(&n) && !blocked.contains(&n) {
                    let l = want.entry(n).or_insert(0);
                    *l = (*l).max(level - 1);
                }
            }
        }
    }
    want.retain(|c, l| current.get(c).is_some_and(|&now| *l > now));
    want
}
