//! Scene geometry as points: the outline loop with the group of each edge,
//! hole shapes, and crack polylines with their mouths. Built from a valid
//! scene by [`SceneGeometry::of`]; validation builds the same pieces one at a
//! time so it can report what is wrong with each.

use super::body::{Hole, Outline};
use super::Scene;
use crate::geometry::{p2, point_in_polygon, polygon_distance, scale_of, P2};
pub use crate::geometry::{segment_segment_distance, HoleShape, CIRCLE_POINTS};

/// A closed loop of straight edges; `groups[i]` names edge i (point i to i+1).
#[derive(Debug, Clone, PartialEq)]
pub struct Loop {
    /// Corner points (m), counter-clockwise for the outline.
    pub points: Vec<P2>,
    /// Group name of each edge.
    pub groups: Vec<String>,
}

/// A crack as a polyline, first point to last.
#[derive(Debug, Clone, PartialEq)]
pub struct CrackLine {
    /// Crack name.
    pub name: String,
    /// Points (m).
    pub points: Vec<P2>,
    /// True when the first point lies on the outline (an edge crack; CMOD is reported).
    pub mouth: bool,
}

impl CrackLine {
    /// Crack tips: the last point, and the first unless it is a mouth, as
    /// `(tip name, position)`; tip names are `<crack>.end` and `<crack>.start`.
    pub fn tips(&self) -> Vec<(String, P2)> {
        let mut t = Vec::new();
        if !self.mouth {
            if let Some(p) = self.points.first() {
                t.push((format!("{}.start", self.name), *p));
            }
        }
        if let Some(p) = self.points.last() {
            t.push((format!("{}.end", self.name), *p));
        }
        t
    }

    /// Crack tips with their growth directions: `(tip name, position, unit vector along
    /// the last segment, pointing out of the crack)`, the start first unless it is a
    /// mouth; none for a polyline of fewer than two points.
    pub fn tip_directions(&self) -> Vec<(String, P2, P2)> {
        let p = &self.points;
        let n = p.len();
        if n < 2 {
            return Vec::new();
        }
        let unit = |d: P2| d / d.norm().max(1e-300);
        let mut t = Vec::new();
        if !self.mouth {
            t.push((format!("{}.start", self.name), p[0], unit(p[0] - p[1])));
        }
        t.push((
            format!("{}.end", self.name),
            p[n - 1],
            unit(p[n - 1] - p[n - 2]),
        ));
        t
    }
}

/// The whole scene geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneGeometry {
    /// Outer loop; `None` for an infinite plate.
    pub outline: Option<Loop>,
    /// Holes with their group names.
    pub holes: Vec<(String, HoleShape)>,
    /// Cracks.
    pub cracks: Vec<CrackLine>,
    /// Remote stress `[sxx, syy, sxy]` (Pa) of an infinite plate.
    pub remote: Option<[f64; 3]>,
}

/// The outline as a loop (as written: orientation is normalised on load), or
/// `None` for an infinite plate or an `Edges` chain that does not close.
pub fn outline_loop(outline: &Outline) -> Option<Loop> {
    match outline {
        Outline::Rectangle {
            x0,
            y0,
            width,
            height,
        } => Some(Loop {
            points: vec![
                P2::new(*x0, *y0),
                P2::new(x0 + width, *y0),
                P2::new(x0 + width, y0 + height),
                P2::new(*x0, y0 + height),
            ],
            groups: outline.edge_names(),
        }),
        Outline::Polygon { points, .. } => Some(Loop {
            points: points.iter().map(|p| p2(*p)).collect(),
            groups: outline.edge_names(),
        }),
        Outline::Edges { edges } => {
            let mut points = Vec::new();
            let mut groups = Vec::new();
            for e in edges {
                let n = e.points.len();
                for p in e.points.iter().take(n.saturating_sub(1)) {
                    points.push(p2(*p));
                    groups.push(e.name.clone());
                }
            }
            Some(Loop { points, groups })
        }
        Outline::Infinite { .. } => None,
    }
}

impl SceneGeometry {
    /// Geometry of a scene (meant for validated scenes; incomplete cracks are skipped).
    pub fn of(scene: &Scene) -> SceneGeometry {
        let outline = outline_loop(&scene.body.outline);
        let holes: Vec<(String, HoleShape)> = scene
            .body
            .holes
            .iter()
            .enumerate()
            .map(|(i, h)| (h.name(i), hole_shape(h)))
            .collect();
        let cracks = scene
            .cracks
            .iter()
            .filter_map(|c| {
                let points = c.polyline()?;
                let mouth = outline
                    .as_ref()
                    .is_some_and(|o| on_loop(&points[0], &o.points));
                Some(CrackLine {
                    name: c.name.clone(),
                    points,
                    mouth,
                })
            })
            .collect();
        SceneGeometry {
            outline,
            holes,
            cracks,
            remote: scene.body.outline.remote_stress(),
        }
    }

    /// Bounding box `(min, max)` of everything drawn (outline, holes, cracks).
    pub fn bounds(&self) -> (P2, P2) {
        let mut pts: Vec<P2> = Vec::new();
        if let Some(o) = &self.outline {
            pts.extend(o.points.iter().copied());
        }
        for (_, h) in &self.holes {
            pts.extend(h.polygon());
        }
        for c in &self.cracks {
            pts.extend(c.points.iter().copied());
        }
        if pts.is_empty() {
            return (P2::new(-1.0, -1.0), P2::new(1.0, 1.0));
        }
        crate::geometry::bounding_box(&pts)
    }

    /// True when `p` lies in the material: inside the outline (or anywhere for
    /// an infinite plate) and not inside a hole.
    pub fn contains(&self, p: &P2) -> bool {
        let in_outline = self
            .outline
            .as_ref()
            .is_none_or(|o| point_in_polygon(p, &o.points));
        in_outline && !self.holes.iter().any(|(_, h)| h.contains(p, 0.0))
    }

    /// The unit normal, pointing into the body, of the outline edge through the mouth of
    /// edge crack `crack` (its first point) that lies closest to the crack's chord (at a
    /// corner two edges pass through the mouth). `None` without an outline, a mouth on it or
    /// a chord. The axis of Tada's strip: its width runs along it, its tension across it.
    pub fn mouth_axis(&self, crack: &CrackLine) -> Option<P2> {
        let o = self.outline.as_ref()?;
        let (first, last) = (crack.points.first()?, crack.points.last()?);
        let chord = last - first;
        let len = chord.norm();
        if len == 0.0 {
            return None;
        }
        let d = chord / len;
        let n = o.points.len();
        (0..n)
            .filter_map(|i| {
                let (p, q) = (o.points[i], o.points[(i + 1) % n]);
                let t = q - p;
                let on = crate::geometry::point_segment_distance(first, &p, &q)
                    <= 1e-9 * len.max(t.norm());
                let m = P2::new(-t.y, t.x) / t.norm();
                on.then(|| if m.dot(&d) < 0.0 { -m } else { m })
            })
            .max_by(|a, b| a.dot(&d).total_cmp(&b.dot(&d)))
    }

    /// All tips `(name, position)` of all cracks.
    pub fn tips(&self) -> Vec<(String, P2)> {
        self.cracks.iter().flat_map(|c| c.tips()).collect()
    }
}

/// True when `p` lies on the loop within a relative tolerance.
pub fn on_loop(p: &P2, pts: &[P2]) -> bool {
    polygon_distance(p, pts) <= 1e-9 * scale_of(pts).max(1.0)
}

/// Exact shape of a scene hole.
pub fn hole_shape(hole: &Hole) -> HoleShape {
    match hole {
        Hole::Circle { center, radius, .. } => HoleShape::Circle {
            center: p2(*center),
            radius: *radius,
        },
        Hole::Polygon { points, .. } => HoleShape::Polygon(points.iter().map(|p| p2(*p)).collect()),
    }
}
