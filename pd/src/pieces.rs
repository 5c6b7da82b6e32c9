//! The pieces of a broken body and the loads they carry.
//!
//! A piece is a connected component of the graph whose vertices are the nodes (or
//! particles) and whose edges are the intact bonds. Under loads held on it (a step load
//! of explicit dynamics), a piece carries the resultant
//! $$F_P = \sum_{i \in P} \lambda\, b_i V_i$$
//! of its nodes' body forces (the tractions' layers, [`crate::boundary`]). Where no node of
//! the piece holds component $c$ (a prescribed displacement or velocity), its momentum
//! obeys $\dot p_c = F_{P,c}$: a piece with $F_{P,c} \ne 0$ accelerates without bound. The
//! intact body under balanced loads has $F_P = 0$ to round-off; a piece cut loose by a
//! crack, or a loaded layer torn off its body, carries an unbalanced load.

use crate::bonds::Bonds;
use crate::geometry::P2;
use crate::refine::Body;
use crate::PdModel;

/// One connected piece of a body.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Its nodes, ascending.
    pub nodes: Vec<usize>,
    /// Resultant of the loads on it (N).
    pub net_force: P2,
    /// Sum of the magnitudes of its nodes' loads (N).
    pub load: f64,
    /// Per component, whether a node of the piece has it prescribed.
    pub held: [bool; 2],
}

impl Piece {
    /// The load the piece cannot carry (N): the components of its resultant that no node
    /// of it holds.
    pub fn unbalanced(&self) -> f64 {
        let f = |c: usize| if self.held[c] { 0.0 } else { self.net_force[c] };
        f(0).hypot(f(1))
    }
}

/// The connected pieces of the graph of intact bonds (`intact[b] != 0`) of `bonds`, with
/// each node's load `force` (N) and prescribed components `held`; ordered by their
/// smallest node. An isolated node is a piece of its own.
pub fn pieces(bonds: &Bonds, intact: &[u8], force: &[P2], held: &[[bool; 2]]) -> Vec<Piece> {
    let n = force
        .len()
        .min(held.len())
        .min(bonds.offsets.len().saturating_sub(1));
    let mut parent: Vec<usize> = (0..n).collect();
    for i in 0..n {
        for b in bonds.row(i) {
            let j = bonds.nbr[b] as usize;
            if intact.get(b).is_some_and(|&f| f != 0) && j < n {
                union(&mut parent, i, j);
            }
        }
    }
    let mut index = vec![usize::MAX; n];
    let mut out: Vec<Piece> = Vec::new();
    for i in 0..n {
        let r = root(&mut parent, i);
        if index[r] == usize::MAX {
            index[r] = out.len();
            out.push(Piece {
                nodes: Vec::new(),
                net_force: [0.0; 2],
                load: 0.0,
                held: [false; 2],
            });
        }
        let p = &mut out[index[r]];
        p.nodes.push(i);
        p.load += force[i][0].hypot(force[i][1]);
        for c in 0..2 {
            p.net_force[c] += force[i][c];
            p.held[c] |= held[i][c];
        }
    }
    out
}

fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (root(parent, a), root(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb);
    }
}

impl PdModel {
    /// The pieces of the model's nodes (real and fictitious) at its load factor
    /// ([`pieces`]): loads `lambda b_i V` (per reference volume on a mixed grid), held
    /// components those of the displacement conditions.
    pub fn pieces(&self) -> Vec<Piece> {
        self.pieces_at(self.load)
    }

    /// [`Self::pieces`] under the loads of load factor `load`.
    pub fn pieces_at(&self, load: f64) -> Vec<Piece> {
        let scale = load * self.grid.volume;
        let force: Vec<P2> = self
            .bc
            .body
            .iter()
            .map(|b| [b[0] * scale, b[1] * scale])
            .collect();
        pieces(&self.bonds, &self.intact, &force, &self.bc.fixed)
    }
}

impl Body {
    /// The pieces of the particles at load factor `load` ([`pieces`]): loads
    /// `load b_k V_k`, held components the prescribed ones.
    pub fn pieces(&self, load: f64) -> Vec<Piece> {
        let force: Vec<P2> = self
            .body
            .iter()
            .zip(&self.dh.volume)
            .map(|(b, v)| [b[0] * load * v, b[1] * load * v])
            .collect();
        pieces(&self.dh.bonds, &self.dh.intact, &force, &self.fixed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{BoundaryCondition, PdProblem, Region};

    /// A strip pulled apart by opposite tractions on its short edges: one piece with a
    /// zero resultant; with every bond across the middle broken, two pieces carrying
    /// +F and -F, the traction times the edge area; holding the left edge in x balances
    /// the left piece.
    #[test]
    fn a_strip_cut_in_two_leaves_two_pieces_with_opposite_loads() {
        let (w, h, t, sigma) = (1.0, 0.2, 0.01, 1e6);
        let mut p = PdProblem {
            region: Region::rectangle([0.0, 0.0], [w, h]),
            dx: 0.05,
            thickness: t,
            youngs_modulus: 1e9,
            ..Default::default()
        };
        for (x, s) in [(0.0, -sigma), (w, sigma)] {
            p.boundary.push(BoundaryCondition::Traction {
                edge: vec![[x, 0.0], [x, h]],
                traction: [s, 0.0],
                depth: None,
            });
        }
        let mut m = PdModel::new(&p).unwrap();
        m.set_load_factor(1.0);
        let whole = m.pieces();
        assert_eq!(whole.len(), 1);
        let f = sigma * h * t;
        assert!(whole[0].unbalanced() < 1e-9 * f, "{:?}", whole[0].net_force);
        let x = m.positions().to_vec();
        let cut = |b: usize, i: usize| {
            let j = m.bonds.nbr[b] as usize;
            (x[i][0] < 0.5) != (x[j][0] < 0.5)
        };
        for i in 0..m.n_nodes() {
            for b in m.bonds.row(i) {
                if cut(b, i) {
                    m.intact[b] = 0;
                }
            }
        }
        let two = m.pieces();
        assert_eq!(two.len(), 2);
        for (piece, sign) in two.iter().zip([-1.0, 1.0]) {
            assert!(
                (piece.net_force[0] - sign * f).abs() < 1e-9 * f,
                "{piece:?}"
            );
            assert!(piece.net_force[1].abs() < 1e-9 * f);
            assert!((piece.unbalanced() - f).abs() < 1e-9 * f);
            assert_eq!(piece.nodes.len(), m.n_nodes() / 2);
        }
        m.bc.fixed[0] = [true, false];
        let held = m.pieces();
        assert_eq!(held[0].held, [true, false]);
        assert_eq!(held[0].unbalanced(), 0.0);
        assert!((held[1].unbalanced() - f).abs() < 1e-9 * f);
    }
}
