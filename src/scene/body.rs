//! `body`: the outer outline (or an infinite plate), holes, and named patches
//! of outline edges.
//!
//! Edge-group names (used by `boundary`, outputs and group element sizes):
//! rectangle edges `bottom`, `right`, `top`, `left`; polygon edges `edge0` ..
//! `edgeN-1` unless named (edge i runs from point i to point i+1); `Edges`
//! chains name each piece; `outline` is the whole outer boundary; each hole is
//! one group (`hole0`, `hole1`, ... unless named); each patch is a group.

use serde::{Deserialize, Serialize};

/// A point `(x, y)` (m).
pub type Pt = (f64, f64);

/// Body: outline, holes and patches.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// Outer boundary, or `Infinite` for an unbounded plate. Required.
    pub outline: Outline,
    /// Holes inside the body. Default: none.
    #[serde(default)]
    pub holes: Vec<Hole>,
    /// Named pieces of outline edges (a loading pin, a support span), usable as
    /// boundary groups. Default: none.
    #[serde(default)]
    pub patches: Vec<Patch>,
}

/// Outer boundary of the body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Outline {
    /// Axis-aligned rectangle with lower-left corner `(x0, y0)` (m) and size
    /// `width` x `height` (m); edges `bottom`, `right`, `top`, `left`.
    Rectangle {
        /// Lower-left corner x (m).
        x0: f64,
        /// Lower-left corner y (m).
        y0: f64,
        /// Extent along x (m), > 0.
        width: f64,
        /// Extent along y (m), > 0.
        height: f64,
    },
    /// Closed polygon (the last point connects to the first; at least 3
    /// points); any orientation, normalised to counter-clockwise on load.
    Polygon {
        /// Corner points (m).
        points: Vec<Pt>,
        /// Name of each edge (edge i from point i to i+1). Default `edge0`..`edgeN-1`.
        #[serde(default)]
        edge_names: Option<Vec<String>>,
    },
    /// Outline made of named polylines that must join end to end and close.
    Edges {
        /// The pieces, in order around the body.
        edges: Vec<NamedEdge>,
    },
    /// Unbounded plate under a remote stress (Pa); no outer boundary. Solved by
    /// superposition: crack faces and holes carry minus the remote traction.
    Infinite {
        /// Remote sigma_xx (Pa). Default 0.
        #[serde(default)]
        sxx: f64,
        /// Remote sigma_yy (Pa). Default 0.
        #[serde(default)]
        syy: f64,
        /// Remote sigma_xy (Pa). Default 0.
        #[serde(default)]
        sxy: f64,
    },
}

/// One named piece of an `Edges` outline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NamedEdge {
    /// Group name of this piece.
    pub name: String,
    /// Polyline points (m), at least 2; its last point is the next piece's first.
    pub points: Vec<Pt>,
}

/// A hole in the body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Hole {
    /// Circular hole.
    Circle {
        /// Centre (m).
        center: Pt,
        /// Radius (m), > 0.
        radius: f64,
        /// Group name. Default `hole<i>` (i = index in `holes`).
        #[serde(default)]
        name: Option<String>,
    },
    /// Polygonal hole (any orientation; normalised to clockwise on load).
    Polygon {
        /// Corner points (m), at least 3.
        points: Vec<Pt>,
        /// Group name. Default `hole<i>`.
        #[serde(default)]
        name: Option<String>,
    },
}

impl Hole {
    /// The hole's group name: given, or `hole<index>`.
    pub fn name(&self, index: usize) -> String {
        let n = match self {
            Hole::Circle { name, .. } | Hole::Polygon { name, .. } => name,
        };
        n.clone().unwrap_or_else(|| format!("hole{index}"))
    }
}

/// A named piece of one outline edge, from `from` to `to` (both on that edge).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Patch {
    /// Group name.
    pub name: String,
    /// Start point on the outline (m).
    pub from: Pt,
    /// End point on the same outline edge (m).
    pub to: Pt,
}

impl Outline {
    /// Names of the outline's edge groups, in order (empty for `Infinite`).
    pub fn edge_names(&self) -> Vec<String> {
        match self {
            Outline::Rectangle { .. } => ["bottom", "right", "top", "left"]
                .iter()
                .map(|s| s.to_string())
                .collect(),
            Outline::Polygon { points, edge_names } => edge_names
                .clone()
                .unwrap_or_else(|| (0..points.len()).map(|i| format!("edge{i}")).collect()),
            Outline::Edges { edges } => edges.iter().map(|e| e.name.clone()).collect(),
            Outline::Infinite { .. } => Vec::new(),
        }
    }

    /// Remote stress `[sxx, syy, sxy]` (Pa) of an infinite plate, `None` otherwise.
    pub fn remote_stress(&self) -> Option<[f64; 3]> {
        match self {
            Outline::Infinite { sxx, syy, sxy } => Some([*sxx, *syy, *sxy]),
            _ => None,
        }
    }
}
