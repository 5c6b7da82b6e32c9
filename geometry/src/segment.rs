//! Segments: projection of a point, distance to a segment, "on the segment", and
//! segment-segment intersection (with a relative tolerance, and exact for PD bond
//! cutting).

use crate::{cross, scale_of, EPS_REL, P2};

/// Distance from `p` to the segment `a`-`b` (a point when `a == b`).
pub fn point_segment_distance(p: &P2, a: &P2, b: &P2) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 == 0.0 {
        return (p - a).norm();
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

/// Distance from `p` to the segment `a`-`b` and the parameter `t` in [0, 1] of the
/// nearest point `a + t (b - a)` (`t = 0` when `a == b`).
pub fn point_segment_projection(p: &P2, a: &P2, b: &P2) -> (f64, f64) {
    let d = b - a;
    let l2 = d.norm_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(&d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((a + t * d - p).norm(), t)
}

/// Distance from `p` to the segment `a`-`b` measured as `hypot` of `(p - a) - t (b - a)`:
/// the arithmetic of the PD setup (grid, pre-crack cutting, boundary layers), which may
/// differ from [`point_segment_distance`] in the last bit.
pub fn point_segment_distance_hypot(p: &P2, a: &P2, b: &P2) -> f64 {
    let ab = b - a;
    let ap = p - a;
    let l2 = ab.x * ab.x + ab.y * ab.y;
    let t = if l2 > 0.0 {
        ((ap.x * ab.x + ap.y * ab.y) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (ap.x - t * ab.x).hypot(ap.y - t * ab.y)
}

/// True when `q` projects inside the segment `a`-`b` (parameter in [0, 1]) and lies within
/// `1e-9 |b - a|` of it. A degenerate segment (`a == b`) contains nothing.
pub fn on_segment(q: &P2, a: &P2, b: &P2) -> bool {
    let d = b - a;
    let t = (q - a).dot(&d) / d.norm_squared();
    (0.0..=1.0).contains(&t) && (a + t * d - q).norm() <= 1e-9 * d.norm()
}

/// How two segments meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SegmentHit {
    /// No common point.
    None,
    /// One common point (possibly an end point of either segment).
    Point(P2),
    /// Collinear segments sharing a piece of positive length.
    Overlap,
}

/// Intersection of segments `a1`-`a2` and `b1`-`b2`, end points included, with a
/// tolerance relative to the coordinates' magnitude ([`EPS_REL`]).
pub fn segment_intersection(a1: &P2, a2: &P2, b1: &P2, b2: &P2) -> SegmentHit {
    let tol = EPS_REL * scale_of(&[*a1, *a2, *b1, *b2]);
    let r = a2 - a1;
    let s = b2 - b1;
    let denom = cross(&r, &s);
    let qp = b1 - a1;
    let scale = r.norm() * s.norm();
    if denom.abs() <= EPS_REL * scale.max(1e-300) {
        return collinear_hit(a1, a2, b1, b2, tol);
    }
    let t = cross(&qp, &s) / denom;
    let u = cross(&qp, &r) / denom;
    let tt = tol / r.norm().max(1e-300);
    let tu = tol / s.norm().max(1e-300);
    if t >= -tt && t <= 1.0 + tt && u >= -tu && u <= 1.0 + tu {
        SegmentHit::Point(a1 + r * t.clamp(0.0, 1.0))
    } else {
        SegmentHit::None
    }
}

/// Parallel case of [`segment_intersection`].
fn collinear_hit(a1: &P2, a2: &P2, b1: &P2, b2: &P2, tol: f64) -> SegmentHit {
    let r = a2 - a1;
    let len = r.norm();
    if len == 0.0 {
        return if point_segment_distance(a1, b1, b2) <= tol {
            SegmentHit::Point(*a1)
        } else {
            SegmentHit::None
        };
    }
    // Distance of b1 from the line of a: parallel but apart.
    if cross(&r, &(b1 - a1)).abs() / len > tol {
        return SegmentHit::None;
    }
    let d = r / len;
    let (t0, t1) = {
        let u = (b1 - a1).dot(&d);
        let v = (b2 - a1).dot(&d);
        (u.min(v), u.max(v))
    };
    let lo = t0.max(0.0);
    let hi = t1.min(len);
    if hi - lo > tol {
        SegmentHit::Overlap
    } else if hi - lo >= -tol {
        SegmentHit::Point(a1 + d * lo)
    } else {
        SegmentHit::None
    }
}

/// True when the two segments have any common point ([`segment_intersection`], with its
/// relative tolerance).
pub fn segments_intersect(a1: &P2, a2: &P2, b1: &P2, b2: &P2) -> bool {
    segment_intersection(a1, a2, b1, b2) != SegmentHit::None
}

/// Whether the segments `p1`-`p2` and `q1`-`q2` intersect, by exact orientation signs (no
/// tolerance; touching counts): the predicate of PD bond cutting.
pub fn segments_intersect_exact(p1: &P2, p2: &P2, q1: &P2, q2: &P2) -> bool {
    let d1 = cross(&(q2 - q1), &(p1 - q1));
    let d2 = cross(&(q2 - q1), &(p2 - q1));
    let d3 = cross(&(p2 - p1), &(q1 - p1));
    let d4 = cross(&(p2 - p1), &(q2 - p1));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |a: &P2, b: &P2, c: &P2, d: f64| {
        d == 0.0
            && c.x >= a.x.min(b.x)
            && c.x <= a.x.max(b.x)
            && c.y >= a.y.min(b.y)
            && c.y <= a.y.max(b.y)
    };
    on(q1, q2, p1, d1) || on(q1, q2, p2, d2) || on(p1, p2, q1, d3) || on(p1, p2, q2, d4)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn x_axis() -> (P2, P2) {
        (P2::new(0.0, 0.0), P2::new(1.0, 0.0))
    }

    #[test]
    fn distance_inside_and_beyond_the_end_points() {
        let (a, b) = x_axis();
        let d = point_segment_distance(&P2::new(0.5, 1.0), &a, &b);
        assert!((d - 1.0).abs() < 1e-15);
        // Beyond b and before a: the distance to the end point.
        let d = point_segment_distance(&P2::new(2.0, 0.0), &a, &b);
        assert!((d - 1.0).abs() < 1e-15);
        let d = point_segment_distance(&P2::new(-3.0, 4.0), &a, &b);
        assert!((d - 5.0).abs() < 1e-15);
        let d = point_segment_distance_hypot(&P2::new(2.0, 1.0), &a, &b);
        assert!((d - 2f64.sqrt()).abs() < 1e-15);
        // Degenerate segment: distance to the point.
        assert_eq!(point_segment_distance(&P2::new(3.0, 4.0), &a, &a), 5.0);
        assert_eq!(
            point_segment_distance_hypot(&P2::new(3.0, 4.0), &a, &a),
            5.0
        );
    }

    #[test]
    fn projection_parameter_is_clamped() {
        let (a, b) = x_axis();
        let (d, t) = point_segment_projection(&P2::new(0.25, -2.0), &a, &b);
        assert_eq!((d, t), (2.0, 0.25));
        let (d, t) = point_segment_projection(&P2::new(4.0, 4.0), &a, &b);
        assert_eq!((d, t), (5.0, 1.0));
        let (d, t) = point_segment_projection(&P2::new(-1.0, 0.0), &a, &b);
        assert_eq!((d, t), (1.0, 0.0));
        assert_eq!(
            point_segment_projection(&P2::new(0.0, 2.0), &a, &a),
            (2.0, 0.0)
        );
    }

    #[test]
    fn on_segment_within_its_ends_only() {
        let (a, b) = x_axis();
        assert!(on_segment(&P2::new(0.5, 0.0), &a, &b));
        assert!(on_segment(&b, &a, &b));
        assert!(!on_segment(&P2::new(1.5, 0.0), &a, &b));
        assert!(!on_segment(&P2::new(0.5, 1e-6), &a, &b));
        assert!(!on_segment(&a, &a, &a));
    }

    #[test]
    fn crossing_segments_meet_at_centre() {
        let hit = segment_intersection(
            &P2::new(0.0, 0.0),
            &P2::new(2.0, 2.0),
            &P2::new(0.0, 2.0),
            &P2::new(2.0, 0.0),
        );
        match hit {
            SegmentHit::Point(p) => assert!((p - P2::new(1.0, 1.0)).norm() < 1e-14),
            other => panic!("expected a point, got {other:?}"),
        }
    }

    #[test]
    fn touching_parallel_and_disjoint_segments() {
        let o = P2::new(0.0, 0.0);
        let a = P2::new(1.0, 0.0);
        assert!(segments_intersect(&o, &a, &a, &P2::new(1.0, 1.0)));
        assert!(!segments_intersect(
            &o,
            &a,
            &P2::new(0.0, 1.0),
            &P2::new(1.0, 1.0)
        ));
        assert_eq!(
            segment_intersection(&o, &a, &P2::new(0.5, 0.0), &P2::new(2.0, 0.0)),
            SegmentHit::Overlap
        );
        assert!(!segments_intersect(
            &o,
            &a,
            &P2::new(1.5, 0.0),
            &P2::new(2.0, 0.0)
        ));
    }

    #[test]
    fn exact_crossing_segments() {
        let p = |x: f64, y: f64| P2::new(x, y);
        assert!(segments_intersect_exact(
            &p(0.0, 0.0),
            &p(1.0, 1.0),
            &p(0.0, 1.0),
            &p(1.0, 0.0)
        ));
        assert!(!segments_intersect_exact(
            &p(0.0, 0.0),
            &p(1.0, 0.0),
            &p(0.0, 1.0),
            &p(1.0, 1.0)
        ));
        // Touching at an end point counts.
        assert!(segments_intersect_exact(
            &p(0.0, 0.0),
            &p(1.0, 0.0),
            &p(1.0, 0.0),
            &p(1.0, 1.0)
        ));
        // No tolerance: a gap of 1e-15 is a miss (the tolerant test calls it a hit).
        let (a1, a2, b1, b2) = (p(0.0, 0.0), p(1.0, 0.0), p(1.0 + 1e-15, 0.0), p(2.0, 1.0));
        assert!(!segments_intersect_exact(&a1, &a2, &b1, &b2));
        assert!(segments_intersect(&a1, &a2, &b1, &b2));
    }
}
