//! Polyline helpers of the growth module: uniform resampling, the first entry of a
//! polyline into a window, and the end of a path that reached the outline
//! ([`end_on_outline`], shared by the PD-BEM and full-PD growth modes so that their paths
//! end by one rule). Lengths, points at an arc length, projections and ray casts are in
//! [`pdbem_geometry`].

use pdbem_bem::V2;
use pdbem_geometry::{point_at, polygon_distance, ray_polygon};

use crate::window::Window;

/// The vertices of the polyline before arc length `s` (the first one always).
pub fn head(line: &[V2], s: f64) -> Vec<V2> {
    let mut out = vec![line[0]];
    let mut acc = 0.0;
    for seg in line.windows(2) {
        acc += (seg[1] - seg[0]).norm();
        if acc >= s {
            break;
        }
        out.push(seg[1]);
    }
    out
}

/// The part of the polyline between arc lengths `s0 < s1`, split into `n` equal straight
/// pieces (`n + 1` points).
pub fn resample_between(line: &[V2], s0: f64, s1: f64, n: usize) -> Vec<V2> {
    let n = n.max(1);
    (0..=n)
        .map(|k| point_at(line, s0 + (s1 - s0) * k as f64 / n as f64))
        .collect()
}

/// Points every `h` (or closer, equal pieces) from arc length `s0` to `s1`, both included.
pub fn resample_spacing(line: &[V2], s0: f64, s1: f64, h: f64) -> Vec<V2> {
    let n = (((s1 - s0) / h).ceil() as usize).max(1);
    resample_between(line, s0, s1, n)
}

/// Every segment split into `round(length / h)` (at least 1) equal pieces: the uniform
/// element ends the BEM mesher puts on a crack polyline of element size `h`.
pub fn subdivide(line: &[V2], h: f64) -> Vec<V2> {
    let mut out = vec![line[0]];
    for seg in line.windows(2) {
        let n = (((seg[1] - seg[0]).norm() / h).round() as usize).max(1);
        out.extend((1..=n).map(|k| seg[0] + (seg[1] - seg[0]) * (k as f64 / n as f64)));
    }
    out
}

/// Arc length at which the polyline first enters the closed window `w` (None if it never
/// does). A start inside the window gives 0.
pub fn entry_length(line: &[V2], w: &Window) -> Option<f64> {
    let mut acc = 0.0;
    if w.contains(line[0], 0.0) {
        return Some(0.0);
    }
    for seg in line.windows(2) {
        let l = (seg[1] - seg[0]).norm();
        if let Some((p, _)) = w.chord(seg[0], seg[1]) {
            return Some(acc + (p - seg[0]).norm());
        }
        acc += l;
    }
    None
}

/// Chord (in dx) along which [`end_on_outline`] continues a path to the outline.
pub const OUTLINE_CHORD_DX: f64 = 3.0;

/// The path of a tip that reached the outline, ended by one rule in every growth mode:
/// the trailing points within `delta` (the horizon) of the outline are dropped, and the
/// path goes on along the chord of its last `chord` (from the last point kept back to the
/// first point at least `chord` from it) to the outline. Within a horizon of the outline
/// the ligament is shorter than a bond: its damage fans out over the whole ligament, and
/// its farthest damaged node (the tracked tip) may lie a few dx to the side along the
/// outline rather than ahead of the crack. Returns the path unchanged when the chord does
/// not meet the outline within 2 delta of the last point kept.
pub fn end_on_outline(path: &[V2], outline: &[V2], delta: f64, chord: f64) -> Vec<V2> {
    let near = |p: &V2| polygon_distance(p, outline) <= delta;
    let kept = path.len() - path.iter().rev().take_while(|p| near(p)).count();
    if kept == 0 {
        return path.to_vec();
    }
    let tip = path[kept - 1];
    let back = path[..kept]
        .iter()
        .rev()
        .find(|p| (tip - **p).norm() >= chord)
        .copied()
        .unwrap_or(path[0]);
    let Some(d) = unit(back, tip) else {
        return path.to_vec();
    };
    match ray_polygon(&tip, &d, outline) {
        Some(s) if s <= 2.0 * delta => {
            let mut out = path[..kept].to_vec();
            out.push(tip + d * s);
            out
        }
        _ => path.to_vec(),
    }
}

/// The path of a tip that ended on `boundary` (the outline, or a hole polygon) made to
/// reach it: unchanged when its last point lies on it (within 1e-9 of the path's length),
/// else continued along the chord of its last `chord` (as [`end_on_outline`]) to the
/// first crossing with the boundary, or, when that ray misses it, straight to the
/// nearest boundary point. Returns the path and the length added (m). PD-BEM ends a tip
/// at the outline when no window around it fits in the body, and at a hole when its
/// window cannot move on without covering it: in both cases the remaining ligament, at
/// most a window side, lies in the window, and the crack is taken through it along its
/// approach.
pub fn join_boundary(path: &[V2], boundary: &[V2], chord: f64) -> (Vec<V2>, f64) {
    let Some(&tip) = path.last() else {
        return (path.to_vec(), 0.0);
    };
    let scale = pdbem_geometry::polyline_length(path).max(chord);
    if polygon_distance(&tip, boundary) <= 1e-9 * scale {
        return (path.to_vec(), 0.0);
    }
    let back = path
        .iter()
        .rev()
        .find(|p| (tip - **p).norm() >= chord)
        .copied()
        .unwrap_or(path[0]);
    let hit = unit(back, tip)
        .and_then(|d| ray_polygon(&tip, &d, boundary).map(|s| tip + d * s))
        .unwrap_or_else(|| nearest_on_polygon(&tip, boundary));
    let mut out = path.to_vec();
    out.push(hit);
    (out, (hit - tip).norm())
}

/// The point of the closed polygon nearest to `p`.
pub fn nearest_on_polygon(p: &V2, poly: &[V2]) -> V2 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let d = b - a;
            let t = ((p - a).dot(&d) / d.norm_squared().max(1e-300)).clamp(0.0, 1.0);
            a + d * t
        })
        .min_by(|x, y| (x - p).norm().total_cmp(&(y - p).norm()))
        .unwrap_or(*p)
}

/// Unit vector from `a` to `b` (None when they coincide).
pub fn unit(a: V2, b: V2) -> Option<V2> {
    let d = b - a;
    let l = d.norm();
    (l > 0.0).then(|| d / l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::window::{Body, WindowSpec};

    #[test]
    fn resampling_keeps_the_ends_and_spacing() {
        let line = [V2::new(0.0, 0.0), V2::new(1.0, 0.0), V2::new(1.0, 1.0)];
        let r = resample_between(&line, 0.5, 1.5, 4);
        assert_eq!(r.len(), 5);
        assert!((r[0] - V2::new(0.5, 0.0)).norm() < 1e-15);
        assert!((r[2] - V2::new(1.0, 0.0)).norm() < 1e-15);
        assert!((r[4] - V2::new(1.0, 0.5)).norm() < 1e-15);
        assert_eq!(resample_spacing(&line, 0.0, 2.0, 0.3).len(), 8);
        assert_eq!(head(&line, 1.5), line[..2].to_vec());
        assert_eq!(head(&line, 1.0), line[..1].to_vec());
    }

    #[test]
    fn a_path_at_the_outline_ends_along_its_approach() {
        let square = [
            V2::new(0.0, 0.0),
            V2::new(10.0, 0.0),
            V2::new(10.0, 10.0),
            V2::new(0.0, 10.0),
        ];
        // Straight down x = 5, then the last horizon (0.3) fans out sideways along y = 0.1.
        let mut path: Vec<V2> = (0..=9)
            .map(|k| V2::new(5.0, 2.0 - 0.2 * k as f64))
            .collect();
        path.push(V2::new(5.25, 0.1));
        let ended = end_on_outline(&path, &square, 0.3, 0.3);
        let last = *ended.last().unwrap();
        assert!((last - V2::new(5.0, 0.0)).norm() < 1e-12, "{last:?}");
        // Points up to the horizon kept, the fan dropped.
        assert_eq!(ended.len(), 10);
        // A path far from the outline is left alone.
        assert_eq!(
            end_on_outline(&path[..5], &square, 0.3, 0.3),
            path[..5].to_vec()
        );
    }

    #[test]
    fn a_path_ended_on_a_boundary_is_joined_to_it() {
        let square = [
            V2::new(0.0, 0.0),
            V2::new(10.0, 0.0),
            V2::new(10.0, 10.0),
            V2::new(0.0, 10.0),
        ];
        // 0.86 m short of the bottom edge, heading down at 45 degrees.
        let path = [V2::new(4.0, 1.86 + 1.0), V2::new(5.0, 1.86)];
        let (joined, added) = join_boundary(&path, &square, 0.3);
        let last = *joined.last().unwrap();
        assert!((last - V2::new(6.86, 0.0)).norm() < 1e-12, "{last:?}");
        assert!((added - 1.86 * 2f64.sqrt()).abs() < 1e-12);
        // Already on it: unchanged.
        let (same, zero) = join_boundary(&joined, &square, 0.3);
        assert_eq!((same.len(), zero), (joined.len(), 0.0));
        // Heading away from a hole (a square hole at x in [6, 8]): the nearest point.
        let hole = [
            V2::new(6.0, 4.0),
            V2::new(6.0, 6.0),
            V2::new(8.0, 6.0),
            V2::new(8.0, 4.0),
        ];
        let (j, _) = join_boundary(&[V2::new(5.5, 5.0), V2::new(5.0, 5.0)], &hole, 0.3);
        assert!((j[2] - V2::new(6.0, 5.0)).norm() < 1e-12);
    }

    #[test]
    fn entry_into_a_window_is_found_on_the_right_segment() {
        let body = Body {
            outline: vec![
                V2::new(-10.0, -10.0),
                V2::new(10.0, -10.0),
                V2::new(10.0, 10.0),
                V2::new(-10.0, 10.0),
            ],
            holes: vec![],
        };
        let spec = WindowSpec {
            center: V2::new(3.0, 0.0),
            angle: 0.0,
            dx: 0.1,
            nx: 20,
            ny: 20,
            horizon_factor: 3.015,
        };
        let w = Window::place(0, spec, &body).unwrap();
        let line = [V2::new(0.0, 0.0), V2::new(1.0, 0.0), V2::new(5.0, 0.0)];
        // The window spans x in [2, 4]: entry at arc length 2.
        assert!((entry_length(&line, &w).unwrap() - 2.0).abs() < 1e-12);
        assert!(entry_length(&line[..2], &w).is_none());
    }
}
