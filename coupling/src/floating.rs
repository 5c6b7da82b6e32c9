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
//! Which pieces: a body with one held piece (prescribed displacements fixing its rigid
//! motions) corrects every other piece; when no piece is held (a free plate), the piece
//! with the most elements keeps the solver's gauge, as the whole body did before it was
//! cut. A piece with one or two free rigid motions beside another piece (a roller only)
//! is refused.

use std::sync::OnceLock;

use nalgebra::{Matrix3, Vector3};
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
}

/// The floating pieces of one prepared BEM system and their rigid responses on the
/// virtual nodes (computed at the first use, for the map of that use).
pub struct FloatingPieces {
    pieces: Vec<Piece>,
    responses: OnceLock<Vec<[Vec<f64>; 3]>>,
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
            if let Some(p) = free.iter().position(|&f| f == 1 || f == 2) {
                return Err(CouplingError::FloatingPiece {
                    message: format!(
                        "piece {p} of {} has {} free rigid motion(s): a piece cut off by \
                         cracks must be held fully by displacement conditions or not at all",
                        free.len(),
                        free[p]
                    ),
                });
            }
            let floating: Vec<usize> = (0..free.len()).filter(|&p| free[p] == 3).collect();
            let count = |p: usize| labels.iter().filter(|&&l| l == p).count();
            let reference = if floating.len() == free.len() {
                floating.iter().copied().max_by_key(|&p| count(p))
            } else {
                None
            };
            for p in floating.into_iter().filter(|&p| Some(p) != reference) {
                let elements: Vec<usize> = (0..labels.len()).filter(|&e| labels[e] == p).collect();
                let centroid = elements.iter().map(|&e| mesh.elements[e].mid).sum::<V2>()
                    / elements.len() as f64;
                let length = (elements
                    .iter()
                    .map(|&e| (mesh.elements[e].mid - centroid).norm_squared())
                    .sum::<f64>()
                    / elements.len() as f64)
                    .sqrt();
                pieces.push(Piece {
                    elements,
                    centroid,
                    length,
                });
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
            let q = fit(p, r, x, xt)?;
            let (f, m) = out_of_balance(p, mesh, sol);
            let q = q + Vector3::new(f.x, f.y, m / p.length) / k;
            move_piece(p, mesh, sol, &q);
            for (k, rk) in r.iter().enumerate() {
                for (v, dv) in xt.iter_mut().zip(rk) {
                    *v += q[k] * dv;
                }
            }
        }
        Ok(())
    }
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

/// Virtual displacements of the piece's unit rigid motions (x, y, rotation 1/length).
fn unit_responses(
    piece: &Piece,
    mesh: &Mesh,
    material: &Material,
    map: DisplacementMap,
    ifaces: &[Interface],
    reconstruct: bool,
) -> [Vec<f64>; 3] {
    std::array::from_fn(|k| {
        let mut q = Vector3::zeros();
        q[k] = 1.0;
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
        move_piece(piece, mesh, &mut sol, &q);
        let view = BemView {
            mesh,
            material,
            solution: &sol,
            background: Background::default(),
        };
        bem_to_virtual(map, &view, ifaces)
    })
}

/// Least-squares rigid motion of the piece in `x - xt`.
fn fit(
    piece: &Piece,
    r: &[Vec<f64>; 3],
    x: &[f64],
    xt: &[f64],
) -> Result<Vector3<f64>, CouplingError> {
    let mut g = Matrix3::<f64>::zeros();
    let mut b = Vector3::<f64>::zeros();
    for k in 0..3 {
        for l in 0..3 {
            g[(k, l)] = r[k].iter().zip(&r[l]).map(|(a, c)| a * c).sum();
        }
        b[k] = r[k]
            .iter()
            .zip(x.iter().zip(xt))
            .map(|(a, (xi, ti))| a * (xi - ti))
            .sum();
    }
    let scale = g.trace().max(f64::MIN_POSITIVE);
    let chol = (g / scale).cholesky().filter(|c| {
        let d = c.l().diagonal();
        d.min() > 1e-6 * d.max()
    });
    match chol {
        Some(c) => Ok(c.solve(&(b / scale))),
        None => Err(CouplingError::FloatingPiece {
            message: format!(
                "the piece of {} elements around ({:.4}, {:.4}) has no prescribed \
                 displacement and too few coupled PD nodes to hold it (it touches no window, \
                 or one along a line); hold it with displacement conditions",
                piece.elements.len(),
                piece.centroid.x,
                piece.centroid.y
            ),
        }),
    }
}
