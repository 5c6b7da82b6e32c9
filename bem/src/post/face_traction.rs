//! Crack-face tractions in the J and interaction integrals of [`super::sif`].
//!
//! The contour integrals of [`super::sif::interaction_integral`] are path independent only
//! when the crack faces inside the contour are traction-free. With tractions $t$ on them
//! (a pressurised crack, `normal` or `x`/`y` conditions on a crack group), the closed path
//! round the region between the contour $\Gamma$ and the tip runs along the faces too,
//! where $n_1 = 0$ and $\sigma_{ij} n_j = t_i$ (outward normal of the body), so (tip frame,
//! straight faces behind the tip; e.g. Anderson, *Fracture Mechanics*, the J contour
//! integral with crack-face tractions)
//! $$J = \oint_\Gamma (W n_1 - \sigma_{ij} n_j u_{i,1})\,ds - \int_{faces} t_i\,u_{i,1}\,dx_1,
//! \qquad M = \oint_\Gamma (\dots)\,ds - \int_{faces} t_i\,u^{aux}_{i,1}\,dx_1,$$
//! the auxiliary Williams fields being traction-free on the faces; $t$ and $u$ are the
//! whole field's, the background of an infinite plate included (whose crack faces the
//! solution loads by minus the remote traction, so that free faces carry none). Over each face, from
//! the contour ($x_1 = -\rho$) to the tip, with the element's traction constant,
//! $\int t_i u_{i,1}\,dx_1 = t_i\,[u_i(x_1^{hi}) - u_i(x_1^{lo})]$ element by element:
//! exact for the Williams displacements ($\propto \sqrt r$ at $\theta = \pm\pi$); for the
//! solution's own displacements, linear between the collocation points of the face and,
//! at the tip, the mean of the two faces' linear extrapolations (for tractions equal and
//! opposite on the two faces, as a pressure, the tip value cancels).
//!
//! Without these terms a crack under unit face pressure (Griffith, $K = \sqrt{\pi a}$) had
//! an interaction-integral $K_I$ 45 % low on the default contour ($\rho = 0.3 a$), so the
//! two extractions disagreed by that much and the error estimate with them.

use super::williams::williams;
use super::FieldEvaluator;
use crate::mesh::V2;

/// Face tractions below this fraction of the largest remote stress are those of free
/// faces in an infinite plate (the solution's minus the remote traction, plus it).
pub const FREE_FACE_TOLERANCE: f64 = 1e-12;

/// One face element's piece inside the contour: its traction in the tip frame, the tip
/// frame's x1 at its two clipped ends (lo < hi <= 0) and which side of the crack it lies
/// on (+pi above the crack line, -pi below).
struct FacePiece {
    t: [f64; 2],
    lo: f64,
    hi: f64,
    theta: f64,
}

/// The crack-face terms to add to the contour integrals of [`super::sif`]: the raw
/// interaction integrals of modes I and II (before the factor E'/2) and J, from the
/// faces of crack `crack` within `radius` behind the tip at `tip` (unit direction `dir`).
/// Zero when no face element there carries a traction.
pub fn face_terms(ev: &FieldEvaluator, crack: usize, tip: V2, dir: V2, radius: f64) -> [f64; 3] {
    let (mesh, mat) = (ev.mesh(), ev.material());
    let nrm = V2::new(-dir.y, dir.x);
    let frame = |v: V2| [v.dot(&dir), v.dot(&nrm)];
    let c = &mesh.cracks[crack];
    let mut out = [0.0; 3];
    let faces: [&[usize]; 2] = [&c.upper, &c.lower];
    let pieces: Vec<Vec<FacePiece>> = faces
        .iter()
        .map(|ids| {
            ids.iter()
                .filter_map(|&e| piece(ev, e, tip, radius, &frame))
                .collect()
        })
        .collect();
    // Free faces: exactly zero, or the round-off of the remote traction and minus it.
    let tol = FREE_FACE_TOLERANCE
        * ev.background()
            .stress
            .iter()
            .fold(0.0, |m, s| s.abs().max(m));
    if pieces
        .iter()
        .flatten()
        .all(|p| p.t[0].abs() <= tol && p.t[1].abs() <= tol)
    {
        return out;
    }
    let (mu, kappa) = (mat.mu(), mat.kappa());
    for (mode, slot) in [(1u8, 0usize), (2, 1)] {
        for p in pieces.iter().flatten() {
            let u = |x1: f64| williams(mode, (-x1).max(0.0), p.theta, mu, kappa).0;
            let (a, b) = (u(p.lo), u(p.hi));
            out[slot] -= p.t[0] * (b[0] - a[0]) + p.t[1] * (b[1] - a[1]);
        }
    }
    let tip_u = tip_displacement(ev, faces, tip, &frame);
    for (ids, ps) in faces.iter().zip(&pieces) {
        let line = face_line(ev, ids, tip, &frame, tip_u);
        for p in ps {
            let (a, b) = (interpolate(&line, p.lo), interpolate(&line, p.hi));
            out[2] -= p.t[0] * (b[0] - a[0]) + p.t[1] * (b[1] - a[1]);
        }
    }
    out
}

/// The part of face element `e` behind the tip and within `radius` of it, or none.
fn piece(
    ev: &FieldEvaluator,
    e: usize,
    tip: V2,
    radius: f64,
    frame: &dyn Fn(V2) -> [f64; 2],
) -> Option<FacePiece> {
    let el = &ev.mesh().elements[e];
    let (xa, xb) = (frame(el.a - tip)[0], frame(el.b - tip)[0]);
    let lo = xa.min(xb).max(-radius);
    let hi = xa.max(xb).min(0.0);
    if hi <= lo {
        return None;
    }
    let n = frame(el.normal);
    Some(FacePiece {
        t: {
            let t = ev.boundary_traction(e);
            frame(V2::new(t[0], t[1]))
        },
        lo,
        hi,
        // The face above the crack line has its outward normal pointing down into the gap.
        theta: if n[1] < 0.0 {
            std::f64::consts::PI
        } else {
            -std::f64::consts::PI
        },
    })
}

/// The displacement of a face as (x1, u in the tip frame) at its collocation points
/// behind the tip, ordered by x1, ending with the tip value at x1 = 0.
fn face_line(
    ev: &FieldEvaluator,
    ids: &[usize],
    tip: V2,
    frame: &dyn Fn(V2) -> [f64; 2],
    tip_u: [f64; 2],
) -> Vec<(f64, [f64; 2])> {
    let mut line: Vec<(f64, [f64; 2])> = ids
        .iter()
        .map(|&e| {
            let x1 = frame(ev.mesh().elements[e].mid - tip)[0];
            let u = ev.boundary_displacement(e);
            (x1, frame(V2::new(u[0], u[1])))
        })
        .filter(|(x1, _)| *x1 < 0.0)
        .collect();
    line.sort_by(|a, b| a.0.total_cmp(&b.0));
    line.push((0.0, tip_u));
    line
}

/// The tip's displacement in the tip frame: the mean over both faces of the line through
/// the two collocation points nearest the tip, at x1 = 0.
fn tip_displacement(
    ev: &FieldEvaluator,
    faces: [&[usize]; 2],
    tip: V2,
    frame: &dyn Fn(V2) -> [f64; 2],
) -> [f64; 2] {
    let mut sum = [0.0; 2];
    let mut count = 0.0;
    for ids in faces {
        let mut line = face_line(ev, ids, tip, frame, [0.0; 2]);
        line.pop();
        let n = line.len();
        let value = match n {
            0 => continue,
            1 => line[0].1,
            _ => {
                let ((x0, u0), (x1, u1)) = (line[n - 2], line[n - 1]);
                let s = -x1 / (x1 - x0);
                [u1[0] + s * (u1[0] - u0[0]), u1[1] + s * (u1[1] - u0[1])]
            }
        };
        sum = [sum[0] + value[0], sum[1] + value[1]];
        count += 1.0;
    }
    if count == 0.0 {
        return sum;
    }
    [sum[0] / count, sum[1] / count]
}

/// The piecewise-linear interpolation of `line` (ordered by x1) at `x1`, constant beyond
/// its first point.
fn interpolate(line: &[(f64, [f64; 2])], x1: f64) -> [f64; 2] {
    let k = line.partition_point(|p| p.0 < x1);
    if k == 0 {
        return line[0].1;
    }
    if k == line.len() {
        return line[k - 1].1;
    }
    let ((xa, ua), (xb, ub)) = (line[k - 1], line[k]);
    let s = if xb > xa { (x1 - xa) / (xb - xa) } else { 0.0 };
    [ua[0] + s * (ub[0] - ua[0]), ua[1] + s * (ub[1] - ua[1])]
}
