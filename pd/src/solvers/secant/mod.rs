//! Secant equilibria of the bond-break re-commit rounds, solved with one
//! factorisation kept over many rounds and corrected by low-rank updates.
//!
//! In a re-commit round every bond acts with its committed factor
//! $T(s_{hist})$ (seed 000 Eq. 12, [`History::Secant`]), so the equilibrium
//! $R(u) = F(u; s_{hist}) + \lambda b = 0$ is a stable elastic problem.
//! From one round to the next only the bonds of the process zone change
//! (their $T$ drops, or they break), so the secant tangent changes by a
//! sum of rank-one terms, one per changed bond pair $p = (i, j)$:
//! $$M = K_0 + W D W^T,\qquad w_p = (e_p \text{ at } i,\ -e_p \text{ at } j),\qquad
//!   d_p = \frac{k_p\,[T_p - T_p^{(0)}]}{|\xi_p|}$$
//! with $K_0$ the secant tangent factorised at some earlier state
//! ([`crate::tangent`], Cholesky) and $e_p$ the bond direction when the pair
//! joined $W$. By the Woodbury identity
//! $$M^{-1} r = y - Z D\,(I + G D)^{-1} W^T y,\qquad y = K_0^{-1} r,\quad
//!   Z = K_0^{-1} W,\quad G = W^T Z,$$
//! so a solve costs two triangular solves plus $O(n\,|W|)$, and each pair
//! costs one triangular solve when it joins $W$ (several joining pairs are
//! solved together). The chord iteration $u \leftarrow u + M^{-1} R(u)$,
//! accelerated by Anderson mixing ([`super::anderson`]), uses the exact
//! residual, so it converges to the exact secant equilibrium; $M$ misses
//! only the change of the geometric stiffness since $K_0$ (bond directions
//! and stretches) and the transverse terms of the changed pairs. A fresh
//! $K_0$ contracts by about 0.015 per iteration on the seed 000 cases (the
//! strain, amplified by the soft bending mode of the three-point bend).
//! When $|W|$ reaches `max_columns`, or an iteration contracts by less than
//! `SecantParams::refactor_contraction`, $K_0$ is refactorised at the current state and
//! $W$ emptied. If the secant tangent is not positive definite (a
//! compressed fragment cut free by the crack), its positive part
//! [`TangentKind::SecantPositive`] is factorised instead.
//!
//! Convergence is measured as in the other solvers ([`Convergence`], seed
//! 000 Eq. 16 on the update by default).
//!
//! Files: this one holds the chord iteration and the refactorisation policy,
//! `woodbury.rs` the low-rank part ($W$, $D$, $Z$, $G$, the correction),
//! `tests.rs` the unit tests.

mod woodbury;

use std::time::Instant;

use super::anderson::Anderson;
use super::{residual_norms, Convergence, SolveInfo};
use crate::error::PdError;
use crate::forces::{History, TangentKind};
use crate::model::PdModel;
use crate::tangent::Tangent;
use woodbury::LowRank;

/// `Tangent::dof` entry of a prescribed DOF.
const FIXED: usize = usize::MAX;

/// Default of [`SecantParams::refactor_contraction`]. A fresh
/// factor contracts the plain chord update by about 0.015 per iteration on
/// the seed 000 cases (the geometric nonlinearity), a stale one by up to
/// the threshold; a factorisation costs 12-20 solves (`crate::bench`).
/// Counting a factorisation as 15 solves, thresholds from 0.03 to 0.2 cost
/// the same within 4 % on the 96 x 24 bend and the 50 x 50 plate
/// (0.1: 1984 iterations and 15 factorisations, and 900 and 22).
pub const CONTRACTION_REFACTOR: f64 = 0.1;

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Parameters of [`SecantSolver::equilibrate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SecantParams {
    /// Convergence measure (seed 000 Eq. 16 by default).
    pub convergence: Convergence,
    /// Relative residual accepted without a further solve.
    pub residual_tol: f64,
    /// Iteration cap per equilibrium.
    pub max_iters: usize,
    /// Largest number of low-rank columns before refactorising.
    pub max_columns: usize,
    /// Anderson mixing depth of the chord iteration (0: plain chord).
    pub anderson_depth: usize,
    /// Contraction per iteration above which $K_0$ is refactorised
    /// ([`CONTRACTION_REFACTOR`] by default).
    pub refactor_contraction: f64,
    /// Refactorisations for poor contraction allowed per equilibrium; one more ends the
    /// iteration with [`PdError::NoConvergence`] (a fallback's turn). `None`: no limit.
    pub max_refactors: Option<usize>,
}

/// Chord iteration on a factorised secant tangent with Woodbury updates.
pub struct SecantSolver {
    low_rank: LowRank,
    /// $K_0$ is factorised and `low_rank` describes its bond state.
    valid: bool,
    rhs: Vec<f64>,
    anderson: Anderson,
    /// Factorisations of $K_0$.
    pub factorizations: usize,
    /// Triangular solve pairs (one per right-hand side).
    pub solves: usize,
}

impl SecantSolver {
    /// Buffers for `model` with at most `max_columns` low-rank columns and
    /// Anderson mixing of depth `anderson_depth`.
    pub fn new(model: &PdModel, n_free: usize, max_columns: usize, anderson_depth: usize) -> Self {
        SecantSolver {
            low_rank: LowRank::new(model.bonds.len(), max_columns),
            valid: false,
            rhs: vec![0.0; n_free],
            anderson: Anderson::new(n_free, anderson_depth),
            factorizations: 0,
            solves: 0,
        }
    }

    /// Forget $K_0$ (the tangent's factor was replaced by another solve).
    pub fn invalidate(&mut self) {
        self.valid = false;
    }

    /// Factorise the secant tangent at the current state as $K_0$ and empty
    /// `W`. If it is not positive definite (a compressed fragment cut free
    /// by the crack), the positive part [`TangentKind::SecantPositive`] is
    /// factorised instead.
    fn refactor(
        &mut self,
        model: &PdModel,
        tangent: &mut Tangent,
        info: &mut SolveInfo,
    ) -> Result<(), PdError> {
        self.valid = false;
        let exact = self.factor_kind(model, tangent, TangentKind::Secant, info);
        if exact.is_err() {
            self.factor_kind(model, tangent, TangentKind::SecantPositive, info)?;
        }
        self.factorizations += 1;
        self.low_rank.reset(model);
        self.valid = true;
        Ok(())
    }

    /// Assemble the tangent of `kind` at the current state and factorise it.
    fn factor_kind(
        &mut self,
        model: &PdModel,
        tangent: &mut Tangent,
        kind: TangentKind,
        info: &mut SolveInfo,
    ) -> Result<(), PdError> {
        let ta = Instant::now();
        model.assemble_tangent(tangent, kind);
        let tf = Instant::now();
        info.time_assembly_s += (tf - ta).as_secs_f64();
        let res = tangent.factorize();
        info.time_factorization_s += tf.elapsed().as_secs_f64();
        info.factorizations += 1;
        res
    }

    /// After a commit: bring `W` and `D` up to date with the bonds whose
    /// secant stiffness changed since $K_0$ (refactorising instead when `W`
    /// would grow past `max_columns`).
    pub fn track_changes(
        &mut self,
        model: &PdModel,
        tangent: &mut Tangent,
        info: &mut SolveInfo,
    ) -> Result<(), PdError> {
        if !self.valid {
            return Ok(());
        }
        let fresh = self.low_rank.update_changed(model);
        if self.low_rank.would_overflow(fresh.len()) {
            return self.refactor(model, tangent, info);
        }
        self.solves += self.low_rank.add_columns(model, tangent, &fresh, info)?;
        Ok(())
    }

    /// `rhs <- M^{-1} rhs` (Woodbury, [`woodbury`]).
    fn apply_inverse(
        &mut self,
        tangent: &mut Tangent,
        info: &mut SolveInfo,
    ) -> Result<(), PdError> {
        let tf = Instant::now();
        tangent.solve_with_last_factor(&mut self.rhs, 1)?;
        info.time_factorization_s += tf.elapsed().as_secs_f64();
        self.solves += 1;
        self.low_rank.correct(&mut self.rhs);
        Ok(())
    }

    /// Iterate $u \leftarrow u + M^{-1} R(u)$ at the model's load with the
    /// secant bond law until `p.convergence` is met. Returns (iterations,
    /// final measure). Refactorises $K_0$ first if it is not current, and
    /// again when an update shrinks by less than a factor 10.
    pub fn equilibrate(
        &mut self,
        model: &mut PdModel,
        tangent: &mut Tangent,
        p: &SecantParams,
        info: &mut SolveInfo,
    ) -> Result<(usize, f64), PdError> {
        if !self.valid {
            self.refactor(model, tangent, info)?;
        }
        self.anderson.reset();
        let mut prev = f64::INFINITY;
        let mut measure = f64::INFINITY;
        let mut rref = 0.0f64;
        let mut refactors = 0;
        for it in 1..=p.max_iters {
            model.compute_forces(History::Secant);
            let (r, rr) = residual_norms(model);
            rref = rref.max(rr);
            let rel = if rref > 0.0 { r / rref } else { r };
            if !rel.is_finite() {
                return Err(PdError::NonFinite {
                    solver: "secant",
                    iteration: it,
                    load: model.load,
                });
            }
            let res_done = matches!(p.convergence, Convergence::Residual { tol } if rel < tol);
            if rel < p.residual_tol || r == 0.0 || res_done {
                info.residual_history.push(rel);
                return Ok((it - 1, rel));
            }
            self.load_residual(model, tangent);
            self.apply_inverse(tangent, info)?;
            let chord = norm(&self.rhs);
            self.anderson.mix(&mut self.rhs);
            measure = self.add_step(model, tangent);
            info.residual_history.push(measure);
            if let Convergence::Displacement { e0 } = p.convergence {
                if measure < e0 {
                    return Ok((it, measure));
                }
            }
            if it > 1 && chord > p.refactor_contraction * prev {
                refactors += 1;
                if p.max_refactors.is_some_and(|m| refactors > m) {
                    return Err(self.no_convergence(model, p, it, measure));
                }
                self.refactor(model, tangent, info)?;
                self.anderson.reset();
            }
            prev = chord;
        }
        Err(self.no_convergence(model, p, p.max_iters, measure))
    }

    /// The error of an equilibrium given up after `iterations` at `measure`.
    fn no_convergence(
        &self,
        model: &PdModel,
        p: &SecantParams,
        iterations: usize,
        measure: f64,
    ) -> PdError {
        PdError::NoConvergence {
            solver: "secant",
            iterations,
            load: model.load,
            measure,
            tolerance: p.convergence.tolerance(),
        }
    }

    /// `u += rhs` at the free DOFs; returns the relative change (Eq. 16).
    fn add_step(&self, model: &mut PdModel, tangent: &Tangent) -> f64 {
        let (mut du2, mut u2) = (0.0, 0.0);
        for i in 0..model.n_nodes() {
            for c in 0..2 {
                let d = tangent.dof[2 * i + c];
                if d != FIXED {
                    model.u[i][c] += self.rhs[d];
                    du2 += self.rhs[d] * self.rhs[d];
                    u2 += model.u[i][c] * model.u[i][c];
                }
            }
        }
        if u2 > 0.0 {
            (du2 / u2).sqrt()
        } else {
            0.0
        }
    }

    /// `rhs` = residual $F + \lambda b$ at the free DOFs (forces computed).
    fn load_residual(&mut self, model: &PdModel, tangent: &Tangent) {
        let lam = model.load;
        for i in 0..model.n_nodes() {
            for c in 0..2 {
                let d = tangent.dof[2 * i + c];
                if d != FIXED {
                    self.rhs[d] = model.force[i][c] + lam * model.bc.body[i][c];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests;
