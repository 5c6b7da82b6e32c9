//! The one error type of the BEM crate. Every variant carries the numbers that explain it.

use thiserror::Error;

/// Errors of mesh generation, assembly, solution and post-processing.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum BemError {
    /// A material constant is out of range.
    #[error("material: {field} = {value}: {reason}")]
    Material {
        /// Field name (`e`, `nu`).
        field: &'static str,
        /// Offending value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// The mesh cannot be built as asked.
    #[error("mesh: {0}")]
    Mesh(String),
    /// Boundary conditions do not match the mesh.
    #[error("boundary conditions: {0}")]
    Boundary(String),
    /// The assembled system is singular or produced non-finite numbers.
    #[error("solve: {reason} (unknowns {unknowns}, condition estimate {condition:.3e})")]
    Singular {
        /// What went wrong.
        reason: String,
        /// Number of unknowns.
        unknowns: usize,
        /// 1-norm condition estimate of the scaled system (infinite when unknown).
        condition: f64,
    },
    /// A post-processing request cannot be served (e.g. a crack without a mouth asked for CMOD).
    #[error("post-processing: {0}")]
    Post(String),
    /// The dense system would exceed the memory budget ([`crate::system::set_system_budget`]).
    #[error(
        "system: {elements} elements ({unknowns} unknowns) need {:.3} GiB for the dense system, over the memory budget of {:.3} GiB",
        bytes / 1073741824.0,
        budget / 1073741824.0
    )]
    TooLarge {
        /// Elements of the mesh.
        elements: usize,
        /// Unknowns of the system.
        unknowns: usize,
        /// Bytes the system needs.
        bytes: f64,
        /// The budget (bytes).
        budget: f64,
    },
}
