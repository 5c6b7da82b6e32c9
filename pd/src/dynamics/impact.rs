//! Region velocities of explicit dynamics ([`super`] module docs, "Region velocities";
//! the impact of seed 004 section 4.3): which free components of which points start
//! with, or keep, a velocity.

use serde::{Deserialize, Serialize};

use crate::error::PdError;
use crate::geometry::P2;
use crate::problem::Selection;

/// A velocity given to the nodes of a region at t = 0, optionally held ([`super`] module docs).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionVelocity {
    /// The nodes (by reference position; `NearPolyline` without a distance takes the
    /// horizon).
    pub region: Selection,
    /// Velocity (m/s).
    pub velocity: P2,
    /// Keep the velocity for the whole run (a prescribed velocity).
    pub hold: bool,
}

/// Initial velocities and held components of the points `pos` (horizon `delta`) under
/// `regions`; prescribed components (`fixed`) stay at rest. Errors when a velocity is
/// not finite or a region holds no point.
pub(crate) fn region_velocities(
    regions: &[RegionVelocity],
    pos: &[P2],
    fixed: &[[bool; 2]],
    delta: f64,
) -> Result<(Vec<P2>, Vec<[bool; 2]>), PdError> {
    let mut v = vec![[0.0; 2]; pos.len()];
    let mut held = vec![[false; 2]; pos.len()];
    for (k, r) in regions.iter().enumerate() {
        if !(r.velocity[0].is_finite() && r.velocity[1].is_finite()) {
            return Err(PdError::invalid(
                format!("velocities[{k}].velocity"),
                format!("must be finite, got {:?}", r.velocity),
            ));
        }
        let mut any = false;
        for (i, x) in pos.iter().enumerate() {
            if !r.region.contains(*x, delta) {
                continue;
            }
            any = true;
            for c in 0..2 {
                if !fixed[i][c] {
                    v[i][c] = r.velocity[c];
                    held[i][c] = r.hold;
                }
            }
        }
        if !any {
            return Err(PdError::invalid(
                format!("velocities[{k}].region"),
                "holds no node of the body",
            ));
        }
    }
    Ok((v, held))
}
