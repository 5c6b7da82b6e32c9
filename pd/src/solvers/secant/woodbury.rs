//! The low-rank part of the secant solver's operator
//! $M = K_0 + W D W^T$ ([`super`]): which bond pairs changed their secant
//! stiffness since $K_0$ was factorised, their columns $w_p$, $Z = K_0^{-1} W$
//! and $G = W^T Z$, and the Woodbury correction
//! $$M^{-1} r = y - Z D\,(I + G D)^{-1} W^T y,\qquad y = K_0^{-1} r .$$

use std::time::Instant;

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::Mat;

use crate::error::PdError;
use crate::material::{degradation, BondLaw};
use crate::model::PdModel;
use crate::solvers::SolveInfo;
use crate::tangent::Tangent;

/// `Tangent::dof` entry of a prescribed DOF.
const FIXED: usize = usize::MAX;
/// `col_of` entry of a pair outside `W`.
const NO_COL: u32 = u32::MAX;
/// `col_of` entry of a changed pair with no free DOF (it does not enter `K`).
const NO_DOF: u32 = u32::MAX - 1;

/// One changed bond pair in `W`.
#[derive(Clone, Copy, Debug)]
struct Column {
    /// Directed bond `i -> j` with `i < j`.
    bond: usize,
    /// Free DOF indices of `(i_x, i_y, j_x, j_y)` (or [`FIXED`]).
    dofs: [usize; 4],
    /// Entries of `w_p` at those DOFs.
    w: [f64; 4],
}

impl Column {
    fn dot(&self, v: &[f64]) -> f64 {
        (0..4)
            .filter(|&k| self.dofs[k] != FIXED)
            .map(|k| self.w[k] * v[self.dofs[k]])
            .sum()
    }
}

/// $W$, $D$, $Z$, $G$ and the LU of $I + G D$.
pub(super) struct LowRank {
    /// Axial secant stiffness $k\,T/|\xi|$ of every directed bond in $K_0$.
    a_ref: Vec<f64>,
    /// Column of each changed pair (indexed by its bond `i -> j`, `i < j`).
    col_of: Vec<u32>,
    cols: Vec<Column>,
    /// $Z = K_0^{-1} W$, column major, `n_free` rows.
    z: Vec<f64>,
    /// $G = W^T Z$, row major with stride `max_columns`.
    g: Vec<f64>,
    /// $D$, one entry per column.
    d: Vec<f64>,
    /// LU of $I + G D$, rebuilt when $D$ or $W$ changed.
    cap: Option<PartialPivLu<f64>>,
    max_columns: usize,
}

impl LowRank {
    /// Room for `max_columns` columns over `bonds` directed bonds.
    pub(super) fn new(bonds: usize, max_columns: usize) -> Self {
        LowRank {
            a_ref: vec![0.0; bonds],
            col_of: vec![NO_COL; bonds],
            cols: Vec::new(),
            z: Vec::new(),
            g: vec![0.0; max_columns * max_columns],
            d: Vec::new(),
            cap: None,
            max_columns,
        }
    }

    /// Columns in use.
    #[cfg(test)]
    pub(super) fn len(&self) -> usize {
        self.cols.len()
    }

    /// Whether `extra` more columns would exceed the room.
    pub(super) fn would_overflow(&self, extra: usize) -> bool {
        self.cols.len() + extra > self.max_columns
    }

    /// Axial secant stiffness of directed bond `b` (0 once broken).
    fn axial(model: &PdModel, b: usize) -> f64 {
        if model.intact[b] == 0 {
            return 0.0;
        }
        let t = match model.law {
            BondLaw::Degrading { s_m, s_c, beta } => degradation(model.s_hist[b], s_m, s_c, beta).0,
            _ => 1.0,
        };
        model.bonds.k[b] * t * model.bonds.inv_len[b]
    }

    /// Empty `W` and take the current bond state as the one of $K_0$.
    pub(super) fn reset(&mut self, model: &PdModel) {
        for c in &self.cols {
            self.col_of[c.bond] = NO_COL;
        }
        for (b, c) in self.col_of.iter_mut().enumerate() {
            if *c == NO_DOF {
                *c = NO_COL;
            }
            self.a_ref[b] = Self::axial(model, b);
        }
        self.cols.clear();
        self.z.clear();
        self.d.clear();
        self.cap = None;
    }

    /// Update `D` for the pairs in `W` and return the changed pairs `(i, b)`
    /// (bond `b = i -> j`, `i < j`) not in it yet.
    pub(super) fn update_changed(&mut self, model: &PdModel) -> Vec<(usize, usize)> {
        let b = &model.bonds;
        self.cap = None;
        let mut fresh = Vec::new();
        for i in 0..model.n_nodes() {
            for bb in b.row(i).filter(|&bb| b.nbr[bb] as usize > i) {
                // A pair already in `W` is updated even if it is back at
                // its reference (a state restored after a failed round).
                let a = Self::axial(model, bb);
                match self.col_of[bb] {
                    NO_COL if a != self.a_ref[bb] => fresh.push((i, bb)),
                    NO_COL | NO_DOF => {}
                    c => self.d[c as usize] = a - self.a_ref[bb],
                }
            }
        }
        fresh
    }

    /// Append the pairs `fresh` to `W` (direction at the current state),
    /// their columns of `Z` (one multi-right-hand-side solve) and of `G`.
    /// Returns the triangular solves spent.
    pub(super) fn add_columns(
        &mut self,
        model: &PdModel,
        tangent: &mut Tangent,
        fresh: &[(usize, usize)],
        info: &mut SolveInfo,
    ) -> Result<usize, PdError> {
        let b = &model.bonds;
        let start = self.cols.len();
        for &(i, bb) in fresh {
            let j = b.nbr[bb] as usize;
            let dofs = [
                tangent.dof[2 * i],
                tangent.dof[2 * i + 1],
                tangent.dof[2 * j],
                tangent.dof[2 * j + 1],
            ];
            if dofs.iter().all(|&d| d == FIXED) {
                self.col_of[bb] = NO_DOF;
                continue;
            }
            let y = [
                b.xi[bb][0] + (model.u[j][0] - model.u[i][0]),
                b.xi[bb][1] + (model.u[j][1] - model.u[i][1]),
            ];
            let l = y[0].hypot(y[1]);
            let e = [y[0] / l, y[1] / l];
            self.col_of[bb] = self.cols.len() as u32;
            self.cols.push(Column {
                bond: bb,
                dofs,
                w: [e[0], e[1], -e[0], -e[1]],
            });
            self.d.push(Self::axial(model, bb) - self.a_ref[bb]);
        }
        let added = self.cols.len() - start;
        if added == 0 {
            return Ok(0);
        }
        let n = tangent.n_free;
        let z0 = self.z.len();
        self.z.resize(z0 + added * n, 0.0);
        for (q, c) in self.cols[start..].iter().enumerate() {
            for k in (0..4).filter(|&k| c.dofs[k] != FIXED) {
                self.z[z0 + q * n + c.dofs[k]] += c.w[k];
            }
        }
        let tf = Instant::now();
        tangent.solve_with_last_factor(&mut self.z[z0..], added)?;
        info.time_factorization_s += tf.elapsed().as_secs_f64();
        let stride = self.max_columns;
        for q in start..self.cols.len() {
            let zq = &self.z[q * n..(q + 1) * n];
            for p in 0..=q {
                let v = self.cols[p].dot(zq);
                self.g[p * stride + q] = v;
                self.g[q * stride + p] = v;
            }
        }
        Ok(added)
    }

    /// Turn $y = K_0^{-1} r$ (in place) into $M^{-1} r$.
    pub(super) fn correct(&mut self, y: &mut [f64]) {
        let r = self.cols.len();
        if r == 0 {
            return;
        }
        let stride = self.max_columns;
        let (g, d) = (&self.g, &self.d);
        let cap = self.cap.get_or_insert_with(|| {
            Mat::from_fn(r, r, |p, q| {
                (if p == q { 1.0 } else { 0.0 }) + g[p * stride + q] * d[q]
            })
            .partial_piv_lu()
        });
        let v = Mat::from_fn(r, 1, |p, _| self.cols[p].dot(y));
        let t = cap.solve(&v);
        let n = y.len();
        for q in 0..r {
            let c = self.d[q] * t[(q, 0)];
            let zq = &self.z[q * n..(q + 1) * n];
            for (x, z) in y.iter_mut().zip(zq) {
                *x -= c * z;
            }
        }
    }
}
