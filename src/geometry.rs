//! Plane geometry helpers used by scene validation, plotting and the runner.
//!
//! Points are `nalgebra::Vector2<f64>` ([`P2`]). Polygons are slices of points,
//! implicitly closed (the last point connects to the first). Orientation follows
//! DESIGN.md: outer boundaries counter-clockwise (positive signed area), holes
//! clockwise.
//!
//! Entry points: [`signed_area`], [`is_ccw`], [`point_in_polygon`],
//! [`segments_intersect`], [`segment_intersection`], [`polygon_self_intersection`],
//! [`point_segment_distance`], [`polygon_distance`], [`circle_polygon`].
//!
//! Tolerances are relative to the size of the inputs: [`EPS_REL`] times the
//! largest coordinate magnitude involved.

use nalgebra::Vector2;

/// A 2-D point or vector (m).
pub type P2 = Vector2<f64>;

/// Relative tolerance for "on the segment" and parallelism tests.
pub const EPS_REL: f64 = 1e-10;

/// Builds a point from a `(x, y)` tuple, as scenes store them.
pub fn p2(t: (f64, f64)) -> P2 {
    P2::new(t.0, t.1)
}

/// 2-D cross product `a.x b.y - a.y b.x`.
pub fn cross(a: &P2, b: &P2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Signed area of a closed polygon (shoelace formula); positive when counter-clockwise.
pub fn signed_area(pts: &[P2]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|i| cross(&pts[i], &pts[(i + 1) % n]))
        .sum::<f64>()
        * 0.5
}

/// True when the polygon runs counter-clockwise (positive signed area).
pub fn is_ccw(pts: &[P2]) -> bool {
    signed_area(pts) > 0.0
}

/// Length scale of a point set: the largest |coordinate| (at least 1e-300),
/// used to turn [`EPS_REL`] into an absolute tolerance.
pub fn scale_of(pts: &[P2]) -> f64 {
    pts.iter()
        .map(|p| p.x.abs().max(p.y.abs()))
        .fold(1e-300, f64::max)
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

/// Distance from `p` to the segment `a`-`b`.
pub fn point_segment_distance(p: &P2, a: &P2, b: &P2) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 == 0.0 {
        return (p - a).norm();
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

/// Smallest distance from `p` to the edges of a closed polygon.
pub fn polygon_distance(p: &P2, pts: &[P2]) -> f64 {
    let n = pts.len();
    (0..n)
        .map(|i| point_segment_distance(p, &pts[i], &pts[(i + 1) % n]))
        .fold(f64::INFINITY, f64::min)
}

/// True when `p` lies within `tol` of the polygon's edges.
pub fn on_polygon_boundary(p: &P2, pts: &[P2], tol: f64) -> bool {
    polygon_distance(p, pts) <= tol
}

/// Point-in-polygon test by ray casting (even-odd rule). Points exactly on an
/// edge may go either way; combine with [`on_polygon_boundary`] when it matters.
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
/// tolerance relative to the coordinates' magnitude.
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

/// True when the two segments have any common point.
pub fn segments_intersect(a1: &P2, a2: &P2, b1: &P2, b2: &P2) -> bool {
    segment_intersection(a1, a2, b1, b2) != SegmentHit::None
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

/// First crossing between the open polyline `line` and the closed polygon
/// `poly`: `(segment index in line, edge index in poly, point)`.
pub fn polyline_polygon_hit(line: &[P2], poly: &[P2]) -> Option<(usize, usize, P2)> {
    let n = poly.len();
    for (i, w) in line.windows(2).enumerate() {
        for j in 0..n {
            match segment_intersection(&w[0], &w[1], &poly[j], &poly[(j + 1) % n]) {
                SegmentHit::None => {}
                SegmentHit::Point(p) => return Some((i, j, p)),
                SegmentHit::Overlap => return Some((i, j, w[0])),
            }
        }
    }
    None
}

/// Points of a circle split into `n` straight edges, clockwise when
/// `clockwise` (holes) and counter-clockwise otherwise, starting at angle 0.
pub fn circle_polygon(center: &P2, radius: f64, n: usize, clockwise: bool) -> Vec<P2> {
    let sign = if clockwise { -1.0 } else { 1.0 };
    (0..n)
        .map(|k| {
            let t = sign * 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            center + P2::new(t.cos(), t.sin()) * radius
        })
        .collect()
}

/// Total length of an open polyline.
pub fn polyline_length(pts: &[P2]) -> f64 {
    pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// Unit vector at `angle_deg` degrees counter-clockwise from the x axis.
pub fn direction(angle_deg: f64) -> P2 {
    let t = angle_deg.to_radians();
    P2::new(t.cos(), t.sin())
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
    }

    #[test]
    fn point_in_square() {
        let s = square();
        assert!(point_in_polygon(&P2::new(0.5, 0.5), &s));
        assert!(!point_in_polygon(&P2::new(1.5, 0.5), &s));
        assert!(!point_in_polygon(&P2::new(0.5, -0.1), &s));
        assert!(on_polygon_boundary(&P2::new(0.5, 1.0), &s, 1e-12));
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
        assert!(!point_in_polygon(&P2::new(1.5, 1.5), &l));
        assert!((signed_area(&l) - 3.0).abs() < 1e-14);
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
    fn distance_to_segment_and_polygon() {
        let d = point_segment_distance(&P2::new(0.5, 1.0), &P2::new(0.0, 0.0), &P2::new(1.0, 0.0));
        assert!((d - 1.0).abs() < 1e-15);
        let d = point_segment_distance(&P2::new(2.0, 0.0), &P2::new(0.0, 0.0), &P2::new(1.0, 0.0));
        assert!((d - 1.0).abs() < 1e-15);
        assert!((polygon_distance(&P2::new(0.5, 0.25), &square()) - 0.25).abs() < 1e-15);
    }

    #[test]
    fn circle_orientation_and_area() {
        let c = circle_polygon(&P2::new(1.0, 2.0), 1.0, 256, true);
        assert!(!is_ccw(&c));
        let area = -signed_area(&c);
        assert!((area - std::f64::consts::PI).abs() < 1e-3);
    }

    #[test]
    fn polyline_crossing_polygon() {
        let line = vec![P2::new(0.5, 0.5), P2::new(0.5, 2.0)];
        let (i, j, p) = polyline_polygon_hit(&line, &square()).expect("crosses top edge");
        assert_eq!((i, j), (0, 2));
        assert!((p - P2::new(0.5, 1.0)).norm() < 1e-14);
        assert!((polyline_length(&line) - 1.5).abs() < 1e-15);
    }
}
