//! Closed polygons: signed area and orientation, bounding box, length scale, point
//! containment, distance to the boundary and self-intersection.

use crate::segment::{point_segment_distance, point_segment_distance_hypot, segment_intersection};
use crate::{cross, SegmentHit, P2};

/// Signed area of a closed polygon (shoelace formula); positive when counter-clockwise.
pub fn signed_area(pts: &[P2]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|i| cross(&pts[i], &pts[(i + 1) % n]))
        .sum::<f64>()
        * 0.5
}

/// Area centroid of a simple closed polygon of non-zero area,
/// $c = \frac{1}{6A}\sum_i (p_i + p_{i+1})\,(p_i \times p_{i+1})$; `None` for a
/// polygon of (numerically) zero area.
pub fn polygon_centroid(pts: &[P2]) -> Option<P2> {
    let a = signed_area(pts);
    let n = pts.len();
    let scale = bounding_box(pts);
    if n < 3 || a.abs() <= 1e-14 * (scale.1 - scale.0).norm_squared() {
        return None;
    }
    let mut c = P2::zeros();
    for i in 0..n {
        let (p, q) = (pts[i], pts[(i + 1) % n]);
        c += (p + q) * cross(&p, &q);
    }
    Some(c / (6.0 * a))
}

/// True when the polygon runs counter-clockwise (positive signed area).
pub fn is_ccw(pts: &[P2]) -> bool {
    signed_area(pts) > 0.0
}

/// Axis-aligned bounding box `(min, max)` of a non-empty point set.
pub fn bounding_box(pts: &[P2]) -> (P2, P2) {
    let mut lo = P2::new(f64::INFINITY, f64::INFINITY);
    let mut hi = P2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in pts {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    (lo, hi)
}

/// Smallest distance from `p` to the edges of a closed polygon
/// ([`point_segment_distance`] per edge; infinite for an empty polygon).
pub fn polygon_distance(p: &P2, pts: &[P2]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|i| point_segment_distance(p, &pts[i], &pts[(i + 1) % n]))
        .fold(f64::INFINITY, f64::min)
}

/// [`polygon_distance`] with the arithmetic of [`point_segment_distance_hypot`]
/// (the PD grid and problem setup).
pub fn polygon_distance_hypot(p: &P2, pts: &[P2]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|i| point_segment_distance_hypot(p, &pts[i], &pts[(i + 1) % n]))
        .fold(f64::INFINITY, f64::min)
}

/// True when `p` lies within `tol` of the polygon's edges.
pub fn on_polygon_boundary(p: &P2, pts: &[P2], tol: f64) -> bool {
    polygon_distance(p, pts) <= tol
}

/// Point-in-polygon test by ray casting (even-odd rule, any orientation). Points exactly
/// on an edge may go either way; combine with [`on_polygon_boundary`] when it matters.
/// An empty polygon contains nothing.
pub fn point_in_polygon(p: &P2, pts: &[P2]) -> bool {
    let n = pts.len();
    let mut inside = false;
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (a, b) = (&pts[i], &pts[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x_cross = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x_cross {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// First pair of non-adjacent edges `(i, j)` of a closed polygon that touch or
/// cross, or a pair of adjacent edges that fold back over each other; `None`
/// for a simple polygon. Edge `i` runs from point `i` to point `i+1`.
pub fn polygon_self_intersection(pts: &[P2]) -> Option<(usize, usize)> {
    let n = pts.len();
    for i in 0..n {
        let (a1, a2) = (&pts[i], &pts[(i + 1) % n]);
        for j in (i + 1)..n {
            let (b1, b2) = (&pts[j], &pts[(j + 1) % n]);
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            match segment_intersection(a1, a2, b1, b2) {
                SegmentHit::None => {}
                SegmentHit::Overlap => return Some((i, j)),
                SegmentHit::Point(_) if !adjacent => return Some((i, j)),
                SegmentHit::Point(_) => {}
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<P2> {
        vec![
            P2::new(0.0, 0.0),
            P2::new(1.0, 0.0),
            P2::new(1.0, 1.0),
            P2::new(0.0, 1.0),
        ]
    }

    #[test]
    fn unit_square_area_and_orientation() {
        let s = square();
        assert!((signed_area(&s) - 1.0).abs() < 1e-15);
        assert!(is_ccw(&s));
        let r: Vec<P2> = s.iter().rev().copied().collect();
        assert!((signed_area(&r) + 1.0).abs() < 1e-15);
        assert!(!is_ccw(&r));
        assert_eq!(signed_area(&[]), 0.0);
    }

    #[test]
    fn centroid_of_an_l_shape() {
        // Unit squares at (0,0), (1,0), (0,1): centroid (5/6, 5/6), either orientation.
        let l = vec![
            P2::new(0.0, 0.0),
            P2::new(2.0, 0.0),
            P2::new(2.0, 1.0),
            P2::new(1.0, 1.0),
            P2::new(1.0, 2.0),
            P2::new(0.0, 2.0),
        ];
        let c = polygon_centroid(&l).unwrap();
        assert!((c - P2::new(5.0 / 6.0, 5.0 / 6.0)).norm() < 1e-15);
        let r: Vec<P2> = l.iter().rev().copied().collect();
        assert!((polygon_centroid(&r).unwrap() - c).norm() < 1e-15);
        assert!(polygon_centroid(&[P2::new(0.0, 0.0), P2::new(1.0, 0.0)]).is_none());
    }

    #[test]
    fn point_in_square() {
        let s = square();
        assert!(point_in_polygon(&P2::new(0.5, 0.5), &s));
        assert!(!point_in_polygon(&P2::new(1.5, 0.5), &s));
        assert!(!point_in_polygon(&P2::new(0.5, -0.1), &s));
        assert!(on_polygon_boundary(&P2::new(0.5, 1.0), &s, 1e-12));
        assert!(!on_polygon_boundary(&P2::new(0.5, 0.5), &s, 1e-12));
        // Clockwise: same answer.
        let r: Vec<P2> = s.iter().rev().copied().collect();
        assert!(point_in_polygon(&P2::new(0.5, 0.5), &r));
        assert!(!point_in_polygon(&P2::new(0.5, 0.5), &[]));
    }

    #[test]
    fn point_in_concave_polygon() {
        // L shape: the notch (1.5, 1.5) is outside.
        let l = vec![
            P2::new(0.0, 0.0),
            P2::new(2.0, 0.0),
            P2::new(2.0, 1.0),
            P2::new(1.0, 1.0),
            P2::new(1.0, 2.0),
            P2::new(0.0, 2.0),
        ];
        assert!(point_in_polygon(&P2::new(0.5, 1.5), &l));
        assert!(point_in_polygon(&P2::new(1.5, 0.5), &l));
        assert!(!point_in_polygon(&P2::new(1.5, 1.5), &l));
        assert!((signed_area(&l) - 3.0).abs() < 1e-14);
    }

    #[test]
    fn bow_tie_self_intersects_square_does_not() {
        assert_eq!(polygon_self_intersection(&square()), None);
        let bow = vec![
            P2::new(0.0, 0.0),
            P2::new(1.0, 1.0),
            P2::new(1.0, 0.0),
            P2::new(0.0, 1.0),
        ];
        assert!(polygon_self_intersection(&bow).is_some());
    }

    #[test]
    fn folded_back_edge_self_intersects() {
        let fold = vec![P2::new(0.0, 0.0), P2::new(2.0, 0.0), P2::new(1.0, 0.0)];
        assert!(polygon_self_intersection(&fold).is_some());
    }

    #[test]
    fn distance_to_the_boundary_both_arithmetics() {
        let s = square();
        assert!((polygon_distance(&P2::new(0.5, 0.25), &s) - 0.25).abs() < 1e-15);
        assert!((polygon_distance_hypot(&P2::new(0.5, 0.2), &s) - 0.2).abs() < 1e-15);
        // Outside, nearest to a corner.
        let d = polygon_distance(&P2::new(2.0, 2.0), &s);
        assert!((d - 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(polygon_distance(&P2::zeros(), &[]), f64::INFINITY);
    }

    #[test]
    fn box_and_scale() {
        let pts = [P2::new(-1.0, 2.0), P2::new(3.0, -4.0), P2::new(0.5, 0.5)];
        let (lo, hi) = bounding_box(&pts);
        assert_eq!(lo, P2::new(-1.0, -4.0));
        assert_eq!(hi, P2::new(3.0, 2.0));
        assert_eq!(crate::scale_of(&pts), 4.0);
        assert_eq!(crate::scale_of(&[]), 1e-300);
    }
}
