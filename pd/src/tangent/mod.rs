//! Sparse tangent over the free DOFs and its solution with faer.
//!
//! $K = -\partial F/\partial u$ (seed 000 Eqs. 8-10, 14-15): for each intact
//! bond the 2x2 block $B$ of [`crate::forces::bond_tangent`] enters $K_{ii}$
//! with $+$ and $K_{ij}$ with $-$; prescribed DOFs are removed (seed 000
//! section 2.3). $K$ is symmetric, so only the lower triangle is stored
//! (CSC, column = free DOF in node order). The pattern holds every bond of
//! the family, broken ones included, so the symbolic Cholesky factorisation
//! is computed once and reused for every Newton iteration. Values are
//! filled in parallel, each node writing only its own columns.
//!
//! Tangents that are not a sum of bond blocks (the state-based model's) fill the same
//! layout row by row on a node stencil ([`Tangent::from_stencil`]).
//!
//! Solve: sparse $LL^T$; if a pivot is not positive (compressed or softening
//! bonds), sparse LU on the full matrix.

mod cholesky;
mod stencil;

pub use cholesky::{check_budget, factor_budget, set_factor_budget};
pub use stencil::Block;

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, SparseColMatRef, SymbolicSparseColMat, Triplet};
use faer::MatMut;
use rayon::prelude::*;

use cholesky::CholeskyFactor;

use crate::bonds::Bonds;
use crate::error::PdError;
use crate::forces::{bond_tangent_scaled, stretch_scale, RowPtr, TangentKind};
use crate::geometry::P2;
use crate::material::BondLaw;

const NONE: usize = usize::MAX;

/// Which factorisation solved the last system.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Factorization {
    /// Sparse Cholesky.
    Cholesky,
    /// Sparse LU fallback (tangent not positive definite).
    Lu,
}

/// Pattern, values and cached symbolic factorisation of the free-DOF tangent.
pub struct Tangent {
    /// Free index of DOF `2i + c`, or `usize::MAX` when prescribed.
    pub dof: Vec<usize>,
    /// Number of free DOFs.
    pub n_free: usize,
    symbolic: SymbolicSparseColMat<usize>,
    /// Start of node `i`'s columns in the value array.
    node_start: Vec<usize>,
    /// Per bond `i -> j` with `j > i`: offset of its entries in node i's
    /// off-diagonal list (sorted by `j`).
    col_off: Vec<u32>,
    values: Vec<f64>,
    llt: Option<CholeskyFactor>,
    /// Fall back to sparse LU when Cholesky finds a non-positive pivot
    /// (default); otherwise that is a [`PdError::LinearSolve`] error.
    pub allow_lu: bool,
    /// Node stencil `(offsets, nodes)` of a [`Tangent::from_stencil`] pattern.
    stencil: Option<(Vec<usize>, Vec<u32>)>,
}

impl Tangent {
    /// Build the pattern for the given bonds and fixed components.
    pub fn new(bonds: &Bonds, fixed: &[[bool; 2]]) -> Result<Self, PdError> {
        let n = fixed.len();
        let mut dof = vec![NONE; 2 * n];
        let mut n_free = 0;
        for i in 0..n {
            for c in 0..2 {
                if !fixed[i][c] {
                    dof[2 * i + c] = n_free;
                    n_free += 1;
                }
            }
        }
        if n_free == 0 {
            return Err(PdError::LinearSolve {
                dofs: 0,
                reason: "every DOF is prescribed".into(),
            });
        }
        // At most 3 entries per node's diagonal block and 4 per bond pair.
        check_pattern(n_free, 3 * n + 2 * bonds.len(), 4 * bonds.len())?;
        // Off-diagonal entries of node i's columns: the free DOFs of its
        // neighbours j > i in increasing j (CSC rows sorted). `col_off[b]`
        // is the position of bond b's first entry within that list.
        let mut col_off = vec![u32::MAX; bonds.len()];
        let mut col_ptr = Vec::with_capacity(n_free + 1);
        let mut row_idx = Vec::new();
        let mut node_start = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut upper: Vec<(usize, usize)> = Vec::new();
        for i in 0..n {
            node_start.push(row_idx.len());
            upper.clear();
            upper.extend(
                bonds
                    .row(i)
                    .filter(|&b| bonds.nbr[b] as usize > i)
                    .map(|b| (bonds.nbr[b] as usize, b)),
            );
            upper.sort_unstable();
            let mut off = 0u32;
            for &(j, b) in &upper {
                col_off[b] = off;
                off += (dof[2 * j] != NONE) as u32 + (dof[2 * j + 1] != NONE) as u32;
            }
            for q in 0..2 {
                if dof[2 * i + q] == NONE {
                    continue;
                }
                for p in q..2 {
                    if dof[2 * i + p] != NONE {
                        row_idx.push(dof[2 * i + p]);
                    }
                }
                for &(j, _) in &upper {
                    for p in 0..2 {
                        if dof[2 * j + p] != NONE {
                            row_idx.push(dof[2 * j + p]);
                        }
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        node_start.push(row_idx.len());
        let nnz = row_idx.len();
        let symbolic = SymbolicSparseColMat::new_checked(n_free, n_free, col_ptr, None, row_idx);
        Ok(Tangent {
            dof,
            n_free,
            symbolic,
            node_start,
            col_off,
            values: vec![0.0; nnz],
            llt: None,
            allow_lu: true,
            stencil: None,
        })
    }

    /// Number of stored (lower-triangle) entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Fill the values at displacement `u` (history frozen).
    pub fn assemble(
        &mut self,
        bonds: &Bonds,
        law: BondLaw,
        intact: &[u8],
        s_hist: &[f64],
        u: &[P2],
    ) {
        self.assemble_in(bonds, law, intact, s_hist, u, TangentKind::Consistent);
    }

    /// Fill the values at displacement `u` with the bond blocks of `kind`
    /// ([`crate::forces::bond_tangent_scaled`]).
    pub fn assemble_in(
        &mut self,
        bonds: &Bonds,
        law: BondLaw,
        intact: &[u8],
        s_hist: &[f64],
        u: &[P2],
        kind: TangentKind,
    ) {
        let vals = RowPtr(self.values.as_mut_ptr());
        let dof = &self.dof;
        let node_start = &self.node_start;
        let col_off = &self.col_off;
        (0..u.len()).into_par_iter().with_min_len(64).for_each(|i| {
            let vp = vals;
            let f0 = dof[2 * i] != NONE;
            let f1 = dof[2 * i + 1] != NONE;
            if !f0 && !f1 {
                return;
            }
            // Layout of node i: col 0 = [diag (1 or 2), off-diag...],
            // col 1 = [diag, off-diag...]; both off-diagonal lists have
            // `n_off` entries.
            let start = node_start[i];
            let n_off =
                (node_start[i + 1] - start - (f0 && f1) as usize - f0 as usize - f1 as usize)
                    / (f0 as usize + f1 as usize);
            let col0_len = if f0 { (1 + f1 as usize) + n_off } else { 0 };
            let off0 = start + if f0 { 1 + f1 as usize } else { 0 };
            let off1 = start + col0_len + 1;
            let mut d = [[0.0; 2]; 2];
            // Tiny diagonal shift (1e-10 of the node's intact stiffness) so an
            // isolated node or a one-directional bond star stays solvable.
            let mut kref = 0.0;
            for b in bonds.row(i) {
                kref += bonds.k[b] * bonds.inv_len[b];
            }
            d[0][0] += 1e-10 * kref;
            d[1][1] += 1e-10 * kref;
            for b in bonds.row(i) {
                let j = bonds.nbr[b] as usize;
                let m = if intact[b] != 0 {
                    let y = [
                        bonds.xi[b][0] + (u[j][0] - u[i][0]),
                        bonds.xi[b][1] + (u[j][1] - u[i][1]),
                    ];
                    let scale = stretch_scale(bonds, b);
                    bond_tangent_scaled(
                        law,
                        bonds.k[b],
                        bonds.inv_len[b],
                        y,
                        s_hist[b],
                        kind,
                        scale,
                    )
                } else {
                    [[0.0; 2]; 2]
                };
                for p in 0..2 {
                    for q in 0..2 {
                        d[p][q] += m[p][q];
                    }
                }
                if j > i {
                    let mut o = col_off[b] as usize;
                    for p in 0..2 {
                        if dof[2 * j + p] == NONE {
                            continue;
                        }
                        // SAFETY: positions lie in node i's own column range.
                        unsafe {
                            if f0 {
                                *vp.0.add(off0 + o) = -m[p][0];
                            }
                            if f1 {
                                *vp.0.add(off1 + o) = -m[p][1];
                            }
                        }
                        o += 1;
                    }
                }
            }
            // SAFETY: diagonal slots of node i's columns.
            unsafe {
                if f0 {
                    *vp.0.add(start) = d[0][0];
                    if f1 {
                        *vp.0.add(start + 1) = d[1][0];
                    }
                }
                if f1 {
                    *vp.0.add(start + col0_len) = d[1][1];
                }
            }
        });
    }

    /// Solve with the last Cholesky factor (of the values at the last
    /// [`Self::solve`] or [`Self::factorize`]), without refactorising: two
    /// triangular solves per right-hand side. `rhs` holds `cols` right-hand
    /// sides of length [`Self::n_free`] one after the other. Errors if no
    /// Cholesky factor is held.
    pub fn solve_with_last_factor(&mut self, rhs: &mut [f64], cols: usize) -> Result<(), PdError> {
        match self.llt.as_mut() {
            Some(llt) if llt.is_valid() && rhs.len() == cols * self.n_free => {
                llt.solve_in_place(rhs, cols);
                Ok(())
            }
            _ => Err(PdError::LinearSolve {
                dofs: self.n_free,
                reason: "no Cholesky factor to reuse".into(),
            }),
        }
    }

    /// Names the Cholesky factor held (a count of this tangent's successful
    /// factorisations), `None` when none is: a solver that factorised can tell whether the
    /// factor is still its own before [`Self::solve_with_last_factor`].
    pub fn factor_generation(&self) -> Option<u64> {
        self.llt.as_ref().and_then(|f| f.generation())
    }

    /// Numeric Cholesky factorisation of the current values, kept for
    /// [`Self::solve_with_last_factor`] (no LU fallback).
    pub fn factorize(&mut self) -> Result<(), PdError> {
        self.factorize_within(factor_budget())
    }

    /// [`Self::factorize`] with a factor of at most `budget` bytes
    /// ([`PdError::TooLarge`] before it is allocated).
    pub fn factorize_within(&mut self, budget: u64) -> Result<(), PdError> {
        if self.llt.is_none() {
            self.llt = Some(CholeskyFactor::new(self.symbolic.as_ref(), budget)?);
        }
        let mat = SparseColMatRef::new(self.symbolic.as_ref(), &self.values);
        let llt = self.llt.as_mut().expect("symbolic factorisation present");
        llt.factor(mat).map_err(|e| PdError::LinearSolve {
            dofs: self.n_free,
            reason: format!("tangent not positive definite (Cholesky: {e:?})"),
        })
    }

    /// The symbolic analysis and the factor's storage now, so that a factor over the
    /// memory budget ([`factor_budget`]) is refused ([`PdError::TooLarge`]) before a
    /// solver starts, not in its first solve.
    pub fn reserve_factor(&mut self) -> Result<(), PdError> {
        if self.llt.is_none() {
            self.llt = Some(CholeskyFactor::new(
                self.symbolic.as_ref(),
                factor_budget(),
            )?);
        }
        Ok(())
    }

    /// Entries the Cholesky factor of this pattern will store, from its symbolic analysis
    /// alone ([`PdError::TooLarge`] over `budget` bytes); nothing numeric is allocated.
    pub fn factor_entries_within(&self, budget: u64) -> Result<usize, PdError> {
        cholesky::symbolic_within(self.symbolic.as_ref(), budget).map(|s| s.len_val())
    }

    /// Stored entries of the Cholesky factor (after the first solve).
    pub fn factor_nnz(&self) -> Option<usize> {
        self.llt.as_ref().map(|f| f.factor_len())
    }

    /// Solve `K x = rhs` in place (rhs over the free DOFs) with a fresh
    /// factorisation of the current values. Returns the factorisation used.
    pub fn solve(&mut self, rhs: &mut [f64]) -> Result<Factorization, PdError> {
        let n = self.n_free;
        if self.llt.is_none() {
            self.llt = Some(CholeskyFactor::new(
                self.symbolic.as_ref(),
                factor_budget(),
            )?);
        }
        let mat = SparseColMatRef::new(self.symbolic.as_ref(), &self.values);
        let llt = self.llt.as_mut().expect("symbolic factorisation present");
        match llt.factor(mat) {
            Ok(()) => {
                llt.solve_in_place(rhs, 1);
                Ok(Factorization::Cholesky)
            }
            Err(e) if !self.allow_lu => Err(PdError::LinearSolve {
                dofs: n,
                reason: format!("tangent not positive definite (Cholesky: {e:?})"),
            }),
            Err(_) => {
                self.solve_lu(rhs)?;
                Ok(Factorization::Lu)
            }
        }
    }

    fn solve_lu(&self, rhs: &mut [f64]) -> Result<(), PdError> {
        let n = self.n_free;
        check_budget(
            &format!("the sparse LU of the tangent of {n} unknowns"),
            lu_bytes(self.values.len(), self.factor_nnz().unwrap_or(0)),
            factor_budget(),
        )?;
        let cp = self.symbolic.col_ptr();
        let ri = self.symbolic.row_idx();
        let mut trip = Vec::with_capacity(2 * self.values.len());
        for c in 0..n {
            for k in cp[c]..cp[c + 1] {
                let r = ri[k];
                let v = self.values[k];
                trip.push(Triplet::new(r, c, v));
                if r != c {
                    trip.push(Triplet::new(c, r, v));
                }
            }
        }
        let full = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &trip).map_err(|e| {
            PdError::LinearSolve {
                dofs: n,
                reason: format!("building the full matrix: {e:?}"),
            }
        })?;
        let lu = full.sp_lu().map_err(|e| PdError::LinearSolve {
            dofs: n,
            reason: format!("tangent not positive definite and LU failed: {e:?}"),
        })?;
        lu.solve_in_place(MatMut::from_column_major_slice_mut(rhs, n, 1));
        if rhs.iter().any(|v| !v.is_finite()) {
            return Err(PdError::LinearSolve {
                dofs: n,
                reason: "singular tangent (LU produced non-finite values); is a rigid-body mode unconstrained?".into(),
            });
        }
        Ok(())
    }
}

/// [`PdError::TooLarge`] before a pattern of `n_free` unknowns with at most `entries`
/// stored entries (row index and value, 16 bytes each) and `extra` bytes of index maps
/// is allocated, against [`factor_budget`].
fn check_pattern(n_free: usize, entries: usize, extra: usize) -> Result<(), PdError> {
    check_budget(
        &format!("the tangent pattern of {n_free} unknowns (up to {entries} entries)"),
        16.0 * entries as f64 + extra as f64,
        factor_budget(),
    )
}

/// Bytes of the LU fallback: the triplets and the full matrix of both triangles (40
/// bytes per stored entry), and L and U of twice the Cholesky factor's entries each
/// (room for pivoting's fill).
fn lu_bytes(entries: usize, cholesky_entries: usize) -> f64 {
    80.0 * entries as f64 + 32.0 * cholesky_entries as f64
}
