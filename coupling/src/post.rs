//! Post-processing of a coupled solution: K_I, K_II and J of a crack tip inside a PD
//! window by the interaction integral ([`pdbem_bem::post::sif::interaction_integral`]) on
//! a circle of BEM interior points around the window ([`window_tip_sif`]).
//!
//! The circle encloses the window (radius at least [`WindowContour::min_factor`] times the
//! largest tip-to-corner distance) and keeps clear of the body's boundary (radius at most
//! [`WindowContour::clearance_factor`] times the tip's distance to the outline and holes);
//! within these bounds it takes [`WindowContour::radius_factor`] times the tip-to-corner
//! distance, or the middle of the bounds when that is smaller.

use pdbem_bem::post::sif::interaction_integral;
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::V2;
use pdbem_geometry::polygon_distance;

use crate::error::CouplingError;
use crate::iteration::{CoupledProblem, CoupledSolution};

/// The contour of [`window_tip_sif`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowContour {
    /// Points on the circle.
    pub points: usize,
    /// Smallest radius over the largest tip-to-corner distance of the window.
    pub min_factor: f64,
    /// Largest radius over the tip's distance to the outline and holes.
    pub clearance_factor: f64,
    /// Preferred radius over the largest tip-to-corner distance.
    pub radius_factor: f64,
}

impl Default for WindowContour {
    /// 64 points, radius 1.25 times the tip-to-corner distance, between 1.1 times it and
    /// 0.9 times the boundary clearance.
    fn default() -> Self {
        Self {
            points: 64,
            min_factor: 1.1,
            clearance_factor: 0.9,
            radius_factor: 1.25,
        }
    }
}

/// SIFs of a tip inside a window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowTipSif {
    /// K_I (Pa sqrt(m)).
    pub k1: f64,
    /// K_II (Pa sqrt(m)).
    pub k2: f64,
    /// J (N/m).
    pub j: f64,
    /// Radius of the contour (m).
    pub radius: f64,
}

/// Interaction-integral SIFs of the tip at `tip` (unit crack direction `direction`,
/// pointing out of the crack) inside window `window` of `pb`, on a circle around the
/// window of BEM interior points of `solution`. `boundaries` are the closed polygons of
/// the body's outline and holes the circle keeps clear of. An error
/// ([`CouplingError::NoSifContour`], with the radii and the largest window that fits)
/// when no circle encloses the window within the clearance, as when a window over a deep
/// edge crack reaches most of the way across the ligament.
pub fn window_tip_sif(
    pb: &CoupledProblem,
    solution: &CoupledSolution,
    window: usize,
    tip: V2,
    direction: V2,
    boundaries: &[Vec<V2>],
    contour: &WindowContour,
) -> Result<WindowTipSif, CouplingError> {
    let radius = contour_radius(pb, window, tip, boundaries, contour)?;
    let ev = FieldEvaluator::new(&pb.mesh, &pb.material, &solution.solution, pb.background);
    let h = pb.windows[window].window.spec.dx;
    let (k1, k2, j) = interaction_integral(&ev, tip, direction, radius, contour.points, h, None);
    Ok(WindowTipSif { k1, k2, j, radius })
}

/// The radius of the contour of [`window_tip_sif`] (see the module docs), or why there
/// is none.
pub fn contour_radius(
    pb: &CoupledProblem,
    window: usize,
    tip: V2,
    boundaries: &[Vec<V2>],
    contour: &WindowContour,
) -> Result<f64, CouplingError> {
    let half_diag = pb.windows[window]
        .window
        .corners()
        .iter()
        .map(|c| (c - tip).norm())
        .fold(0.0, f64::max);
    let mut clearance = f64::INFINITY;
    for b in boundaries {
        clearance = clearance.min(polygon_distance(&tip, b));
    }
    let r_min = contour.min_factor * half_diag;
    let r_max = contour.clearance_factor * clearance;
    if r_min >= r_max {
        let corner_limit = r_max / contour.min_factor;
        return Err(CouplingError::NoSifContour {
            window,
            corner_distance: half_diag,
            min_radius: r_min,
            max_radius: r_max,
            clearance,
            min_factor: contour.min_factor,
            clearance_factor: contour.clearance_factor,
            corner_limit,
            side_limit: std::f64::consts::SQRT_2 * corner_limit,
        });
    }
    Ok((contour.radius_factor * half_diag).min(0.5 * (r_min + r_max).max(r_min)))
}
