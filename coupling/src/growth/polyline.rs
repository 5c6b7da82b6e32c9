//! Polyline helpers of the growth module: length, point at an arc length, uniform
//! resampling and the first entry of a polyline into a window.

use pdbem_bem::V2;

use crate::window::Window;

/// Length of a polyline (m).
pub fn length(line: &[V2]) -> f64 {
    line.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// The point at arc length `s` (clamped to the ends).
pub fn point_at(line: &[V2], s: f64) -> V2 {
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

/// Arc length of the point of the polyline nearest to `p`.
pub fn project(line: &[V2], p: V2) -> f64 {
    let mut acc = 0.0;
    let mut best = (f64::INFINITY, 0.0);
    for seg in line.windows(2) {
        let (d, t) = crate::window::segment_distance(p, seg[0], seg[1]);
        let l = (seg[1] - seg[0]).norm();
        if d < best.0 {
            best = (d, acc + t * l);
        }
        acc += l;
    }
    best.1
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
        assert!((length(&line) - 2.0).abs() < 1e-15);
        let r = resample_between(&line, 0.5, 1.5, 4);
        assert_eq!(r.len(), 5);
        assert!((r[0] - V2::new(0.5, 0.0)).norm() < 1e-15);
        assert!((r[2] - V2::new(1.0, 0.0)).norm() < 1e-15);
        assert!((r[4] - V2::new(1.0, 0.5)).norm() < 1e-15);
        assert_eq!(resample_spacing(&line, 0.0, 2.0, 0.3).len(), 8);
        assert!((project(&line, V2::new(1.2, 0.4)) - 1.4).abs() < 1e-15);
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
