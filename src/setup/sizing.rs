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

use anyhow::{Context, Result};
use pdbem_bem::mesh::LoopSpec;
use pdbem_bem::{Mesh, MeshBuilder};

use crate::geometry::{polyline_length, P2};
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// Default circle discretization (elements per circular hole).
pub const DEFAULT_ELEMENTS_PER_CIRCLE: usize = 128;
pub use crate::scene::bem::{DEFAULT_CRACK_FRACTION, DEFAULT_OUTLINE_FRACTION};

/// Element sizes of a scene at one refinement level.
#[derive(Debug, Clone, PartialEq)]
pub struct Sizing {
    /// Size where no group size applies (m), refined.
    pub base: f64,
    /// Elements on each circular hole, refined.
    pub per_circle: usize,
    /// Element size of each crack in scene order (m), refined.
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
        let mut b = MeshBuilder::new();
        for l in loops {
            b.add_loop(l.clone());
        }
        let loops_only = b.build().context("meshing the outline and holes")?;
        let cracks = scene
            .cracks
            .iter()
            .zip(&geo.cracks)
            .map(|(c, line)| {
                let l = crack_length_scale(&loops_only, &line.points, line.mouth);
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
fn crack_length_scale(loops: &Mesh, pts: &[P2], mouth: bool) -> f64 {
    let len: f64 = polyline_length(pts);
    let mut l = if mouth { len } else { 0.5 * len };
    let mut tips = vec![*pts.last().unwrap_or(&P2::zeros())];
    if !mouth {
        tips.push(pts[0]);
    }
    for t in tips {
        for e in &loops.elements {
            let d = e.b - e.a;
            let s = ((t - e.a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            let dist = (e.a + s * d - t).norm();
            if dist > 1e-9 * len {
                l = l.min(dist);
            }
        }
    }
    l
}
