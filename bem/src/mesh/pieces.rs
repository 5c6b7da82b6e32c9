//! The connected pieces of the body a mesh bounds.
//!
//! A crack running from the outline to a hole (in the PD-BEM coupling: a window) cuts the
//! body in two; each piece then has rigid-body motions of its own
//! ([`crate::system`] borders each piece's free motions separately).
//!
//! The boundary is traced as closed circuits of elements, the body on the left of each
//! (DESIGN.md orientation). Where several elements leave the end point of the element
//! just traversed (a crack mouth, a crack entering a hole, coincident crack faces), the
//! circuit takes the first one clockwise from the way back, the reverse of the
//! element just traversed (the body side of the junction). A way out that runs straight
//! back (the other face of a coincident crack) comes last: it is taken only at a tip.
//! Counter-clockwise circuits (positive area) are the outer boundaries of the pieces;
//! the others (holes, cracks inside a piece) belong to the smallest outer circuit around
//! them.

use pdbem_geometry::{point_in_polygon, signed_area};

use super::{Mesh, V2};

/// End points closer than this fraction of the smallest element are one vertex.
const VERTEX_TOLERANCE: f64 = 1e-6;

/// Piece index of every element (pieces numbered from 0 in order of their first
/// element), or `None` when the elements do not close into circuits (a mesh built by
/// hand with loose ends): callers then treat the body as one piece.
pub fn pieces(mesh: &Mesh) -> Option<Vec<usize>> {
    let circuits = circuits(mesh)?;
    let polys: Vec<Vec<V2>> = circuits
        .iter()
        .map(|c| c.iter().map(|&e| mesh.elements[e].a).collect())
        .collect();
    let areas: Vec<f64> = polys.iter().map(|p| signed_area(p)).collect();
    let scale: f64 = mesh.elements.iter().map(|e| e.h).sum::<f64>().powi(2);
    let outer: Vec<usize> = (0..circuits.len())
        .filter(|&i| areas[i] > 1e-12 * scale)
        .collect();
    if outer.is_empty() {
        return None;
    }
    let mut owner = vec![usize::MAX; circuits.len()];
    for &i in &outer {
        owner[i] = i;
    }
    for i in 0..circuits.len() {
        if owner[i] != usize::MAX {
            continue;
        }
        let probe = mesh.elements[circuits[i][0]].mid;
        owner[i] = outer
            .iter()
            .copied()
            .filter(|&o| point_in_polygon(&probe, &polys[o]))
            .min_by(|&a, &b| areas[a].total_cmp(&areas[b]))?;
    }
    // Circuits in order of their first element: pieces get their numbers in the order
    // of their first element.
    let mut order: Vec<usize> = (0..circuits.len()).collect();
    order.sort_by_key(|&i| circuits[i].iter().min().copied().unwrap_or(usize::MAX));
    let mut label = vec![usize::MAX; mesh.len()];
    let mut number = vec![usize::MAX; circuits.len()];
    let mut next = 0;
    for i in order {
        let o = owner[i];
        if number[o] == usize::MAX {
            number[o] = next;
            next += 1;
        }
        for &e in &circuits[i] {
            label[e] = number[o];
        }
    }
    Some(label)
}

/// The boundary as closed circuits of element indices (see the module docs).
fn circuits(mesh: &Mesh) -> Option<Vec<Vec<usize>>> {
    let n = mesh.len();
    let hmin = mesh
        .elements
        .iter()
        .map(|e| e.h)
        .fold(f64::INFINITY, f64::min);
    let starts = Starts::new(mesh, VERTEX_TOLERANCE * hmin);
    let mut used = vec![false; n];
    let mut out = Vec::new();
    for start in 0..n {
        if used[start] {
            continue;
        }
        let mut circuit = vec![start];
        used[start] = true;
        let mut cur = start;
        loop {
            let next = successor(mesh, &starts, cur)?;
            if next == start {
                break;
            }
            if used[next] {
                return None;
            }
            used[next] = true;
            circuit.push(next);
            cur = next;
        }
        out.push(circuit);
    }
    Some(out)
}

/// Element start points sorted by x, for the elements starting at a point.
struct Starts {
    by_x: Vec<(f64, usize)>,
    tol: f64,
}

impl Starts {
    fn new(mesh: &Mesh, tol: f64) -> Self {
        let mut by_x: Vec<(f64, usize)> = mesh
            .elements
            .iter()
            .enumerate()
            .map(|(i, e)| (e.a.x, i))
            .collect();
        by_x.sort_by(|a, b| a.0.total_cmp(&b.0));
        Starts { by_x, tol }
    }

    /// Elements starting within the tolerance of `p`.
    fn at<'a>(&'a self, mesh: &'a Mesh, p: V2) -> impl Iterator<Item = usize> + 'a {
        let lo = self.by_x.partition_point(|(x, _)| *x < p.x - self.tol);
        self.by_x[lo..]
            .iter()
            .take_while(move |(x, _)| *x <= p.x + self.tol)
            .map(|(_, i)| *i)
            .filter(move |&i| (mesh.elements[i].a - p).norm() <= self.tol)
    }
}

/// The element the circuit takes after `e`: of the elements starting at `e`'s end, the
/// first clockwise from the way back (an exact way back last).
fn successor(mesh: &Mesh, starts: &Starts, e: usize) -> Option<usize> {
    let el = &mesh.elements[e];
    let back = -el.tangent;
    let angle_back = back.y.atan2(back.x);
    let tau = std::f64::consts::TAU;
    starts
        .at(mesh, el.b)
        .map(|i| {
            let t = mesh.elements[i].tangent;
            // Clockwise angle from the way back, in (0, 2 pi].
            let mut cw = (angle_back - t.y.atan2(t.x)).rem_euclid(tau);
            if cw < 1e-9 {
                cw = tau;
            }
            (i, cw)
        })
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{CrackSpec, FaceMode, LoopSpec, MeshBuilder};

    fn rect(x0: f64, y0: f64, w: f64, h: f64, size: f64, is_hole: bool) -> LoopSpec {
        let group = if is_hole { "hole" } else { "outer" };
        LoopSpec {
            edge_groups: vec![group.to_string(); 4],
            is_hole,
            ..LoopSpec::rectangle(x0, y0, w, h, size)
        }
    }

    fn crack(name: &str, a: V2, b: V2, faces: FaceMode) -> CrackSpec {
        CrackSpec {
            name: name.into(),
            points: vec![a, b],
            faces,
            element_size: 0.05,
            tip: None,
        }
    }

    fn count(labels: &[usize]) -> usize {
        labels.iter().copied().max().map_or(0, |m| m + 1)
    }

    #[test]
    fn an_edge_crack_leaves_one_piece() {
        let mut b = MeshBuilder::new();
        b.add_loop(rect(0.0, 0.0, 2.0, 1.0, 0.1, false));
        let (m, t) = (V2::new(1.0, 1.0), V2::new(1.0, 0.5));
        b.add_crack(crack("c", m, t, FaceMode::Coincident));
        assert_eq!(count(&pieces(&b.build().unwrap()).unwrap()), 1);
    }

    #[test]
    fn a_hole_and_an_inner_crack_belong_to_the_piece_around_them() {
        let mut b = MeshBuilder::new();
        b.add_loop(rect(0.0, 0.0, 2.0, 1.0, 0.1, false));
        b.add_loop(rect(0.4, 0.4, 0.2, 0.2, 0.05, true));
        let (p, q) = (V2::new(1.2, 0.5), V2::new(1.6, 0.5));
        b.add_crack(crack("c", p, q, FaceMode::Coincident));
        assert_eq!(count(&pieces(&b.build().unwrap()).unwrap()), 1);
    }

    /// A crack from the top edge to a hole and one from the hole to the bottom edge cut
    /// the plate into a left and a right piece, with coincident faces or a gap.
    #[test]
    fn cracks_from_the_outline_through_a_hole_cut_two_pieces() {
        for faces in [FaceMode::Coincident, FaceMode::Gap(1e-4)] {
            let mut b = MeshBuilder::new();
            b.add_loop(rect(0.0, 0.0, 2.0, 1.0, 0.1, false));
            b.add_loop(rect(0.8, 0.4, 0.4, 0.2, 0.05, true));
            b.add_crack(crack("top", V2::new(1.0, 1.0), V2::new(1.0, 0.6), faces));
            b.add_crack(crack("bottom", V2::new(1.0, 0.4), V2::new(1.0, 0.0), faces));
            let mesh = b.build().unwrap();
            let labels = pieces(&mesh).unwrap();
            assert_eq!(count(&labels), 2, "{faces:?}");
            for (e, l) in mesh.elements.iter().zip(&labels) {
                // Away from the cut, the side of x = 1 decides the piece.
                if (e.mid.x - 1.0).abs() > 1e-3 {
                    assert_eq!(*l == labels[0], e.mid.x < 1.0, "{faces:?} {:?}", e.mid);
                }
            }
        }
    }

    /// One crack from the top edge into the hole does not cut the plate.
    #[test]
    fn a_crack_from_the_outline_into_a_hole_leaves_one_piece() {
        let mut b = MeshBuilder::new();
        b.add_loop(rect(0.0, 0.0, 2.0, 1.0, 0.1, false));
        b.add_loop(rect(0.8, 0.4, 0.4, 0.2, 0.05, true));
        let (m, e) = (V2::new(1.0, 1.0), V2::new(1.0, 0.6));
        b.add_crack(crack("top", m, e, FaceMode::Coincident));
        assert_eq!(count(&pieces(&b.build().unwrap()).unwrap()), 1);
    }
}
