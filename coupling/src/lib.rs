//! # pdbem-coupling: PD windows iterated against the BEM body (seed 002 section 2.3)
//!
//! Map of the crate:
//! - [`relaxation`]: interface acceleration behind one trait: constant, Aitken (seed 002
//!   Eqs. 25-28) and IQN-ILS.
//!
//! Windows, interface maps, Algorithm 1 and Algorithm 2 arrive with issues 4 and 5.

pub mod relaxation;
