//! Validation of `pd.refine_zones` (fixed zones of finer cells on a stand-alone PD grid,
//! `pdbem_pd::mixed`).

use super::Checker;
use crate::scene::{PdSolver, PdTraction, Scene};

/// Most zones a scene may give: each node of the grid is tested against every zone.
pub const MAX_ZONES: usize = 100;

/// `pd.refine_zones`: stand-alone PD only (PD-BEM windows refine with `coupling.refine`),
/// not beside `pd.refinement` (the adaptive particles), not under explicit dynamics or
/// transfer-function tractions (both need a uniform grid, `pdbem_pd::problem`); each zone
/// a finite centre, a positive half side and 1 or 2 levels. A zone that holds no cell
/// centre of the grid, or covers a pin of a pure-traction scene, is refused when the
/// problem is built (`crate::setup::pd`), which `pdbem check` does.
pub(super) fn check(c: &mut Checker, scene: &Scene, pd: &crate::scene::PdSettings) {
    let zones = &pd.refine_zones;
    if zones.is_empty() {
        return;
    }
    if scene.coupling.is_some() || scene.growth.is_some() {
        c.fail_at(
            "pd.refine_zones",
            "zones refine a stand-alone PD grid; PD-BEM windows refine around the tips they serve with `coupling.refine`: drop `coupling`/`growth` or the field",
        );
    }
    if pd.refinement.is_some() {
        c.fail_at(
            "pd.refine_zones",
            "give `pd.refinement` (seed 004's adaptive particles) or `pd.refine_zones` (fixed zones of finer cells on the grid), not both",
        );
    }
    if matches!(pd.solver, PdSolver::Explicit(_)) {
        c.fail_at(
            "pd.refine_zones",
            "explicit dynamics steps a uniform grid (or `pd.refinement`'s particles): drop the zones or choose Adr, Implicit or Switching",
        );
    }
    if pd.traction == PdTraction::TransferFunction {
        c.fail_at(
            "pd.traction",
            "the transfer functions spread tractions over a uniform grid: use BodyForceLayer with `pd.refine_zones`",
        );
    }
    if zones.len() > MAX_ZONES {
        c.fail(
            "pd.refine_zones",
            zones.len(),
            format!("at most {MAX_ZONES} zones (every node is tested against each)"),
        );
    }
    for (i, z) in zones.iter().enumerate() {
        let path = format!("pd.refine_zones.{i}");
        c.finite(&format!("{path}.centre"), z.centre.0);
        c.finite(&format!("{path}.centre"), z.centre.1);
        c.positive(&format!("{path}.half_size"), z.half_size, "zone half side");
        if !(1..=pdbem_pd::mixed::MAX_LEVELS).contains(&z.levels) {
            c.fail(
                format!("{path}.levels"),
                z.levels,
                "splits per cell must be 1 (4 children, dx / 2) or 2 (16 children, dx / 4)",
            );
        }
    }
}
