//! Exact hole shapes ([`HoleShape`]: circle or polygon) and the queries scenes, meshing
//! and growth make of them: boundary polygon, distance, containment, clearance of a
//! segment, size.

use crate::{
    bounding_box, circle_polygon, point_in_polygon, point_segment_distance, polygon_distance,
    segments_intersect, signed_area, P2,
};

/// Points of a circle when a polygon is needed (plots, overlap tests).
pub const CIRCLE_POINTS: usize = 256;

/// A hole, exact.
#[derive(Debug, Clone, PartialEq)]
pub enum HoleShape {
    /// Circle with centre and radius (m).
    Circle {
        /// Centre (m).
        center: P2,
        /// Radius (m).
        radius: f64,
    },
    /// Polygon (m).
    Polygon(Vec<P2>),
}

impl HoleShape {
    /// Points of the hole boundary, clockwise (circles with [`CIRCLE_POINTS`]).
    pub fn polygon(&self) -> Vec<P2> {
        match self {
            HoleShape::Circle { center, radius } => {
                circle_polygon(center, *radius, CIRCLE_POINTS, true)
            }
            HoleShape::Polygon(p) => {
                let mut p = p.clone();
                if signed_area(&p) > 0.0 {
                    p.reverse();
                }
                p
            }
        }
    }

    /// Distance from `p` to the hole boundary (m).
    pub fn boundary_distance(&self, p: &P2) -> f64 {
        match self {
            HoleShape::Circle { center, radius } => ((p - center).norm() - radius).abs(),
            HoleShape::Polygon(pts) => polygon_distance(p, pts),
        }
    }

    /// True when `p` is strictly inside the hole (more than `tol` from its boundary).
    pub fn contains(&self, p: &P2, tol: f64) -> bool {
        let inside = match self {
            HoleShape::Circle { center, radius } => (p - center).norm() < *radius,
            HoleShape::Polygon(pts) => point_in_polygon(p, pts),
        };
        inside && self.boundary_distance(p) > tol
    }

    /// Smallest distance from the segment `a`-`b` to the hole's inside: <= 0
    /// means the segment reaches into or touches the hole (circles exact,
    /// polygons through their edges).
    pub fn segment_clearance(&self, a: &P2, b: &P2) -> f64 {
        match self {
            HoleShape::Circle { center, radius } => point_segment_distance(center, a, b) - radius,
            HoleShape::Polygon(pts) => {
                if point_in_polygon(a, pts) || point_in_polygon(b, pts) {
                    return -1.0;
                }
                let n = pts.len();
                (0..n)
                    .map(|i| segment_segment_distance(a, b, &pts[i], &pts[(i + 1) % n]))
                    .fold(f64::INFINITY, f64::min)
            }
        }
    }

    /// A length scale of the hole (m): radius, or half the bounding-box diagonal.
    pub fn size(&self) -> f64 {
        match self {
            HoleShape::Circle { radius, .. } => *radius,
            HoleShape::Polygon(p) => {
                let (lo, hi) = bounding_box(p);
                0.5 * (hi - lo).norm()
            }
        }
    }
}

/// Distance between two segments (0 when they intersect).
pub fn segment_segment_distance(a1: &P2, a2: &P2, b1: &P2, b2: &P2) -> f64 {
    if segments_intersect(a1, a2, b1, b2) {
        return 0.0;
    }
    [
        point_segment_distance(a1, b1, b2),
        point_segment_distance(a2, b1, b2),
        point_segment_distance(b1, a1, a2),
        point_segment_distance(b2, a1, a2),
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min)
}
