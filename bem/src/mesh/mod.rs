//! Boundary meshes of straight constant elements.
//!
//! Entry points: [`MeshBuilder`] (closed loops, holes, cracks with two faces, element size per
//! group, uniform refinement near crack tips) producing a [`Mesh`] of [`Element`]s with named
//! groups and [`Crack`] records pairing the two faces station by station.
//!
//! Orientation (DESIGN.md): the outer boundary runs counter-clockwise and holes clockwise, so
//! the body lies to the left of every element and the outward normal is the right-hand
//! normal $(t_y, -t_x)$. A crack's "upper" face is the face to the left of the crack's
//! polyline direction; its elements run along that direction (normal pointing into the
//! crack), the lower face's elements run against it.

mod breaks;
mod builder;
mod pieces;
mod size_field;
mod spacing;
mod spec;
pub mod stencil;

pub use builder::{CrackSpec, FaceMode, LoopSpec, MeshBuilder, TipRefinement, MAX_ELEMENTS};
pub use pieces::pieces;
pub use size_field::{march, SizeField, SizeSource, SourceShape, DEFAULT_GRADING};
pub use spacing::subdivide;

use nalgebra::Vector2;

/// Two-vector alias used throughout the crate.
pub type V2 = Vector2<f64>;

/// One straight constant element.
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    /// Start point.
    pub a: V2,
    /// End point.
    pub b: V2,
    /// Midpoint: the collocation node.
    pub mid: V2,
    /// Unit tangent (b - a)/h.
    pub tangent: V2,
    /// Unit outward normal (right-hand normal of the tangent).
    pub normal: V2,
    /// Length.
    pub h: f64,
    /// Index into [`Mesh::groups`].
    pub group: usize,
}

impl Element {
    /// Element from its end points.
    pub fn new(a: V2, b: V2, group: usize) -> Self {
        let d = b - a;
        let h = d.norm();
        let tangent = d / h;
        Self {
            a,
            b,
            mid: 0.5 * (a + b),
            tangent,
            normal: V2::new(tangent.y, -tangent.x),
            h,
            group,
        }
    }
}

/// A crack in the mesh: its polyline and the element indices of both faces.
#[derive(Debug, Clone, PartialEq)]
pub struct Crack {
    /// Name given in the scene.
    pub name: String,
    /// Polyline from its start to its end.
    pub points: Vec<V2>,
    /// Whether the start point is a tip (false when it is a mouth on the boundary).
    pub start_is_tip: bool,
    /// Whether the end point is a tip.
    pub end_is_tip: bool,
    /// Upper-face elements, ordered along the polyline.
    pub upper: Vec<usize>,
    /// Lower-face elements, `lower[i]` facing `upper[i]`.
    pub lower: Vec<usize>,
    /// Arc length of station i (element midpoint) from the polyline start.
    pub stations: Vec<f64>,
    /// Face separation (0 for coincident faces).
    pub gap: f64,
}

impl Crack {
    /// Total length of the polyline.
    pub fn length(&self) -> f64 {
        pdbem_geometry::polyline_length(&self.points)
    }

    /// The mouth point, if the crack starts on the boundary.
    pub fn mouth(&self) -> Option<V2> {
        (!self.start_is_tip).then(|| self.points[0])
    }
}

/// A boundary mesh: elements, group names, cracks.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// All elements, loops first, then crack faces.
    pub elements: Vec<Element>,
    /// Group names; elements refer to them by index.
    pub groups: Vec<String>,
    /// Crack records.
    pub cracks: Vec<Crack>,
    /// Closed loops as element index ranges in traversal order (for tangential derivatives).
    pub loops: Vec<std::ops::Range<usize>>,
}

impl Mesh {
    /// Index of a group by name.
    pub fn group(&self, name: &str) -> Option<usize> {
        self.groups.iter().position(|g| g == name)
    }

    /// Element indices of a group.
    pub fn group_elements(&self, g: usize) -> impl Iterator<Item = usize> + '_ {
        self.elements
            .iter()
            .enumerate()
            .filter(move |(_, e)| e.group == g)
            .map(|(i, _)| i)
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// True when the mesh has no element.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// Polyline tips: (crack index, is_end, tip point, unit direction ahead of the tip).
    pub fn tips(&self) -> Vec<(usize, bool, V2, V2)> {
        let mut out = Vec::new();
        for (ci, c) in self.cracks.iter().enumerate() {
            let n = c.points.len();
            if c.start_is_tip {
                let d = (c.points[0] - c.points[1]).normalize();
                out.push((ci, false, c.points[0], d));
            }
            if c.end_is_tip {
                let d = (c.points[n - 1] - c.points[n - 2]).normalize();
                out.push((ci, true, c.points[n - 1], d));
            }
        }
        out
    }
}
