//! Validation of `coupling.refine` (refined PD windows, `pdbem_pd::mixed`).

use super::Checker;
use crate::scene::{GrowthMode, Placement, Scene};

/// `coupling.refine`: a zone of positive size with 1 or 2 levels, two horizons inside an
/// `AtTips` window (whose tip is its centre; other placements are checked when the
/// windows are built); in PD-BEM growth, a move distance that keeps the tip in the fine
/// cells from one window to the next (`pdbem_coupling::growth::fine_zone`).
pub(super) fn check(
    c: &mut Checker,
    scene: &Scene,
    co: &crate::scene::Coupling,
    r: &crate::scene::WindowRefine,
) {
    if !(1..=2).contains(&r.levels) {
        c.fail(
            "coupling.refine.levels",
            r.levels,
            "splits per cell must be 1 (4 children) or 2 (16 children)",
        );
    }
    if !c.positive("coupling.refine.half_size", r.half_size, "zone half side") {
        return;
    }
    let m = scene
        .pd
        .as_ref()
        .map_or(crate::scene::pd::default_horizon_factor(), |p| {
            p.horizon_factor
        });
    let dx = co.dx();
    let max = 0.5 * co.side - 2.0 * m * dx - 0.5 * dx;
    let fits_window = r.half_size <= max + 1e-9 * dx;
    if co.placement == Placement::AtTips && !fits_window {
        c.fail(
            "coupling.refine.half_size",
            r.half_size,
            format!(
                "the zone must stay two horizons (2 m dx = {:.4} m) inside the window of side {}: half_size at most {:.4} m",
                2.0 * m * dx,
                co.side,
                max.max(0.0)
            ),
        );
    }
    let growth = scene
        .growth
        .as_ref()
        .filter(|g| g.mode == GrowthMode::PdBem);
    let levels_ok = (1..=2).contains(&r.levels);
    if let (Some(g), Placement::AtTips, true) = (growth, &co.placement, fits_window && levels_ok) {
        let fit = pdbem_coupling::growth::fine_zone::max_move_distance(
            co.n,
            dx,
            m * dx,
            r.half_size,
            r.levels,
        );
        let d = g.move_distance.unwrap_or(0.25 * co.side);
        if d > fit {
            c.fail(
                "growth.move_distance",
                d,
                format!(
                    "a refined window's crack grows only through its fine cells and the window moves before the tip leaves them; a move of {d} m would leave the new window's pre-crack (one dx short of the tip) outside its fine cells (coupling.refine: half_size {}, levels {}): at most {fit:.4} m, or a larger half_size or window",
                    r.half_size, r.levels
                ),
            );
        }
    }
}
