//! Rules of `cracks`: one complete form, non-zero length, inside the body
//! (only the first point may touch the outline or a hole: the mouth), clear
//! of holes and of the other cracks.

use super::{fmt_pt, Checker};
use crate::geometry::{
    bounding_box, point_in_polygon, polygon_distance, polyline_length, segment_intersection,
    SegmentHit, P2,
};
use crate::scene::shapes::{hole_shape, outline_loop, HoleShape};
use crate::scene::{Crack, Faces, Scene};

/// Checks every crack (the body is known to be sound).
pub fn check(c: &mut Checker, scene: &Scene) {
    let outline = outline_loop(&scene.body.outline).map(|l| l.points);
    let holes: Vec<HoleShape> = scene.body.holes.iter().map(hole_shape).collect();
    let scale = body_scale(outline.as_deref(), &holes, scene);
    let tol = 1e-9 * scale;
    let mut lines: Vec<(usize, Vec<P2>)> = Vec::new();
    for (i, crack) in scene.cracks.iter().enumerate() {
        let path = format!("cracks.{i}");
        let Some(pts) = check_form(c, &path, crack) else {
            continue;
        };
        if let Some(o) = &outline {
            check_in_outline(c, &path, &pts, o, tol);
        }
        for (k, h) in holes.iter().enumerate() {
            check_clear_of_hole(c, &path, &pts, h, k, tol);
        }
        for (j, other) in &lines {
            if polylines_cross(&pts, other) {
                c.fail_at(
                    path.clone(),
                    format!(
                        "crack crosses cracks.{j} ('{}'): cracks must not touch",
                        scene.cracks[*j].name
                    ),
                );
            }
        }
        check_faces(c, &path, crack, polyline_length(&pts));
        lines.push((i, pts));
    }
}

fn body_scale(outline: Option<&[P2]>, holes: &[HoleShape], scene: &Scene) -> f64 {
    let mut pts: Vec<P2> = outline.map(|o| o.to_vec()).unwrap_or_default();
    for h in holes {
        pts.extend(h.polygon());
    }
    for cr in &scene.cracks {
        pts.extend(cr.polyline().unwrap_or_default());
    }
    if pts.is_empty() {
        return 1.0;
    }
    let (lo, hi) = bounding_box(&pts);
    (hi - lo).norm().max(1e-300)
}

/// One complete form, finite numbers, non-zero length, no zero-length
/// segments, not self-intersecting; returns the polyline.
fn check_form(c: &mut Checker, path: &str, crack: &Crack) -> Option<Vec<P2>> {
    if let Err(reason) = crack.form() {
        c.fail_at(path, reason);
        return None;
    }
    if let Some(l) = crack.length {
        if !c.finite(&format!("{path}.length"), l) {
            return None;
        }
        if l <= 0.0 {
            c.fail(
                format!("{path}.length"),
                l,
                "crack of zero length: length must be > 0",
            );
            return None;
        }
    }
    if let Some(a) = crack.angle_deg {
        if !c.finite(&format!("{path}.angle_deg"), a) {
            return None;
        }
    }
    let pts = crack.polyline()?;
    if pts.iter().any(|p| !p.x.is_finite() || !p.y.is_finite()) {
        c.fail_at(path, "coordinates must be finite numbers");
        return None;
    }
    if pts.len() < 2 {
        c.fail(
            format!("{path}.points"),
            format!("{} points", pts.len()),
            "a crack polyline needs at least 2 points",
        );
        return None;
    }
    for (k, w) in pts.windows(2).enumerate() {
        if (w[1] - w[0]).norm() == 0.0 {
            c.fail(
                format!("{path}.points.{}", k + 1),
                fmt_pt(&w[1]),
                "crack of zero length: repeated point",
            );
            return None;
        }
    }
    if polyline_self_crossing(&pts) {
        c.fail_at(format!("{path}.points"), "crack polyline crosses itself");
        return None;
    }
    Some(pts)
}

/// First point inside or on the outline (a mouth); every other point strictly
/// inside; no segment leaves the body.
fn check_in_outline(c: &mut Checker, path: &str, pts: &[P2], outline: &[P2], tol: f64) {
    let inside = |p: &P2| point_in_polygon(p, outline) && polygon_distance(p, outline) > tol;
    let first_ok = inside(&pts[0]) || polygon_distance(&pts[0], outline) <= tol;
    if !first_ok {
        c.fail(
            path,
            fmt_pt(&pts[0]),
            "crack outside the body: its first point lies outside the outline",
        );
        return;
    }
    for (k, p) in pts.iter().enumerate().skip(1) {
        if !inside(p) {
            let what = if polygon_distance(p, outline) <= tol {
                "touches the outline: only a crack's first point (its mouth) may lie on the outline"
            } else {
                "crack outside the body: point lies outside the outline"
            };
            c.fail(path, format!("point {k} {}", fmt_pt(p)), what);
            return;
        }
    }
    let n = outline.len();
    for (k, w) in pts.windows(2).enumerate() {
        for e in 0..n {
            match segment_intersection(&w[0], &w[1], &outline[e], &outline[(e + 1) % n]) {
                SegmentHit::None => {}
                SegmentHit::Point(q) if k == 0 && (q - pts[0]).norm() <= tol => {}
                SegmentHit::Point(q) => {
                    c.fail_at(
                        path,
                        format!(
                            "crack outside the body: segment {k} crosses the outline at {}",
                            fmt_pt(&q)
                        ),
                    );
                    return;
                }
                SegmentHit::Overlap => {
                    c.fail_at(path, format!("segment {k} runs along the outline"));
                    return;
                }
            }
        }
    }
}

/// No point inside the hole, no segment reaching it (the first point may lie on it).
fn check_clear_of_hole(c: &mut Checker, path: &str, pts: &[P2], h: &HoleShape, k: usize, tol: f64) {
    for (s, w) in pts.windows(2).enumerate() {
        let clearance = h.segment_clearance(&w[0], &w[1]);
        if clearance > tol {
            continue;
        }
        let mouth_on_hole =
            s == 0 && h.boundary_distance(&w[0]) <= tol && !h.contains(&w[1], tol) && {
                // Only the mouth touches: shorten the segment slightly and re-test.
                let a = w[0] + (w[1] - w[0]) * 1e-6;
                h.segment_clearance(&a, &w[1]) > 0.0
            };
        if !mouth_on_hole {
            c.fail_at(
                path,
                format!("crack crossing a hole: segment {s} reaches body.holes.{k}"),
            );
            return;
        }
    }
}

/// Gap faces: gap > 0 and much smaller than the crack.
fn check_faces(c: &mut Checker, path: &str, crack: &Crack, length: f64) {
    if let Faces::Gap(g) = crack.faces {
        let p = format!("{path}.faces");
        if c.positive(&p, g, "face gap") && g >= 0.25 * length {
            c.fail(p, g, "face gap must be below 0.25 of the crack length");
        }
    }
}

fn polyline_self_crossing(pts: &[P2]) -> bool {
    let n = pts.len();
    for i in 0..n.saturating_sub(1) {
        for j in (i + 2)..n.saturating_sub(1) {
            if segment_intersection(&pts[i], &pts[i + 1], &pts[j], &pts[j + 1]) != SegmentHit::None
            {
                return true;
            }
        }
        if i + 2 < n {
            // Adjacent segments folding back overlap.
            if segment_intersection(&pts[i], &pts[i + 1], &pts[i + 1], &pts[i + 2])
                == SegmentHit::Overlap
            {
                return true;
            }
        }
    }
    false
}

fn polylines_cross(a: &[P2], b: &[P2]) -> bool {
    a.windows(2).any(|s| {
        b.windows(2)
            .any(|t| segment_intersection(&s[0], &s[1], &t[0], &t[1]) != SegmentHit::None)
    })
}
