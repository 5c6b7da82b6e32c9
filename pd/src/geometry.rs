//! Small planar geometry helpers on `[f64; 2]` points: point in polygon,
//! point-segment distance, segment intersection, signed area.
//!
//! These serve grid generation ([`crate::grid`]) and pre-crack cutting
//! ([`crate::bonds`]); points are plain arrays so that problem files stay
//! free of library types.

/// A 2-D point or vector.
pub type P2 = [f64; 2];

/// Difference `a - b`.
#[inline]
pub fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}

/// Euclidean norm.
#[inline]
pub fn norm(a: P2) -> f64 {
    a[0].hypot(a[1])
}

/// 2-D cross product `a x b`.
#[inline]
pub fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// Dot product.
#[inline]
pub fn dot(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// Signed area of a closed polygon (positive when counter-clockwise).
pub fn signed_area(poly: &[P2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| cross(poly[i], poly[(i + 1) % n]))
        .sum::<f64>()
        * 0.5
}

/// Point-in-polygon by the even-odd ray rule (closed polygon, any orientation).
pub fn point_in_polygon(p: P2, poly: &[P2]) -> bool {
    let n = poly.len();
    let mut inside = false;
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (poly[i], poly[j]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            if p[0] < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Distance from `p` to the segment `[a, b]`.
pub fn dist_point_segment(p: P2, a: P2, b: P2) -> f64 {
    let ab = sub(b, a);
    let ap = sub(p, a);
    let l2 = ab[0] * ab[0] + ab[1] * ab[1];
    let t = if l2 > 0.0 {
        ((ap[0] * ab[0] + ap[1] * ab[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm([ap[0] - t * ab[0], ap[1] - t * ab[1]])
}

/// Distance from `p` to an open polyline (a single point counts as a polyline).
pub fn dist_point_polyline(p: P2, line: &[P2]) -> f64 {
    match line.len() {
        0 => f64::INFINITY,
        1 => norm(sub(p, line[0])),
        _ => line
            .windows(2)
            .map(|w| dist_point_segment(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min),
    }
}

/// Distance from `p` to the boundary of a closed polygon.
pub fn dist_point_polygon_boundary(p: P2, poly: &[P2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| dist_point_segment(p, poly[i], poly[(i + 1) % n]))
        .fold(f64::INFINITY, f64::min)
}

/// Length of an open polyline.
pub fn polyline_length(line: &[P2]) -> f64 {
    line.windows(2).map(|w| norm(sub(w[1], w[0]))).sum()
}

/// Whether the segments `[p1, p2]` and `[q1, q2]` intersect (touching counts).
pub fn segments_intersect(p1: P2, p2: P2, q1: P2, q2: P2) -> bool {
    let d1 = cross(sub(q2, q1), sub(p1, q1));
    let d2 = cross(sub(q2, q1), sub(p2, q1));
    let d3 = cross(sub(p2, p1), sub(q1, p1));
    let d4 = cross(sub(p2, p1), sub(q2, p1));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |a: P2, b: P2, c: P2, d: f64| {
        d == 0.0
            && c[0] >= a[0].min(b[0])
            && c[0] <= a[0].max(b[0])
            && c[1] >= a[1].min(b[1])
            && c[1] <= a[1].max(b[1])
    };
    on(q1, q2, p1, d1) || on(q1, q2, p2, d2) || on(p1, p2, q1, d3) || on(p1, p2, q2, d4)
}

/// Whether the segment `[a, b]` crosses an open polyline.
pub fn segment_crosses_polyline(a: P2, b: P2, line: &[P2]) -> bool {
    line.windows(2)
        .any(|w| segments_intersect(a, b, w[0], w[1]))
}

/// Whether the bond `[a, b]` crosses the crack polyline `line` away from its two ends.
///
/// A pre-crack is open at its ends: a bond that meets the crack within `tol` (m, along
/// the crack) of its first or last point is not cut. On a regular grid with the tip
/// between node rows, whole families of bonds cross the crack line exactly at the tip
/// (pairs of nodes placed symmetrically about it); counting them as cut lengthens the
/// crack by a fraction of dx (measured: +0.35 dx of effective length, +2.4 % CMOD on the
/// seed 002 SENT window at dx = 0.1 m). Joints between segments are inclusive, so a
/// polyline has no gaps. Bonds parallel to a segment never cross it.
pub fn segment_crosses_crack(a: P2, b: P2, line: &[P2], tol: f64) -> bool {
    // Decide on the canonical orientation of the bond so that i -> j and j -> i agree
    // to the last bit.
    let (a, b) = if (a[0], a[1]) <= (b[0], b[1]) {
        (a, b)
    } else {
        (b, a)
    };
    let last = line.len().saturating_sub(2);
    line.windows(2).enumerate().any(|(k, w)| {
        let (q1, q2) = (w[0], w[1]);
        if !segments_intersect(a, b, q1, q2) {
            return false;
        }
        let (first, end) = (k == 0, k == last);
        if !first && !end {
            return true;
        }
        let s = sub(q2, q1);
        let len = norm(s);
        let u_min = if first { tol / len } else { 0.0 };
        let u_max = if end { 1.0 - tol / len } else { 1.0 };
        let r = sub(b, a);
        let denom = cross(r, s);
        if denom.abs() <= 1e-14 * norm(r) * len {
            return collinear_overlap(a, b, q1, s, u_min, u_max);
        }
        let u = cross(sub(q1, a), r) / denom;
        (!first || u > u_min) && (!end || u < u_max)
    })
}

/// Whether the segment `[a, b]`, parallel to the crack segment `q1 + u s`, lies on its
/// line and overlaps it for some u in (u_min, u_max): a bond along the crack line is cut
/// (a node on the crack is then isolated rather than left hanging on bonds along the
/// crack, which would make the stiffness singular).
fn collinear_overlap(a: P2, b: P2, q1: P2, s: P2, u_min: f64, u_max: f64) -> bool {
    let ss = dot(s, s);
    if cross(sub(a, q1), s).abs() > 1e-12 * ss {
        return false;
    }
    let ua = dot(sub(a, q1), s) / ss;
    let ub = dot(sub(b, q1), s) / ss;
    ua.min(ub) < u_max && ua.max(ub) > u_min
}

/// Rotate `p` by `angle` (radians, counter-clockwise) about the origin.
#[inline]
pub fn rotate(p: P2, angle: f64) -> P2 {
    let (s, c) = angle.sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_area_inside_and_distances() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_eq!(signed_area(&sq), 1.0);
        assert!(point_in_polygon([0.5, 0.5], &sq));
        assert!(!point_in_polygon([1.5, 0.5], &sq));
        assert!((dist_point_polygon_boundary([0.5, 0.2], &sq) - 0.2).abs() < 1e-15);
        assert!(
            (dist_point_segment([2.0, 1.0], [0.0, 0.0], [1.0, 0.0]) - 2f64.sqrt()).abs() < 1e-15
        );
    }

    #[test]
    fn crack_ends_are_open_and_the_rule_is_symmetric() {
        let crack = [[0.0, 0.0], [0.0, 1.0]];
        let tol = 1e-9;
        // Crosses inside: cut, both orientations.
        assert!(segment_crosses_crack([-0.1, 0.4], [0.1, 0.6], &crack, tol));
        assert!(segment_crosses_crack([0.1, 0.6], [-0.1, 0.4], &crack, tol));
        // Crosses exactly at the tip or the start: open ends, not cut.
        assert!(!segment_crosses_crack(
            [-0.25, 0.75],
            [0.25, 1.25],
            &crack,
            tol
        ));
        assert!(!segment_crosses_crack(
            [0.25, 1.25],
            [-0.25, 0.75],
            &crack,
            tol
        ));
        assert!(!segment_crosses_crack(
            [-0.1, -0.1],
            [0.1, 0.1],
            &crack,
            tol
        ));
        // Just inside the tip: cut; beyond it: not.
        assert!(segment_crosses_crack(
            [-0.1, 0.99],
            [0.1, 0.99],
            &crack,
            tol
        ));
        assert!(!segment_crosses_crack(
            [-0.1, 1.01],
            [0.1, 1.01],
            &crack,
            tol
        ));
        // A node on the crack: every bond touching the crack inside it is cut,
        // including bonds along the crack line.
        assert!(segment_crosses_crack([0.0, 0.5], [0.2, 0.7], &crack, tol));
        assert!(segment_crosses_crack([0.0, 0.5], [0.0, 0.6], &crack, tol));
        assert!(!segment_crosses_crack([0.0, 1.0], [0.0, 1.3], &crack, tol));
        // A joint of a polyline is inclusive (no gap between segments).
        let bent = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
        assert!(segment_crosses_crack(
            [-0.25, 0.75],
            [0.25, 1.25],
            &bent,
            tol
        ));
    }

    #[test]
    fn crossing_segments() {
        assert!(segments_intersect(
            [0.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [1.0, 0.0]
        ));
        assert!(!segments_intersect(
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [1.0, 1.0]
        ));
        // Touching at an end point counts.
        assert!(segments_intersect(
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0]
        ));
    }
}
