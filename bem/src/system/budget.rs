//! The memory budget of a dense BEM system: a system whose matrix, $8 n^2$ bytes for
//! $n = 2N + m$ unknowns ($N$ elements, $m$ free rigid modes), would pass it is refused
//! with [`BemError::TooLarge`] before anything is allocated. The application passes its
//! budget ([`set_system_budget`]); a mesh that grows during a run (crack growth adds
//! elements at every window relocation) then ends the run with a reason instead of
//! exhausting the machine's memory.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::BemError;

/// Bytes a dense system may take ([`set_system_budget`]); default 8 GiB.
static SYSTEM_BUDGET: AtomicU64 = AtomicU64::new(8 << 30);

/// Sets the bytes a dense system (matrix and work vectors) may take.
pub fn set_system_budget(bytes: u64) {
    SYSTEM_BUDGET.store(bytes.max(1), Ordering::Relaxed);
}

/// The budget of [`set_system_budget`] in bytes.
pub fn system_budget() -> u64 {
    SYSTEM_BUDGET.load(Ordering::Relaxed)
}

/// [`BemError::TooLarge`] when the dense system of `elements` elements and `unknowns`
/// unknowns (`bytes` bytes) exceeds the budget.
pub(super) fn check(elements: usize, unknowns: usize, bytes: usize) -> Result<(), BemError> {
    let budget = system_budget();
    if (bytes as u64) <= budget {
        return Ok(());
    }
    Err(BemError::TooLarge {
        elements,
        unknowns,
        bytes: bytes as f64,
        budget: budget as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Over the budget: refused with the sizes named; at it: accepted.
    #[test]
    fn a_system_over_the_budget_is_refused() {
        assert!(check(10, 20, 8 << 30).is_ok());
        let e = check(40_000, 80_000, (8 << 30) + 1).unwrap_err();
        assert!(e.to_string().contains("40000 elements"), "{e}");
    }
}
