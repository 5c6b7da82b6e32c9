//! Rules of `body`: outline, holes, patches.

use super::{fmt_pt, Checker};
use crate::geometry::{
    bounding_box, p2, point_in_polygon, polygon_distance, polygon_self_intersection, signed_area,
    P2,
};
use crate::scene::shapes::{hole_shape, outline_loop, segment_segment_distance, HoleShape};
use crate::scene::{Hole, Outline, Scene};

/// Checks the outline, holes and patches; returns true when the outline and
/// holes are sound enough for the crack rules to use.
pub fn check(c: &mut Checker, scene: &Scene) -> bool {
    let before = c.issues.len();
    let outline = check_outline(c, &scene.body.outline);
    if c.issues.len() > before {
        return false;
    }
    let holes_ok = check_holes(c, scene, outline.as_deref());
    check_patches(c, scene, outline.as_deref());
    holes_ok
}

/// Outline rules; returns the outline points when finite and sound.
fn check_outline(c: &mut Checker, outline: &Outline) -> Option<Vec<P2>> {
    match outline {
        Outline::Rectangle {
            x0,
            y0,
            width,
            height,
        } => {
            c.finite("body.outline.x0", *x0);
            c.finite("body.outline.y0", *y0);
            c.positive("body.outline.width", *width, "rectangle width");
            c.positive("body.outline.height", *height, "rectangle height");
        }
        Outline::Polygon { points, edge_names } => {
            if let Some(names) = edge_names {
                if names.len() != points.len() {
                    c.fail(
                        "body.outline.edge_names",
                        names.len(),
                        format!(
                            "give one name per edge: the polygon has {} edges",
                            points.len()
                        ),
                    );
                }
            }
            check_polygon(c, "body.outline.points", &to_p2(points));
        }
        Outline::Edges { edges } => check_chain(c, edges),
        Outline::Infinite { sxx, syy, sxy } => {
            c.finite("body.outline.sxx", *sxx);
            c.finite("body.outline.syy", *syy);
            c.finite("body.outline.sxy", *sxy);
            return None;
        }
    }
    Some(outline_loop(outline)?.points)
}

fn to_p2(points: &[(f64, f64)]) -> Vec<P2> {
    points.iter().map(|p| p2(*p)).collect()
}

/// A simple closed polygon: >= 3 finite points, no zero-length edge, not
/// self-intersecting, non-zero area.
pub fn check_polygon(c: &mut Checker, path: &str, pts: &[P2]) -> bool {
    if pts.len() < 3 {
        c.fail(
            path,
            format!("{} points", pts.len()),
            "a polygon needs at least 3 points",
        );
        return false;
    }
    if pts.iter().any(|p| !p.x.is_finite() || !p.y.is_finite()) {
        c.fail_at(path, "coordinates must be finite numbers");
        return false;
    }
    let n = pts.len();
    let (lo, hi) = bounding_box(pts);
    let size = (hi - lo).norm();
    for i in 0..n {
        if (pts[(i + 1) % n] - pts[i]).norm() <= 1e-12 * size {
            c.fail(
                format!("{path}.{}", (i + 1) % n),
                fmt_pt(&pts[(i + 1) % n]),
                format!("repeats point {i}: edges must have non-zero length (the polygon closes itself; do not repeat the first point)"),
            );
            return false;
        }
    }
    if let Some((i, j)) = polygon_self_intersection(pts) {
        c.fail_at(
            path,
            format!("outline is self-intersecting: edge {i} meets edge {j}"),
        );
        return false;
    }
    if signed_area(pts).abs() <= 1e-12 * size * size {
        c.fail_at(path, "polygon has zero area");
        return false;
    }
    true
}

/// `Edges` outline: each piece >= 2 points, consecutive pieces join, the last
/// returns to the first, and the resulting polygon is simple.
fn check_chain(c: &mut Checker, edges: &[crate::scene::NamedEdge]) {
    if edges.is_empty() {
        c.fail_at("body.outline.edges", "an outline needs at least one edge");
        return;
    }
    let all: Vec<P2> = edges.iter().flat_map(|e| to_p2(&e.points)).collect();
    let (lo, hi) = bounding_box(&all);
    let tol = 1e-9 * (hi - lo).norm().max(1e-300);
    for (i, e) in edges.iter().enumerate() {
        if e.points.len() < 2 {
            c.fail(
                format!("body.outline.edges.{i}.points"),
                format!("{} points", e.points.len()),
                "an edge needs at least 2 points",
            );
            return;
        }
    }
    for (i, e) in edges.iter().enumerate() {
        let next = &edges[(i + 1) % edges.len()];
        let end = p2(*e.points.last().unwrap_or(&(0.0, 0.0)));
        let start = p2(next.points[0]);
        if (end - start).norm() > tol {
            c.fail_at(
                format!("body.outline.edges.{i}"),
                format!(
                    "outline not closed: edge '{}' ends at {} but edge '{}' starts at {}",
                    e.name,
                    fmt_pt(&end),
                    next.name,
                    fmt_pt(&start)
                ),
            );
            return;
        }
    }
    if let Some(lp) = outline_loop(&Outline::Edges {
        edges: edges.to_vec(),
    }) {
        check_polygon(c, "body.outline.edges", &lp.points);
    }
}

/// Each hole is valid, inside the outline, clear of the outline and of the other holes.
fn check_holes(c: &mut Checker, scene: &Scene, outline: Option<&[P2]>) -> bool {
    let before = c.issues.len();
    let mut shapes: Vec<(usize, HoleShape)> = Vec::new();
    for (i, hole) in scene.body.holes.iter().enumerate() {
        let path = format!("body.holes.{i}");
        if !check_hole_shape(c, &path, hole) {
            continue;
        }
        let shape = hole_shape(hole);
        if let Some(o) = outline {
            check_hole_in_outline(c, &path, &shape, o);
        }
        for (j, other) in &shapes {
            if holes_overlap(&shape, other) {
                c.fail_at(
                    path.clone(),
                    format!("hole overlaps body.holes.{j}: holes must be apart"),
                );
            }
        }
        shapes.push((i, shape));
    }
    c.issues.len() == before
}

fn check_hole_shape(c: &mut Checker, path: &str, hole: &Hole) -> bool {
    match hole {
        Hole::Circle { center, radius, .. } => {
            let ok = c.finite(&format!("{path}.center"), center.0)
                & c.finite(&format!("{path}.center"), center.1);
            ok & c.positive(&format!("{path}.radius"), *radius, "hole radius")
        }
        Hole::Polygon { points, .. } => check_polygon(c, &format!("{path}.points"), &to_p2(points)),
    }
}

fn check_hole_in_outline(c: &mut Checker, path: &str, shape: &HoleShape, outline: &[P2]) {
    let boundary = shape.polygon();
    let probe = match shape {
        HoleShape::Circle { center, .. } => *center,
        HoleShape::Polygon(p) => p[0],
    };
    if !point_in_polygon(&probe, outline) && polygon_distance(&probe, outline) > 0.0 {
        c.fail_at(path, "hole lies outside the body outline");
        return;
    }
    let clear = match shape {
        HoleShape::Circle { center, radius } => polygon_distance(center, outline) > *radius,
        HoleShape::Polygon(p) => {
            p.iter().all(|q| point_in_polygon(q, outline))
                && crate::geometry::polyline_polygon_hit(&closed(p), outline).is_none()
        }
    };
    if !clear || boundary.iter().any(|q| !point_in_polygon(q, outline)) {
        c.fail_at(
            path,
            "hole overlaps the outline: it must lie strictly inside the body",
        );
    }
}

fn closed(p: &[P2]) -> Vec<P2> {
    let mut v = p.to_vec();
    v.push(p[0]);
    v
}

/// True when two holes touch or overlap (circles exactly, others through their polygons).
fn holes_overlap(a: &HoleShape, b: &HoleShape) -> bool {
    if let (
        HoleShape::Circle {
            center: c1,
            radius: r1,
        },
        HoleShape::Circle {
            center: c2,
            radius: r2,
        },
    ) = (a, b)
    {
        return (c1 - c2).norm() <= r1 + r2;
    }
    let (pa, pb) = (a.polygon(), b.polygon());
    if pa.iter().any(|p| b.contains(p, 0.0)) || pb.iter().any(|p| a.contains(p, 0.0)) {
        return true;
    }
    let n = pa.len();
    let m = pb.len();
    (0..n).any(|i| {
        (0..m).any(|j| {
            segment_segment_distance(&pa[i], &pa[(i + 1) % n], &pb[j], &pb[(j + 1) % m]) == 0.0
        })
    })
}

/// Patches: named, on one outline edge, non-zero length.
fn check_patches(c: &mut Checker, scene: &Scene, outline: Option<&[P2]>) {
    for (i, patch) in scene.body.patches.iter().enumerate() {
        let path = format!("body.patches.{i}");
        let Some(o) = outline else {
            c.fail_at(path, "an infinite plate has no outline to put a patch on");
            continue;
        };
        let (a, b) = (p2(patch.from), p2(patch.to));
        if (b - a).norm() == 0.0 {
            c.fail_at(path, "patch has zero length");
            continue;
        }
        let n = o.len();
        let tol = 1e-9 * crate::geometry::scale_of(o).max(1.0);
        let on_one_edge = (0..n).any(|k| {
            let (p, q) = (&o[k], &o[(k + 1) % n]);
            crate::geometry::point_segment_distance(&a, p, q) <= tol
                && crate::geometry::point_segment_distance(&b, p, q) <= tol
        });
        if !on_one_edge {
            c.fail_at(
                path,
                "patch end points must both lie on the same outline edge",
            );
        }
    }
}
