//! The interface between one window and the BEM body: which BEM elements face the
//! window, which PD virtual nodes they feed, and which bonds carry force across them.
//!
//! - Virtual node -> element (seed 002 Eq. 23 and Fig. 6): each coupled virtual node
//!   belongs to the nearest interface element (its row; the corner blocks go to the
//!   corner elements).
//! - Bond -> element: every bond from a coupled virtual node on the BEM side of an
//!   element's line to a node on the window side that crosses the element gives it its
//!   force (half through an element end point). This is the flux definition of the PD
//!   traction across a line; it coincides with the row sum of Eq. 24 away from corners
//!   (translation invariance along a side) and stays exact at the corners, where bonds
//!   between virtual nodes cut through the window.
//!
//! Virtual nodes of outer sides with prescribed displacements are not coupled: they keep
//! the values their boundary condition gave them.

use pdbem_bem::{Mesh, V2};
use pdbem_pd::PdModel;

use crate::error::CouplingError;
use crate::window::{SideKind, Window};
use pdbem_geometry::point_segment_projection;

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
    /// The bonds carrying force across each element: (coupled virtual node index in the
    /// model, CSR bond index, slot in `elements` of the element the bond crosses, share of
    /// the bond's force: 1, or 1/2 through an end point shared by two elements).
    pub crossings: Vec<(usize, usize, usize, f64)>,
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
        if elements.len() != expected {
            return Err(CouplingError::Interface {
                window: index,
                message: format!(
                    "{} interface elements (expected {expected}, one of length dx = {} per node row)",
                    elements.len(),
                    w.spec.dx
                ),
            });
        }
        // The count can be right while lengths are not (an element split in two and
        // another one missing); name the first element off dx.
        let bad_len = elements
            .iter()
            .find(|&&e| (mesh.elements[e].h - w.spec.dx).abs() > 1e-6 * w.spec.dx);
        if let Some(&e) = bad_len {
            let el = &mesh.elements[e];
            let n_bad = elements
                .iter()
                .filter(|&&e| (mesh.elements[e].h - w.spec.dx).abs() > 1e-6 * w.spec.dx)
                .count();
            return Err(CouplingError::Interface {
                window: index,
                message: format!(
                    "{n_bad} of the {} interface elements are not of length dx = {}: element {e} \
                     at ({:.4}, {:.4}) has length {:.6} (one element per node row is needed; \
                     window corners ({:.4}, {:.4}) to ({:.4}, {:.4}))",
                    elements.len(),
                    w.spec.dx,
                    el.mid.x,
                    el.mid.y,
                    el.h,
                    w.corners()[0].x,
                    w.corners()[0].y,
                    w.corners()[2].x,
                    w.corners()[2].y
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
        let crossings = bond_crossings(mesh, &elements, model, &coupled);
        Ok(Interface {
            elements,
            coupled,
            positions,
            node_element,
            base,
            crossings,
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
        w.sides[k] == SideKind::Interface && point_segment_projection(&p, &a, &b).0 <= tol
    })
}

/// A virtual node is coupled when its nearest window side is an interface.
fn is_coupled(w: &Window, x: V2) -> bool {
    let mut best = (f64::INFINITY, SideKind::Outer);
    for k in 0..4 {
        let (a, b) = w.side(k);
        let d = point_segment_projection(&x, &a, &b).0;
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
    nearest_elements(mesh, elements, x)[0].0
}

/// Slots of the elements nearest to `x` with equal shares: one element, or the two that
/// share an end point at `x` (within 1e-9 of the element length).
fn nearest_elements(mesh: &Mesh, elements: &[usize], x: V2) -> Vec<(usize, f64)> {
    let dist = |e: usize| {
        let el = &mesh.elements[e];
        point_segment_projection(&x, &el.a, &el.b).0
    };
    let best = elements
        .iter()
        .map(|&e| dist(e))
        .fold(f64::INFINITY, f64::min);
    let ties: Vec<usize> = elements
        .iter()
        .enumerate()
        .filter(|&(_, &e)| dist(e) <= best + 1e-9 * mesh.elements[e].h)
        .map(|(s, _)| s)
        .collect();
    let share = 1.0 / ties.len() as f64;
    ties.into_iter().map(|s| (s, share)).collect()
}

/// The PD flux across every interface element: each bond from a coupled virtual node i
/// on the BEM side of the element's line to a node j (real, or coupled virtual) on the
/// window side whose segment crosses the element, with its share (1, or 1/2 through an
/// end point shared by two elements).
///
/// This is the traction of PD across a line, element by element, and is exact under
/// uniform strain up to the bulk calibration, corners included
/// (`tests/traction_map.rs`). Both directions of a bond are seen, so a bond between two
/// virtual nodes that cuts a window corner is counted on both elements it crosses, with
/// opposite signs.
fn bond_crossings(
    mesh: &Mesh,
    elements: &[usize],
    model: &PdModel,
    coupled: &[usize],
) -> Vec<(usize, usize, usize, f64)> {
    let pos = model.positions();
    let n_real = model.n_real();
    let bonds = model.bonds();
    let v0 = model.virtual_nodes().start;
    let is_coupled: std::collections::HashSet<usize> = coupled.iter().map(|k| v0 + k).collect();
    let mut out = Vec::new();
    for &k in coupled {
        let i = v0 + k;
        let xi = V2::new(pos[i][0], pos[i][1]);
        for b in bonds.row(i) {
            let j = bonds.nbr[b] as usize;
            if j >= n_real && !is_coupled.contains(&j) {
                continue;
            }
            let xj = V2::new(pos[j][0], pos[j][1]);
            for (slot, &e) in elements.iter().enumerate() {
                let share = crossing_share(&mesh.elements[e], xi, xj);
                if share > 0.0 {
                    out.push((i, b, slot, share));
                }
            }
        }
    }
    out
}

/// Share of the bond xi (BEM side) -> xj (window side) in the flux across element `el`:
/// 1 when it crosses the element's interior, 1/2 through one of its end points, else 0.
fn crossing_share(el: &pdbem_bem::mesh::Element, xi: V2, xj: V2) -> f64 {
    let (si, sj) = ((xi - el.mid).dot(&el.normal), (xj - el.mid).dot(&el.normal));
    // The element normal points into the window: i outside, j inside.
    if si >= 0.0 || sj <= 0.0 {
        return 0.0;
    }
    let c = xi + si / (si - sj) * (xj - xi);
    let along = (c - el.mid).dot(&el.tangent).abs();
    let scale = xi.abs().max().max(xj.abs().max()).max(el.mid.abs().max());
    let (half, tol) = (0.5 * el.h, pdbem_geometry::tie_band(el.h, scale));
    if along < half - tol {
        1.0
    } else if along <= half + tol {
        0.5
    } else {
        0.0
    }
}
