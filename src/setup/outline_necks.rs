//! Necks of a boundary loop: two pieces of the same loop (the outline, or a polygon hole)
//! that face each other across a strip of material narrower than the elements there, far
//! apart along the loop (a waist between two slots, a thin bridge). The hole-to-boundary
//! gaps of [`super::close_holes`] are the same defect between two loops.
//!
//! Measured on a 0.2 m x 0.1 m bar held on its left edge and pulled on its right, with
//! two slots 0.01 m wide from its top and bottom edges leaving a neck of width g at
//! mid-length (default elements h = 1e-3 m), against a reference with elements of g / 8
//! on the slot ends and g / 4 on the slot sides (g / 16 and g / 8 moved it by 0.3 %),
//! by g / h with h = 2.24e-3 m the larger element at the neck (the default mesh holds
//! 1.06e-3 to 2.24e-3 m there):
//!
//! | g / h | right edge's displacement | stress in the neck's middle (estimate) |
//! |---|---|---|
//! | 4.5 | -0.3 % | -0.8 % (3.4 %) |
//! | 1.3 | +3.5 % | +3.6 % (7.4 %) |
//! | 0.45 | +7.2 % | +5.2 % (7.0 %) |
//! | 0.13 | +12.1 % | **+11.7 % (1.5 %)** |
//!
//! The body's compliance carries no estimate, and below one element the stress estimate
//! misses the error, as at a hole's gap. Elements of a quarter of the gap on the neck's
//! faces alone do not help (the displacement stays +6.6 % at g / h = 0.45): the slot
//! sides that meet the neck at its corners need them too. With every piece within two
//! elements of the neck at g / 4: +0.4 % (g / h = 0.45) and -0.7 % (0.13), stresses within
//! their estimates. So a neck narrower than [`super::close_holes::GAP_RESOLUTION`] times the
//! larger element at it gets a note naming every edge group near it and the size that
//! resolves it. A gap across the outside of the body (a narrow slot) is no neck: the
//! crack-like slot was measured to give K within 0.2 % with elements far wider than it.

use pdbem_bem::mesh::{Element, Mesh};

use crate::geometry::{point_segment_distance, segment_segment_distance, P2};
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

use super::close_holes::{closest_on, nearest_midpoint, GAP_RESOLUTION, RESOLVING_FRACTION};

/// Two pieces of a loop count as a neck only when the loop runs at least this many gap
/// widths between them: the flanks of a wedge of half-angle theta near its tip are
/// 1 / sin(theta) gaps apart along the loop, so wedges blunter than about 29 degrees are
/// never necks.
pub const ALONG_LOOP: f64 = 4.0;

/// The worst resolved crossing of one neck of a loop (a pair of edge groups).
#[derive(Debug, Clone, PartialEq)]
pub struct Neck {
    /// Edge groups of the two faces (in loop order).
    pub groups: [String; 2],
    /// Width of the neck (m).
    pub gap: f64,
    /// Lengths of the two elements at the narrowest crossing (m).
    pub h: [f64; 2],
    /// Midpoint of the narrowest crossing (m).
    pub at: P2,
    /// Every edge group with an element within two of the larger elements of a crossing
    /// of the neck: the pieces the advised size applies to.
    pub nearby: Vec<String>,
}

impl Neck {
    /// Width over the larger element at the crossing.
    pub fn resolution(&self) -> f64 {
        self.gap / self.h[0].max(self.h[1])
    }
}

/// The necks of every loop of `mesh` narrower than [`GAP_RESOLUTION`] times their
/// elements, one per pair of edge groups.
pub fn necks(mesh: &Mesh) -> Vec<Neck> {
    let mut out: Vec<Neck> = Vec::new();
    for range in mesh.loops.iter().filter(|r| r.len() > 3) {
        let elements = &mesh.elements[range.clone()];
        for neck in loop_necks(mesh, elements) {
            match out.iter_mut().find(|o| o.groups == neck.groups) {
                Some(o) => merge(o, neck),
                None => out.push(neck),
            }
        }
    }
    out
}

/// One neck from two crossings of the same pair of groups: the worse resolved crossing,
/// and the pieces near either.
fn merge(into: &mut Neck, other: Neck) {
    let mut nearby = std::mem::take(&mut into.nearby);
    for g in &other.nearby {
        if !nearby.contains(g) {
            nearby.push(g.clone());
        }
    }
    if other.resolution() < into.resolution() {
        *into = other;
    }
    into.nearby = nearby;
}

/// The under-resolved crossings of one loop (elements in traversal order).
fn loop_necks(mesh: &Mesh, elements: &[Element]) -> Vec<Neck> {
    let start: Vec<f64> = elements
        .iter()
        .scan(0.0, |s, e| {
            let at = *s;
            *s += e.h;
            Some(at)
        })
        .collect();
    let total: f64 = elements.iter().map(|e| e.h).sum();
    // Sweep along x: two elements nearer than GAP_RESOLUTION times the larger one have
    // midpoints within GAP_RESOLUTION h_max + (h_e + h_f) / 2 <= (1 + GAP_RESOLUTION) h_max.
    let h_max = elements.iter().map(|e| e.h).fold(0.0, f64::max);
    let window = (1.0 + GAP_RESOLUTION) * h_max;
    let mut order: Vec<usize> = (0..elements.len()).collect();
    order.sort_by(|&a, &b| elements[a].mid.x.total_cmp(&elements[b].mid.x));
    let mut out = Vec::new();
    for (k, &a) in order.iter().enumerate() {
        for &b in order[k + 1..]
            .iter()
            .take_while(|&&b| elements[b].mid.x - elements[a].mid.x <= window)
        {
            let (i, j) = (a.min(b), a.max(b));
            let (e, f) = (&elements[i], &elements[j]);
            let reach = GAP_RESOLUTION * e.h.max(f.h);
            if (f.mid - e.mid).norm() - 0.5 * (e.h + f.h) >= reach {
                continue;
            }
            let gap = segment_segment_distance(&e.a, &e.b, &f.a, &f.b);
            let between = start[j] - (start[i] + e.h);
            let around = total - (start[j] + f.h) + start[i];
            let touching = gap <= 0.0; // neighbours along the loop
            if touching
                || gap >= reach
                || between.min(around) < ALONG_LOOP * gap
                || !across_material(e, f)
            {
                continue;
            }
            let at = nearest_midpoint(e, f);
            out.push(Neck {
                groups: [mesh.groups[e.group].clone(), mesh.groups[f.group].clone()],
                gap,
                h: [e.h, f.h],
                at,
                nearby: nearby_groups(mesh, elements, &at, 2.0 * e.h.max(f.h) + gap),
            });
        }
    }
    out
}

/// Whether the segment between the nearest points of `e` and `f` runs through the body:
/// it leaves each element against its outward normal.
fn across_material(e: &Element, f: &Element) -> bool {
    let v = closest_on(f, e) - closest_on(e, f);
    if v.norm() > 0.0 {
        v.dot(&e.normal) < 0.0 && v.dot(&f.normal) > 0.0
    } else {
        e.normal.dot(&f.normal) < 0.0
    }
}

/// The edge groups of `elements` with an element within `radius` of `at`, in loop order.
fn nearby_groups(mesh: &Mesh, elements: &[Element], at: &P2, radius: f64) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    for e in elements {
        let name = &mesh.groups[e.group];
        if point_segment_distance(at, &e.a, &e.b) <= radius && !names.contains(name) {
            names.push(name.clone());
        }
    }
    names
}

/// The under-resolved necks of `scene`'s static BEM mesh (refinement 1). A scene that
/// does not mesh has none here (its run refuses it); an infinite plate's holes are
/// checked like an outline.
pub fn unresolved(scene: &Scene) -> Vec<Neck> {
    let geo = SceneGeometry::of(scene);
    let Ok(builder) = super::bem::mesh_builder(scene, &geo, 1.0) else {
        return Vec::new();
    };
    let Ok(mesh) = builder.build() else {
        return Vec::new();
    };
    necks(&mesh)
}

/// The note of an unresolved neck, with the size that resolves it.
pub fn note(n: &Neck) -> String {
    let fine = RESOLVING_FRACTION * n.gap;
    let advice: Vec<String> = n
        .nearby
        .iter()
        .map(|g| format!("bem.group_sizes.{g} <= {fine:.3e} m"))
        .collect();
    format!(
        "the boundary '{}' faces '{}' across a neck of material {:.3e} m wide at ({:.4e}, \
         {:.4e}), {:.2} of the larger element there ({:.3e} m and {:.3e} m; a note under \
         {GAP_RESOLUTION}): the body's stiffness through it and the stress in it are not \
         resolved (measured: a bar's end displacement 12 % and the neck's stress 12 % high \
         with an estimate of 1.5 % at 0.13 elements), and refining the neck's faces alone does \
         not help; elements of a quarter of the width on every piece near it resolve it \
         (measured within 1 %): {} (an Edges outline gives a short piece its own size)",
        n.groups[0],
        n.groups[1],
        n.gap,
        n.at.x,
        n.at.y,
        n.resolution(),
        n.h[0],
        n.h[1],
        advice.join(", "),
    )
}
