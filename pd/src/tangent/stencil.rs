//! The free-DOF tangent on a general node stencil: the layout of [`Tangent::new`] (lower
//! triangle, node `i`'s two columns holding its diagonal block and the rows of the stencil
//! nodes `j > i`), for tangents that are not a sum over bonds. The state-based tangent
//! (`crate::state_based`) couples a node to its neighbours' neighbours through the
//! dilatation, so its stencil is the two-hop family.

use rayon::prelude::*;

use super::{Tangent, NONE};
use crate::error::PdError;
use crate::forces::RowPtr;

/// A 2 x 2 block `K[i][m][p][q] = K_{(i,p),(m,q)}`.
pub type Block = [[f64; 2]; 2];

impl Tangent {
    /// The pattern of a tangent whose row `i` is nonzero on the nodes
    /// `nodes[offsets[i]..offsets[i + 1]]` (sorted, containing `i`), with the fixed
    /// components removed. The tangent keeps the stencil for [`Self::assemble_rows`].
    pub fn from_stencil(
        (offsets, nodes): (Vec<usize>, Vec<u32>),
        fixed: &[[bool; 2]],
    ) -> Result<Self, PdError> {
        let n = fixed.len();
        let mut dof = vec![NONE; 2 * n];
        let mut n_free = 0;
        for i in 0..n {
            for c in 0..2 {
                if !fixed[i][c] {
                    dof[2 * i + c] = n_free;
                    n_free += 1;
                }
            }
        }
        if n_free == 0 {
            return Err(PdError::LinearSolve {
                dofs: 0,
                reason: "every DOF is prescribed".into(),
            });
        }
        // At most 3 entries per node's diagonal block and 2 per stencil entry.
        super::check_pattern(n_free, 3 * n + 2 * nodes.len(), 0)?;
        let mut col_ptr = Vec::with_capacity(n_free + 1);
        let mut row_idx = Vec::new();
        let mut node_start = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        for i in 0..n {
            node_start.push(row_idx.len());
            let upper = nodes[offsets[i]..offsets[i + 1]]
                .iter()
                .map(|&j| j as usize)
                .filter(|&j| j > i);
            for q in 0..2 {
                if dof[2 * i + q] == NONE {
                    continue;
                }
                for p in q..2 {
                    if dof[2 * i + p] != NONE {
                        row_idx.push(dof[2 * i + p]);
                    }
                }
                for j in upper.clone() {
                    for p in 0..2 {
                        if dof[2 * j + p] != NONE {
                            row_idx.push(dof[2 * j + p]);
                        }
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        node_start.push(row_idx.len());
        let nnz = row_idx.len();
        let symbolic =
            faer::sparse::SymbolicSparseColMat::new_checked(n_free, n_free, col_ptr, None, row_idx);
        Ok(Tangent {
            dof,
            n_free,
            symbolic,
            node_start,
            col_off: Vec::new(),
            values: vec![0.0; nnz],
            llt: None,
            allow_lu: true,
            stencil: Some((offsets, nodes)),
        })
    }

    /// The stencil of a [`Tangent::from_stencil`] pattern: `(offsets, nodes)`.
    pub fn stencil(&self) -> Option<(&[usize], &[u32])> {
        self.stencil
            .as_ref()
            .map(|(o, n)| (o.as_slice(), n.as_slice()))
    }

    /// Fill the values of a [`Tangent::from_stencil`] pattern row by row:
    /// `row(i, stencil_i, blocks)` writes `K[i][m]` for every stencil node `m` of `i`,
    /// in stencil order, into `blocks` (zeroed, one per stencil node). Only the lower
    /// triangle is read (the tangent is symmetric). Rows run in parallel, each with its
    /// own scratch `S`. Does nothing on a bond pattern ([`Tangent::new`]).
    pub fn assemble_rows<S: Send>(
        &mut self,
        init: impl Fn() -> S + Send + Sync,
        row: impl Fn(&mut S, usize, &[u32], &mut [Block]) + Send + Sync,
    ) {
        let Some((offsets, nodes)) = self.stencil.as_ref() else {
            return;
        };
        let vals = RowPtr(self.values.as_mut_ptr());
        let dof = &self.dof;
        let node_start = &self.node_start;
        let n = offsets.len() - 1;
        (0..n).into_par_iter().with_min_len(16).for_each_init(
            || (init(), Vec::<Block>::new()),
            |(scratch, blocks), i| {
                let vp = vals;
                let f0 = dof[2 * i] != NONE;
                let f1 = dof[2 * i + 1] != NONE;
                if !f0 && !f1 {
                    return;
                }
                let st = &nodes[offsets[i]..offsets[i + 1]];
                blocks.clear();
                blocks.resize(st.len(), [[0.0; 2]; 2]);
                row(scratch, i, st, blocks);
                let start = node_start[i];
                let n_off =
                    (node_start[i + 1] - start - (f0 && f1) as usize - f0 as usize - f1 as usize)
                        / (f0 as usize + f1 as usize);
                let col0_len = if f0 { (1 + f1 as usize) + n_off } else { 0 };
                let off0 = start + if f0 { 1 + f1 as usize } else { 0 };
                let off1 = start + col0_len + 1;
                let mut o = 0;
                for (k, &j) in st.iter().enumerate() {
                    let j = j as usize;
                    let r = blocks[k];
                    if j == i {
                        // SAFETY: diagonal slots of node i's own columns.
                        unsafe {
                            if f0 {
                                *vp.0.add(start) = r[0][0];
                                if f1 {
                                    *vp.0.add(start + 1) = r[1][0];
                                }
                            }
                            if f1 {
                                *vp.0.add(start + col0_len) = r[1][1];
                            }
                        }
                        continue;
                    }
                    if j < i {
                        continue;
                    }
                    for p in 0..2 {
                        if dof[2 * j + p] == NONE {
                            continue;
                        }
                        // SAFETY: positions lie in node i's own column range. Column
                        // (i, q), row (j, p) holds K[(j,p),(i,q)] = K[(i,q),(j,p)].
                        unsafe {
                            if f0 {
                                *vp.0.add(off0 + o) = r[0][p];
                            }
                            if f1 {
                                *vp.0.add(off1 + o) = r[1][p];
                            }
                        }
                        o += 1;
                    }
                }
            },
        );
    }
}
