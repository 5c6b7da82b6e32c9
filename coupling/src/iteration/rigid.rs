//! The windows' rigid-motion balance of the traction ordering (module docs of
//! [`super::traction`]): $G(q) = G_0 + A q$ with $A$ the resultants of the BEM tractions
//! of unit rigid motions of each floating window, and $q = -A^{+} G_0$.

use nalgebra::{DMatrix, DVector};
use pdbem_bem::{Bc, BemSystem, Solution, V2};

use super::CoupledProblem;
use crate::error::CouplingError;
use crate::traction_window::{is_floating, TractionWindow};

/// Singular values of the balance matrix below this times E are dropped.
const RANK_TOLERANCE: f64 = 1e-6;

/// The BEM side of the windows' rigid-motion balance (module docs).
pub struct RigidBalance {
    /// Floating windows (indices).
    floating: Vec<usize>,
    /// Per floating window: centre (m) and rotation length scale (m).
    frames: Vec<(V2, f64)>,
    /// Pseudo-inverse of the balance matrix A (3 per floating window, square).
    pinv: DMatrix<f64>,
}

impl RigidBalance {
    /// Unit rigid-motion responses of `system` (factored with displacement interfaces).
    pub(super) fn new(problem: &CoupledProblem, system: &BemSystem) -> Result<Self, CouplingError> {
        let floating: Vec<usize> = (0..problem.windows.len())
            .filter(|&i| is_floating(&problem.windows[i]))
            .collect();
        let frames: Vec<(V2, f64)> = floating
            .iter()
            .map(|&i| {
                let w = &problem.windows[i].window;
                let (lx, ly) = w.size();
                (w.spec.center, 0.5 * lx.hypot(ly))
            })
            .collect();
        let m = 3 * floating.len();
        let mut bcs = problem.bcs.clone();
        let base = system.solve_with(&bcs)?;
        let mut a = DMatrix::zeros(m, m);
        for (col, &wi) in floating.iter().enumerate() {
            for mode in 0..3 {
                let mut q = [0.0; 3];
                q[mode] = 1.0;
                set_rigid(problem, wi, frames[col], q, &mut bcs);
                let sol = system.solve_with(&bcs)?;
                let g = resultants(problem, &floating, &frames, &sol, Some(&base));
                for (row, v) in g.iter().enumerate() {
                    a[(row, 3 * col + mode)] = *v;
                }
                set_rigid(problem, wi, frames[col], [0.0; 3], &mut bcs);
            }
        }
        let cut = RANK_TOLERANCE * problem.material.e;
        let pinv = if m == 0 {
            DMatrix::zeros(0, 0)
        } else {
            a.svd(true, true)
                .pseudo_inverse(cut)
                .map_err(|e| CouplingError::InvalidStep {
                    message: format!("rigid balance of the windows: {e}"),
                })?
        };
        Ok(RigidBalance {
            floating,
            frames,
            pinv,
        })
    }
}

/// Rigid motion of unknowns q = (a_x, a_y, theta L) on window `wi`'s interface elements.
fn set_rigid(
    problem: &CoupledProblem,
    wi: usize,
    (c, l): (V2, f64),
    q: [f64; 3],
    bcs: &mut [[Bc; 2]],
) {
    for &e in &problem.windows[wi].interface.elements {
        let r = problem.mesh.elements[e].mid - c;
        let th = q[2] / l;
        bcs[e] = [
            Bc::Displacement(q[0] - th * r.y),
            Bc::Displacement(q[1] + th * r.x),
        ];
    }
}

/// Traction resultants of every floating window (3 each: F_x, F_y, M / L per unit
/// thickness) of `sol`, minus those of `base` when given.
fn resultants(
    problem: &CoupledProblem,
    floating: &[usize],
    frames: &[(V2, f64)],
    sol: &Solution,
    base: Option<&Solution>,
) -> Vec<f64> {
    let mut g = vec![0.0; 3 * floating.len()];
    for (k, &wi) in floating.iter().enumerate() {
        let (c, l) = frames[k];
        for &e in &problem.windows[wi].interface.elements {
            let el = &problem.mesh.elements[e];
            let mut t = sol.t[e];
            if let Some(b) = base {
                t = [t[0] - b.t[e][0], t[1] - b.t[e][1]];
            }
            let r = el.mid - c;
            g[3 * k] += t[0] * el.h;
            g[3 * k + 1] += t[1] * el.h;
            g[3 * k + 2] += (r.x * t[1] - r.y * t[0]) * el.h / l;
        }
    }
    g
}

/// Sets the floating windows' rigid motions that balance them against the BEM solution
/// `sol` (computed without motions) and adds them to their `given` displacements;
/// whether any motion is non-zero.
pub(super) fn balance_windows(
    problem: &CoupledProblem,
    rb: &RigidBalance,
    tws: &mut [TractionWindow],
    sol: &Solution,
    scale: f64,
) -> bool {
    if rb.floating.is_empty() {
        return false;
    }
    let mut g = resultants(problem, &rb.floating, &rb.frames, sol, None);
    for (k, &wi) in rb.floating.iter().enumerate() {
        let tw = &tws[wi];
        let (f, m) = tw.outer_resultant(scale);
        let th = problem.thickness;
        g[3 * k] -= f[0] / th;
        g[3 * k + 1] -= f[1] / th;
        g[3 * k + 2] -= m / th / rb.frames[k].1;
    }
    let q = -(&rb.pinv * DVector::from_vec(g));
    if q.iter().all(|v| *v == 0.0) {
        return false;
    }
    for (k, &wi) in rb.floating.iter().enumerate() {
        let tw = &mut tws[wi];
        tw.motion = [q[3 * k], q[3 * k + 1], q[3 * k + 2] / rb.frames[k].1];
        let shifts: Vec<[f64; 2]> = tw
            .elements
            .iter()
            .map(|&e| tw.rigid_at(problem.mesh.elements[e].mid))
            .collect();
        for (u, r) in tw.given.iter_mut().zip(shifts) {
            u[0] += r[0];
            u[1] += r[1];
        }
    }
    true
}
