//! Tangential-derivative stencil for the linear reconstruction of boundary displacement.
//!
//! Constant elements cannot represent a rigid rotation: a piecewise-constant linear field
//! leaves spurious tractions of about 0.2 mu omega at every collocation point, whatever h
//! (test `rigid_rotation_residual_traction_shrinks_with_h`), and that is why deep edge cracks,
//! whose halves rotate, converge slowly (REFERENCES.md). The remedy keeps one unknown per
//! element but integrates $u(s) \approx u_j + g_j (s - s_j)$ over element j, with the
//! tangential derivative $g_j$ from the neighbours along the same straight side:
//! central differences inside a side or a smooth chain (polygonal circles: turns below 30
//! degrees), one-sided at corners, crack tips and crack mouths, none for an element alone
//! on its side. Linear fields, rigid rotation included, are then integrated exactly on
//! straight sides: the patch test becomes exact to round-off.
//!
//! Crack faces rotate with the body too, so they are reconstructed as well, except within
//! `FACE_TIP_ZONE` L of a tip (L as in [`crate::post::sif::tip_length_scale`]): there the
//! opening behaves like sqrt(r), and the crack-opening fit and the interaction integral
//! (both inside 0.3 L) are calibrated for constant elements. Measured on the H = 2W strip
//! (K against Tada, outline h = 0.1, crack h = 0.025), a/W = 0.2 / 0.5 / 0.8:
//! faces all constant +0.06 / -0.13 / -2.3 %; zone 0.3 L: -0.40 / -0.46 / -1.1 %;
//! zone 0.6 L: +0.03 / -0.10 / -0.43 % (the last is -0.08 % against the FEM table, which
//! Tada exceeds by 0.33 % at 0.8); zone 1.0 L: +0.06 / -0.07 / -0.81 %. Reconstructing up
//! to the tip (central or sqrt(r)-aware differences) overshoots by +4 to +11 %.

use super::{Mesh, V2};

/// g_j = sum_k w_k u_k, per element j: (element k, weight w_k) pairs (empty: no reconstruction).
pub type Stencil = Vec<Vec<(usize, f64)>>;

/// Crack-face zone kept constant around each tip, as a fraction of L (see module docs).
pub const FACE_TIP_ZONE: f64 = 0.6;

/// Tolerance for "same straight side" and "contiguous": relative to the element length.
const TOL: f64 = 1e-9;

/// Largest turn between neighbouring elements of one smooth chain (polygonal circles turn
/// by 2 pi / n; rectangle corners, 90 degrees, break the chain).
const MAX_TURN_COS: f64 = 0.866; // cos 30 degrees

fn smooth(mesh: &Mesh, a: usize, b: usize) -> bool {
    let (ea, eb) = (&mesh.elements[a], &mesh.elements[b]);
    ea.tangent.dot(&eb.tangent) > MAX_TURN_COS
}

/// Builds the stencil from the closed loops (in traversal order) and the crack faces
/// outside the tip zones.
pub fn tangential_stencil(mesh: &Mesh) -> Stencil {
    let n = mesh.len();
    let mut prev: Vec<Option<usize>> = vec![None; n];
    let mut next: Vec<Option<usize>> = vec![None; n];
    let mouths: Vec<V2> = mesh
        .cracks
        .iter()
        .flat_map(|c| {
            let mut v = Vec::new();
            if !c.start_is_tip {
                v.push(c.points[0]);
            }
            if !c.end_is_tip {
                v.push(*c.points.last().unwrap());
            }
            v
        })
        .collect();
    let joined = |a: usize, b: usize| {
        // b follows a: contiguous, collinear, and not at a crack mouth.
        let (ea, eb) = (&mesh.elements[a], &mesh.elements[b]);
        let tol = TOL * ea.h.max(eb.h);
        (ea.b - eb.a).norm() <= tol
            && smooth(mesh, a, b)
            && !mouths.iter().any(|m| (m - ea.b).norm() <= 1e3 * tol)
    };
    for r in &mesh.loops {
        let ids: Vec<usize> = r.clone().collect();
        let k = ids.len();
        for i in 0..k {
            let (a, b) = (ids[i], ids[(i + 1) % k]);
            if joined(a, b) {
                next[a] = Some(b);
                prev[b] = Some(a);
            }
        }
    }
    for c in &mesh.cracks {
        link_faces(mesh, c, FACE_TIP_ZONE, &joined, &mut prev, &mut next);
    }
    (0..n)
        .map(|j| {
            let sj = |k: usize| {
                (mesh.elements[k].mid - mesh.elements[j].mid).dot(&mesh.elements[j].tangent)
            };
            match (prev[j], next[j]) {
                (Some(p), Some(q)) => {
                    // Three-point derivative, exact for quadratics on graded elements;
                    // the central difference (u_q - u_p)/(s_q - s_p) on uniform ones.
                    let (hm, hp) = (-sj(p), sj(q));
                    if ((hp - hm) / (hp + hm)).abs() < 1e-9 {
                        let d = hp + hm;
                        vec![(q, 1.0 / d), (p, -1.0 / d)]
                    } else {
                        vec![
                            (q, hm / (hp * (hm + hp))),
                            (j, (hp - hm) / (hm * hp)),
                            (p, -hp / (hm * (hm + hp))),
                        ]
                    }
                }
                (None, Some(q)) => {
                    let d = sj(q);
                    vec![(q, 1.0 / d), (j, -1.0 / d)]
                }
                (Some(p), None) => {
                    let d = -sj(p);
                    vec![(j, 1.0 / d), (p, -1.0 / d)]
                }
                (None, None) => Vec::new(),
            }
        })
        .collect()
}

/// Links the face elements of `c` that lie farther than `zone` L from every tip (L as in
/// [`crate::post::sif::tip_length_scale`]).
fn link_faces(
    mesh: &Mesh,
    c: &super::Crack,
    zone: f64,
    joined: &dyn Fn(usize, usize) -> bool,
    prev: &mut [Option<usize>],
    next: &mut [Option<usize>],
) {
    let total = c.length();
    let ci = mesh
        .cracks
        .iter()
        .position(|x| std::ptr::eq(x, c))
        .unwrap_or(0);
    let tips: Vec<(f64, f64)> = [
        (c.start_is_tip, 0.0, c.points[0]),
        (c.end_is_tip, total, *c.points.last().unwrap()),
    ]
    .iter()
    .filter(|t| t.0)
    .map(|t| {
        (
            t.1,
            zone * crate::post::sif::tip_length_scale(mesh, ci, t.2),
        )
    })
    .collect();
    let free = |i: usize| tips.iter().all(|(s, r)| (c.stations[i] - s).abs() > *r);
    let m = c.stations.len();
    for i in 0..m.saturating_sub(1) {
        if !(free(i) && free(i + 1)) {
            continue;
        }
        let (a, b) = (c.upper[i], c.upper[i + 1]);
        if joined(a, b) {
            next[a] = Some(b);
            prev[b] = Some(a);
        }
        // Lower-face elements run against the polyline: lower[i+1] precedes lower[i].
        let (a, b) = (c.lower[i + 1], c.lower[i]);
        if joined(a, b) {
            next[a] = Some(b);
            prev[b] = Some(a);
        }
    }
}

/// Tangential derivatives g_j of an element field `u` by the stencil.
pub fn apply(stencil: &Stencil, u: &[[f64; 2]]) -> Vec<[f64; 2]> {
    stencil
        .iter()
        .map(|row| {
            let mut g = [0.0; 2];
            for &(k, w) in row {
                g[0] += w * u[k][0];
                g[1] += w * u[k][1];
            }
            g
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{LoopSpec, MeshBuilder};

    #[test]
    fn stencil_differentiates_linear_fields_exactly_on_each_side() {
        let mut b = MeshBuilder::new();
        b.add_loop(LoopSpec::rectangle(0.0, 0.0, 2.0, 1.0, 0.25));
        let m = b.build().unwrap();
        let st = tangential_stencil(&m);
        // Rigid rotation u = (-y, x): du/ds = (-t_y, t_x) along the tangent t.
        let u: Vec<[f64; 2]> = m.elements.iter().map(|e| [-e.mid.y, e.mid.x]).collect();
        let g = apply(&st, &u);
        for (e, gj) in m.elements.iter().zip(&g) {
            assert!((gj[0] + e.tangent.y).abs() < 1e-12 && (gj[1] - e.tangent.x).abs() < 1e-12);
        }
    }
}
