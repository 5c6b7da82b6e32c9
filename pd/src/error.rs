//! The one error type of `pdbem-pd`.
//!
//! Every variant carries the numbers that explain it, and input errors name
//! the offending field of [`crate::PdProblem`] and the violated constraint,
//! in the spirit of faer's `CgError::NoConvergence { abs_residual, .. }`.

use thiserror::Error;

/// Errors returned by model construction and the solvers.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum PdError {
    /// A field of the problem description violates a constraint.
    #[error("invalid input `{field}`: {reason}")]
    InvalidInput {
        /// Dotted path of the field, e.g. `failure.s_m`.
        field: String,
        /// What is wrong and what to change, with the numbers.
        reason: String,
    },
    /// A slice passed to the model has the wrong length.
    #[error("length mismatch for {what}: expected {expected}, got {got}")]
    LengthMismatch {
        /// Which argument.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Length received.
        got: usize,
    },
    /// A solver produced a non-finite value.
    #[error("{solver}: non-finite value at iteration {iteration} (load factor {})", factor_text(*load))]
    NonFinite {
        /// Solver name.
        solver: &'static str,
        /// Iteration (within the load step) where it happened.
        iteration: usize,
        /// Load factor of the step.
        load: f64,
    },
    /// The residual grew by more than the allowed factor.
    #[error(
        "{solver} diverged at iteration {iteration} (load factor {}): residual {residual:.3e} grew from {initial:.3e}",
        factor_text(*load)
    )]
    Diverged {
        /// Solver name.
        solver: &'static str,
        /// Iteration where the growth was detected.
        iteration: usize,
        /// Load factor of the step.
        load: f64,
        /// Current residual measure.
        residual: f64,
        /// Smallest residual measure seen in the step.
        initial: f64,
    },
    /// A load step's bond-breaking rounds ran out before the bond history settled: bonds
    /// still broke, or stretches still grew past their committed history.
    #[error(
        "{solver}: the bond history did not settle in {rounds} re-converged rounds at load factor {} (last round: {broken} directed bonds broke, the largest stretch grew {growth:.3e} past its history, allowed {allowed:.3e}): no quasi-static equilibrium was reached at this load (a crack running unstably, or a load step too large for the breaking rounds)",
        factor_text(*load)
    )]
    Unsettled {
        /// Solver name.
        solver: &'static str,
        /// Rounds done.
        rounds: usize,
        /// Load factor of the step.
        load: f64,
        /// Directed bonds broken in the last round.
        broken: usize,
        /// Largest growth of a stretch past its history in the last round.
        growth: f64,
        /// The growth allowed.
        allowed: f64,
    },
    /// The iteration cap was reached without meeting the tolerance.
    #[error(
        "{solver} did not converge in {iterations} iterations (load factor {}): measure {measure:.3e} > tolerance {tolerance:.3e}",
        factor_text(*load)
    )]
    NoConvergence {
        /// Solver name.
        solver: &'static str,
        /// Iterations done.
        iterations: usize,
        /// Load factor of the step.
        load: f64,
        /// Last convergence measure.
        measure: f64,
        /// Requested tolerance.
        tolerance: f64,
    },
    /// A sparse factor would exceed the memory budget ([`crate::tangent::set_factor_budget`]).
    #[error("{what} would need {}, over the budget of {}", size_text(*bytes), size_text(*budget))]
    TooLarge {
        /// What would be allocated.
        what: String,
        /// Its estimated size (bytes).
        bytes: f64,
        /// The budget (bytes).
        budget: f64,
    },
    /// A solve ended with a node farther from its reference position than the body's
    /// size beyond the largest prescribed displacement ([`crate::solvers::check_bounded`]):
    /// a small-strain model has no such equilibrium; the nodes are held only by bonds that
    /// carry no force (softened past `s_c` with the history frozen) and ran away.
    #[error(
        "{solver}: a displacement of {displacement:.3e} m at load factor {} exceeds the largest prescribed one ({prescribed:.3e} m) by more than the body's size ({size:.3e} m): a runaway state (nodes held only by bonds that carry no force), not an equilibrium",
        factor_text(*load)
    )]
    Runaway {
        /// Solver name.
        solver: &'static str,
        /// Load factor of the step.
        load: f64,
        /// The largest displacement of a real node (m).
        displacement: f64,
        /// The largest prescribed displacement (m).
        prescribed: f64,
        /// The diagonal of the nodes' bounding box (m).
        size: f64,
    },
    /// The sparse linear solve failed (all fallbacks included).
    #[error("linear solve failed ({dofs} free DOFs): {reason}")]
    LinearSolve {
        /// Number of unknowns.
        dofs: usize,
        /// Message from the factorization.
        reason: String,
    },
}

/// `bytes` in KiB, MiB or GiB with three significant digits.
fn size_text(bytes: f64) -> String {
    let (v, unit) = if bytes >= (1u64 << 30) as f64 {
        (bytes / (1u64 << 30) as f64, "GiB")
    } else if bytes >= (1u64 << 20) as f64 {
        (bytes / (1u64 << 20) as f64, "MiB")
    } else {
        (bytes / 1024.0, "KiB")
    };
    format!("{v:.3} {unit}")
}

/// A load factor as the messages show it: as it prints when short (0.6, 3.3, 8.1);
/// otherwise to 7 significant digits, trailing zeros dropped, in decimal form from 1e-3
/// to 1e6 (0.1 + 0.2 is 0.3, 2.7600000000000002 is 2.76) and in exponent form outside
/// (1e300 prints 301 digits: 1e300).
pub fn factor_text(load: f64) -> String {
    let plain = load.to_string();
    if plain.len() <= 12 || !load.is_finite() {
        return plain;
    }
    let trim = |m: &str| -> String {
        if m.contains('.') {
            m.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            m.to_string()
        }
    };
    let a = load.abs();
    if (1e-3..1e6).contains(&a) {
        let decimals = (6 - a.log10().floor() as i32).max(0) as usize;
        trim(&format!("{load:.decimals$}"))
    } else {
        let e = format!("{load:.6e}");
        let (m, x) = e.split_once('e').unwrap_or((&e, "0"));
        format!("{}e{x}", trim(m))
    }
}

impl PdError {
    /// Shorthand for [`PdError::InvalidInput`].
    pub fn invalid(field: impl Into<String>, reason: impl Into<String>) -> Self {
        PdError::InvalidInput {
            field: field.into(),
            reason: reason.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_factors_print_short() {
        let e = |load| PdError::NonFinite {
            solver: "adr",
            iteration: 1,
            load,
        };
        assert!(e(0.6).to_string().ends_with("(load factor 0.6)"));
        assert!(e(1e300).to_string().ends_with("(load factor 1e300)"));
        assert!(e(0.1 + 0.2).to_string().ends_with("(load factor 0.3)"));
        assert!(e(2.7600000000000002)
            .to_string()
            .ends_with("(load factor 2.76)"));
        assert!(e(7.0 / 9.0)
            .to_string()
            .ends_with("(load factor 0.7777778)"));
        assert!(e(-1.0 / 3.0e9)
            .to_string()
            .ends_with("(load factor -3.333333e-10)"));
        assert!(e(123456.78901234)
            .to_string()
            .ends_with("(load factor 123456.8)"));
    }
}
