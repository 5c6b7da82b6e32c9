//! Planar geometry shared by every pdbem crate (the BEM and PD solvers, the coupling and
//! the application), so that each rule is written once.
//!
//! Points are `nalgebra::Vector2<f64>` ([`P2`]). Polygons are slices of points,
//! implicitly closed (the last point connects to the first). Orientation follows
//! DESIGN.md: outer boundaries counter-clockwise (positive signed area), holes
//! clockwise.
//!
//! Map (everything is re-exported at the crate root):
//! - this file: [`P2`], [`p2`], [`cross`], [`direction`], [`rotate`], [`scale_of`],
//!   [`grid_centres`], [`EPS_REL`], [`tie_band`];
//! - [`polygon`]: signed area, centroid and orientation, bounding box, scale, containment,
//!   distance to the boundary, self-intersection;
//! - [`segment`]: projection of a point and distance to a segment, "on the segment",
//!   segment-segment intersection (tolerant, and exact for bond cutting);
//! - [`polyline`]: length, point at an arc length, arc length of the nearest point,
//!   distance, first crossing with a polygon;
//! - [`ray`]: ray casts against a segment, a polygon and a circle;
//! - [`circle`]: circles as polygons;
//! - [`shape`]: exact hole shapes (circle or polygon) and their queries.
//!
//! Tolerances are relative to the size of the inputs ([`EPS_REL`] times the largest
//! coordinate magnitude involved) unless a function says otherwise. Where two callers
//! relied on slightly different arithmetic (`hypot` against `sqrt` of the squared norm),
//! both variants are kept under distinct names (`*_hypot`) so that no result changes.

pub mod circle;
pub mod polygon;
pub mod polyline;
pub mod ray;
pub mod segment;
pub mod shape;

pub use circle::circle_polygon;
pub use polygon::{
    bounding_box, is_ccw, on_polygon_boundary, point_in_polygon, polygon_centroid,
    polygon_distance, polygon_distance_hypot, polygon_self_intersection, signed_area,
};
pub use polyline::{
    point_at, polyline_distance_hypot, polyline_length, polyline_length_hypot,
    polyline_polygon_hit, polyline_project,
};
pub use ray::{ray_circle, ray_polygon, ray_segment};
pub use segment::{
    on_segment, point_segment_distance, point_segment_distance_hypot, point_segment_projection,
    segment_intersection, segments_intersect, segments_intersect_exact, SegmentHit,
};
pub use shape::{segment_segment_distance, HoleShape, CIRCLE_POINTS};

use nalgebra::Vector2;

/// A 2-D point or vector (m).
pub type P2 = Vector2<f64>;

/// Relative tolerance for "on the segment" and parallelism tests.
pub const EPS_REL: f64 = 1e-10;

/// Half-width of the band in which a lattice test counts a tie (a cell centre on a
/// zone's edge, a bond through an element's end point): `1e-9` of the test's `length`,
/// or the round-off of coordinates of size `magnitude` where that is larger. Positions
/// are rounded to their magnitude (a body placed at 1e7 m carries them to 1.9e-9 m), so a
/// band of 1e-9 of a 0.1 m cell there decided ties at random.
pub fn tie_band(length: f64, magnitude: f64) -> f64 {
    (1e-9 * length).max(64.0 * f64::EPSILON * magnitude)
}

/// Builds a point from a `(x, y)` tuple, as scenes store them.
pub fn p2(t: (f64, f64)) -> P2 {
    P2::new(t.0, t.1)
}

/// Length scale of a point set: the largest |coordinate| (at least 1e-300),
/// used to turn [`EPS_REL`] into an absolute tolerance.
pub fn scale_of(pts: &[P2]) -> f64 {
    pts.iter()
        .map(|p| p.x.abs().max(p.y.abs()))
        .fold(1e-300, f64::max)
}

/// The centres of an `n` x `n` grid of equal cells over the box `lo`-`hi`, row by row
/// from `lo` (sampling points for field snapshots).
pub fn grid_centres(lo: &P2, hi: &P2, n: usize) -> Vec<P2> {
    (0..n * n)
        .map(|k| {
            let (i, j) = ((k % n) as f64 + 0.5, (k / n) as f64 + 0.5);
            P2::new(
                lo.x + (hi.x - lo.x) * i / n as f64,
                lo.y + (hi.y - lo.y) * j / n as f64,
            )
        })
        .collect()
}

/// 2-D cross product `a.x b.y - a.y b.x`.
pub fn cross(a: &P2, b: &P2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Unit vector at `angle_deg` degrees counter-clockwise from the x axis.
pub fn direction(angle_deg: f64) -> P2 {
    let t = angle_deg.to_radians();
    P2::new(t.cos(), t.sin())
}

/// `p` rotated by `angle` (radians, counter-clockwise) about the origin.
#[inline]
pub fn rotate(p: &P2, angle: f64) -> P2 {
    let (s, c) = angle.sin_cos();
    P2::new(c * p.x - s * p.y, s * p.x + c * p.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_direction_and_rotation() {
        let x = P2::new(1.0, 0.0);
        let y = P2::new(0.0, 1.0);
        assert_eq!(cross(&x, &y), 1.0);
        assert_eq!(cross(&y, &x), -1.0);
        assert!((direction(90.0) - y).norm() < 1e-15);
        assert!((rotate(&x, std::f64::consts::FRAC_PI_2) - y).norm() < 1e-15);
        assert_eq!(p2((1.0, 2.0)), P2::new(1.0, 2.0));
    }

    #[test]
    fn grid_centres_are_cell_centres_row_by_row() {
        let g = grid_centres(&P2::new(0.0, 0.0), &P2::new(2.0, 4.0), 2);
        assert_eq!(
            g,
            vec![
                P2::new(0.5, 1.0),
                P2::new(1.5, 1.0),
                P2::new(0.5, 3.0),
                P2::new(1.5, 3.0)
            ]
        );
    }
}
