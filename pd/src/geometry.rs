//! PD's planar geometry on `[f64; 2]` points: the adapters to [`pdbem_geometry`] (point
//! in polygon, distances, lengths, signed area, segment crossings, rotation) and the
//! pre-crack cutting rule of bonds ([`segment_crosses_crack`]).
//!
//! These serve grid generation ([`crate::grid`]), pre-crack cutting ([`crate::bonds`]) and
//! the problem set-up ([`crate::problem`], [`crate::boundary`]); points stay plain arrays
//! so that problem files and the solvers' data stay free of library types, and are
//! converted to [`pdbem_geometry::P2`] at the call. Distances and lengths use the
//! `*_hypot` variants, the arithmetic pd always used.

use pdbem_geometry as g;

/// A 2-D point or vector.
pub type P2 = [f64; 2];

/// The [`pdbem_geometry::P2`] of an array point.
#[inline]
pub fn to_g(p: P2) -> g::P2 {
    g::P2::new(p[0], p[1])
}

/// The array point of a [`pdbem_geometry::P2`].
#[inline]
pub fn from_g(p: g::P2) -> P2 {
    [p.x, p.y]
}

/// Array points as [`pdbem_geometry::P2`].
pub fn to_g_all(pts: &[P2]) -> Vec<g::P2> {
    pts.iter().map(|&p| to_g(p)).collect()
}

/// Signed area of a closed polygon (positive when counter-clockwise).
pub fn signed_area(poly: &[P2]) -> f64 {
    g::signed_area(&to_g_all(poly))
}

/// Point-in-polygon by the even-odd ray rule (closed polygon, any orientation).
pub fn point_in_polygon(p: P2, poly: &[P2]) -> bool {
    g::point_in_polygon(&to_g(p), &to_g_all(poly))
}

/// Distance from `p` to the segment `[a, b]`.
pub fn dist_point_segment(p: P2, a: P2, b: P2) -> f64 {
    g::point_segment_distance_hypot(&to_g(p), &to_g(a), &to_g(b))
}

/// Distance from `p` to an open polyline (a single point counts as a polyline).
pub fn dist_point_polyline(p: P2, line: &[P2]) -> f64 {
    g::polyline_distance_hypot(&to_g(p), &to_g_all(line))
}

/// Distance from `p` to the boundary of a closed polygon.
pub fn dist_point_polygon_boundary(p: P2, poly: &[P2]) -> f64 {
    g::polygon_distance_hypot(&to_g(p), &to_g_all(poly))
}

/// Length of an open polyline.
pub fn polyline_length(line: &[P2]) -> f64 {
    g::polyline_length_hypot(&to_g_all(line))
}

/// Whether the segments `[p1, p2]` and `[q1, q2]` intersect (touching counts; exact
/// orientation signs, [`pdbem_geometry::segments_intersect_exact`]).
pub fn segments_intersect(p1: P2, p2: P2, q1: P2, q2: P2) -> bool {
    g::segments_intersect_exact(&to_g(p1), &to_g(p2), &to_g(q1), &to_g(q2))
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
    let (a, b) = (to_g(a), to_g(b));
    let last = line.len().saturating_sub(2);
    line.windows(2).enumerate().any(|(k, w)| {
        let (q1, q2) = (to_g(w[0]), to_g(w[1]));
        if !g::segments_intersect_exact(&a, &b, &q1, &q2) {
            return false;
        }
        let (first, end) = (k == 0, k == last);
        if !first && !end {
            return true;
        }
        let s = q2 - q1;
        let len = s.x.hypot(s.y);
        let u_min = if first { tol / len } else { 0.0 };
        let u_max = if end { 1.0 - tol / len } else { 1.0 };
        let r = b - a;
        let denom = g::cross(&r, &s);
        if denom.abs() <= 1e-14 * r.x.hypot(r.y) * len {
            return collinear_overlap(&a, &b, &q1, &s, u_min, u_max);
        }
        let u = g::cross(&(q1 - a), &r) / denom;
        (!first || u > u_min) && (!end || u < u_max)
    })
}

/// Whether the segment `[a, b]`, parallel to the crack segment `q1 + u s`, lies on its
/// line and overlaps it for some u in (u_min, u_max): a bond along the crack line is cut
/// (a node on the crack is then isolated rather than left hanging on bonds along the
/// crack, which would make the stiffness singular).
fn collinear_overlap(a: &g::P2, b: &g::P2, q1: &g::P2, s: &g::P2, u_min: f64, u_max: f64) -> bool {
    let ss = s.dot(s);
    if g::cross(&(a - q1), s).abs() > 1e-12 * ss {
        return false;
    }
    let ua = (a - q1).dot(s) / ss;
    let ub = (b - q1).dot(s) / ss;
    ua.min(ub) < u_max && ua.max(ub) > u_min
}

/// Rotate `p` by `angle` (radians, counter-clockwise) about the origin.
#[inline]
pub fn rotate(p: P2, angle: f64) -> P2 {
    from_g(g::rotate(&to_g(p), angle))
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
