//! Pieces of the BEM body that only PD windows hold.
//!
//! When a macro crack runs from the outline into a window (the last window of a crack
//! crossing the body, seed 002 Algorithm 2 step 9), or two cracks join through a window,
//! the BEM body falls into pieces ([`pdbem_bem::mesh::pieces`]). A piece with no
//! prescribed displacement is held only through the window's ligament. Under the
//! interface tractions of the Dirichlet-Neumann iteration its BEM problem fixes its
//! displacement only up to a rigid motion $r = (a_x, a_y, \theta)$ (the BEM solver picks
//! one by its bordering constraint), while PD needs the actual motion on its virtual
//! nodes: the piece's equilibrium, $F = \sum_e t_e h_e = 0$ and
//! $M = \sum_e (x_e - c) \times t_e h_e = 0$ over its elements, decides it.
//!
//! The motion is made part of the fixed-point map, which stays a function of the
//! virtual-node displacements $x$ alone (so the relaxation schemes see an ordinary map):
//! with $\tilde x_0$ the virtual displacements of the BEM solution and $R$ the virtual
//! displacements of the piece's unit rigid motions,
//! 1. the piece's current motion is the least-squares fit $q = \arg\min
//!    \|x - \tilde x_0 - R q\|$ (what PD was given);
//! 2. it is corrected by the out-of-balance load, $\tilde q = q + K^{-1} G$ with
//!    $G = (F_x, F_y, M / L)$ ($L$ the piece's RMS element distance from its
//!    centroid $c$) and $K = 0.01 E$ (a deliberately soft guess of the window's
//!    stiffness against the motion, `STIFFNESS_FACTOR`; the accelerators correct it
//!    from the iterates);
//! 3. $\tilde x = \tilde x_0 + R \tilde q$, and the BEM solution of the piece is moved by
//!    the same motion.
//!
//! A fixed point has $q = \tilde q$, so $G = 0$: the piece is in equilibrium under its
//! scene loads and the PD interface forces. When the window's ligament breaks, nothing
//! balances the load and the iteration diverges: the crack has cut the body.
//!
//! **Partly held pieces.** A piece whose displacement conditions fix some of its rigid
//! motions but not all (a roller, a displacement prescribed in one direction) is
//! corrected along its free motions only: with $V$ the basis of those motions
//! ([`pdbem_bem::BemSystem::free_motions`], orthonormalised in the $q$ coordinates
//! above), $q = V a$, the fit is over $a$, and the step is $\tilde a = a + K^{-1} V^T G$.
//! A free motion leaves every displacement-prescribed component unmoved, so the
//! reactions do no work on it and $V^T G$ is the out-of-balance of the loads along it;
//! the fixed point has $V^T G = 0$, the piece's equilibrium along the motions its
//! conditions leave free. A fully free piece has $V = I$ (the three motions above).
//!
//! Which pieces: a body with a held piece (prescribed displacements fixing all its rigid
//! motions) corrects every other piece along its free motions; when no piece is held and
//! every piece is free (a free plate), the piece with the most elements keeps the
//! solver's gauge, as the whole body did before it was cut. Partly held pieces with no
//! fully held one (a body held by rollers alone, cut apart) are refused: the body's own
//! free motions would then be shared between pieces.

use std::sync::OnceLock;

use nalgebra::{DMatrix, DVector, Vector3};
use pdbem_bem::post::Background;
use pdbem_bem::{BemSystem, Material, Mesh, Solution, V2};

use crate::error::CouplingError;
use crate::interface::Interface;
use crate::maps::{bem_to_virtual, BemView, DisplacementMap};

/// K = this times E in step 2 (see the module docs). Measured on an edge crack cut
/// through to a window flush with the far edge (seed 002 tension plate, crack to 0.95 m
/// from the edge, 20 x 20 window, IQN-ILS, psi = 1e-6): 0.01 E converges in 20
/// iterations, 0.1 E in 22, E in 27, all to the same CMOD within 2e-6; with E = 1e3 Pa,
/// where the window rotates by ~0.1 rad and PD's geometric nonlinearity shows, E stalls
/// at a residual of 1e-3 while 0.01 E and 0.1 E converge. Too stiff a guess makes the
/// map nearly the identity along the motion (eigenvalue 1 - K_true / K), which the
/// secant methods cannot resolve; too soft a guess only overshoots, which they can.
const STIFFNESS_FACTOR: f64 = 0.01;

/// One floating piece.
struct Piece {
    elements: Vec<usize>,
    centroid: V2,
    /// Length scale of the rotation unknown (RMS distance of the elements from the
    /// centroid).
    length: f64,
    /// Its free motions in the coordinates $q = (a_x, a_y, \theta L)$, orthonormal: the
    /// unit vectors for a piece with no prescribed displacement.
    modes: Vec<Vector3<f64>>,
}

/// The floating pieces of one prepared BEM system and their rigid responses on the
/// virtual nodes, one per free motion (computed at the first use, for the map of that
/// use).
pub struct FloatingPieces {
    pieces: Vec<Piece>,
    responses: OnceLock<Vec<Vec<Vec<f64>>>>,
}

impl FloatingPieces {
    /// No piece to correct (the traction ordering holds every piece by the interface
    /// displacements).
    pub fn none() -> Self {
        FloatingPieces {
            pieces: Vec::new(),
            responses: OnceLock::new(),
        }
    }

    /// The pieces of `system` to correct (see the module docs).
    pub fn new(mesh: &Mesh, system: &BemSystem) -> Result<Self, CouplingError> {
        let labels = system.pieces();
        let free = system.free_modes_per_piece();
        let mut pieces = Vec::new();
        if free.len() > 1 {
            let partly = free.iter().position(|&f| f == 1 || f == 2);
            if let (Some(p), false) = (partly, free.contains(&0)) {
                return Err(CouplingError::FloatingPiece {
                    message: format!(
                        "piece {p} of {} has {} free rigid motion(s) and no piece is fully \
                         held: a body cut apart by cracks needs one piece whose displacement \
                         conditions fix all its rigid motions",
                        free.len(),
                        free[p]
                    ),
                });
            }
            let count = |p: usize| labels.iter().filter(|&&l| l == p).count();
            let reference = if free.iter().all(|&f| f == 3) {
                (0..free.len()).max_by_key(|&p| count(p))
            } else {
                None
            };
            for p in (0..free.len()).filter(|&p| free[p] > 0 && Some(p) != reference) {
                pieces.push(piece(mesh, system, labels, p, free[p]));
            }
        }
        Ok(FloatingPieces {
            pieces,
            responses: OnceLock::new(),
        })
    }

    /// Number of pieces corrected.
    pub fn len(&self) -> usize {
        self.pieces.len()
    }

    /// True when no piece needs correcting.
    pub fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }

    /// Applies steps 1-3 of the module docs to the BEM solution `sol` and its virtual
    /// displacements `xt`, given the virtual displacements `x` PD was solved with.
    #[allow(clippy::too_many_arguments)]
    pub fn correct(
        &self,
        mesh: &Mesh,
        material: &Material,
        map: DisplacementMap,
        ifaces: &[Interface],
        x: &[f64],
        sol: &mut Solution,
        xt: &mut [f64],
    ) -> Result<(), CouplingError> {
        let responses = self.responses.get_or_init(|| {
            self.pieces
                .iter()
                .map(|p| unit_responses(p, mesh, material, map, ifaces, !sol.du.is_empty()))
                .collect()
        });
        let k = STIFFNESS_FACTOR * material.e;
        for (p, r) in self.pieces.iter().zip(responses) {
            let a = fit(p, r, x, xt)?;
            let (f, m) = out_of_balance(p, mesh, sol);
            let g = Vector3::new(f.x, f.y, m / p.length);
            let a: Vec<f64> = a
                .iter()
                .zip(&p.modes)
                .map(|(ak, v)| ak + v.dot(&g) / k)
                .collect();
            let q = a.iter().zip(&p.modes).map(|(ak, v)| v * *ak).sum();
            move_piece(p, mesh, sol, &q);
            for (ak, rk) in a.iter().zip(r) {
                for (v, dv) in xt.iter_mut().zip(rk) {
                    *v += ak * dv;
                }
            }
        }
        Ok(())
    }
}

/// Piece `p` of `system` with `free` free motions: its elements, frame and motions.
fn piece(mesh: &Mesh, system: &BemSystem, labels: &[usize], p: usize, free: usize) -> Piece {
    let elements: Vec<usize> = (0..labels.len()).filter(|&e| labels[e] == p).collect();
    let centroid =
        elements.iter().map(|&e| mesh.elements[e].mid).sum::<V2>() / elements.len() as f64;
    let length = (elements
        .iter()
        .map(|&e| (mesh.elements[e].mid - centroid).norm_squared())
        .sum::<f64>()
        / elements.len() as f64)
        .sqrt();
    let modes = if free == 3 {
        vec![Vector3::x(), Vector3::y(), Vector3::z()]
    } else {
        let (c, motions) = system.free_motions(mesh, p);
        let d = centroid - c;
        // The same motion about this piece's centroid, in q = (a_x, a_y, theta L).
        let raw = motions
            .iter()
            .map(|&[ax, ay, th]| Vector3::new(ax - th * d.y, ay + th * d.x, th * length));
        orthonormal(raw)
    };
    Piece {
        elements,
        centroid,
        length,
        modes,
    }
}

/// Gram-Schmidt on `vectors` (dropping any that depend on the earlier ones).
fn orthonormal(vectors: impl Iterator<Item = Vector3<f64>>) -> Vec<Vector3<f64>> {
    let mut out: Vec<Vector3<f64>> = Vec::new();
    for v in vectors {
        let scale = v.norm();
        let w = out.iter().fold(v, |w, u| w - u * u.dot(&w));
        if w.norm() > 1e-8 * scale {
            out.push(w.normalize());
        }
    }
    out
}

/// The rigid displacement of motion `q` at `p`.
fn rigid_at(piece: &Piece, q: &Vector3<f64>, p: V2) -> V2 {
    let theta = q[2] / piece.length;
    let d = p - piece.centroid;
    V2::new(q[0] - theta * d.y, q[1] + theta * d.x)
}

/// Moves the piece's elements by the rigid motion `q` (and the tangential derivative
/// of the linear reconstruction, when present, by its rotation).
fn move_piece(piece: &Piece, mesh: &Mesh, sol: &mut Solution, q: &Vector3<f64>) {
    let theta = q[2] / piece.length;
    for &e in &piece.elements {
        let el = &mesh.elements[e];
        let v = rigid_at(piece, q, el.mid);
        sol.u[e][0] += v.x;
        sol.u[e][1] += v.y;
        if let Some(du) = sol.du.get_mut(e) {
            du[0] -= theta * el.tangent.y;
            du[1] += theta * el.tangent.x;
        }
    }
}

/// Net force and moment (about the centroid) of the tractions on the piece.
fn out_of_balance(piece: &Piece, mesh: &Mesh, sol: &Solution) -> (V2, f64) {
    let mut f = V2::zeros();
    let mut m = 0.0;
    for &e in &piece.elements {
        let el = &mesh.elements[e];
        let t = V2::new(sol.t[e][0], sol.t[e][1]) * el.h;
        let d = el.mid - piece.centroid;
        f += t;
        m += pdbem_geometry::cross(&d, &t);
    }
    (f, m)
}

/// Virtual displacements of the piece's free motions ([`Piece::modes`]).
fn unit_responses(
    piece: &Piece,
    mesh: &Mesh,
    material: &Material,
    map: DisplacementMap,
    ifaces: &[Interface],
    reconstruct: bool,
) -> Vec<Vec<f64>> {
    piece
        .modes
        .iter()
        .map(|q| {
            let mut sol = Solution {
                u: vec![[0.0; 2]; mesh.len()],
                t: vec![[0.0; 2]; mesh.len()],
                lambda: Vec::new(),
                du: if reconstruct {
                    vec![[0.0; 2]; mesh.len()]
                } else {
                    Vec::new()
                },
            };
            move_piece(piece, mesh, &mut sol, q);
            let view = BemView {
                mesh,
                material,
                solution: &sol,
                background: Background::default(),
            };
            bem_to_virtual(map, &view, ifaces)
        })
        .collect()
}

/// Least-squares coefficients of the piece's free motions in `x - xt`.
fn fit(piece: &Piece, r: &[Vec<f64>], x: &[f64], xt: &[f64]) -> Result<Vec<f64>, CouplingError> {
    let n = r.len();
    let g = DMatrix::from_fn(n, n, |k, l| {
        r[k].iter().zip(&r[l]).map(|(a, c)| a * c).sum::<f64>()
    });
    let b = DVector::from_fn(n, |k, _| {
        r[k].iter()
            .zip(x.iter().zip(xt))
            .map(|(a, (xi, ti))| a * (xi - ti))
            .sum()
    });
    let scale = g.trace().max(f64::MIN_POSITIVE);
    let chol = (g / scale).cholesky().filter(|c| {
        let d = c.l().diagonal();
        d.min() > 1e-6 * d.max()
    });
    match chol {
        Some(c) => Ok(c.solve(&(b / scale)).iter().copied().collect()),
        None => Err(CouplingError::FloatingPiece {
            message: format!(
                "the piece of {} elements around ({:.4}, {:.4}) is not held along {} of its \
                 rigid motions and has too few coupled PD nodes to hold it (it touches no \
                 window, or one along a line); hold it with displacement conditions",
                piece.elements.len(),
                piece.centroid.x,
                piece.centroid.y,
                piece.modes.len()
            ),
        }),
    }
}
