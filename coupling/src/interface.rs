//! The interface between one window and the BEM body: which BEM elements face the
//! window, which PD virtual nodes they feed, and which bonds carry force across them.
//!
//! - Virtual node -> element (seed 002 Eq. 23 and Fig. 6): each coupled virtual node
//!   belongs to the nearest interface element (its row; the corner blocks go to the
//!   corner elements).
//! - Bond -> element: each intact bond from a coupled virtual node to a real node crosses
//!   the window boundary once; the element holding the crossing point receives its force.
//!   This is the flux definition of the PD traction across a line, and coincides with the
//!   row sum of Eq. 24 away from corners (translation invariance along a side).
//!
//! Virtual nodes of outer sides with prescribed displacements are not coupled: they keep
//! the values their boundary condition gave them.

use pdbem_bem::{Mesh, V2};
use pdbem_pd::PdModel;

use crate::error::CouplingError;
use crate::window::{segment_distance, SideKind, Window};

/// One window's interface data.
#[derive(Debug, Clone)]
pub struct Interface {
    /// Interface elements of the BEM mesh (indices), in mesh order.
    pub elements: Vec<usize>,
    /// Coupled virtual nodes, as positions in `PdModel::virtual_nodes()` order.
    pub coupled: Vec<usize>,
    /// Reference positions of the coupled virtual nodes (m).
    pub positions: Vec<V2>,
    /// Slot in `elements` of each coupled virtual node (nearest element).
    pub node_element: Vec<usize>,
    /// Prescribed base values of all virtual nodes as built (outer conditions kept).
    pub base: Vec<[f64; 2]>,
    /// Bonds from coupled virtual nodes to real nodes: (virtual node index in the model,
    /// CSR bond index, slot in `elements` of the element the bond crosses).
    pub crossings: Vec<(usize, usize, usize)>,
    /// Bonds between two coupled virtual nodes whose segment passes through the window
    /// (near its corners): (first node, CSR bond, entry slot, exit slot). Each pair once.
    pub passes: Vec<(usize, usize, usize, usize)>,
}

impl Interface {
    /// Matches window `w` (index `index`) with the elements of group `group` in `mesh` and
    /// the virtual nodes of `model`.
    pub fn new(
        index: usize,
        w: &Window,
        mesh: &Mesh,
        group: usize,
        model: &PdModel,
    ) -> Result<Interface, CouplingError> {
        let tol = 1e-6 * w.spec.dx;
        let elements: Vec<usize> = mesh
            .group_elements(group)
            .filter(|&e| on_interface(w, mesh.elements[e].mid, tol))
            .collect();
        let expected: usize = (0..4)
            .filter(|&k| w.sides[k] == SideKind::Interface)
            .map(|k| if k % 2 == 0 { w.spec.nx } else { w.spec.ny })
            .sum();
        let bad_len = elements
            .iter()
            .any(|&e| (mesh.elements[e].h - w.spec.dx).abs() > 1e-6 * w.spec.dx);
        if elements.len() != expected || bad_len {
            return Err(CouplingError::Interface {
                window: index,
                message: format!(
                    "{} interface elements (expected {expected}, one of length dx = {} per node row)",
                    elements.len(),
                    w.spec.dx
                ),
            });
        }
        let pos = model.positions();
        let vr = model.virtual_nodes();
        let bc = model.boundary();
        let base: Vec<[f64; 2]> = vr.clone().map(|i| bc.base[i]).collect();
        let (mut coupled, mut positions, mut node_element) = (Vec::new(), Vec::new(), Vec::new());
        for (k, i) in vr.clone().enumerate() {
            let x = V2::new(pos[i][0], pos[i][1]);
            if !is_coupled(w, x) {
                continue;
            }
            coupled.push(k);
            positions.push(x);
            node_element.push(nearest_element(mesh, &elements, x));
        }
        let crossings = bond_crossings(w, mesh, &elements, model, &coupled);
        let passes = bond_passes(w, mesh, &elements, model, &coupled);
        Ok(Interface {
            elements,
            coupled,
            positions,
            node_element,
            base,
            crossings,
            passes,
        })
    }

    /// Number of interface unknowns (2 per coupled virtual node).
    pub fn len(&self) -> usize {
        2 * self.coupled.len()
    }

    /// Whether there is no coupled node.
    pub fn is_empty(&self) -> bool {
        self.coupled.is_empty()
    }
}

/// Whether point `p` lies on an interface side of `w`.
fn on_interface(w: &Window, p: V2, tol: f64) -> bool {
    (0..4).any(|k| {
        let (a, b) = w.side(k);
        w.sides[k] == SideKind::Interface && segment_distance(p, a, b).0 <= tol
    })
}

/// A virtual node is coupled when its nearest window side is an interface.
fn is_coupled(w: &Window, x: V2) -> bool {
    let mut best = (f64::INFINITY, SideKind::Outer);
    for k in 0..4 {
        let (a, b) = w.side(k);
        let d = segment_distance(x, a, b).0;
        // Ties (corner diagonals) go to the interface.
        if d < best.0 - 1e-9 * w.spec.dx
            || (d <= best.0 + 1e-9 * w.spec.dx && w.sides[k] == SideKind::Interface)
        {
            best = (d, w.sides[k]);
        }
    }
    best.1 == SideKind::Interface
}

/// Slot of the element nearest to `x` (ties: the first in mesh order).
fn nearest_element(mesh: &Mesh, elements: &[usize], x: V2) -> usize {
    let mut best = (f64::INFINITY, 0);
    for (s, &e) in elements.iter().enumerate() {
        let el = &mesh.elements[e];
        let d = segment_distance(x, el.a, el.b).0;
        if d < best.0 - 1e-12 * el.h {
            best = (d, s);
        }
    }
    best.1
}

/// Every intact bond from a coupled virtual node to a real node, with the element its
/// segment crosses.
fn bond_crossings(
    w: &Window,
    mesh: &Mesh,
    elements: &[usize],
    model: &PdModel,
    coupled: &[usize],
) -> Vec<(usize, usize, usize)> {
    let pos = model.positions();
    let n_real = model.n_real();
    let bonds = model.bonds();
    let intact = model.bond_intact();
    let v0 = model.virtual_nodes().start;
    let mut out = Vec::new();
    for &k in coupled {
        let i = v0 + k;
        let xi = V2::new(pos[i][0], pos[i][1]);
        for b in bonds.row(i) {
            let j = bonds.nbr[b] as usize;
            if j >= n_real || intact[b] == 0 {
                continue;
            }
            let xj = V2::new(pos[j][0], pos[j][1]);
            let c = w.boundary_crossing(xi, xj);
            out.push((i, b, nearest_element(mesh, elements, c)));
        }
    }
    out
}

/// Bonds between coupled virtual nodes that cut through the window (corner regions).
/// The window transmits their force: the entry element (near the first node) receives
/// the force the first node exerts on the second, the exit element its opposite.
fn bond_passes(
    w: &Window,
    mesh: &Mesh,
    elements: &[usize],
    model: &PdModel,
    coupled: &[usize],
) -> Vec<(usize, usize, usize, usize)> {
    let pos = model.positions();
    let bonds = model.bonds();
    let v0 = model.virtual_nodes().start;
    let is_coupled: std::collections::HashSet<usize> = coupled.iter().map(|k| v0 + k).collect();
    let mut out = Vec::new();
    for &k in coupled {
        let i = v0 + k;
        let xi = V2::new(pos[i][0], pos[i][1]);
        for b in bonds.row(i) {
            let j = bonds.nbr[b] as usize;
            if j <= i || !is_coupled.contains(&j) {
                continue;
            }
            let xj = V2::new(pos[j][0], pos[j][1]);
            if let Some((p, q)) = w.chord(xi, xj) {
                let (a, c) = (
                    nearest_element(mesh, elements, p),
                    nearest_element(mesh, elements, q),
                );
                if a != c {
                    out.push((i, b, a, c));
                }
            }
        }
    }
    out
}
