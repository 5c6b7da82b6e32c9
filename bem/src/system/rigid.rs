//! Rigid-body modes left free by the prescribed displacements.
//!
//! The three rigid motions (x and y translation, rotation about the centroid scaled by the
//! mesh size) are evaluated at every element's collocation point. Restricted to the
//! displacement-prescribed components they span a Gram matrix G; the eigenvectors of G with
//! (relatively) zero eigenvalue are the motions the conditions do not fix. They are returned
//! orthonormalised over all degrees of freedom. A body cut into pieces (a crack from the
//! outline into a PD window) has these motions per piece: a piece without prescribed
//! displacements floats, whatever holds the others.

use super::Bc;
use crate::mesh::Mesh;
use nalgebra::{Matrix3, SymmetricEigen};

/// Free rigid modes of the pieces of a body ([`crate::mesh::pieces`]).
pub(super) struct FreeModes {
    /// Vectors over the 2 N degrees of freedom (orthonormal, each supported on its piece).
    pub modes: Vec<Vec<f64>>,
    /// Piece of every element.
    pub pieces: Vec<usize>,
    /// Number of free modes of every piece.
    pub per_piece: Vec<usize>,
}

/// Free rigid modes of every piece of the body.
pub(super) fn free_modes(mesh: &Mesh, bcs: &[[Bc; 2]]) -> FreeModes {
    let pieces = crate::mesh::pieces(mesh).unwrap_or_else(|| vec![0; mesh.len()]);
    let count = pieces.iter().copied().max().map_or(0, |m| m + 1);
    let mut modes = Vec::new();
    let mut per_piece = Vec::with_capacity(count);
    for p in 0..count {
        let m = piece_modes(mesh, bcs, &pieces, p);
        per_piece.push(m.len());
        modes.extend(m);
    }
    FreeModes {
        modes,
        pieces,
        per_piece,
    }
}

/// The rigid frame of one piece: its elements, centroid (mean of the collocation points),
/// size (largest collocation-point distance from the centroid) and the free rigid motions
/// as unit coefficient vectors over (x translation, y translation, rotation about the
/// centroid scaled by `scale`).
pub(super) struct PieceFrame {
    /// Elements of the piece.
    pub elements: Vec<usize>,
    /// Mean collocation point.
    pub centroid: crate::V2,
    /// Largest collocation-point distance from the centroid.
    pub scale: f64,
    /// Free motions: eigenvectors of the Gram matrix of the three rigid motions on the
    /// displacement-prescribed components with (relatively) zero eigenvalue.
    pub free: Vec<nalgebra::Vector3<f64>>,
}

/// The rigid frame of piece `p` (see the module docs).
pub(super) fn piece_frame(mesh: &Mesh, bcs: &[[Bc; 2]], labels: &[usize], p: usize) -> PieceFrame {
    let elements: Vec<usize> = (0..mesh.len()).filter(|&e| labels[e] == p).collect();
    let c = elements
        .iter()
        .map(|&e| mesh.elements[e].mid)
        .sum::<crate::V2>()
        / elements.len() as f64;
    let scale = elements
        .iter()
        .map(|&e| (mesh.elements[e].mid - c).norm())
        .fold(0.0, f64::max)
        .max(1e-300);
    let mut g = Matrix3::<f64>::zeros();
    let mut full = Matrix3::<f64>::zeros();
    for &e in &elements {
        let q = (mesh.elements[e].mid - c) / scale;
        // Rows: the three unit motions at this collocation point, per component.
        let rows = [[1.0, 0.0, -q.y], [0.0, 1.0, q.x]];
        for (comp, row) in rows.iter().enumerate() {
            for k in 0..3 {
                for l in 0..3 {
                    let v = row[k] * row[l];
                    full[(k, l)] += v;
                    if bcs[e][comp].is_displacement() {
                        g[(k, l)] += v;
                    }
                }
            }
        }
    }
    let eig = SymmetricEigen::new(g);
    let tol = 1e-10 * full.trace();
    let free = (0..3)
        .filter(|&k| eig.eigenvalues[k] <= tol)
        .map(|k| eig.eigenvectors.column(k).into_owned())
        .collect();
    PieceFrame {
        elements,
        centroid: c,
        scale,
        free,
    }
}

/// Free rigid modes of piece `p` over all degrees of freedom (see the module docs).
fn piece_modes(mesh: &Mesh, bcs: &[[Bc; 2]], labels: &[usize], p: usize) -> Vec<Vec<f64>> {
    let nel = mesh.len();
    let frame = piece_frame(mesh, bcs, labels, p);
    let mut modes: Vec<Vec<f64>> = Vec::new();
    for v in &frame.free {
        let mut m = vec![0.0; 2 * nel];
        for &e in &frame.elements {
            let q = (mesh.elements[e].mid - frame.centroid) / frame.scale;
            m[2 * e] = v[0] - v[2] * q.y;
            m[2 * e + 1] = v[1] + v[2] * q.x;
        }
        for prev in &modes {
            let dot: f64 = prev.iter().zip(&m).map(|(a, b)| a * b).sum();
            for (x, p) in m.iter_mut().zip(prev) {
                *x -= dot * p;
            }
        }
        let norm = m.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm > 0.0 {
            m.iter_mut().for_each(|x| *x /= norm);
            modes.push(m);
        }
    }
    modes
}
