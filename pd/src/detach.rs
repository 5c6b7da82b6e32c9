//! Detaching free nodes that their intact bonds cannot hold in place (a node hanging by
//! one bond or a straight chain), so the Newton tangent stays non-singular after bonds
//! break ([`PdModel::detach_unsupported_nodes`]).

use crate::PdModel;

impl PdModel {
    /// Detaches the free nodes that their intact bonds cannot hold in place: a node whose
    /// intact bonds are all parallel (one bond, or a straight chain) has no in-plane
    /// stiffness across them, only the geometric term `f / l`, which vanishes at
    /// equilibrium and turns negative in compression. Such a node makes the Newton tangent
    /// singular up to its `1e-10` diagonal shift (Cholesky fails, LU amplifies round-off
    /// by `1e10`) and the solve stalls. Its remaining intact bonds (not the
    /// [`crate::forces::NO_FAIL`] ones) are broken, both directions, repeated until every
    /// free node with an intact bond is supported in two directions; an isolated node
    /// carries no force and is harmless. Returns the nodes detached.
    ///
    /// "Parallel": the smallest eigenvalue of the node's bond-direction stiffness
    /// $\sum_b (k_b / l_b)\, n_b n_b^T$ is below `1e-6` of its trace (the bonds of a
    /// horizon are at least one lattice angle, atan(1/3) = 18 deg, apart, which gives
    /// a ratio of about 0.05 for two bonds).
    pub fn detach_unsupported_nodes(&mut self) -> usize {
        let b = &self.bonds;
        let mut detached = 0;
        loop {
            let mut changed = false;
            for i in 0..self.u.len() {
                let f = self.bc.fixed[i];
                if f[0] && f[1] {
                    continue;
                }
                let (mut sxx, mut sxy, mut syy, mut n_intact) = (0.0, 0.0, 0.0, 0);
                for k in b.row(i) {
                    if self.intact[k] == 0 {
                        continue;
                    }
                    n_intact += 1;
                    let w = b.k[k] * b.inv_len[k];
                    let (nx, ny) = (b.xi[k][0] * b.inv_len[k], b.xi[k][1] * b.inv_len[k]);
                    sxx += w * nx * nx;
                    sxy += w * nx * ny;
                    syy += w * ny * ny;
                }
                if n_intact == 0 {
                    continue;
                }
                let tr = sxx + syy;
                let det = sxx * syy - sxy * sxy;
                // Smallest eigenvalue of the symmetric 2 x 2 matrix.
                let lmin = 0.5 * tr - (0.25 * tr * tr - det).max(0.0).sqrt();
                if lmin > 1e-6 * tr {
                    continue;
                }
                let mut any = false;
                for k in b.row(i) {
                    if self.intact[k] != 1 {
                        continue;
                    }
                    let j = b.nbr[k] as usize;
                    self.intact[k] = 0;
                    if let Some(r) = b.row(j).find(|&r| b.nbr[r] as usize == i) {
                        self.intact[r] = 0;
                    }
                    any = true;
                }
                if any {
                    detached += 1;
                    changed = true;
                }
            }
            if !changed {
                return detached;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::problem::{Failure, PdProblem, Region};
    use crate::PdModel;

    #[test]
    fn a_node_hanging_by_one_bond_is_detached() {
        let p = PdProblem {
            region: Region::rectangle([0.0, 0.0], [8.0, 8.0]),
            dx: 1.0,
            youngs_modulus: 1.0,
            failure: Failure::CriticalStretch { s0: 0.01 },
            ..Default::default()
        };
        let mut m = PdModel::new(&p).unwrap();
        assert_eq!(m.detach_unsupported_nodes(), 0);
        let b = m.bonds().clone();
        // Node 27 (a bulk node) keeps only its first bond, both directions cut elsewhere.
        let i = 27;
        let keep = b.row(i).next().unwrap();
        for k in b.row(i).skip(1) {
            let j = b.nbr[k] as usize;
            m.intact[k] = 0;
            let r = b.row(j).find(|&r| b.nbr[r] as usize == i).unwrap();
            m.intact[r] = 0;
        }
        assert_eq!(m.intact[keep], 1);
        let before = m.broken_bonds();
        assert_eq!(m.detach_unsupported_nodes(), 1);
        assert!(b.row(i).all(|k| m.intact[k] == 0));
        assert_eq!(m.broken_bonds(), before + 1);
        // The pair stays symmetric: every broken direction has a broken reverse.
        for n in 0..m.n_nodes() {
            for k in b.row(n) {
                let j = b.nbr[k] as usize;
                let r = b.row(j).find(|&r| b.nbr[r] as usize == n).unwrap();
                assert_eq!(m.intact[k], m.intact[r]);
            }
        }
    }
}
