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

/// Free rigid modes of piece `p` (see the module docs).
fn piece_modes(mesh: &Mesh, bcs: &[[Bc; 2]], labels: &[usize], p: usize) -> Vec<Vec<f64>> {
    let nel = mesh.len();
    let mine: Vec<usize> = (0..nel).filter(|&e| labels[e] == p).collect();
    let c = mine
        .iter()
        .map(|&e| mesh.elements[e].mid)
        .sum::<crate::V2>()
        / mine.len() as f64;
    let scale = mine
        .iter()
        .map(|&e| (mesh.elements[e].mid - c).norm())
        .fold(0.0, f64::max)
        .max(1e-300);
    let on = |d: usize| labels[d / 2] == p;
    let basis: [Vec<f64>; 3] = [
        (0..2 * nel)
            .map(|d| if on(d) && d % 2 == 0 { 1.0 } else { 0.0 })
            .collect(),
        (0..2 * nel)
            .map(|d| if on(d) && d % 2 == 1 { 1.0 } else { 0.0 })
            .collect(),
        (0..2 * nel)
            .map(|d| {
                if !on(d) {
                    return 0.0;
                }
                let q = (mesh.elements[d / 2].mid - c) / scale;
                if d % 2 == 0 {
                    -q.y
                } else {
                    q.x
                }
            })
            .collect(),
    ];
    let mut g = Matrix3::<f64>::zeros();
    let mut full = Matrix3::<f64>::zeros();
    for &e in &mine {
        for comp in 0..2 {
            let d = 2 * e + comp;
            for k in 0..3 {
                for l in 0..3 {
                    let v = basis[k][d] * basis[l][d];
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
    let mut modes: Vec<Vec<f64>> = Vec::new();
    for k in 0..3 {
        if eig.eigenvalues[k] > tol {
            continue;
        }
        let v = eig.eigenvectors.column(k);
        let mut m: Vec<f64> = (0..2 * nel)
            .map(|d| (0..3).map(|l| v[l] * basis[l][d]).sum())
            .collect();
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
