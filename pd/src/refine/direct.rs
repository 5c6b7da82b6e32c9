//! Conjugate gradients on the refined body preconditioned by a sparse Cholesky factor of
//! its own stiffness ([`super::linear`]'s operator, assembled).
//!
//! The linearised dual-horizon energy of [`super::linear`] is
//! $\Pi = \tfrac12 v^T K v$ with
//! $$K = \sum_b c_b\,(n_b n_b^T)\ \text{on}\ (k, j) + \sum_k 2a_kV_k\, g_k g_k^T,\qquad
//!   c_b = \frac{T_b V_k \beta_b V'_b}{|\xi_b|},\quad
//!   g_k = \sum_{b\in H_k} \frac{T_b\omega_b V'_b}{|\xi_b|}\,n_b\,(e_j - e_k),$$
//! so a particle couples to its neighbours' neighbours (the dilatation). [`Factor`]
//! assembles $K + \varepsilon I$ on that two-hop stencil ([`crate::tangent::Tangent`]'s
//! layout, prescribed components removed) and factors it once; $\varepsilon$ is
//! [`SHIFT`] times the mean diagonal, so a body held by tractions alone (three rigid
//! modes) still factors, and since a scalar shift keeps $K$'s eigenvectors, the iterates
//! stay orthogonal to the rigid modes as plain CG's do.
//!
//! [`Solver`] keeps the factor while only bonds break (the broken bonds change $K$ by a
//! few low-rank terms, so the old factor stays a good preconditioner) and refactors when
//! particles split, after a solve that took more than [`REFRESH`] iterations, or when a
//! solve on the kept factor has not converged in [`STALE`] (it then restarts on a fresh
//! one). A body the crack has parted has no equilibrium under its loads; the solve then
//! stalls and fails after [`FRESH_CAP`] iterations on a fresh factor, as the plain CG
//! stalls at its cap. A pattern or factor over the memory budget is not allocated: the
//! solves then run as plain CG ([`Solver::plain`]).

use rayon::prelude::*;

use super::Body;
use crate::error::PdError;
use crate::geometry::P2;
use crate::tangent::{check_budget, Block, Tangent};

/// Shift of the factored matrix relative to its mean diagonal entry.
pub const SHIFT: f64 = 1e-9;

/// Iterations after which a kept factor is replaced by a fresh one.
pub const STALE: usize = 30;

/// Iterations of a solve above which the next solve refactors (a factorisation costs
/// about as much as 20 iterations' triangular solves).
pub const REFRESH: usize = 10;

/// Iterations allowed on a fresh factor before the solve fails.
pub const FRESH_CAP: usize = 300;

/// The factored, shifted stiffness of one body state.
pub struct Factor {
    tangent: Tangent,
    /// Free index of component `2 i + c`, `usize::MAX` when prescribed (the tangent's).
    dof: Vec<usize>,
    particles: usize,
}

/// The two-hop stencil of every particle: itself, its family and dual horizon, and the
/// families of every particle whose family holds it (sorted).
fn stencil(body: &Body, owner: &[u32]) -> (Vec<usize>, Vec<u32>) {
    let dh = &body.dh;
    let n = body.len();
    let rows: Vec<Vec<u32>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let mut s = vec![i as u32];
            let add_family = |k: usize, s: &mut Vec<u32>| {
                s.push(k as u32);
                s.extend(dh.bonds.row(k).map(|b| dh.bonds.nbr[b]));
            };
            add_family(i, &mut s);
            for &b in &dh.dual[dh.dual_offsets[i]..dh.dual_offsets[i + 1]] {
                add_family(owner[b as usize] as usize, &mut s);
            }
            s.sort_unstable();
            s.dedup();
            s
        })
        .collect();
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0);
    let mut nodes = Vec::new();
    for r in rows {
        nodes.extend_from_slice(&r);
        offsets.push(nodes.len());
    }
    (offsets, nodes)
}

/// Row `i` of `K + shift I` into `blocks` (one per stencil node, stencil order).
fn row(
    body: &Body,
    owner: &[u32],
    g_self: &[P2],
    shift: f64,
    i: usize,
    st: &[u32],
    blocks: &mut [Block],
) {
    let dh = &body.dh;
    let bonds = &dh.bonds;
    let at = |m: usize| st.binary_search(&(m as u32)).expect("stencil node");
    let unit = |b: usize| {
        let il = bonds.inv_len[b];
        [bonds.xi[b][0] * il, bonds.xi[b][1] * il]
    };
    let add = |blocks: &mut [Block], m: usize, w: f64, a: P2, c: P2| {
        let blk = &mut blocks[at(m)];
        for p in 0..2 {
            for q in 0..2 {
                blk[p][q] += w * a[p] * c[q];
            }
        }
    };
    // Deviatoric bars: own bonds (i the owner) and dual bonds (i the neighbour).
    let spring = |b: usize, k: usize| {
        f64::from(dh.intact[b]) * dh.volume[k] * dh.beta[b] * bonds.vol_factor[b] * bonds.inv_len[b]
    };
    for b in bonds.row(i) {
        let (c, nv, j) = (spring(b, i), unit(b), bonds.nbr[b] as usize);
        add(blocks, i, c, nv, nv);
        add(blocks, j, -c, nv, nv);
    }
    let dual = &dh.dual[dh.dual_offsets[i]..dh.dual_offsets[i + 1]];
    for &b in dual {
        let b = b as usize;
        let k = owner[b] as usize;
        let (c, nv) = (spring(b, k), unit(b));
        add(blocks, i, c, nv, nv);
        add(blocks, k, -c, nv, nv);
    }
    // Dilatation: 2 a_k V_k g_k[i] g_k[m]^T over the owners k whose g_k reaches i.
    let weight = |b: usize| {
        let w = f64::from(dh.intact[b]) * dh.omega[b] * bonds.vol_factor[b] * bonds.inv_len[b];
        let nv = unit(b);
        [w * nv[0], w * nv[1]]
    };
    let owner_term = |k: usize, gi: P2, blocks: &mut [Block]| {
        let coef = 2.0 * dh.a[k] * dh.volume[k];
        if coef == 0.0 || (gi[0] == 0.0 && gi[1] == 0.0) {
            return;
        }
        add(blocks, k, coef, gi, g_self[k]);
        for b in bonds.row(k) {
            add(blocks, bonds.nbr[b] as usize, coef, gi, weight(b));
        }
    };
    owner_term(i, g_self[i], blocks);
    for &b in dual {
        let b = b as usize;
        owner_term(owner[b] as usize, weight(b), blocks);
    }
    let d = &mut blocks[at(i)];
    d[0][0] += shift;
    d[1][1] += shift;
}

impl Factor {
    /// Assemble and factor `K + shift I` of `body`'s current bonds, within `budget`
    /// bytes for the pattern and for the factor ([`PdError::TooLarge`] before either
    /// is allocated).
    pub fn new(body: &Body, budget: u64) -> Result<Self, PdError> {
        let dh = &body.dh;
        let owner = dh.owners();
        let bonds = &dh.bonds;
        let g_self: Vec<P2> = (0..body.len())
            .map(|k| {
                let mut g = [0.0; 2];
                for b in bonds.row(k) {
                    let w = f64::from(dh.intact[b])
                        * dh.omega[b]
                        * bonds.vol_factor[b]
                        * bonds.inv_len[b]
                        * bonds.inv_len[b];
                    g[0] -= w * bonds.xi[b][0];
                    g[1] -= w * bonds.xi[b][1];
                }
                g
            })
            .collect();
        let diag = super::linear::diagonal(dh);
        let mean = diag.iter().map(|d| d[0] + d[1]).sum::<f64>() / (2 * body.len()).max(1) as f64;
        let shift = SHIFT * mean;
        let st = stencil(body, &owner);
        // Lower triangle: about two entries (row index and value, 16 bytes) per stencil
        // node and component pair.
        check_budget(
            &format!("the assembled stiffness of {} particles", body.len()),
            32.0 * st.1.len() as f64,
            budget,
        )?;
        let mut tangent = Tangent::from_stencil(st, &body.fixed)?;
        tangent.allow_lu = false;
        tangent.assemble_rows(
            || (),
            |_, i, st, blocks| row(body, &owner, &g_self, shift, i, st, blocks),
        );
        tangent.factorize_within(budget)?;
        Ok(Factor {
            dof: tangent.dof.clone(),
            tangent,
            particles: body.len(),
        })
    }

    /// `z = (K + shift I)^{-1} r` on the free components (prescribed ones zero).
    pub(crate) fn apply_inverse(&mut self, r: &[P2]) -> Result<Vec<P2>, PdError> {
        let dof = &self.dof;
        let mut rhs = vec![0.0; self.tangent.n_free];
        for (i, ri) in r.iter().enumerate() {
            for c in 0..2 {
                let d = dof[2 * i + c];
                if d != usize::MAX {
                    rhs[d] = ri[c];
                }
            }
        }
        self.tangent.solve_with_last_factor(&mut rhs, 1)?;
        Ok((0..r.len())
            .map(|i| {
                std::array::from_fn(|c| {
                    let d = dof[2 * i + c];
                    if d == usize::MAX {
                        0.0
                    } else {
                        rhs[d]
                    }
                })
            })
            .collect())
    }
}

/// Factor-preconditioned solves of one body through its ramp (module docs).
#[derive(Default)]
pub struct Solver {
    factor: Option<Factor>,
    /// Factorisations so far.
    pub factorizations: usize,
    /// Why the solves fell back to plain conjugate gradients ([`super::linear::solve`]):
    /// the factor would exceed the memory budget
    /// ([`crate::tangent::set_factor_budget`]). The results are the same, only slower.
    pub plain: Option<String>,
    /// Bytes the pattern and the factor may take; `None`: the process's
    /// [`crate::tangent::factor_budget`].
    pub budget: Option<u64>,
}

/// Plain conjugate-gradient iterations allowed per solve: `2000 + 50 sqrt(n)` for `n`
/// unknowns. A connected plate converges in about `5 sqrt(n)`; a body the crack has
/// parted stalls, and the cap turns that into a failed solve in seconds.
fn cg_cap(particles: usize) -> usize {
    2000 + (50.0 * ((2 * particles) as f64).sqrt()) as usize
}

impl Solver {
    /// Solve `K u = f` at load factor `load` as [`super::linear::solve`] does (same
    /// loads, prescribed values, tolerance and warm start); returns the iterations.
    pub fn solve(&mut self, body: &mut Body, load: f64, tol: f64) -> Result<usize, PdError> {
        if self.plain.is_some() {
            return super::linear::solve(body, load, tol, cg_cap(body.len()));
        }
        if self
            .factor
            .as_ref()
            .is_some_and(|f| f.particles != body.len())
        {
            self.factor = None;
        }
        let fresh = self.factor.is_none();
        if fresh {
            match self.refactor(body) {
                Err(e @ PdError::TooLarge { .. }) => {
                    self.plain = Some(e.to_string());
                    return super::linear::solve(body, load, tol, cg_cap(body.len()));
                }
                r => r?,
            }
        }
        let cap = if fresh { FRESH_CAP } else { STALE };
        let saved = body.u.clone();
        match self.pcg(body, load, tol, cap) {
            Ok(it) => {
                // A stale factor that costs more iterations than a refactorisation
                // is worth is replaced before the next solve.
                if it > REFRESH {
                    self.factor = None;
                }
                Ok(it)
            }
            Err(_) if !fresh => {
                body.u = saved;
                self.refactor(body)?;
                self.pcg(body, load, tol, FRESH_CAP).map(|it| it + STALE)
            }
            Err(e) => Err(e),
        }
    }

    fn refactor(&mut self, body: &Body) -> Result<(), PdError> {
        self.factor = None;
        let budget = self.budget.unwrap_or_else(crate::tangent::factor_budget);
        self.factor = Some(Factor::new(body, budget)?);
        self.factorizations += 1;
        Ok(())
    }

    fn pcg(&mut self, body: &mut Body, load: f64, tol: f64, cap: usize) -> Result<usize, PdError> {
        let factor = self.factor.as_mut().expect("factored");
        super::linear::pcg(
            body,
            load,
            tol,
            cap,
            "refined body (factor-preconditioned conjugate gradients)",
            |r| factor.apply_inverse(r),
        )
    }
}
