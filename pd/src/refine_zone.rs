//! Refinement zones of a PD grid ([`crate::mixed`]): the square zones whose coarse cells
//! are split into children of half (or a quarter of) the spacing.

use serde::{Deserialize, Serialize};

use crate::error::PdError;
use crate::geometry::P2;

/// Largest refinement level of a zone.
pub const MAX_LEVELS: u32 = 2;

/// A square zone (axis-aligned) whose coarse cells are split `levels` times.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefineZone {
    /// Centre (m).
    pub centre: P2,
    /// Half the side (m): coarse cells whose centres are within this Chebyshev distance
    /// of the centre are split.
    pub half_size: f64,
    /// Splits per coarse cell (1: 4 children, 2: 16), at most [`MAX_LEVELS`].
    pub levels: u32,
}

impl RefineZone {
    /// Whether the coarse cell centred at `x` is split by this zone.
    pub fn contains(&self, x: P2) -> bool {
        let magnitude = [x[0], x[1], self.centre[0], self.centre[1]]
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        let tol = pdbem_geometry::tie_band(self.half_size, magnitude);
        (x[0] - self.centre[0]).abs() <= self.half_size + tol
            && (x[1] - self.centre[1]).abs() <= self.half_size + tol
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
