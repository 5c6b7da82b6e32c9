//! Refinement zones of a PD grid ([`crate::mixed`]): the square zones whose coarse cells
//! are split into children of half (or a quarter of) the spacing. A zone's sides run
//! along the grid's lattice axes ([`crate::problem::PdProblem::grid_angle`]), so on a
//! grid turned with an inclined crack it splits the same cells as on the unturned grid.

use serde::{Deserialize, Serialize};

use crate::error::PdError;
use crate::geometry::P2;

/// Largest refinement level of a zone.
pub const MAX_LEVELS: u32 = 2;

/// A square zone, its sides along the grid's lattice axes, whose coarse cells are split
/// `levels` times.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefineZone {
    /// Centre (m).
    pub centre: P2,
    /// Half the side (m): coarse cells whose centres are within this Chebyshev distance
    /// of the centre, measured along the lattice axes, are split.
    pub half_size: f64,
    /// Splits per coarse cell (1: 4 children, 2: 16), at most [`MAX_LEVELS`].
    pub levels: u32,
}

impl RefineZone {
    /// Whether the coarse cell centred at `x` is split by this zone on a grid whose
    /// lattice axes are `axes` (`(cos, sin)` of the grid angle,
    /// [`crate::surface::lattice_axes`]: exact at multiples of 90 degrees, so an
    /// axis-aligned or quarter-turned grid measures the global components to the bit).
    pub fn contains(&self, x: P2, (c, s): (f64, f64)) -> bool {
        let magnitude = [x[0], x[1], self.centre[0], self.centre[1]]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let tol = pdbem_geometry::tie_band(self.half_size, magnitude);
        let d = [x[0] - self.centre[0], x[1] - self.centre[1]];
        let (u, v) = (c * d[0] + s * d[1], c * d[1] - s * d[0]);
        u.abs() <= self.half_size + tol && v.abs() <= self.half_size + tol
    }
}

/// Checks the zone's own values; `k` is its index in `refine_zones`.
pub fn check_zone(k: usize, z: &RefineZone) -> Result<(), PdError> {
    let f = format!("refine_zones[{k}]");
    if !(z.centre[0].is_finite() && z.centre[1].is_finite()) {
        return Err(PdError::invalid(
            format!("{f}.centre"),
            format!("non-finite point {:?}", z.centre),
        ));
    }
    if !(z.half_size.is_finite() && z.half_size > 0.0) {
        return Err(PdError::invalid(
            format!("{f}.half_size"),
            format!("must be positive and finite, got {}", z.half_size),
        ));
    }
    if !(1..=MAX_LEVELS).contains(&z.levels) {
        return Err(PdError::invalid(
            format!("{f}.levels"),
            format!(
                "must be 1 or 2 (4 or 16 children per cell), got {}",
                z.levels
            ),
        ));
    }
    Ok(())
}
