//! Load balance of the pieces of a finite body against the rigid motions their
//! displacement conditions leave free.
//!
//! A piece whose prescribed displacements do not fix a rigid motion $v$ (all three for a
//! body with no displacement condition) is in equilibrium only if the prescribed tractions
//! do no work on $v$. With constant tractions on straight elements the resultant is exact:
//! $$F = \sum_e t_e h_e, \qquad M = \sum_e (x_e - c) \times t_e\, h_e,$$
//! summed over the traction-prescribed components ($x_e$ the element midpoint, $c$ the
//! piece's mean collocation point). The work on the unit motion $v = (a_x, a_y, \theta)$
//! (rotation scaled by the piece size $L$, as in the solver's rigid modes) is
//! $W_v = a_x F_x + a_y F_y + \theta M / L$. The solver's bordering
//! ([`super`] module docs) returns *a* solution whatever $W_v$ is: for $W_v \ne 0$ it is
//! the solution of a different, balanced load, silently wrong.
//!
//! The load is out of balance when $|W_v| > \tau S$ for a free $v$, with
//! $S = \sum_e h_e (|t_x| + |t_y|)$ (which bounds $|F|$ and $|M|/L$) and
//! $\tau$ = [`BALANCE_TOLERANCE`]. A balanced scene load (uniform tractions on opposite
//! edges, pressure on a closed hole or on both crack faces) balances exactly in this
//! discrete form, to rounding (about 1e-15 S).
//!
//! Entry point: [`load_imbalance`].

use super::rigid::piece_frame;
use super::Bc;
use crate::mesh::{Mesh, V2};

/// Relative tolerance $\tau$ of the balance check (see the module docs). Balanced loads
/// balance to rounding (measured below 1e-14 on every case of `cases/`), so 1e-6 leaves
/// eight orders of margin and still catches any imbalance that would move a SIF by more
/// than about 1e-6 of its value.
pub const BALANCE_TOLERANCE: f64 = 1e-6;

/// The out-of-balance load of one piece.
#[derive(Debug, Clone, PartialEq)]
pub struct Imbalance {
    /// Piece index ([`crate::mesh::pieces`]).
    pub piece: usize,
    /// Point the moment is taken about: the piece's mean collocation point (m).
    pub centroid: V2,
    /// Resultant force of the prescribed tractions, per unit thickness (N/m).
    pub force: [f64; 2],
    /// Resultant moment about `centroid`, per unit thickness (N m/m), counter-clockwise
    /// positive.
    pub moment: f64,
    /// Rigid motions the piece's displacement conditions leave free (1 to 3).
    pub free_motions: usize,
    /// Largest $|W_v| / S$ over the free motions (above [`BALANCE_TOLERANCE`]).
    pub relative: f64,
    /// Element groups with a non-zero prescribed traction on the piece.
    pub groups: Vec<usize>,
}

/// Resultant (F_x, F_y, M about `c`) and magnitude S of the prescribed tractions on
/// `elements`, and the groups that carry them.
fn resultant(
    mesh: &Mesh,
    bcs: &[[Bc; 2]],
    elements: &[usize],
    c: V2,
) -> ([f64; 3], f64, Vec<usize>) {
    let (mut r, mut s) = ([0.0; 3], 0.0);
    let mut groups = Vec::new();
    for &i in elements {
        let e = &mesh.elements[i];
        let t = bcs[i].map(|b| match b {
            Bc::Traction(v) => v,
            Bc::Displacement(_) => 0.0,
        });
        if t == [0.0; 2] {
            continue;
        }
        let q = e.mid - c;
        r[0] += t[0] * e.h;
        r[1] += t[1] * e.h;
        r[2] += (q.x * t[1] - q.y * t[0]) * e.h;
        s += (t[0].abs() + t[1].abs()) * e.h;
        if !groups.contains(&e.group) {
            groups.push(e.group);
        }
    }
    groups.sort_unstable();
    (r, s, groups)
}

/// Pieces of the finite body `mesh` whose prescribed tractions are out of balance (by more
/// than `tolerance`, relative, see the module docs) along a rigid motion their
/// displacement conditions leave free. Empty when every piece is in balance or held.
/// Not meaningful for an infinite body (no rigid motions: a net force goes to infinity).
pub fn load_imbalance(mesh: &Mesh, bcs: &[[Bc; 2]], tolerance: f64) -> Vec<Imbalance> {
    if mesh.is_empty() || bcs.len() != mesh.len() {
        return Vec::new();
    }
    let labels = crate::mesh::pieces(mesh).unwrap_or_else(|| vec![0; mesh.len()]);
    let count = labels.iter().copied().max().map_or(0, |m| m + 1);
    let mut out = Vec::new();
    for p in 0..count {
        let frame = piece_frame(mesh, bcs, &labels, p);
        if frame.free.is_empty() {
            continue;
        }
        let (r, s, groups) = resultant(mesh, bcs, &frame.elements, frame.centroid);
        if s == 0.0 {
            continue;
        }
        let load = nalgebra::Vector3::new(r[0], r[1], r[2] / frame.scale);
        let relative = frame
            .free
            .iter()
            .map(|v| v.dot(&load).abs() / s)
            .fold(0.0, f64::max);
        if relative > tolerance {
            out.push(Imbalance {
                piece: p,
                centroid: frame.centroid,
                force: [r[0], r[1]],
                moment: r[2],
                free_motions: frame.free.len(),
                relative,
                groups,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{LoopSpec, MeshBuilder};

    /// A 2 x 1 rectangle with edge groups bottom, right, top, left.
    fn rectangle() -> Mesh {
        let mut b = MeshBuilder::new();
        b.add_loop(LoopSpec {
            points: vec![
                V2::new(0.0, 0.0),
                V2::new(2.0, 0.0),
                V2::new(2.0, 1.0),
                V2::new(0.0, 1.0),
            ],
            edge_groups: ["bottom", "right", "top", "left"]
                .map(String::from)
                .to_vec(),
            edge_sizes: vec![0.1; 4],
            is_hole: false,
        });
        b.build().unwrap()
    }

    /// Conditions: traction `(tx, ty)` per group name, zero traction elsewhere.
    fn tractions(mesh: &Mesh, on: &[(&str, [Bc; 2])]) -> Vec<[Bc; 2]> {
        let mut bcs = vec![[Bc::Traction(0.0); 2]; mesh.len()];
        for (name, bc) in on {
            let g = mesh.group(name).unwrap();
            for i in mesh.group_elements(g) {
                bcs[i] = *bc;
            }
        }
        bcs
    }

    #[test]
    fn opposite_edge_tension_balances() {
        let m = rectangle();
        let bcs = tractions(
            &m,
            &[
                ("left", [Bc::Traction(-1.0), Bc::Traction(0.0)]),
                ("right", [Bc::Traction(1.0), Bc::Traction(0.0)]),
            ],
        );
        assert!(load_imbalance(&m, &bcs, BALANCE_TOLERANCE).is_empty());
    }

    #[test]
    fn one_sided_tension_reports_its_resultant() {
        let m = rectangle();
        let bcs = tractions(&m, &[("right", [Bc::Traction(2.0), Bc::Traction(0.0)])]);
        let out = load_imbalance(&m, &bcs, BALANCE_TOLERANCE);
        assert_eq!(out.len(), 1);
        let i = &out[0];
        // 2 Pa over the 1 m right edge; the edge is on the centroid's line: no moment.
        assert!((i.force[0] - 2.0).abs() < 1e-12 && i.force[1].abs() < 1e-12);
        assert!(i.moment.abs() < 1e-12);
        assert_eq!(i.free_motions, 3);
        assert_eq!(i.groups, vec![m.group("right").unwrap()]);
    }

    #[test]
    fn opposite_shear_is_a_couple() {
        let m = rectangle();
        // Shear +1 on the right edge (y up) and -1 on the left: F = 0, M = 2 N m/m.
        let bcs = tractions(
            &m,
            &[
                ("left", [Bc::Traction(0.0), Bc::Traction(-1.0)]),
                ("right", [Bc::Traction(0.0), Bc::Traction(1.0)]),
            ],
        );
        let out = load_imbalance(&m, &bcs, BALANCE_TOLERANCE);
        assert_eq!(out.len(), 1);
        assert!(out[0].force[0].abs() < 1e-12 && out[0].force[1].abs() < 1e-12);
        assert!((out[0].moment - 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_clamped_edge_holds_any_load() {
        let m = rectangle();
        let bcs = tractions(
            &m,
            &[
                ("left", [Bc::Displacement(0.0); 2]),
                ("right", [Bc::Traction(2.0), Bc::Traction(5.0)]),
            ],
        );
        assert!(load_imbalance(&m, &bcs, BALANCE_TOLERANCE).is_empty());
    }

    #[test]
    fn a_roller_leaves_the_sliding_direction_free() {
        let m = rectangle();
        // The bottom edge fixed in y only: rotation and y translation are held, x is free.
        let roller = [Bc::Traction(0.0), Bc::Displacement(0.0)];
        let held = tractions(
            &m,
            &[
                ("bottom", roller),
                ("top", [Bc::Traction(0.0), Bc::Traction(1.0)]),
            ],
        );
        assert!(load_imbalance(&m, &held, BALANCE_TOLERANCE).is_empty());
        let sliding = tractions(
            &m,
            &[
                ("bottom", roller),
                ("right", [Bc::Traction(1.0), Bc::Traction(0.0)]),
            ],
        );
        let out = load_imbalance(&m, &sliding, BALANCE_TOLERANCE);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].free_motions, 1);
    }
}
