//! Post-processing of a boundary solution.
//!
//! - [`field`]: displacement and stress at interior points (Somigliana identities, with the
//!   same element integrals as the system, so points close to the boundary stay accurate);
//!   hoop (tangential) stress along boundary loops; an optional uniform remote field added
//!   for infinite bodies solved by superposition.
//! - [`sif`]: K_I, K_II from crack-face displacement (least-squares fit that removes the
//!   constant-element bias, REFERENCES.md) and from the interaction (M) integral on a circle
//!   of interior points; J; kink angle by maximum circumferential stress; CMOD.
//! - [`williams`]: the near-tip fields of unit K, the integrals' auxiliary fields.
//! - [`face_traction`]: the crack-face terms of J and the interaction integral when the
//!   faces inside the contour carry tractions.

pub mod face_traction;
pub mod field;
pub mod sif;
pub mod williams;

pub use field::{Background, FieldEvaluator};
pub use sif::{cmod, kink_angle, TipResult};
