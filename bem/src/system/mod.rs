//! Boundary conditions, assembly of the Burton-Miller system, rigid-body modes, the kept LU
//! factorization and the solution.
//!
//! Entry point: [`BemSystem::new`] (assemble + factor, returns [`SolveInfo`]) and
//! [`BemSystem::solve`] / [`BemSystem::solve_with`] (one substitution per right-hand side).
//!
//! Per collocation element i and element j the 2x2 blocks are
//! $H^c_{ij} = \alpha(\delta_{ij}I + \hat T_{ij}) + \beta_i \hat H_{ij}$ and
//! $G^c_{ij} = \alpha \hat U_{ij} + \beta_i(\hat K_{ij} - \delta_{ij} I)$, and the equations
//! read $\sum_j H^c_{ij} u_j = \sum_j G^c_{ij} t_j$ (seed 002 Eqs. 21-22). Each component
//! of each element has either its displacement or its traction prescribed; the unknown one
//! becomes a column of A, the known one goes to the right-hand side.
//!
//! **Rigid-body modes.** Where the prescribed displacements do not fix the three rigid
//! motions (pure-traction bodies such as the seed-002 plates), the free modes R (rigid
//! motions evaluated at the collocation points) border the system,
//! $\begin{bmatrix} A & R \\ R^T & 0 \end{bmatrix}\begin{bmatrix} u \\ \lambda\end{bmatrix}
//! = \begin{bmatrix} b \\ 0 \end{bmatrix}$: the constraint picks one member of the family of
//! solutions and $\lambda$ absorbs the discretization's small load imbalance. REFERENCES.md
//! records that least squares, truncated SVD or projection give -80 to -96 % errors on deep
//! edge cracks while this bordering does not. Gauge-free results (SIF, CMOD, stress) do not
//! depend on the chosen member. Infinite bodies have no rigid modes. The bordering
//! returns a solution even for loads that do work on a free mode (an unbalanced body):
//! [`balance::load_imbalance`] finds them before a solve.
//!
//! **Scaling.** Columns of A are scaled to unit max-norm before factorization (traction and
//! displacement unknowns have different units); the condition estimate refers to that
//! scaled matrix.

mod assemble;
pub mod balance;
mod budget;
mod cache;
mod condition;
mod rigid;

use crate::mesh::Mesh;
use crate::{BemError, Material};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{MatMut, MatRef, Par};
use std::time::Instant;

pub use budget::{set_system_budget, system_budget};
pub use cache::PairCache;

/// Prescribed value of one component on one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bc {
    /// Prescribed displacement (m).
    Displacement(f64),
    /// Prescribed traction t = sigma . n (Pa).
    Traction(f64),
}

impl Bc {
    /// The prescribed value.
    pub fn value(&self) -> f64 {
        match *self {
            Bc::Displacement(v) | Bc::Traction(v) => v,
        }
    }

    fn is_displacement(&self) -> bool {
        matches!(self, Bc::Displacement(_))
    }
}

/// Parameters of assembly and solution.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveParams {
    /// Weight of the CBIE (seed 002 Eq. 21: 1).
    pub alpha: f64,
    /// beta = beta_factor * h(x) / E. REFERENCES.md: -1 reinforces the diagonal in this
    /// convention; +1 is kept only to demonstrate the ill-conditioning it causes.
    pub beta_factor: f64,
    /// Infinite body (only holes and cracks): no rigid-body modes.
    pub infinite: bool,
    /// Element groups whose prescribed values may change between solves (e.g. coupling
    /// interfaces): their right-hand-side columns are kept.
    pub variable_groups: Vec<usize>,
    /// Estimate the 1-norm condition number of the scaled system (a few extra solves).
    pub estimate_condition: bool,
    /// Precompute the response of the unknowns to the variable groups' values,
    /// R = A^{-1} B_var (one multi-column substitution, about 2 n^2 m flops), so a further
    /// right-hand side costs one n x m product instead of a substitution through the whole
    /// factor. Pays off when many solves change few values (coupling iterations).
    pub precompute_response: bool,
    /// Integrate the boundary displacement as linear on each element, with the tangential
    /// derivative reconstructed from neighbouring elements ([`crate::mesh::stencil`]).
    /// Rigid rotation becomes exact; deep edge cracks converge far faster.
    pub reconstruct: bool,
}

impl Default for SolveParams {
    fn default() -> Self {
        Self {
            alpha: 1.0,
            beta_factor: -1.0,
            infinite: false,
            variable_groups: Vec::new(),
            estimate_condition: true,
            precompute_response: false,
            reconstruct: true,
        }
    }
}

/// Timings and diagnostics of assembly and factorization.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct SolveInfo {
    /// Number of elements.
    pub elements: usize,
    /// Number of unknowns (including rigid-mode multipliers).
    pub unknowns: usize,
    /// Free rigid-body modes removed by bordering.
    pub rigid_modes: usize,
    /// Wall time of assembly (s).
    pub assembly_s: f64,
    /// Wall time of the LU factorization (s).
    pub factor_s: f64,
    /// 1-norm condition estimate of the scaled system (NaN when not estimated).
    pub condition: f64,
    /// Bytes held by the factorization and kept right-hand-side columns.
    pub memory_bytes: usize,
    /// Wall time of the precomputed response (s; 0 without `precompute_response`).
    pub response_s: f64,
    /// Element pairs whose blocks came from a [`PairCache`] instead of integration.
    pub reused_pairs: usize,
}

/// Boundary solution: displacement and traction of every element (global x, y).
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// Displacement at each element's collocation point.
    pub u: Vec<[f64; 2]>,
    /// Traction on each element.
    pub t: Vec<[f64; 2]>,
    /// Rigid-mode multipliers (the load imbalance absorbed; near zero for balanced loads).
    pub lambda: Vec<f64>,
    /// Tangential displacement derivative of each element when the linear reconstruction
    /// is on (empty otherwise).
    pub du: Vec<[f64; 2]>,
}

/// What a solve of a mesh allocates, known before the system is assembled.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BemFootprint {
    /// Elements.
    pub elements: usize,
    /// Unknowns: two per element plus one multiplier per free rigid mode.
    pub unknowns: usize,
    /// Bytes of the dense system (factorised in place) and its work vectors, as
    /// [`SolveInfo::memory_bytes`] counts them without a precomputed response.
    pub matrix_bytes: usize,
}

/// The footprint of solving `mesh` under `bcs` with `params` (the free rigid modes are
/// found as the assembly finds them); saturates instead of overflowing.
pub fn footprint(mesh: &Mesh, bcs: &[[Bc; 2]], params: &SolveParams) -> BemFootprint {
    let modes = if params.infinite || bcs.len() != mesh.len() {
        0
    } else {
        rigid::free_modes(mesh, bcs).modes.len()
    };
    let n = (2 * mesh.len()).saturating_add(modes);
    BemFootprint {
        elements: mesh.len(),
        unknowns: n,
        matrix_bytes: dense_bytes(n),
    }
}

/// Bytes of an n x n f64 system and four work vectors.
fn dense_bytes(n: usize) -> usize {
    n.saturating_mul(n)
        .saturating_mul(8)
        .saturating_add(n.saturating_mul(32))
}

/// An assembled and factored boundary element system.
pub struct BemSystem {
    n_el: usize,
    n: usize,
    lu: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    col_scale: Vec<f64>,
    bcs: Vec<[Bc; 2]>,
    rhs: Vec<f64>,
    /// Degrees of freedom whose prescribed values may change, and their right-hand-side
    /// columns as one column-major n x m matrix (applied with one parallel product).
    variable_dofs: Vec<usize>,
    variable_cols: Vec<f64>,
    /// With `precompute_response`: the base solution A^{-1} b and R = A^{-1} B_var.
    response: Option<(Vec<f64>, Vec<f64>)>,
    stencil: Option<crate::mesh::stencil::Stencil>,
    info: SolveInfo,
    /// Piece of every element ([`crate::mesh::pieces`]).
    pieces: Vec<usize>,
    /// Free rigid modes of every piece (0 to 3).
    free_in_piece: Vec<usize>,
}

impl BemSystem {
    /// Assembles and factors the system for `mesh` with per-element conditions `bcs`.
    pub fn new(
        mesh: &Mesh,
        material: &Material,
        bcs: &[[Bc; 2]],
        params: &SolveParams,
    ) -> Result<Self, BemError> {
        Self::new_with_cache(mesh, material, bcs, params, None)
    }

    /// The same; with a `cache`, the blocks of the element pairs it holds from an earlier
    /// assembly are copied instead of integrated, and this mesh's blocks are left in it
    /// ([`PairCache`]; bit-identical to [`Self::new`]).
    pub fn new_with_cache(
        mesh: &Mesh,
        material: &Material,
        bcs: &[[Bc; 2]],
        params: &SolveParams,
        cache: Option<&mut PairCache>,
    ) -> Result<Self, BemError> {
        if bcs.len() != mesh.len() {
            return Err(BemError::Boundary(format!(
                "{} conditions for {} elements",
                bcs.len(),
                mesh.len()
            )));
        }
        if mesh.is_empty() {
            return Err(BemError::Mesh("no elements".into()));
        }
        let t0 = Instant::now();
        let rigid::FreeModes {
            modes,
            pieces,
            per_piece: free_in_piece,
        } = if params.infinite {
            rigid::FreeModes {
                modes: Vec::new(),
                pieces: vec![0; mesh.len()],
                per_piece: vec![0],
            }
        } else {
            rigid::free_modes(mesh, bcs)
        };
        let unknowns = (2 * mesh.len()).saturating_add(modes.len());
        budget::check(mesh.len(), unknowns, dense_bytes(unknowns))?;
        let stencil = params
            .reconstruct
            .then(|| crate::mesh::stencil::tangential_stencil(mesh));
        let asm = assemble::assemble(mesh, material, bcs, params, &modes, stencil.as_ref(), cache);
        let assembly_s = t0.elapsed().as_secs_f64();
        let n = asm.n;
        let mut sys = Self {
            n_el: mesh.len(),
            n,
            lu: asm.a,
            perm: vec![0; n],
            perm_inv: vec![0; n],
            col_scale: asm.col_scale,
            bcs: bcs.to_vec(),
            rhs: asm.rhs,
            variable_dofs: asm.variable.iter().map(|(d, _)| *d).collect(),
            variable_cols: asm.variable.into_iter().flat_map(|(_, c)| c).collect(),
            response: None,
            stencil,
            pieces,
            free_in_piece,
            info: SolveInfo {
                elements: mesh.len(),
                unknowns: n,
                rigid_modes: modes.len(),
                assembly_s,
                reused_pairs: asm.reused,
                ..Default::default()
            },
        };
        let t1 = Instant::now();
        sys.factor();
        sys.info.factor_s = t1.elapsed().as_secs_f64();
        if params.precompute_response && !sys.variable_dofs.is_empty() {
            let t2 = Instant::now();
            sys.precompute_response();
            sys.info.response_s = t2.elapsed().as_secs_f64();
        }
        let vmem = sys.variable_cols.len() * 8 * if sys.response.is_some() { 2 } else { 1 };
        sys.info.memory_bytes = dense_bytes(n) + vmem;
        sys.info.condition = if params.estimate_condition {
            condition::estimate_cond1(&sys, asm.norm1)
        } else {
            f64::NAN
        };
        if sys
            .lu
            .iter()
            .step_by(n + 1)
            .any(|d| *d == 0.0 || !d.is_finite())
        {
            return Err(BemError::Singular {
                reason: "zero or non-finite pivot in the LU factorization".into(),
                unknowns: n,
                condition: sys.info.condition,
            });
        }
        Ok(sys)
    }

    /// Diagnostics of assembly and factorization.
    pub fn info(&self) -> &SolveInfo {
        &self.info
    }

    /// Piece of every element: the body cut apart by cracks has several
    /// ([`crate::mesh::pieces`]; all 0 for an infinite body).
    pub fn pieces(&self) -> &[usize] {
        &self.pieces
    }

    /// Rigid modes left free in every piece (3 for a piece with no prescribed
    /// displacement). The solution fixes them by the bordering constraint, which is
    /// arbitrary: the displacement of a free piece is known up to these motions.
    pub fn free_modes_per_piece(&self) -> &[usize] {
        &self.free_in_piece
    }

    /// The rigid motions left free in piece `p` of `mesh` (the mesh this system was built
    /// for): the piece's centroid (mean collocation point) and one `(a_x, a_y, theta)`
    /// per free motion, a translation and a rotation (radians) about that centroid,
    /// [`Self::free_modes_per_piece`] of them. Every such motion leaves the piece's
    /// displacement-prescribed components unmoved, so the reactions do no work on it.
    pub fn free_motions(&self, mesh: &Mesh, p: usize) -> (crate::V2, Vec<[f64; 3]>) {
        let frame = rigid::piece_frame(mesh, &self.bcs, &self.pieces, p);
        let motions = frame
            .free
            .iter()
            .map(|v| [v[0], v[1], v[2] / frame.scale])
            .collect();
        (frame.centroid, motions)
    }

    fn factor(&mut self) {
        let n = self.n;
        let par = Par::rayon(0);
        let mat = MatMut::from_column_major_slice_mut(&mut self.lu, n, n);
        let mut mem = MemBuffer::new(factor::lu_in_place_scratch::<usize, f64>(
            n,
            n,
            par,
            Default::default(),
        ));
        factor::lu_in_place(
            mat,
            &mut self.perm,
            &mut self.perm_inv,
            par,
            MemStack::new(&mut mem),
            Default::default(),
        );
    }

    /// R = A^{-1} B_var (all columns in one blocked substitution) and x0 = A^{-1} b.
    fn precompute_response(&mut self) {
        let (n, m) = (self.n, self.variable_dofs.len());
        let mut r = self.variable_cols.clone();
        let lu = MatRef::from_column_major_slice(&self.lu, n, n);
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let par = Par::rayon(0);
        let mut mem = MemBuffer::new(solve::solve_in_place_scratch::<usize, f64>(n, m, par));
        let rhs = MatMut::from_column_major_slice_mut(&mut r, n, m);
        solve::solve_in_place_with_conj(
            lu,
            lu,
            perm,
            faer::Conj::No,
            rhs,
            par,
            MemStack::new(&mut mem),
        );
        let mut x0 = self.rhs.clone();
        self.substitute(&mut x0, false);
        self.response = Some((x0, r));
    }

    /// Solves A x = b in place with the kept factorization (b in scaled unknowns).
    pub(crate) fn substitute(&self, b: &mut [f64], transpose: bool) {
        let n = self.n;
        let lu = MatRef::from_column_major_slice(&self.lu, n, n);
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        // The substitution is memory bound: both cores read the factor faster than one.
        let par = if n > 2000 { Par::rayon(0) } else { Par::Seq };
        let mut mem = MemBuffer::new(solve::solve_in_place_scratch::<usize, f64>(n, 1, par));
        let stack = MemStack::new(&mut mem);
        if transpose {
            solve::solve_transpose_in_place_with_conj(
                lu,
                lu,
                perm,
                faer::Conj::No,
                rhs,
                par,
                stack,
            );
        } else {
            solve::solve_in_place_with_conj(lu, lu, perm, faer::Conj::No, rhs, par, stack);
        }
    }

    /// Solves with the prescribed values given at construction.
    pub fn solve(&self) -> Result<Solution, BemError> {
        let mut b = self.rhs.clone();
        self.finish(&mut b, &self.bcs)
    }

    /// Solves with new prescribed values. Only elements of `variable_groups` may change
    /// their values, and no component may change its kind (displacement / traction).
    pub fn solve_with(&self, bcs: &[[Bc; 2]]) -> Result<Solution, BemError> {
        if bcs.len() != self.n_el {
            return Err(BemError::Boundary(format!(
                "{} conditions for {} elements",
                bcs.len(),
                self.n_el
            )));
        }
        let mut b = match &self.response {
            Some((x0, _)) => x0.clone(),
            None => self.rhs.clone(),
        };
        let mut is_var = vec![false; 2 * self.n_el];
        let dv: Vec<f64> = self
            .variable_dofs
            .iter()
            .map(|&dof| {
                is_var[dof] = true;
                let (el, c) = (dof / 2, dof % 2);
                bcs[el][c].value() - self.bcs[el][c].value()
            })
            .collect();
        if dv.iter().any(|v| *v != 0.0) {
            let m = dv.len();
            // With the precomputed response b already holds x0 and R maps dv to the unknowns.
            let kept = self
                .response
                .as_ref()
                .map_or(&self.variable_cols, |(_, r)| r);
            let cols = MatRef::from_column_major_slice(kept, self.n, m);
            let x = MatRef::from_column_major_slice(&dv, m, 1);
            let out = MatMut::from_column_major_slice_mut(&mut b, self.n, 1);
            let par = if self.n * m > 1 << 20 {
                Par::rayon(0)
            } else {
                Par::Seq
            };
            faer::linalg::matmul::matmul(out, faer::Accum::Add, cols, x, 1.0, par);
        }
        for (el, (new, old)) in bcs.iter().zip(&self.bcs).enumerate() {
            for c in 0..2 {
                if new[c].is_displacement() != old[c].is_displacement()
                    || (!is_var[2 * el + c] && new[c] != old[c])
                {
                    return Err(BemError::Boundary(format!(
                        "element {el} component {c}: {:?} -> {:?} needs a new assembly (only values of variable groups may change)",
                        old[c], new[c]
                    )));
                }
            }
        }
        if self.response.is_some() {
            return self.unpack(&b, bcs);
        }
        self.finish(&mut b, bcs)
    }

    fn finish(&self, b: &mut [f64], bcs: &[[Bc; 2]]) -> Result<Solution, BemError> {
        self.substitute(b, false);
        self.unpack(b, bcs)
    }

    /// Solution from the scaled unknowns `b`.
    fn unpack(&self, b: &[f64], bcs: &[[Bc; 2]]) -> Result<Solution, BemError> {
        if b.iter().any(|v| !v.is_finite()) {
            return Err(BemError::Singular {
                reason: "non-finite solution".into(),
                unknowns: self.n,
                condition: self.info.condition,
            });
        }
        let mut sol = Solution {
            u: vec![[0.0; 2]; self.n_el],
            t: vec![[0.0; 2]; self.n_el],
            lambda: b[2 * self.n_el..].to_vec(),
            du: Vec::new(),
        };
        for el in 0..self.n_el {
            for c in 0..2 {
                let dof = 2 * el + c;
                let x = b[dof] * self.col_scale[dof];
                match bcs[el][c] {
                    Bc::Displacement(v) => {
                        sol.u[el][c] = v;
                        sol.t[el][c] = x;
                    }
                    Bc::Traction(v) => {
                        sol.u[el][c] = x;
                        sol.t[el][c] = v;
                    }
                }
            }
        }
        if let Some(st) = &self.stencil {
            sol.du = crate::mesh::stencil::apply(st, &sol.u);
        }
        Ok(sol)
    }
}
