//! Numeric sparse $LL^T$ of the free-DOF tangent with faer's low-level API:
//! the symbolic analysis (AMD ordering) is computed once per pattern; the
//! factor values and the workspace are kept between Newton iterations, so a
//! numeric factorisation allocates nothing, and the parallelism is chosen
//! by size instead of taken from faer's global setting.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::LltError;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::PdError;

/// Free DOFs from which the numeric factorisation and its solves run in parallel
/// whatever their density. Measured on the 2 shared cores: on the PMB tangent 900 DOFs
/// 9.6 against 1.1 ms per factorisation sequential, 5000 DOFs equal; Newton's
/// crack-initiation ramp on a uniform 1 mm PMB plate (10 000 DOFs, 196 factorisations):
/// 10.4-11.0 s of factorisation and solves in parallel against 11.0-12.1 s sequential.
const PARALLEL_MIN_DOFS: usize = 8_000;

/// Flops per DOF of a factorisation from which it and its solves run in parallel below
/// [`PARALLEL_MIN_DOFS`]. faer's supernodal factorisation runs its supernodes in order
/// and only their dense kernels in parallel, so what pays is the size of the dense
/// blocks, and flops per DOF measure it (they grow as the square of the separators). The
/// state-based tangent's two-hop stencil makes them large at few DOFs: the
/// displacement-controlled cells case (`seed004_edge_crack_initiation_displacement_cells`,
/// 3551-5099 DOFs, 0.25-0.47 MFlop per DOF) took 50-52 s of factorisation sequential and
/// 42-43 s with this rule (the same loads and iterations). On single factorisations of
/// unit squares (best of five, sequential over parallel time, two to four sessions each,
/// noisy on this machine): state-based n = 40 (3197 DOFs, 0.17 MFlop per DOF) 0.8-1.2,
/// n = 60 (7197 DOFs, 0.39) 0.8-1.1, n = 80 (0.61) 1.1-1.5, n = 100 (0.86) 1.2-1.5; PMB
/// (at most 0.23 MFlop per DOF up to 28 800 DOFs) 0.3-1.02, although the whole ramp
/// above gains slightly in parallel.
const PARALLEL_MIN_FLOPS_PER_DOF: f64 = 3e5;

/// Whether the factorisation of `dofs` DOFs and `flops` flops runs in parallel
/// ([`PARALLEL_MIN_DOFS`], [`PARALLEL_MIN_FLOPS_PER_DOF`]; more than one thread).
fn parallel_pays(dofs: usize, flops: f64) -> bool {
    rayon::current_num_threads() > 1
        && (dofs >= PARALLEL_MIN_DOFS || flops >= PARALLEL_MIN_FLOPS_PER_DOF * dofs as f64)
}

/// Bytes a factor's values may take ([`set_factor_budget`]); default 8 GiB.
static FACTOR_BUDGET: AtomicU64 = AtomicU64::new(8 << 30);

/// Sets the bytes a sparse factor (or an assembled pattern) may take; the application
/// passes its memory budget. Above it a factorisation is refused with
/// [`PdError::TooLarge`] before it allocates.
pub fn set_factor_budget(bytes: u64) {
    FACTOR_BUDGET.store(bytes.max(1), Ordering::Relaxed);
}

/// The budget of [`set_factor_budget`] in bytes.
pub fn factor_budget() -> u64 {
    FACTOR_BUDGET.load(Ordering::Relaxed)
}

/// [`PdError::TooLarge`] when `bytes` of `what` exceed `budget` bytes.
pub fn check_budget(what: &str, bytes: f64, budget: u64) -> Result<(), PdError> {
    let budget = budget as f64;
    if bytes <= budget {
        return Ok(());
    }
    Err(PdError::TooLarge {
        what: what.into(),
        bytes,
        budget,
    })
}

/// The symbolic analysis of the lower-triangle `pattern` (AMD ordering), refused with
/// [`PdError::TooLarge`] when the factor's values would exceed `budget` bytes.
pub(super) fn symbolic_within(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    budget: u64,
) -> Result<SymbolicCholesky<usize>, PdError> {
    let n = pattern.nrows();
    let symbolic = factorize_symbolic_cholesky(
        pattern,
        Side::Lower,
        SymmetricOrdering::Amd,
        Default::default(),
    )
    .map_err(|e| PdError::LinearSolve {
        dofs: n,
        reason: format!("symbolic Cholesky: {e:?}"),
    })?;
    check_budget(
        &format!(
            "the sparse Cholesky factor of {n} unknowns ({} entries)",
            symbolic.len_val()
        ),
        8.0 * symbolic.len_val() as f64,
        budget,
    )?;
    Ok(symbolic)
}

/// Sparse $LL^T$ factor: symbolic analysis, factor values, workspace.
pub(super) struct CholeskyFactor {
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    scratch: MemBuffer,
    /// Right-hand sides the workspace holds room for.
    scratch_cols: usize,
    par: Par,
    /// `l_values` hold the factor of the last successful factorisation.
    valid: bool,
    /// Successful numeric factorisations so far (names the factor held).
    generation: u64,
}

/// Floating-point operations of one numeric factorisation of `symbolic`: per supernode
/// of `w` columns over `r` rows, $\sum_{c<w} (r-c)^2$ (the rank-1 updates of its columns
/// and of the rows below them).
pub(super) fn factor_flops(symbolic: &SymbolicCholesky<usize>) -> f64 {
    use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => {
            let (begin, end) = (s.supernode_begin(), s.supernode_end());
            let ptr = s.col_ptr_for_row_idx();
            (0..s.n_supernodes())
                .map(|k| {
                    let w = (end[k] - begin[k]) as f64;
                    let r = w + (ptr[k + 1] - ptr[k]) as f64;
                    // sum_{c<w} (r-c)^2 in closed form.
                    let sq = |x: f64| x * (x + 1.0) * (2.0 * x + 1.0) / 6.0;
                    sq(r) - sq(r - w)
                })
                .sum()
        }
        SymbolicCholeskyRaw::Simplicial(s) => {
            let ptr = s.col_ptr();
            (0..s.ncols())
                .map(|j| ((ptr[j + 1] - ptr[j]) as f64).powi(2))
                .sum()
        }
    }
}

impl CholeskyFactor {
    /// Symbolic analysis of the lower-triangle `pattern` (AMD ordering).
    /// A geometric nested dissection of the grid (separators three node
    /// columns wide) was tried instead: on the 100 x 100 and 150 x 150
    /// tangents it stored 3-4 % fewer factor entries and factored within
    /// 10 % of AMD's time, not worth its code.
    pub(super) fn new(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        budget: u64,
    ) -> Result<Self, PdError> {
        let n = pattern.nrows();
        let symbolic = symbolic_within(pattern, budget)?;
        let par = if parallel_pays(n, factor_flops(&symbolic)) {
            Par::rayon(0)
        } else {
            Par::Seq
        };
        let mut f = CholeskyFactor {
            l_values: vec![0.0; symbolic.len_val()],
            symbolic,
            scratch: MemBuffer::new(StackReq::EMPTY),
            scratch_cols: 0,
            par,
            valid: false,
            generation: 0,
        };
        f.reserve_cols(1);
        Ok(f)
    }

    /// Grow the workspace to hold the factorisation and a solve with `cols`
    /// right-hand sides.
    fn reserve_cols(&mut self, cols: usize) {
        if cols <= self.scratch_cols {
            return;
        }
        let req = StackReq::any_of(&[
            self.symbolic
                .factorize_numeric_llt_scratch::<f64>(self.par, Default::default()),
            self.symbolic.solve_in_place_scratch::<f64>(cols, self.par),
        ]);
        self.scratch = MemBuffer::new(req);
        self.scratch_cols = cols;
    }

    /// Stored values of the factor (a measure of the fill).
    pub(super) fn factor_len(&self) -> usize {
        self.l_values.len()
    }

    /// Numeric factorisation of `mat` (lower triangle, the pattern of
    /// [`Self::new`]). On error no factor is held.
    pub(super) fn factor(&mut self, mat: SparseColMatRef<'_, usize, f64>) -> Result<(), LltError> {
        let stack = MemStack::new(&mut self.scratch);
        self.valid = false;
        self.symbolic.factorize_numeric_llt(
            &mut self.l_values,
            mat,
            Side::Lower,
            Default::default(),
            self.par,
            stack,
            Default::default(),
        )?;
        self.valid = true;
        self.generation += 1;
        Ok(())
    }

    /// Whether a factor is held (the last factorisation succeeded).
    pub(super) fn is_valid(&self) -> bool {
        self.valid
    }

    /// The held factor's number among the successful factorisations (`None`: none held).
    pub(super) fn generation(&self) -> Option<u64> {
        self.valid.then_some(self.generation)
    }

    /// `rhs <- K^-1 rhs` with the last factor, `rhs` holding `cols`
    /// right-hand sides of length `n` one after the other (column major).
    pub(super) fn solve_in_place(&mut self, rhs: &mut [f64], cols: usize) {
        let n = self.symbolic.nrows();
        debug_assert_eq!(rhs.len(), n * cols);
        self.reserve_cols(cols);
        let stack = MemStack::new(&mut self.scratch);
        LltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, cols),
            self.par,
            stack,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::SymbolicSparseColMat;

    /// The lower triangle of an `n x n` matrix whose column `j` holds rows `rows(j)`.
    fn lower(n: usize, rows: impl Fn(usize) -> Vec<usize>) -> SymbolicSparseColMat<usize> {
        let mut ptr = vec![0];
        let mut idx = Vec::new();
        for j in 0..n {
            idx.extend(rows(j));
            ptr.push(idx.len());
        }
        SymbolicSparseColMat::new_checked(n, n, ptr, None, idx)
    }

    #[test]
    fn factor_flops_count_the_dense_and_the_diagonal_cases() {
        // Dense: one supernode, sum_{c<n} (n-c)^2 = n(n+1)(2n+1)/6, about n^3/3.
        let n = 60;
        let dense = lower(n, |j| (j..n).collect());
        let s = symbolic_within(dense.as_ref(), u64::MAX).unwrap();
        let want = (n * (n + 1) * (2 * n + 1) / 6) as f64;
        assert_eq!(factor_flops(&s), want);
        // Diagonal: one flop per column.
        let diag = lower(n, |j| vec![j]);
        let s = symbolic_within(diag.as_ref(), u64::MAX).unwrap();
        assert_eq!(factor_flops(&s), n as f64);
    }
}
