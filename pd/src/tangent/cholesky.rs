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

/// Free DOFs from which the numeric factorisation and solve run in
/// parallel. Below it the rayon hand-offs of faer's supernodal kernels cost
/// more than they save. Measured on the 2 shared cores (median of four,
/// parallel against sequential): 900 DOFs 9.6 against 1.1 ms per
/// factorisation; 5000 DOFs equal; 10000 DOFs 13 against 19 ms per solve;
/// 20000 DOFs 25 against 52 ms per solve.
const PARALLEL_MIN_DOFS: usize = 8_000;

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
        let par = if n >= PARALLEL_MIN_DOFS {
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
        Ok(())
    }

    /// Whether a factor is held (the last factorisation succeeded).
    pub(super) fn is_valid(&self) -> bool {
        self.valid
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
