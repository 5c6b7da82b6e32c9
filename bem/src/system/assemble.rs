//! Parallel assembly of the scaled, bordered system (column pairs per element, rayon).

use super::cache::{pair_blocks, PairBlocks, PairCache};
use super::{Bc, SolveParams};
use crate::integrate::KernelConsts;
use crate::mesh::stencil::Stencil;
use crate::mesh::Mesh;
use crate::Material;
use rayon::prelude::*;

/// The assembled system: column-major `a` (n x n), right-hand side, kept columns.
pub(super) struct Assembled {
    pub n: usize,
    pub a: Vec<f64>,
    pub rhs: Vec<f64>,
    pub col_scale: Vec<f64>,
    pub variable: Vec<(usize, Vec<f64>)>,
    pub norm1: f64,
    /// Element pairs copied from the cache.
    pub reused: usize,
}

/// Per-thread accumulator of the right-hand side and the kept columns.
#[derive(Default)]
struct Acc {
    rhs: Vec<f64>,
    variable: Vec<(usize, Vec<f64>)>,
}

/// Elements per sequential fold of the assembly's right-hand side (a fixed split keeps
/// the floating-point summation order independent of the thread scheduling).
const FOLD_CHUNK: usize = 16;

pub(super) fn assemble(
    mesh: &Mesh,
    material: &Material,
    bcs: &[[Bc; 2]],
    params: &SolveParams,
    modes: &[Vec<f64>],
    stencil: Option<&Stencil>,
    cache: Option<&mut PairCache>,
) -> Assembled {
    let kc = KernelConsts::from(material);
    let nel = mesh.len();
    // Old index of every element in the cached mesh, and storage for this mesh's blocks.
    let old: Vec<Option<usize>> = match cache.as_deref() {
        Some(c) => c.matches(mesh, material, params),
        None => vec![None; nel],
    };
    let reused = old.iter().filter(|o| o.is_some()).count().pow(2);
    let mut cache = cache;
    let keep = cache.is_some() && PairCache::keeps(nel);
    let mut kept: Vec<PairBlocks> = match cache.as_deref_mut() {
        Some(c) if keep => c.take_blocks(nel * nel),
        _ => Vec::new(),
    };
    let ndof = 2 * nel;
    // First-moment (reconstruction) coefficients of u, column (j, c) = H^c_1[:, (j, c)].
    let mut first = match (stencil.is_some(), cache.as_deref_mut()) {
        (false, _) => Vec::new(),
        (true, Some(c)) => c.take_moments(ndof * ndof),
        (true, None) => vec![0.0; ndof * ndof],
    };
    let mut kept_cols: Vec<Option<&mut [PairBlocks]>> = if keep {
        kept.chunks_mut(nel).map(Some).collect()
    } else {
        (0..nel).map(|_| None).collect()
    };
    let from = cache.as_deref();
    let n = ndof + modes.len();
    let mut a = vec![0.0; n * n];
    let els = &mesh.elements;
    let variable_el: Vec<bool> = els
        .iter()
        .map(|e| params.variable_groups.contains(&e.group))
        .collect();

    let mut first_cols: Vec<Option<&mut [f64]>> = if stencil.is_some() {
        first.chunks_mut(2 * ndof).map(Some).collect()
    } else {
        (0..nel).map(|_| None).collect()
    };
    let acc = a[..n * ndof]
        .par_chunks_mut(2 * n)
        .zip(first_cols.par_iter_mut())
        .zip(kept_cols.par_iter_mut())
        .enumerate()
        // Fixed chunks folded in order, then merged in order: the right-hand side sums do
        // not depend on how rayon splits the work (a plain fold + reduce groups them by
        // rayon's adaptive splitting, which depends on the thread scheduling).
        .fold_chunks(
            FOLD_CHUNK,
            Acc::default,
            |mut acc, (j, ((cols, fcols), kcol))| {
                let ej = &els[j];
                let (c0, c1) = cols.split_at_mut(n);
                let mut known = [vec![0.0; 0], vec![0.0; 0]];
                let keep = [0, 1].map(|c| bcs[j][c].value() != 0.0 || variable_el[j]);
                for c in 0..2 {
                    if keep[c] {
                        known[c] = vec![0.0; n];
                    }
                }
                for (i, ei) in els.iter().enumerate() {
                    let blk = match (from, old[i], old[j]) {
                        (Some(c), Some(oi), Some(oj)) => *c.get(oi, oj),
                        _ => {
                            let beta = params.beta_factor * ei.h / material.e;
                            let linear = fcols.is_some();
                            pair_blocks(ei, ej, i == j, &kc, params.alpha, beta, linear)
                        }
                    };
                    if let Some(k) = kcol.as_deref_mut() {
                        k[i] = blk;
                    }
                    if let Some(f) = fcols.as_deref_mut() {
                        for r in 0..2 {
                            for c in 0..2 {
                                f[c * ndof + 2 * i + r] = blk[8 + 2 * r + c];
                            }
                        }
                    }
                    let hc = |r: usize, c: usize| blk[2 * r + c];
                    let gc = |r: usize, c: usize| blk[4 + 2 * r + c];
                    for c in 0..2 {
                        let col = if c == 0 { &mut *c0 } else { &mut *c1 };
                        for r in 0..2 {
                            // (coefficient of the unknown, left-hand-side coefficient of the known)
                            let (unk, kno) = if bcs[j][c].is_displacement() {
                                (-gc(r, c), hc(r, c))
                            } else {
                                (hc(r, c), -gc(r, c))
                            };
                            col[2 * i + r] = unk;
                            if keep[c] {
                                // Known values move to the right-hand side with opposite sign.
                                known[c][2 * i + r] = -kno;
                            }
                        }
                    }
                }
                if acc.rhs.is_empty() {
                    acc.rhs = vec![0.0; n];
                }
                for c in 0..2 {
                    if !keep[c] {
                        continue;
                    }
                    let v = bcs[j][c].value();
                    for (b, k) in acc.rhs.iter_mut().zip(&known[c]) {
                        *b += k * v;
                    }
                    if variable_el[j] {
                        acc.variable
                            .push((2 * j + c, std::mem::take(&mut known[c])));
                    }
                }
                // Rigid-mode multiplier rows: R^T x = 0 (entries on u-unknown columns).
                for (k, mode) in modes.iter().enumerate() {
                    for c in 0..2 {
                        let col = if c == 0 { &mut *c0 } else { &mut *c1 };
                        col[ndof + k] = mode[2 * j + c];
                    }
                }
                acc
            },
        )
        .collect::<Vec<Acc>>()
        .into_iter()
        .fold(Acc::default(), |mut x, y| {
            if x.rhs.is_empty() {
                return Acc {
                    rhs: y.rhs,
                    variable: [x.variable, y.variable].concat(),
                };
            }
            if !y.rhs.is_empty() {
                for (a, b) in x.rhs.iter_mut().zip(&y.rhs) {
                    *a += b;
                }
            }
            x.variable.extend(y.variable);
            x
        });
    let mut rhs = if acc.rhs.is_empty() {
        vec![0.0; n]
    } else {
        acc.rhs
    };
    let mut variable = acc.variable;
    variable.sort_by_key(|(d, _)| *d);
    drop(first_cols);
    drop(kept_cols);
    if let Some(st) = stencil {
        add_reconstruction(&mut a, n, ndof, &first, st, bcs, &mut rhs, &mut variable);
    }
    if let Some(c) = cache {
        c.store(mesh, material, params, kept);
        c.give_moments(first);
    }

    // Bordering columns: R over all equation rows.
    for (k, mode) in modes.iter().enumerate() {
        let col = &mut a[(ndof + k) * n..(ndof + k + 1) * n];
        col[..ndof].copy_from_slice(mode);
    }
    // The constraint rows act on unknown displacements only.
    for j in 0..nel {
        for c in 0..2 {
            if bcs[j][c].is_displacement() {
                for k in 0..modes.len() {
                    a[(2 * j + c) * n + ndof + k] = 0.0;
                }
            }
        }
    }
    let col_scale = scale_columns(&mut a, n, ndof);
    let norm1 = (0..n)
        .map(|c| a[c * n..(c + 1) * n].iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    rhs.truncate(n);
    Assembled {
        n,
        a,
        rhs,
        col_scale,
        variable,
        norm1,
        reused,
    }
}

/// Adds the linear-reconstruction terms: u-column (k, c) gains
/// sum_j w_jk H^c_1[:, (j, c)] over the elements j whose stencil uses k. Unknown
/// displacements take it into A, prescribed ones into the right-hand side.
fn add_reconstruction(
    a: &mut [f64],
    n: usize,
    ndof: usize,
    first: &[f64],
    st: &Stencil,
    bcs: &[[Bc; 2]],
    rhs: &mut [f64],
    variable: &mut [(usize, Vec<f64>)],
) {
    let nel = ndof / 2;
    let mut reverse: Vec<Vec<(usize, f64)>> = vec![Vec::new(); nel];
    for (j, row) in st.iter().enumerate() {
        for &(k, w) in row {
            reverse[k].push((j, w));
        }
    }
    let known: Vec<(usize, Vec<f64>)> = a[..n * ndof]
        .par_chunks_mut(n)
        .enumerate()
        .filter_map(|(dof, col)| {
            let (k, c) = (dof / 2, dof % 2);
            if reverse[k].is_empty() {
                return None;
            }
            let mut add = vec![0.0; ndof];
            for &(j, w) in &reverse[k] {
                let src = &first[(2 * j + c) * ndof..(2 * j + c + 1) * ndof];
                for (x, y) in add.iter_mut().zip(src) {
                    *x += w * y;
                }
            }
            if bcs[k][c].is_displacement() {
                Some((dof, add))
            } else {
                for (x, y) in col[..ndof].iter_mut().zip(&add) {
                    *x += y;
                }
                None
            }
        })
        .collect();
    for (dof, add) in known {
        let v = bcs[dof / 2][dof % 2].value();
        for (b, x) in rhs.iter_mut().zip(&add) {
            *b -= x * v;
        }
        if let Some((_, col)) = variable.iter_mut().find(|(d, _)| *d == dof) {
            for (b, x) in col.iter_mut().zip(&add) {
                *b -= x;
            }
        }
    }
}

/// Scales the first `ndof` columns to unit max-norm (over the equation rows); returns the
/// factors d with x = d * y.
fn scale_columns(a: &mut [f64], n: usize, ndof: usize) -> Vec<f64> {
    a[..n * ndof]
        .par_chunks_mut(n)
        .map(|col| {
            let m = col[..ndof].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let d = if m > 0.0 { 1.0 / m } else { 1.0 };
            for v in col[..ndof].iter_mut() {
                *v *= d;
            }
            d
        })
        .collect()
}
