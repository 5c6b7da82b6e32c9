//! Open polylines: length, point at an arc length, arc length of the nearest point,
//! distance to a point, first crossing with a polygon.

use crate::segment::{
    point_segment_distance_hypot, point_segment_projection, segment_intersection,
};
use crate::{SegmentHit, P2};

/// Total length of an open polyline (`sqrt` of the squared segment lengths).
pub fn polyline_length(pts: &[P2]) -> f64 {
    pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// [`polyline_length`] with `hypot` segment lengths (the PD boundary layers), which may
/// differ in the last bit.
pub fn polyline_length_hypot(pts: &[P2]) -> f64 {
    pts.windows(2)
        .map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y))
        .sum()
}

/// The point at arc length `s` along the polyline, clamped to its ends (zero-length
/// segments are skipped). Panics on an empty polyline.
pub fn point_at(line: &[P2], s: f64) -> P2 {
    let mut acc = 0.0;
    for w in line.windows(2) {
        let l = (w[1] - w[0]).norm();
        if acc + l >= s && l > 0.0 {
            let f = ((s - acc) / l).clamp(0.0, 1.0);
            return w[0] + f * (w[1] - w[0]);
        }
        acc += l;
    }
    *line.last().expect("non-empty polyline")
}

/// Arc length of the point of the polyline nearest to `p` (the first segment wins a tie;
/// 0 for fewer than two points).
pub fn polyline_project(line: &[P2], p: &P2) -> f64 {
    let mut acc = 0.0;
    let mut best = (f64::INFINITY, 0.0);
    for seg in line.windows(2) {
        let (d, t) = point_segment_projection(p, &seg[0], &seg[1]);
        let l = (seg[1] - seg[0]).norm();
        if d < best.0 {
            best = (d, acc + t * l);
        }
        acc += l;
    }
    best.1
}

/// Distance from `p` to an open polyline, with the arithmetic of
/// [`point_segment_distance_hypot`] (the PD setup). A single point counts as a polyline;
/// an empty one is infinitely far.
pub fn polyline_distance_hypot(p: &P2, line: &[P2]) -> f64 {
    match line.len() {
        0 => f64::INFINITY,
        1 => (p.x - line[0].x).hypot(p.y - line[0].y),
        _ => line
            .windows(2)
            .map(|w| point_segment_distance_hypot(p, &w[0], &w[1]))
            .fold(f64::INFINITY, f64::min),
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    fn bent() -> [P2; 3] {
        [P2::new(0.0, 0.0), P2::new(1.0, 0.0), P2::new(1.0, 1.0)]
    }

    fn square() -> Vec<P2> {
        vec![
            P2::new(0.0, 0.0),
            P2::new(1.0, 0.0),
            P2::new(1.0, 1.0),
            P2::new(0.0, 1.0),
        ]
    }

    #[test]
    fn lengths_agree_on_simple_lines() {
        let line = bent();
        assert!((polyline_length(&line) - 2.0).abs() < 1e-15);
        assert!((polyline_length_hypot(&line) - 2.0).abs() < 1e-15);
        let diag = [P2::zeros(), P2::new(3.0, 4.0)];
        assert_eq!(polyline_length(&diag), 5.0);
        assert_eq!(polyline_length_hypot(&diag), 5.0);
        assert_eq!(polyline_length(&diag[..1]), 0.0);
    }

    #[test]
    fn point_at_an_arc_length_is_clamped() {
        let line = bent();
        assert!((point_at(&line, 0.5) - P2::new(0.5, 0.0)).norm() < 1e-15);
        assert!((point_at(&line, 1.5) - P2::new(1.0, 0.5)).norm() < 1e-15);
        assert_eq!(point_at(&line, -1.0), line[0]);
        assert_eq!(point_at(&line, 9.0), line[2]);
        // A repeated point is skipped.
        let rep = [line[0], line[0], line[1]];
        assert!((point_at(&rep, 0.25) - P2::new(0.25, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn projection_onto_a_polyline() {
        let line = bent();
        assert!((polyline_project(&line, &P2::new(1.2, 0.4)) - 1.4).abs() < 1e-15);
        assert!((polyline_project(&line, &P2::new(-1.0, -1.0))).abs() < 1e-15);
        assert!((polyline_project(&line, &P2::new(1.0, 3.0)) - 2.0).abs() < 1e-15);
    }

    #[test]
    fn distance_to_a_polyline() {
        let line = bent();
        assert!((polyline_distance_hypot(&P2::new(0.5, -0.5), &line) - 0.5).abs() < 1e-15);
        assert!((polyline_distance_hypot(&P2::new(2.0, 2.0), &line) - 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(polyline_distance_hypot(&P2::new(3.0, 4.0), &line[..1]), 5.0);
        assert_eq!(polyline_distance_hypot(&P2::zeros(), &[]), f64::INFINITY);
    }

    #[test]
    fn polyline_crossing_polygon() {
        let line = vec![P2::new(0.5, 0.5), P2::new(0.5, 2.0)];
        let (i, j, p) = polyline_polygon_hit(&line, &square()).expect("crosses top edge");
        assert_eq!((i, j), (0, 2));
        assert!((p - P2::new(0.5, 1.0)).norm() < 1e-14);
        assert!((polyline_length(&line) - 1.5).abs() < 1e-15);
        let outside = vec![P2::new(2.0, 0.0), P2::new(2.0, 1.0)];
        assert!(polyline_polygon_hit(&outside, &square()).is_none());
    }
}
