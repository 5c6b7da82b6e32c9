//! What a crack is to the mesh builder ([`CrackSpec`], its faces and tip refinement) and
//! the element limit every builder and break walker respects.

use super::V2;

/// How the two faces of a crack sit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaceMode {
    /// Both faces on the crack line (the dual BIE keeps the system regular).
    Coincident,
    /// Faces offset by +-gap/2 along the crack normal, meeting at the tips.
    Gap(f64),
}

/// Uniform refinement near crack tips.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipRefinement {
    /// Element size within `radius` of the tip.
    pub size: f64,
    /// Radius of the uniform fine zone.
    pub radius: f64,
}

/// A crack: an open polyline with two faces.
#[derive(Debug, Clone, PartialEq)]
pub struct CrackSpec {
    /// Name (groups `<name>.upper`, `<name>.lower`).
    pub name: String,
    /// Polyline; an end on a loop is a mouth, any other end is a tip.
    pub points: Vec<V2>,
    /// Coincident faces or a gap.
    pub faces: FaceMode,
    /// Element size along the crack.
    pub element_size: f64,
    /// Optional refinement at the tips.
    pub tip: Option<TipRefinement>,
}

/// Most elements `MeshBuilder::build` makes before it gives up (a size field or an element
/// size that asks for more is a scene error found by `MeshBuilder::count` first).
pub const MAX_ELEMENTS: usize = 10_000_000;
