//! Path comparison between growth runs (PD-BEM, BEM-only, full PD of one scene).
//!
//! Two tip paths are compared over their common reach: both are cut where they first get
//! as far from their initial tip as the other path ever gets (the smaller of the two
//! reaches), and the deviation is the Hausdorff distance between the cut polylines,
//! max(sup_a d(a, B), sup_b d(b, A)), with d the distance from a point to a polyline.
//! Paths that end at different places (one mode stops earlier) are so compared where both
//! exist; paths that run apart show the distance where they part. The reach, not the arc
//! length, sets the cut: a path traced on the PD lattice zig-zags by about a node spacing,
//! which adds arc length without adding reach (full PD on `growth_tension_edge`: 8.48 m of
//! path over an 8 m ligament), and an arc-length cut would then compare points that lie
//! at different depths.

use pdbem_geometry::{point_segment_distance, P2};

use super::history::TipPath;

/// Points of a path.
fn polyline(p: &TipPath) -> Vec<P2> {
    p.points.iter().map(|q| P2::new(q.x, q.y)).collect()
}

/// Distance from `p` to the polyline `line` (a single point when it has one).
pub fn distance_to_polyline(p: &P2, line: &[P2]) -> f64 {
    match line {
        [] => f64::INFINITY,
        [q] => (p - q).norm(),
        _ => line
            .windows(2)
            .map(|w| point_segment_distance(p, &w[0], &w[1]))
            .fold(f64::INFINITY, f64::min),
    }
}

/// Hausdorff distance of two polylines, sampled at their vertices and at `samples` points
/// per segment.
fn hausdorff(a: &[P2], b: &[P2]) -> f64 {
    let one_way = |from: &[P2], to: &[P2]| {
        let mut worst: f64 = 0.0;
        for w in from.windows(2) {
            for k in 0..=8 {
                let p = w[0] + (w[1] - w[0]) * (k as f64 / 8.0);
                worst = worst.max(distance_to_polyline(&p, to));
            }
        }
        if from.len() == 1 {
            worst = distance_to_polyline(&from[0], to);
        }
        worst
    };
    one_way(a, b).max(one_way(b, a))
}

/// Largest distance of a polyline's points from its first point.
pub fn reach(line: &[P2]) -> f64 {
    line.first()
        .map(|o| line.iter().map(|p| (p - o).norm()).fold(0.0, f64::max))
        .unwrap_or(0.0)
}

/// The polyline up to where it first gets `r` away from its first point (the crossing
/// point found by bisection on that segment).
pub fn cut_at_reach(line: &[P2], r: f64) -> Vec<P2> {
    let Some(o) = line.first().copied() else {
        return Vec::new();
    };
    let mut out = vec![o];
    for w in line.windows(2) {
        if (w[1] - o).norm() >= r {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..60 {
                let m = 0.5 * (lo + hi);
                if (w[0] + (w[1] - w[0]) * m - o).norm() < r {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            out.push(w[0] + (w[1] - w[0]) * hi);
            return out;
        }
        out.push(w[1]);
    }
    out
}

/// The part of a path its tip reached at loads below `load`, up to the first point reached
/// at `load` or later (the initial tip always).
pub fn reached_below(p: &TipPath, load: f64) -> TipPath {
    let mut points: Vec<_> = p
        .points
        .iter()
        .take_while(|q| q.load < load)
        .copied()
        .collect();
    if points.is_empty() {
        points.extend(p.points.first().copied());
    }
    TipPath {
        name: p.name.clone(),
        points,
        ended: None,
    }
}

/// Deviation of two tip paths over their common reach (m), and that reach (m).
pub fn path_deviation(a: &TipPath, b: &TipPath) -> (f64, f64) {
    let (pa, pb) = (polyline(a), polyline(b));
    let common = reach(&pa).min(reach(&pb));
    let (ca, cb) = (cut_at_reach(&pa, common), cut_at_reach(&pb, common));
    (hausdorff(&ca, &cb), common)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::history::PathPoint;

    fn path(pts: &[(f64, f64)]) -> TipPath {
        TipPath {
            name: "t".into(),
            points: pts
                .iter()
                .map(|&(x, y)| PathPoint {
                    x,
                    y,
                    step: 0,
                    load: 0.0,
                })
                .collect(),
            ended: None,
        }
    }

    #[test]
    fn parallel_paths_deviate_by_their_offset_over_the_common_length() {
        // A straight path down 8 m and a shorter one offset by 0.1 m with a zig-zag.
        let a = path(&[(10.0, 8.0), (10.0, 4.0), (10.0, 0.0)]);
        let b = path(&[(10.0, 8.0), (10.1, 7.0), (10.1, 5.0)]);
        let (d, common) = path_deviation(&a, &b);
        // b reaches (10.1, 5): 3.0017 m from the start; a is cut at the same distance.
        assert!((common - 0.1f64.hypot(3.0)).abs() < 1e-12);
        assert!((d - 0.1).abs() < 2e-4, "{d}");
        // A zig-zag adds arc length but not reach: compared at the same depth.
        let z = path(&[
            (10.0, 8.0),
            (10.1, 7.5),
            (9.9, 7.0),
            (10.1, 6.5),
            (10.0, 6.0),
        ]);
        let (d, common) = path_deviation(&a, &z);
        assert!(
            (common - 2.0).abs() < 1e-12 && (d - 0.1).abs() < 1e-12,
            "{d} {common}"
        );
        // Kinked against straight: the deviation is the distance at the common end.
        let c = path(&[(0.0, 0.0), (1.0, 0.0)]);
        let k = path(&[(0.0, 0.0), (0.6, 0.8)]);
        let (d, _) = path_deviation(&c, &k);
        assert!((d - 0.8).abs() < 1e-12, "{d}");
        assert!(path_deviation(&a, &a).0 < 1e-12);
    }

    #[test]
    fn a_path_is_cut_where_its_tip_reached_the_load() {
        let mut p = path(&[(0.0, 0.0), (0.0, -1.0), (0.0, -2.0), (1.0, -2.0)]);
        for (q, f) in p.points.iter_mut().zip([0.08, 0.1, 0.18, 0.2]) {
            q.load = f;
        }
        let cut = reached_below(&p, 0.2);
        assert_eq!(cut.points.len(), 3);
        assert_eq!((cut.points[2].x, cut.points[2].y), (0.0, -2.0));
        // A straight path down 2 m deviates from p by 1 m over the whole path, not below
        // load 0.2.
        let s = path(&[(0.0, 0.0), (0.0, -2.5)]);
        assert!((path_deviation(&p, &s).0 - 1.0).abs() < 1e-12);
        assert!(path_deviation(&cut, &s).0 < 1e-12);
        assert_eq!(reached_below(&p, 0.01).points.len(), 1);
    }
}
