//! Holes closer to another boundary than the elements there: the ligament between a hole
//! and the outline (or another hole) is narrower than the BEM elements on its sides, and
//! the stress in it is not resolved.
//!
//! The stress in a ligament of width $g$ next to a hole of radius $R$ grows as the
//! ligament thins (about as $\sqrt{R/g}$), and constant elements follow it once they are
//! no longer than $g$ on both sides. Measured on a 0.2 m x 0.1 m plate pulled along its
//! length by 1 Pa, a hole of R = 0.01 m at a gap g under its top edge, the peak hoop stress
//! (`hoop_peak`) of the default mesh (hole elements 4.9e-4 m, edge elements 1e-3 m) against
//! a reference with elements of g / 8 on both sides (converged to within 1 %), as
//! g / h with h the larger of the two element sizes at the gap:
//!
//! | g / h | default (estimate) | reference | error |
//! |---|---|---|---|
//! | 5 | 5.25 (0.04) | 5.23 | +0.2 % |
//! | 3 | 6.63 (0.19) | 6.55 | +1.3 % |
//! | 2 | 8.23 (0.68) | 7.94 | +3.7 % |
//! | 1.5 | 9.89 (1.92) | 9.14 | +8.1 % |
//! | 1 | 14.5 (26) | 11.2 | +29 % |
//! | 0.5 | 25.4 (12.5) | 15.8 | +60 % |
//! | 0.3 | 43.4 (31) | 20.8 | +109 % |
//! | 0.1 | 22.7 (5.2) | 36.8 | -38 % |
//!
//! (the g / h = 0.5 row on an outline whose top edge is three pieces, the same sizes).
//! Down to g = h the two-level estimate follows the error; below it the value jumps either
//! way and the estimate with it, missing the error at g / h = 0.1 (and at 0.01, against
//! the sqrt(R/g) extrapolation of the references: 35 with an estimate of 72 against about
//! 115). One side refined is not enough: at g / h = 0.3 with the hole at elements of g / 10
//! (2048 per circle) and the edge at its default the peak is 49.2 (estimate 13.8), with the
//! edge at g / 8 and the hole at its default 41.8 (16.1), against 20.8.
//!
//! So a hole whose gap to the outline or to another hole is less than [`GAP_RESOLUTION`]
//! times the larger element size at the gap gets a note (in every mode whose fields come
//! from the BEM, and in `pdbem check`) naming the sizes that resolve it. Gaps between a
//! hole and a crack are the crack's ligament ([`super::thin_ligament`]) or its tip's
//! length scale ([`super::sizing`]); necks of the outline itself are
//! [`super::outline_necks`]'s.

use pdbem_bem::mesh::{Element, Mesh};

use crate::geometry::{segment_segment_distance, P2};
use crate::scene::shapes::{HoleShape, SceneGeometry};
use crate::scene::Scene;

/// A hole whose gap to another boundary is less than this many times the larger element
/// size at the gap gets a note (module docs: at 1 the estimate still covered the error,
/// at 0.1 it missed it).
pub const GAP_RESOLUTION: f64 = 1.0;

/// Elements of this fraction of the gap on both sides resolve it: measured at g / 4, the
/// hoop peak 1.9 % (g = 0.1 R), 3.9 % (0.03 R) and 7.0 % (0.01 R) above its value at
/// g / 8, within the estimates (8 %, 22 %, 68 %); g / 8 against g / 4 at most 7 %.
pub const RESOLVING_FRACTION: f64 = 0.25;

/// The narrowest gap between a hole and another loop of the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct HoleGap {
    /// Hole index in scene order.
    pub hole: usize,
    /// The other boundary: an outline edge group or another hole's name.
    pub other: String,
    /// Whether `other` is a hole.
    pub other_is_hole: bool,
    /// Gap width (m).
    pub gap: f64,
    /// Length of the hole's element at the gap (m).
    pub h_hole: f64,
    /// Length of the other boundary's element at the gap (m).
    pub h_other: f64,
    /// Midpoint of the gap (m).
    pub at: P2,
}

impl HoleGap {
    /// Gap over the larger element size at the gap.
    pub fn resolution(&self) -> f64 {
        self.gap / self.h_hole.max(self.h_other)
    }
}

/// The narrowest gap of every hole of `mesh` (the static BEM mesh of `geo`) to the other
/// loops: the outline and the other holes.
pub fn gaps(geo: &SceneGeometry, mesh: &Mesh) -> Vec<HoleGap> {
    let loop_hole = |r: &std::ops::Range<usize>| {
        let name = &mesh.groups[mesh.elements[r.start].group];
        geo.holes.iter().position(|(n, _)| n == name)
    };
    let loops: Vec<(Option<usize>, &[Element])> = mesh
        .loops
        .iter()
        .filter(|r| !r.is_empty())
        .map(|r| (loop_hole(r), &mesh.elements[r.clone()]))
        .collect();
    let mut out = Vec::new();
    for (i, (hole, elements)) in loops.iter().enumerate() {
        let Some(hole) = *hole else { continue };
        let others = loops
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .flat_map(|(_, (_, e))| e.iter());
        if let Some((d, e, f)) = nearest_pair(elements, others) {
            let other_is_hole = geo.holes.iter().any(|(n, _)| *n == mesh.groups[f.group]);
            out.push(HoleGap {
                hole,
                other: mesh.groups[f.group].clone(),
                other_is_hole,
                gap: d,
                h_hole: e.h,
                h_other: f.h,
                at: nearest_midpoint(e, f),
            });
        }
    }
    out
}

/// The closest pair (distance, element of `a`, element of `others`). Elements of `others`
/// are visited nearest bounding box first and the search stops when the next box lies
/// farther than the best pair.
fn nearest_pair<'a>(
    a: &'a [Element],
    others: impl Iterator<Item = &'a Element>,
) -> Option<(f64, &'a Element, &'a Element)> {
    let (lo, hi) = bounds(a.iter().flat_map(|e| [e.a, e.b]));
    let mut ranked: Vec<(f64, &Element)> = others
        .map(|f| {
            let (flo, fhi) = bounds([f.a, f.b].into_iter());
            (box_distance((lo, hi), (flo, fhi)), f)
        })
        .collect();
    ranked.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut best: Option<(f64, &Element, &Element)> = None;
    for (box_d, f) in ranked {
        if best.is_some_and(|b| box_d > b.0) {
            break;
        }
        for e in a {
            let d = segment_segment_distance(&e.a, &e.b, &f.a, &f.b);
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, e, f));
            }
        }
    }
    best
}

fn bounds(points: impl Iterator<Item = P2>) -> (P2, P2) {
    points.fold(
        (P2::repeat(f64::INFINITY), P2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(&p), hi.sup(&p)),
    )
}

fn box_distance(a: (P2, P2), b: (P2, P2)) -> f64 {
    let dx = (b.0.x - a.1.x).max(a.0.x - b.1.x).max(0.0);
    let dy = (b.0.y - a.1.y).max(a.0.y - b.1.y).max(0.0);
    dx.hypot(dy)
}

/// Midpoint between the nearer ends of two elements (where the note says the gap is).
pub(super) fn nearest_midpoint(e: &Element, f: &Element) -> P2 {
    let pe = closest_on(e, f);
    let pf = closest_on(f, e);
    0.5 * (pe + pf)
}

/// The point of element `e` nearest element `f` (nearest of its ends or of the
/// projections of `f`'s ends).
pub(super) fn closest_on(e: &Element, f: &Element) -> P2 {
    let project = |p: &P2| {
        let t = ((p - e.a).dot(&e.tangent)).clamp(0.0, e.h);
        e.a + e.tangent * t
    };
    [e.a, e.b, project(&f.a), project(&f.b)]
        .into_iter()
        .min_by(|x, y| {
            let dx = crate::geometry::point_segment_distance(x, &f.a, &f.b);
            let dy = crate::geometry::point_segment_distance(y, &f.a, &f.b);
            dx.total_cmp(&dy)
        })
        .unwrap_or(e.mid)
}

/// The gaps of `scene`'s static BEM mesh (refinement 1) under [`GAP_RESOLUTION`]. A scene
/// that does not mesh has none here (its run refuses it).
pub fn unresolved(scene: &Scene) -> Vec<HoleGap> {
    let geo = SceneGeometry::of(scene);
    if geo.holes.is_empty() {
        return Vec::new();
    }
    let Ok(builder) = super::bem::mesh_builder(scene, &geo, 1.0) else {
        return Vec::new();
    };
    let Ok(mesh) = builder.build() else {
        return Vec::new();
    };
    let all = gaps(&geo, &mesh);
    let names: Vec<&str> = geo.holes.iter().map(|(n, _)| n.as_str()).collect();
    // Two holes nearest each other: one note, on the first.
    let reported_by_other = |g: &HoleGap| {
        all.iter().any(|o| {
            o.hole < g.hole
                && g.other_is_hole
                && g.other == names[o.hole]
                && o.other == names[g.hole]
        })
    };
    all.iter()
        .filter(|g| g.resolution() < GAP_RESOLUTION && !reported_by_other(g))
        .cloned()
        .collect()
}

/// The note of an unresolved gap, with the sizes that resolve it.
pub fn note(scene: &Scene, g: &HoleGap) -> String {
    let geo = SceneGeometry::of(scene);
    let (name, shape) = &geo.holes[g.hole];
    let fine = RESOLVING_FRACTION * g.gap;
    let mut advice = Vec::new();
    if g.h_hole > fine {
        advice.push(match shape {
            HoleShape::Circle { radius, .. } => format!(
                "bem.elements_per_circle >= {:.0}",
                (std::f64::consts::TAU * radius / fine).ceil()
            ),
            HoleShape::Polygon(_) => format!("bem.group_sizes.{name} <= {fine:.3e} m"),
        });
    }
    if g.h_other > fine {
        advice.push(if g.other_is_hole {
            format!("the same for '{}'", g.other)
        } else {
            format!(
                "bem.group_sizes.{} <= {fine:.3e} m (an Edges outline gives a short piece of an \
                 edge its own size)",
                g.other
            )
        });
    }
    format!(
        "holes.{} ('{name}'): its gap to {} '{}' at ({:.4e}, {:.4e}) is {:.3e} m, {:.2} of the \
         larger element there (hole {:.3e} m, '{}' {:.3e} m; a note under {GAP_RESOLUTION}): \
         the stress in that ligament (hoop_peak_{name}, boundary.csv, fields near it) is not \
         resolved, and below one element the two-level estimate was measured to miss the error \
         (a hoop peak 38 % low with an estimate of 14 %, 2.4x high with an estimate of 28 % \
         when only the hole was refined); elements of a quarter of the gap on both sides \
         resolve it (measured within 7 %, within their estimate): {}",
        g.hole,
        if g.other_is_hole {
            "hole"
        } else {
            "the outline edge"
        },
        g.other,
        g.at.x,
        g.at.y,
        g.gap,
        g.resolution(),
        g.h_hole,
        g.other,
        g.h_other,
        advice.join(" and "),
    )
}
