//! What the geometry plot draws besides the body: load arrows and supports from the
//! scene's `boundary`, the PD window outlines of coupled and PD-BEM growth runs, and the
//! direction in which each tip's label is pushed off its crack.
//!
//! Arrows follow the traction t = sigma . n of each loaded edge group (one arrow per
//! stretch of about 1/12 of the body's size, all of one length: they show direction,
//! not magnitude); an arrow of a tension load starts on the edge and points away from the
//! body, one of a compression load ends on the edge. A prescribed displacement of zero is
//! a support (square markers), a non-zero one an arrow of its own colour.

use crate::geometry::P2;
use crate::plot::geometry::{Arrow, ArrowKind};
use crate::scene::shapes::SceneGeometry;
use crate::scene::{BoundaryCondition, Component, GrowthMode, Scene};

/// Arrows and support markers of a scene's boundary conditions.
pub fn boundary_marks(scene: &Scene) -> (Vec<Arrow>, Vec<(f64, f64)>) {
    let geo = SceneGeometry::of(scene);
    let (lo, hi) = geo.bounds();
    let size = (hi - lo).norm().max(1e-300);
    let mut arrows = Vec::new();
    let mut supports = Vec::new();
    for bc in &scene.boundary {
        for (a, b, n) in group_edges(scene, &geo, &bc.on) {
            let len = (b - a).norm();
            let count = ((len / (size / 12.0)).round() as usize).clamp(1, 8);
            for k in 0..count {
                let p = a + (b - a) * ((k as f64 + 0.5) / count as f64);
                marks_at(bc, p, n, (b - a) / len.max(1e-300), size, &mut arrows);
                if is_support(bc) {
                    supports.push((p.x + 0.01 * size * n.x, p.y + 0.01 * size * n.y));
                }
            }
        }
    }
    (arrows, supports)
}

/// True when the condition holds a component at zero displacement.
fn is_support(bc: &BoundaryCondition) -> bool {
    [bc.x, bc.y].contains(&Component::Displacement(0.0))
}

/// The arrows of `bc` at edge point `p` with outward normal `n` and running direction `t`.
fn marks_at(bc: &BoundaryCondition, p: P2, n: P2, t: P2, size: f64, out: &mut Vec<Arrow>) {
    let comp = |c: Component| match c {
        Component::Traction(v) => (v, 0.0),
        Component::Displacement(v) => (0.0, v),
        Component::Free => (0.0, 0.0),
    };
    let ((tx, ux), (ty, uy)) = (comp(bc.x), comp(bc.y));
    let traction = P2::new(tx, ty) + n * bc.normal.unwrap_or(0.0) + t * bc.shear.unwrap_or(0.0);
    let shown = 0.07 * size;
    if traction.norm() > 0.0 {
        out.push(arrow(
            p,
            traction / traction.norm(),
            n,
            shown,
            ArrowKind::Traction,
        ));
    }
    let u = P2::new(ux, uy);
    if u.norm() > 0.0 {
        out.push(arrow(p, u / u.norm(), n, shown, ArrowKind::Displacement));
    }
}

/// An arrow of length `len` along `d` at edge point `p`: from the edge outwards when `d`
/// points out of the body, onto the edge from outside when it points in; an arrow along
/// the edge (shear) a quarter of its length outside, so it does not cover the edge.
fn arrow(p: P2, d: P2, n: P2, len: f64, kind: ArrowKind) -> Arrow {
    let along = d.dot(&n);
    let base = if along.abs() < 0.3 {
        p + n * 0.25 * len
    } else {
        p
    };
    let (from, to) = if along >= -1e-12 {
        (base, base + d * len)
    } else {
        (base - d * len, base)
    };
    Arrow {
        from: (from.x, from.y),
        to: (to.x, to.y),
        kind,
    }
}

/// The straight edges `(a, b, outward normal)` of an edge group: outline edges, a patch,
/// or a hole (whose outward normal points into the hole). Crack faces give none.
fn group_edges(scene: &Scene, geo: &SceneGeometry, group: &str) -> Vec<(P2, P2, P2)> {
    let right = |a: P2, b: P2| {
        let d = (b - a) / (b - a).norm().max(1e-300);
        P2::new(d.y, -d.x)
    };
    let mut out = Vec::new();
    if let Some(o) = &geo.outline {
        let m = o.points.len();
        for i in 0..m {
            if o.groups[i] == group || group == "outline" {
                let (a, b) = (o.points[i], o.points[(i + 1) % m]);
                out.push((a, b, right(a, b)));
            }
        }
    }
    if let Some(p) = scene.body.patches.iter().find(|p| p.name == group) {
        let (a, b) = (crate::geometry::p2(p.from), crate::geometry::p2(p.to));
        let n = outline_normal_at(geo, (a + b) * 0.5).unwrap_or_else(|| right(a, b));
        out.push((a, b, n));
    }
    if let Some((_, h)) = geo.holes.iter().find(|(n, _)| n == group) {
        let mut pts = h.polygon();
        if crate::geometry::is_ccw(&pts) {
            pts.reverse();
        }
        let m = pts.len();
        // A circle's polygon has many short edges: take every few of them.
        let every = (m / 12).max(1);
        for i in (0..m).step_by(every) {
            let (a, b) = (pts[i], pts[(i + every).min(m) % m]);
            out.push((a, b, right(a, b)));
        }
    }
    out
}

/// Outward normal of the outline edge nearest to `p`.
fn outline_normal_at(geo: &SceneGeometry, p: P2) -> Option<P2> {
    let o = geo.outline.as_ref()?;
    let m = o.points.len();
    (0..m)
        .map(|i| (o.points[i], o.points[(i + 1) % m]))
        .min_by(|x, y| {
            let d = |e: &(P2, P2)| crate::geometry::point_segment_distance(&p, &e.0, &e.1);
            d(x).partial_cmp(&d(y)).unwrap_or(std::cmp::Ordering::Equal)
        })
        .map(|(a, b)| {
            let d = (b - a) / (b - a).norm().max(1e-300);
            P2::new(d.y, -d.x)
        })
}

/// Outlines of the PD windows of a coupled or PD-BEM growth scene (none otherwise, or
/// when the windows cannot be built).
pub fn window_outlines(scene: &Scene) -> Vec<Vec<(f64, f64)>> {
    let (Some(co), Some(pd)) = (&scene.coupling, &scene.pd) else {
        return Vec::new();
    };
    if scene
        .growth
        .as_ref()
        .is_some_and(|g| g.mode != GrowthMode::PdBem)
    {
        return Vec::new();
    }
    let geo = SceneGeometry::of(scene);
    let Ok((specs, _)) = crate::setup::coupled::window_specs(scene, &geo, co, pd) else {
        return Vec::new();
    };
    specs
        .iter()
        .map(|w| {
            let (c, s) = (w.angle.cos(), w.angle.sin());
            let (hx, hy) = (0.5 * w.nx as f64 * w.dx, 0.5 * w.ny as f64 * w.dx);
            [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]
                .iter()
                .map(|(x, y)| (w.center.x + c * x - s * y, w.center.y + s * x + c * y))
                .collect()
        })
        .collect()
}

/// Unit direction of each named tip out of its crack (for placing its label), or
/// `(0, 1)` for a tip the scene geometry does not know.
pub fn tip_directions(scene: &Scene, tips: &[(String, (f64, f64))]) -> Vec<(f64, f64)> {
    let geo = SceneGeometry::of(scene);
    let known: Vec<(String, P2, P2)> = geo.cracks.iter().flat_map(|c| c.tip_directions()).collect();
    tips.iter()
        .map(|(name, _)| {
            known
                .iter()
                .find(|(n, _, _)| n == name)
                .map_or((0.0, 1.0), |(_, _, d)| (d.x, d.y))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const PLATE: &str = r#"(
        name: "marks",
        material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 2, height: 1)),
        cracks: [(name: "c", center: (1, 0.5), angle_deg: 0, length: 0.4)],
        boundary: [
            (on: "top", y: Traction(1)),
            (on: "bottom", y: Traction(-1)),
            (on: "left", x: Displacement(0)),
            (on: "right", normal: -2),
        ],
    )"#;

    #[test]
    fn arrows_point_out_for_tension_and_in_for_compression() {
        let s = Scene::from_ron_str(PLATE, "marks.ron").expect("valid");
        let (arrows, supports) = boundary_marks(&s);
        let top: Vec<_> = arrows.iter().filter(|a| a.from.1 >= 1.0 - 1e-9).collect();
        assert!(
            !top.is_empty() && top.iter().all(|a| a.to.1 > a.from.1),
            "{top:?}"
        );
        let bottom: Vec<_> = arrows.iter().filter(|a| a.from.1 <= 1e-9).collect();
        assert!(!bottom.is_empty() && bottom.iter().all(|a| a.to.1 < a.from.1));
        // Compression on the right: the arrow ends on the edge, pointing in (-x).
        let right: Vec<_> = arrows
            .iter()
            .filter(|a| (a.to.0 - 2.0).abs() < 1e-9)
            .collect();
        assert!(!right.is_empty() && right.iter().all(|a| a.from.0 > a.to.0));
        assert!(!supports.is_empty() && supports.iter().all(|p| p.0 < 0.0));
        let dirs = tip_directions(
            &s,
            &[("c.end".into(), (1.2, 0.5)), ("c.start".into(), (0.8, 0.5))],
        );
        assert_eq!(dirs, [(1.0, 0.0), (-1.0, 0.0)]);
    }
}
