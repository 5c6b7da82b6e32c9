//! The one BEM sizing rule of a scene, used by validation, `check` and every mode of
//! `run` (static BEM, coupled, all three growth modes).
//!
//! Element sizes (each divided by the refinement factor `refine`, 2 for the fine level of
//! a Richardson pair):
//! - **outline edges and polygon holes**: `bem.group_sizes.<group>`, else
//!   `bem.element_size`, else [`DEFAULT_OUTLINE_FRACTION`] of the smaller side of the
//!   outline's bounding box (an infinite plate: [`DEFAULT_CRACK_FRACTION`] of its largest
//!   feature, the longest crack or the largest hole diameter);
//! - **circular holes**: `bem.elements_per_circle` elements (times `refine`), else
//!   [`DEFAULT_ELEMENTS_PER_CIRCLE`];
//! - **crack faces**: `bem.group_sizes.<crack>`, else the smaller of the outline size and
//!   L/80, with L the tip length scale: the crack length for a crack with a mouth (its
//!   first point on the outline or on a hole), half of it for an interior crack, or the
//!   distance from a tip to the nearest outline or hole element when that is shorter. The
//!   interaction integral wants its contour (0.25-0.3 L) at least ~20 elements wide, and
//!   the face reconstruction keeps 0.6 L around each tip constant
//!   (`pdbem_bem::mesh::stencil`). In the coupled modes a crack with a tip in a PD window
//!   is meshed at the window spacing dx instead (unless `bem.group_sizes` names it): the
//!   BEM faces next to a window take the interface's resolution
//!   ([`super::coupled::macro_body`]);
//! - **PD windows**: dx = `coupling.side / coupling.n` ([`crate::scene::Coupling::dx`]).

use std::collections::BTreeMap;

use anyhow::{bail, Result};
use pdbem_bem::mesh::{LoopSpec, SizeField, SizeSource, SourceShape, DEFAULT_GRADING};
use pdbem_coupling::growth::bem_only::sizing::TipSizing;

use crate::geometry::{bounding_box, point_segment_distance, polyline_length, signed_area, P2};
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// Default circle discretization (elements per circular hole).
pub const DEFAULT_ELEMENTS_PER_CIRCLE: usize = 128;
pub use crate::scene::bem::{DEFAULT_CRACK_FRACTION, DEFAULT_OUTLINE_FRACTION};

/// Smallest tip length scale the mesh resolves, relative to the largest extent of the
/// geometry: below it the tip elements (L/80) come within a few hundred ulps of the
/// coordinates and the tip is refused ([`LocalSizes::of`]).
pub const MIN_FEATURE_RATIO: f64 = 1e-7;
/// Radius of the uniform tip zone in units of the tip length scale L. At 1 L the whole
/// ligament of a deep edge crack is meshed at the tip size. Measured on the H = 2W SENT
/// strip at the default element size W/100 (K_I against Tada; against the FEM table
/// where it exists): zone 0.6 L, grading 0.2: a/W = 0.8 +0.46 % (FEM), 0.99 +3.3 %;
/// zone 1 L, grading 0.05: 0.2 -0.02 %, 0.5 -0.12 %, 0.8 +0.03 %, 0.99 +0.45 %.
pub const TIP_ZONE: f64 = 1.0;
/// Grading of the tip sources (element growth about 1.05 per element): the crack faces
/// and the boundaries next to a tip coarsen slowly (see [`TIP_ZONE`]). Refinement
/// divides it with every size: the K error of a graded mesh is about proportional to the
/// grading times the decades between the tip size and the base size (two colinear cracks
/// 1e-4 c apart: grading 0.05 +2.4 %, 0.02 +1.2 %), so h / 2 must halve it too for the
/// h against h / 2 error estimate to see that error.
pub const TIP_GRADING: f64 = 0.05;
/// Far from every crack, hole and patch, default-size outline edges grow (at the field's
/// grading) from the base size to the larger of the base size and
/// min(thickness / 2, diagonal / 100), thickness = 2 area / perimeter of the outline.
pub const FAR_THICKNESS_FRACTION: f64 = 1.0;
/// Radius, in units of the outline's smaller bounding-box side, around cracks, holes and
/// patches within which default-size outline edges keep the base size (ordinary plates
/// lie wholly inside it and mesh exactly as before local sizing).
pub const FEATURE_ZONE: f64 = 1.5;

/// Element sizes of a scene at one refinement level.
#[derive(Debug, Clone, PartialEq)]
pub struct Sizing {
    /// Size where no group size applies (m), refined.
    pub base: f64,
    /// Elements on each circular hole, refined.
    pub per_circle: usize,
    /// Uniform element size of each crack in scene order (m), refined: the coupled and
    /// growth meshes use it along the whole crack.
    pub cracks: Vec<f64>,
    /// `bem.group_sizes`, refined.
    groups: BTreeMap<String, f64>,
}

impl Sizing {
    /// The sizes of `scene` with every size divided by `refine`. The crack length scales
    /// are measured on the outline and hole loops of that level (`loops`).
    pub fn of(scene: &Scene, geo: &SceneGeometry, loops: &[LoopSpec], refine: f64) -> Result<Self> {
        let base0 = scene.bem.base_size(geo);
        let groups: BTreeMap<String, f64> = scene
            .bem
            .group_sizes
            .iter()
            .map(|(g, s)| (g.clone(), s / refine))
            .collect();
        let per_circle = circle_elements(scene, refine);
        let cracks = scene
            .cracks
            .iter()
            .zip(&geo.cracks)
            .map(|(c, line)| {
                let l = crack_length_scale(loops, &line.points, line.mouth);
                scene
                    .bem
                    .group_sizes
                    .get(&c.name)
                    .copied()
                    .unwrap_or_else(|| base0.min(l * DEFAULT_CRACK_FRACTION))
                    / refine
            })
            .collect();
        Ok(Sizing {
            base: base0 / refine,
            per_circle,
            cracks,
            groups,
        })
    }

    /// Size of an outline edge group or polygon hole (m).
    pub fn group(&self, name: &str) -> f64 {
        self.groups.get(name).copied().unwrap_or(self.base)
    }
}

/// Elements on each circular hole at refinement `refine`.
pub fn circle_elements(scene: &Scene, refine: f64) -> usize {
    ((scene
        .bem
        .elements_per_circle
        .unwrap_or(DEFAULT_ELEMENTS_PER_CIRCLE) as f64)
        * refine)
        .round() as usize
}

/// Tip length scale of a crack before meshing: its length (half for interior cracks), or
/// the distance from a tip to the outline / holes if shorter.
fn crack_length_scale(loops: &[LoopSpec], pts: &[P2], mouth: bool) -> f64 {
    let len: f64 = polyline_length(pts);
    let mut l = if mouth { len } else { 0.5 * len };
    let mut tips = vec![*pts.last().unwrap_or(&P2::zeros())];
    if !mouth {
        tips.push(pts[0]);
    }
    for t in tips {
        for (a, b, _) in loop_edges(loops) {
            let dist = point_segment_distance(&t, &a, &b);
            if dist > 1e-9 * len {
                l = l.min(dist);
            }
        }
    }
    l
}

/// Every edge of the loops as (start, end, group).
fn loop_edges(loops: &[LoopSpec]) -> impl Iterator<Item = (P2, P2, &str)> {
    loops.iter().flat_map(|l| {
        let n = l.points.len();
        (0..n).map(move |i| {
            (
                l.points[i],
                l.points[(i + 1) % n],
                l.edge_groups[i].as_str(),
            )
        })
    })
}

/// One crack tip and its local feature size.
#[derive(Debug, Clone, PartialEq)]
pub struct TipFeature {
    /// Crack index in scene order.
    pub crack: usize,
    /// True for the crack's last point.
    pub at_end: bool,
    /// Tip position (m).
    pub point: P2,
    /// Tip length scale L (m): the crack length (half for a crack with two tips), or the
    /// distance to the nearest other boundary or crack if shorter.
    pub scale: f64,
    /// What sets L: "its length" or the nearest group or crack.
    pub nearest: String,
}

/// The local-feature sizes of the static BEM mesh (issue 17). Refinement `refine` divides
/// every size and every grading.
///
/// - every crack tip (not named in `bem.group_sizes`, without `bem.tip_refinement`) is a
///   source of size min(base, L / 80) with a uniform zone of radius [`TIP_ZONE`] L,
///   which holds the crack-opening fit (0.3 L), the interaction integral (0.3 L) and the
///   constant face zone of the tangential stencil (0.6 L,
///   [`pdbem_bem::mesh::stencil::FACE_TIP_ZONE`]); the crack faces grow from it to the
///   base size, and every other boundary near the tip (the remaining ligament, a
///   neighbouring crack, a hole) is refined by the same source;
/// - with the default element size, cracks, holes and patches are sources of the base
///   size within [`FEATURE_ZONE`] of the outline's smaller side, and outline edges grow
///   beyond to the far size (see [`FAR_THICKNESS_FRACTION`]): a 1000:1 strip needs a
///   few thousand elements, not 2e5.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalSizes {
    /// The field (before the mesh adds mouth sources): the tip sources and `features`.
    pub field: SizeField,
    /// The sources other than the tips (cracks, holes and patches keeping the base size
    /// with the default element size): what a re-meshed growth geometry keeps while its
    /// tips move ([`Self::tip_rule`]).
    pub features: SizeField,
    /// Size cap of default-size outline edges (m), refined; `None` keeps the base size.
    pub far: Option<f64>,
    /// The tips and their length scales.
    pub tips: Vec<TipFeature>,
}

impl LocalSizes {
    /// The local sizes of `scene` at refinement `refine` (the loops as [`super::bem::loops`]
    /// makes them at that level). An error names a tip whose length scale is below
    /// [`MIN_FEATURE_RATIO`] of the geometry.
    pub fn of(scene: &Scene, geo: &SceneGeometry, loops: &[LoopSpec], refine: f64) -> Result<Self> {
        let base0 = scene.bem.base_size(geo);
        let tips = tip_features(geo, loops);
        let extent = geometry_extent(geo);
        let mut field = SizeField::default();
        for t in &tips {
            if t.scale.is_nan() || t.scale <= 0.0 || t.scale < MIN_FEATURE_RATIO * extent {
                let c = &scene.cracks[t.crack];
                bail!(
                    "{}: cracks.{} ('{}'): its {} tip lies {:.3e} m from {}, {:.1e} of the body's size {:.3e} m: \
                     too close for the BEM mesh to resolve (limit {:.0e}); move the tip or the crack \
                     at least {:.3e} m away",
                    scene.file_label().display(),
                    t.crack,
                    c.name,
                    if t.at_end { "end" } else { "start" },
                    t.scale,
                    t.nearest,
                    t.scale / extent,
                    extent,
                    MIN_FEATURE_RATIO,
                    MIN_FEATURE_RATIO * extent
                );
            }
            let name = &scene.cracks[t.crack].name;
            if scene.bem.group_sizes.contains_key(name) || scene.bem.tip_refinement.is_some() {
                continue;
            }
            let h = base0.min(t.scale * DEFAULT_CRACK_FRACTION) / refine;
            field.sources.push(
                SizeSource::point(t.point, h, TIP_ZONE * t.scale).graded(TIP_GRADING / refine),
            );
        }
        let mut features = SizeField::default();
        let far = far_size(scene, geo, base0).map(|far| {
            let side = geo
                .outline
                .as_ref()
                .map(|o| {
                    let (lo, hi) = bounding_box(&o.points);
                    (hi - lo).min()
                })
                .unwrap_or(0.0);
            for shape in feature_shapes(scene, geo) {
                features.sources.push(SizeSource {
                    shape,
                    size: base0 / refine,
                    radius: FEATURE_ZONE * side,
                    grading: DEFAULT_GRADING / refine,
                });
            }
            far / refine
        });
        field.sources.extend(features.sources.iter().cloned());
        Ok(LocalSizes {
            field,
            features,
            far,
            tips,
        })
    }

    /// The tip rule of the field for geometries whose tips move (BEM-only growth,
    /// `pdbem_coupling::growth::bem_only::sizing`): size min(base, L / 80) over
    /// [`TIP_ZONE`] L graded at [`TIP_GRADING`], all at refinement `refine`; `None` when
    /// the scene fixes crack sizes (`bem.group_sizes` names a crack, or
    /// `bem.tip_refinement`), whose cracks keep those sizes.
    pub fn tip_rule(scene: &Scene, geo: &SceneGeometry, refine: f64) -> Option<TipSizing> {
        let fixed = scene.bem.tip_refinement.is_some()
            || scene
                .cracks
                .iter()
                .any(|c| scene.bem.group_sizes.contains_key(&c.name));
        (!fixed).then(|| TipSizing {
            fraction: DEFAULT_CRACK_FRACTION,
            zone: TIP_ZONE,
            grading: TIP_GRADING,
            base: scene.bem.base_size(geo) / refine,
        })
    }
}

/// The far size of default-size outline edges (module docs), `None` when the scene gives
/// an element size or has no outline, or the far size is not above the base size.
fn far_size(scene: &Scene, geo: &SceneGeometry, base: f64) -> Option<f64> {
    if scene.bem.element_size.is_some() {
        return None;
    }
    let o = geo.outline.as_ref()?;
    let n = o.points.len();
    let perimeter: f64 = (0..n)
        .map(|i| (o.points[(i + 1) % n] - o.points[i]).norm())
        .sum();
    let thickness = 2.0 * signed_area(&o.points).abs() / perimeter;
    let (lo, hi) = bounding_box(&o.points);
    let far = (FAR_THICKNESS_FRACTION * thickness).min((hi - lo).norm() / 100.0);
    (far > base).then_some(far)
}

/// Cracks, holes and patch ends as source shapes.
fn feature_shapes(scene: &Scene, geo: &SceneGeometry) -> Vec<SourceShape> {
    let mut out: Vec<SourceShape> = geo
        .cracks
        .iter()
        .map(|c| SourceShape::Polyline(c.points.clone()))
        .collect();
    for (_, h) in &geo.holes {
        let mut p = h.polygon();
        if let Some(&first) = p.first() {
            p.push(first);
        }
        out.push(SourceShape::Polyline(p));
    }
    for p in &scene.body.patches {
        out.push(SourceShape::Point(P2::new(p.from.0, p.from.1)));
        out.push(SourceShape::Point(P2::new(p.to.0, p.to.1)));
    }
    out
}

/// Largest extent of the geometry's bounding box (m).
/// The largest extent of the geometry's bounding box (m).
pub fn geometry_extent(geo: &SceneGeometry) -> f64 {
    let (lo, hi) = geo.bounds();
    (hi - lo).max()
}

/// [`TipFeature::nearest`] of a tip whose length scale is its crack's own length.
pub const OWN_LENGTH: &str = "its own length";

/// Every crack tip of the scene with its length scale: a crack end is a tip unless it
/// lies on a loop edge (within 1e-9 of the crack's length: the mesh builder's mouths).
pub fn tip_features(geo: &SceneGeometry, loops: &[LoopSpec]) -> Vec<TipFeature> {
    let mut out = Vec::new();
    for (ci, c) in geo.cracks.iter().enumerate() {
        let len = polyline_length(&c.points);
        let tol = 1e-9 * len.max(geometry_extent(geo));
        let ends = [c.points[0], *c.points.last().unwrap_or(&c.points[0])];
        let on_loop =
            |p: &P2| loop_edges(loops).any(|(a, b, _)| point_segment_distance(p, &a, &b) <= tol);
        let is_tip = [!on_loop(&ends[0]), !on_loop(&ends[1])];
        let own = if is_tip[0] && is_tip[1] {
            0.5 * len
        } else {
            len
        };
        for k in 0..2 {
            if !is_tip[k] {
                continue;
            }
            let p = ends[k];
            let mut scale = own;
            let mut nearest = OWN_LENGTH.to_string();
            for (a, b, g) in loop_edges(loops) {
                let d = point_segment_distance(&p, &a, &b);
                if d < scale {
                    scale = d;
                    nearest = format!("'{g}'");
                }
            }
            for (cj, other) in geo.cracks.iter().enumerate() {
                if cj == ci {
                    continue;
                }
                let d = other
                    .points
                    .windows(2)
                    .map(|w| point_segment_distance(&p, &w[0], &w[1]))
                    .fold(f64::INFINITY, f64::min);
                if d < scale {
                    scale = d;
                    nearest = format!("crack '{}'", other.name);
                }
            }
            out.push(TipFeature {
                crack: ci,
                at_end: k == 1,
                point: p,
                scale,
                nearest,
            });
        }
    }
    out
}
