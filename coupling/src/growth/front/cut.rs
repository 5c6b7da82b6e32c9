//! When the cracks of a [`Front`] cut the body apart ([`Front::separated`]), and which
//! holes the tips ran into.

use super::Front;

impl Front {
    /// True when the cracks cut the body through (structural failure): a group of joined
    /// cracks touches the outline at two points or more, or the groups close a chain of
    /// cuts through the holes (a crack from the outline into a hole and another from the
    /// hole to the outline, or a crack from a hole back to it). Seen as a graph whose
    /// nodes are the outline and the holes, each group linking the boundaries it touches
    /// (mouths, tips ended on the outline or at a hole), a cycle cuts a piece off.
    pub fn separated(&self) -> bool {
        let mut contacts: Vec<Vec<usize>> = vec![Vec::new(); self.cracks.len()];
        for (i, c) in self.cracks.iter().enumerate() {
            if c.mouth {
                contacts[self.root(i)].push(0);
            }
        }
        for t in &self.tips {
            let node = match t.ended.as_deref() {
                Some("outline") => Some(0),
                Some(e) => e
                    .strip_prefix("hole:")
                    .and_then(|h| self.holes.iter().position(|(n, _)| n == h))
                    .map(|i| i + 1),
                None => None,
            };
            if let Some(n) = node {
                contacts[self.root(t.crack)].push(n);
            }
        }
        let mut graph = BoundaryGraph::new(1 + self.holes.len());
        for group in contacts {
            for w in group.windows(2) {
                if graph.link(w[0], w[1]) {
                    return true;
                }
            }
        }
        false
    }

    /// The holes (by name) that a tip ended at.
    pub fn holes_reached(&self) -> Vec<String> {
        let mut out: Vec<String> = self
            .tips
            .iter()
            .filter_map(|t| t.ended.as_deref()?.strip_prefix("hole:").map(String::from))
            .collect();
        out.dedup();
        out
    }
}

/// The boundaries (node 0 the outline, node 1 + h hole h) linked so far by the cracks:
/// union-find, a link between two boundaries already linked closes a cycle, a cut.
pub(crate) struct BoundaryGraph {
    parent: Vec<usize>,
}

impl BoundaryGraph {
    /// `n` boundaries, none linked.
    pub(crate) fn new(n: usize) -> Self {
        BoundaryGraph {
            parent: (0..n).collect(),
        }
    }

    /// Number of boundaries.
    pub(crate) fn len(&self) -> usize {
        self.parent.len()
    }

    fn root(&self, mut i: usize) -> usize {
        while self.parent[i] != i {
            i = self.parent[i];
        }
        i
    }

    /// Links boundaries `a` and `b`; true when they were linked already (a cycle).
    pub(crate) fn link(&mut self, a: usize, b: usize) -> bool {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra == rb {
            return true;
        }
        self.parent[ra] = rb;
        false
    }

    /// The boundaries linked with `a`.
    pub(crate) fn cycle_nodes(&self, a: usize) -> Vec<usize> {
        let r = self.root(a);
        (0..self.len()).filter(|&b| self.root(b) == r).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::plate;
    use super::super::Obstacle;
    use pdbem_geometry::{HoleShape, P2};

    #[test]
    fn a_tip_passing_a_hole_joins_it_and_two_cracks_through_a_hole_cut_the_body() {
        // A square hole [6, 8] x [6, 8]; a crack along y = 5.5 passes under it with its
        // next end within the margin: it joins the hole at the nearest point.
        let square = HoleShape::Polygon(vec![
            P2::new(6.0, 6.0),
            P2::new(8.0, 6.0),
            P2::new(8.0, 8.0),
            P2::new(6.0, 8.0),
        ]);
        let mut f = plate(&[("a", (0.0, 5.5), 0.0, 5.5)], vec![square.clone()]);
        let hit = f.step_ahead(0, P2::new(1.0, 0.0), 1.0, 0.6);
        assert_eq!(hit, Obstacle::Hole("hole0".into()));
        let q = f.tip_position(0);
        assert!((q - P2::new(6.0, 6.0)).norm() < 1e-12, "{q:?}");
        assert!(!f.separated());
        // A second edge crack from the top edge down into the hole: outline - hole -
        // outline, the piece between them is cut off.
        let mut f = plate(
            &[("a", (0.0, 7.0), 0.0, 5.0), ("b", (7.0, 10.0), -90.0, 1.5)],
            vec![square],
        );
        assert_eq!(
            f.step_ahead(0, P2::new(1.0, 0.0), 1.0, 0.1),
            Obstacle::Hole("hole0".into())
        );
        assert!(!f.separated());
        let b = f.tip_index(1, true).expect("tip b.end");
        assert_eq!(
            f.step_ahead(b, P2::new(0.0, -1.0), 0.5, 0.1),
            Obstacle::Hole("hole0".into())
        );
        assert!(f.separated());
        assert_eq!(f.holes_reached(), vec!["hole0".to_string()]);
    }
}
