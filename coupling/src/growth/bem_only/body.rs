//! The body of a BEM-only run ([`BemOnlyBody`]): what every re-meshed geometry shares,
//! and the engine's error.

use pdbem_bem::mesh::{CrackSpec, LoopSpec, SizeField};
use pdbem_bem::post::Background;
use pdbem_bem::{Material, SolveParams};

use super::sizing::TipSizing;
use crate::error::CouplingError;

/// The body of a BEM-only run: what every re-meshed geometry shares.
#[derive(Debug, Clone)]
pub struct BemOnlyBody {
    /// Outline (split at its groups) and hole loops with their element sizes.
    pub loops: Vec<LoopSpec>,
    /// The initial cracks in front order: name, polyline, faces, element size and the
    /// tip refinement of the initial mesh.
    pub cracks: Vec<CrackSpec>,
    /// Material.
    pub material: Material,
    /// Solver parameters.
    pub params: SolveParams,
    /// Remote stress at unit load (infinite plates; zero otherwise).
    pub background: Background,
    /// Crack-opening fit range as a fraction of the tip length scale.
    pub fit_fraction: f64,
    /// Local-feature sizing of every geometry ([`sizing`]); `None` (cracks with sizes
    /// fixed by the scene): each crack at its element size, with the initial tip
    /// refinement and, once grown, a uniform zone of da/8 within da of every tip.
    pub sizing: Option<TipSizing>,
    /// Sources of the size field other than the tips (features, outline coarsening),
    /// used with `sizing`.
    pub field: SizeField,
    /// Cracks whose K is the interaction integral's, by name: those with a condition on
    /// one face alone, where the crack-opening fit is biased (its K_II 19 % low on a
    /// Griffith crack with one face pressed; `pdbem::run_bem::level::tip_result`).
    pub integral_cracks: Vec<String>,
    /// The integral's contour: radius as a fraction of the tip length scale (at most the
    /// fit range, the straight run behind a grown tip) and points.
    pub contour: (f64, usize),
}

/// A BEM-only growth error with `message`.
pub(crate) fn fail(message: String) -> CouplingError {
    CouplingError::Growth {
        mode: "BEM-only",
        message,
    }
}
