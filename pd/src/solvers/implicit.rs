//! Implicit Newton-Raphson on the full nonlinear equilibrium (seed 000
//! section 2).
//!
//! Each iteration solves $K_m \Delta u_m = -E(u_m)$ (Eq. 5) over the free DOFs
//! with the analytic tangent of Eqs. 8-10 and 14-15 ([`crate::tangent`]),
//! prescribed DOFs removed (section 2.3); while the residual falls fast enough a step
//! solves with the factor of an earlier $K$ of the same bonds instead ([`Newton`]). The
//! bond history is frozen during the iterations and committed once a step converges;
//! brittle bonds that pass `s0` then break and the step is re-solved until no bond
//! breaks. Convergence: Eq. 16 on the Newton update, or the relative residual (checked
//! before factorising, which saves the last solve). A backtracking line search halves
//! the update of a fresh step while the residual grows; NaN, a residual growing past
//! `1e6` times its start, or the iteration cap are errors.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{norm2_free, residual_norms, Convergence, PhaseKind, SolveInfo, StepRecord};
use crate::error::PdError;
use crate::forces::{History, TangentKind};
use crate::geometry::P2;
use crate::material::BondLaw;
use crate::model::PdModel;
use crate::tangent::{Factorization, Tangent};

/// Newton-Raphson parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ImplicitParams {
    /// Load factor to reach.
    pub target_load: f64,
    /// Number of equal load increments.
    pub steps: usize,
    /// Convergence on the Newton update; default Eq. 16 with `e0 = 1e-9`.
    pub convergence: Convergence,
    /// Relative residual accepted without a further solve.
    pub residual_tol: f64,
    /// Cap on the Newton iterations with a new tangent per solve; steps on a kept factor
    /// ([`Newton`]) come on top (each lowers the residual tenfold, or is followed by a new
    /// tangent).
    pub max_iters: usize,
    /// Re-solves per step after brittle bonds break.
    pub max_break_rounds: usize,
}

impl Default for ImplicitParams {
    fn default() -> Self {
        ImplicitParams {
            target_load: 1.0,
            steps: 1,
            convergence: Convergence::default(),
            residual_tol: 1e-10,
            max_iters: 50,
            max_break_rounds: 100,
        }
    }
}

/// A Newton step on a kept factor ([`Newton`]) whose residual fell by at least this factor
/// keeps the factor for the next step and may end the iteration: the chord iteration's
/// threshold ([`super::secant::CONTRACTION_REFACTOR`]). Not tuned: in the crack-initiation
/// ramps the kept steps lower the residual about 1e4-fold (docs/seed004.md, "Newton on a
/// kept factor").
pub const KEPT_FACTOR_CONTRACTION: f64 = super::secant::CONTRACTION_REFACTOR;

/// Reusable Newton buffers: tangent pattern, symbolic factorisation, vectors.
///
/// **Steps on a kept factor.** A step may solve with the Cholesky factor of an earlier
/// tangent of the same bonds instead of a new one: two triangular solves instead of an
/// assembly and a factorisation. The factor is this Newton's last one within the same
/// [`Self::equilibrate`], or that of the [`Self::predict_to`] just before it, at the load
/// it predicted. The residual decides: a step that lowers it by
/// [`KEPT_FACTOR_CONTRACTION`] or more keeps the factor; one that lowers it less is kept
/// but the next step refactorises; one that does not lower it is undone and the step is
/// taken with a fresh tangent. Only a step of the first kind or a fresh Newton step may
/// end the iteration, so the convergence measure of a kept-factor step bounds the error
/// as a Newton step's does. A factor is never reused across broken bonds or, for the
/// degrading law, a changed bond history (the tangent changes there by more than a small
/// strain): after a break round the first step factorises. `max_iters` counts the steps
/// with a new tangent.
pub struct Newton {
    /// Tangent pattern and values.
    pub tangent: Tangent,
    rhs: Vec<f64>,
    u_save: Vec<P2>,
    /// The factor this Newton made last (the tangent's factor generation) and the
    /// model's bond state then ([`bond_state`]).
    kept: Option<(u64, (usize, u64))>,
    /// The last call was [`Self::predict_to`], to this load factor: the next
    /// [`Self::equilibrate`] at that load may start on its factor.
    predicted: Option<f64>,
    /// Whether steps may reuse a kept factor (type docs; default true). Off, every step
    /// factorises, as before this rule.
    pub reuse_factor: bool,
}

/// What the tangent depends on besides the displacements: the broken bonds, and for a
/// degrading law the bonds' history (a fingerprint of its bits). Brittle and elastic bonds
/// have no history in their tangent.
fn bond_state(model: &PdModel) -> (usize, u64) {
    let history = match model.law() {
        BondLaw::Degrading { .. } => model.s_hist.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, s| {
            (h ^ s.to_bits()).wrapping_mul(0x0100_0000_01b3)
        }),
        BondLaw::Elastic | BondLaw::Brittle { .. } => 0,
    };
    (model.broken_bonds(), history)
}

/// How a Newton step went ([`Newton::equilibrate`]).
enum Stepped {
    /// Taken; the residual is `r`; the next step may use the kept factor.
    Taken { r: f64, du2: f64, keep: bool },
    /// A kept-factor step that did not lower the residual, undone.
    Undone,
}

impl Newton {
    /// Build the tangent pattern for `model` and its factor's storage
    /// ([`PdError::TooLarge`] over the memory budget, before any solve).
    pub fn new(model: &PdModel) -> Result<Self, PdError> {
        let mut tangent = model.new_tangent()?;
        tangent.reserve_factor()?;
        let nf = tangent.n_free;
        Ok(Newton {
            tangent,
            rhs: vec![0.0; nf],
            u_save: vec![[0.0; 2]; model.n_nodes()],
            kept: None,
            predicted: None,
            reuse_factor: true,
        })
    }

    /// Whether the tangent holds this Newton's last factor, made with the model's bonds
    /// and history as they are.
    fn factor_kept_for(&self, model: &PdModel) -> bool {
        match (self.kept, self.tangent.factor_generation()) {
            (Some((g, state)), Some(held)) => {
                self.reuse_factor && g == held && state == bond_state(model)
            }
            _ => false,
        }
    }

    /// Records the factor just made (a Cholesky factor; an LU solve keeps none).
    fn record_factor(&mut self, model: &PdModel, fact: Factorization) {
        self.kept = match (fact, self.tangent.factor_generation()) {
            (Factorization::Cholesky, Some(g)) => Some((g, bond_state(model))),
            _ => None,
        };
    }

    /// Factorises the tangent's values and solves `rhs` in place, counting and timing it
    /// in `info`; the factor is kept for later steps ([`Self::record_factor`]).
    fn factor_and_solve(&mut self, model: &PdModel, info: &mut SolveInfo) -> Result<(), PdError> {
        let tf = Instant::now();
        let fact = self.tangent.solve(&mut self.rhs)?;
        info.time_factorization_s += tf.elapsed().as_secs_f64();
        info.factorizations += 1;
        if fact == Factorization::Lu {
            info.lu_fallbacks += 1;
        }
        self.record_factor(model, fact);
        Ok(())
    }

    /// The residual `F + lambda b` at the free DOFs into `rhs`.
    fn fill_rhs(&mut self, model: &PdModel) {
        let lam = model.load;
        for i in 0..model.n_nodes() {
            for c in 0..2 {
                let d = self.tangent.dof[2 * i + c];
                if d != usize::MAX {
                    self.rhs[d] = model.force[i][c] + lam * model.bc.body[i][c];
                }
            }
        }
    }

    /// `u = u_save + alpha rhs` at the free DOFs; returns the squared update.
    fn apply_update(&self, model: &mut PdModel, alpha: f64) -> f64 {
        let mut du2 = 0.0;
        for i in 0..model.n_nodes() {
            for c in 0..2 {
                let d = self.tangent.dof[2 * i + c];
                if d != usize::MAX {
                    let du = alpha * self.rhs[d];
                    model.u[i][c] = self.u_save[i][c] + du;
                    du2 += du * du;
                }
            }
        }
        du2
    }

    /// A Newton step with a fresh tangent and factor, with backtracking while the
    /// residual `r` grows.
    fn fresh_step(
        &mut self,
        model: &mut PdModel,
        r: f64,
        info: &mut SolveInfo,
    ) -> Result<Stepped, PdError> {
        let ta = Instant::now();
        model.assemble_tangent(&mut self.tangent, TangentKind::Consistent);
        info.time_assembly_s += ta.elapsed().as_secs_f64();
        self.fill_rhs(model);
        self.factor_and_solve(model, info)?;
        self.u_save.copy_from_slice(&model.u);
        let (mut alpha, mut du2, mut rn) = (1.0, 0.0, r);
        for _ in 0..6 {
            du2 = self.apply_update(model, alpha);
            model.compute_forces(History::Frozen);
            rn = residual_norms(model).0;
            if rn.is_finite() && (rn <= 1.5 * r || alpha < 0.05) {
                break;
            }
            alpha *= 0.5;
        }
        let keep = self.reuse_factor && self.kept.is_some();
        Ok(Stepped::Taken { r: rn, du2, keep })
    }

    /// A Newton step on the kept factor (type docs): taken whole, or undone if the
    /// residual `r` does not fall.
    fn kept_factor_step(
        &mut self,
        model: &mut PdModel,
        r: f64,
        info: &mut SolveInfo,
    ) -> Result<Stepped, PdError> {
        let t = Instant::now();
        self.fill_rhs(model);
        self.tangent.solve_with_last_factor(&mut self.rhs, 1)?;
        info.time_factorization_s += t.elapsed().as_secs_f64();
        info.kept_factor_solves += 1;
        self.u_save.copy_from_slice(&model.u);
        let du2 = self.apply_update(model, 1.0);
        model.compute_forces(History::Frozen);
        let rn = residual_norms(model).0;
        if !(rn.is_finite() && rn < r) {
            model.u.copy_from_slice(&self.u_save);
            model.compute_forces(History::Frozen);
            return Ok(Stepped::Undone);
        }
        let keep = rn <= KEPT_FACTOR_CONTRACTION * r;
        Ok(Stepped::Taken { r: rn, du2, keep })
    }

    /// Newton iterations to equilibrium at the model's current load (history
    /// frozen). Returns (iterations, final measure). Steps may reuse a kept factor (type
    /// docs); an undone kept-factor step is not an iteration.
    pub fn equilibrate(
        &mut self,
        model: &mut PdModel,
        p: &ImplicitParams,
        info: &mut SolveInfo,
    ) -> Result<(usize, f64), PdError> {
        model.compute_forces(History::Frozen);
        let (mut r, rref0) = residual_norms(model);
        let mut r0 = r;
        let mut measure = f64::INFINITY;
        let mut prev_measure = f64::INFINITY;
        let mut last_rel = f64::INFINITY;
        // A call starts on a kept factor only after the predictor: a solve never depends
        // on what this Newton solved before it (a growth run resumed from a checkpoint
        // builds a new one and must repeat the uninterrupted run bit for bit).
        let mut use_kept = self.predicted.take() == Some(model.load) && self.factor_kept_for(model);
        // Iterations, and of them those with a new tangent (the cap counts these).
        let (mut it, mut fresh) = (0, 0);
        while fresh < p.max_iters {
            let rref = rref0.max(residual_norms(model).1);
            if !r.is_finite() {
                return Err(PdError::NonFinite {
                    solver: "implicit",
                    iteration: it + 1,
                    load: model.load,
                });
            }
            let rel = if rref > 0.0 { r / rref } else { r };
            if rel < p.residual_tol || r == 0.0 {
                info.residual_history.push(rel);
                return Ok((it, rel));
            }
            if r > 1e6 * r0.max(f64::MIN_POSITIVE) {
                return Err(PdError::Diverged {
                    solver: "implicit",
                    iteration: it + 1,
                    load: model.load,
                    residual: r,
                    initial: r0,
                });
            }
            let on_kept = use_kept;
            let stepped = if on_kept {
                self.kept_factor_step(model, r, info)?
            } else {
                fresh += 1;
                self.fresh_step(model, r, info)?
            };
            let Stepped::Taken { r: rn, du2, keep } = stepped else {
                use_kept = false;
                continue;
            };
            it += 1;
            r = rn;
            use_kept = keep;
            let u2 = norm2_free(&model.u, &model.bc.fixed);
            measure = if u2 > 0.0 { (du2 / u2).sqrt() } else { 0.0 };
            if it == 1 {
                r0 = r0.max(r);
            }
            let rref = rref0.max(residual_norms(model).1);
            let rel = if rref > 0.0 { r / rref } else { r };
            info.residual_history.push(rel);
            last_rel = rel;
            // A kept-factor step that contracted poorly says little about the error left.
            if on_kept && !keep {
                prev_measure = f64::INFINITY;
                continue;
            }
            let done = match p.convergence {
                Convergence::Displacement { e0 } => measure < e0,
                Convergence::Residual { tol } => rel < tol,
            };
            // Round-off floor: the update stopped shrinking at a tiny size.
            let stagnant = it > 2 && measure > 0.5 * prev_measure && measure < 1e-7;
            prev_measure = measure;
            if stagnant {
                return Ok((it, rel));
            }
            if done || rel < p.residual_tol {
                return Ok((it, rel));
            }
        }
        Err(PdError::NoConvergence {
            solver: "implicit",
            iterations: it,
            load: model.load,
            // The quantity the criterion tests (the relative residual for `Residual`, not
            // the displacement change).
            measure: match p.convergence {
                Convergence::Displacement { .. } => measure,
                Convergence::Residual { .. } => last_rel,
            },
            tolerance: p.convergence.tolerance(),
        })
    }

    /// Move to load factor `lam` with a linear predictor: the prescribed
    /// increments `du_c` are imposed and the free DOFs follow
    /// `K_ff du_f = -K_fc du_c` with the tangent of the current state, so the
    /// first Newton iterate does not see bonds next to the boundary stretched
    /// by the whole increment (which would put them past `s_c`).
    pub fn predict_to(
        &mut self,
        model: &mut PdModel,
        lam: f64,
        info: &mut SolveInfo,
    ) -> Result<(), PdError> {
        let dl = lam - model.load;
        let any = model
            .bc
            .fixed
            .iter()
            .zip(&model.bc.base)
            .any(|(f, b)| (f[0] && b[0] != 0.0) || (f[1] && b[1] != 0.0));
        self.predicted = None;
        if dl == 0.0 || !any {
            model.set_load_factor(lam);
            return Ok(());
        }
        let ta = Instant::now();
        model.assemble_tangent(&mut self.tangent, TangentKind::Consistent);
        info.time_assembly_s += ta.elapsed().as_secs_f64();
        self.rhs.iter_mut().for_each(|r| *r = 0.0);
        let b = &model.bonds;
        let du: Vec<P2> = model
            .bc
            .base
            .iter()
            .map(|x| [dl * x[0], dl * x[1]])
            .collect();
        let osb = model.add_prescribed_coupling(&self.tangent.dof, &du, &mut self.rhs);
        for i in (0..model.n_nodes()).filter(|_| !osb) {
            for bb in b.row(i) {
                if model.intact[bb] == 0 {
                    continue;
                }
                let j = b.nbr[bb] as usize;
                let fj = model.bc.fixed[j];
                if !fj[0] && !fj[1] {
                    continue;
                }
                let du = [
                    if fj[0] { dl * model.bc.base[j][0] } else { 0.0 },
                    if fj[1] { dl * model.bc.base[j][1] } else { 0.0 },
                ];
                let y = [
                    b.xi[bb][0] + (model.u[j][0] - model.u[i][0]),
                    b.xi[bb][1] + (model.u[j][1] - model.u[i][1]),
                ];
                let m = crate::forces::bond_tangent_scaled(
                    model.law,
                    b.k[bb],
                    b.inv_len[bb],
                    y,
                    model.s_hist[bb],
                    crate::forces::TangentKind::Consistent,
                    crate::forces::stretch_scale(b, bb),
                );
                for p in 0..2 {
                    let d = self.tangent.dof[2 * i + p];
                    if d != usize::MAX {
                        self.rhs[d] += m[p][0] * du[0] + m[p][1] * du[1];
                    }
                }
            }
        }
        self.factor_and_solve(model, info)?;
        self.predicted = Some(lam);
        for i in 0..model.n_nodes() {
            for c in 0..2 {
                let d = self.tangent.dof[2 * i + c];
                if d != usize::MAX {
                    model.u[i][c] += self.rhs[d];
                }
            }
        }
        model.set_load_factor(lam);
        Ok(())
    }

    /// One load step at load factor `lam`: equilibrate, commit the history,
    /// and re-solve while brittle bonds break.
    pub fn load_step(
        &mut self,
        model: &mut PdModel,
        lam: f64,
        p: &ImplicitParams,
        info: &mut SolveInfo,
    ) -> Result<usize, PdError> {
        self.predict_to(model, lam, info)?;
        let mut iters = 0;
        for _ in 0..p.max_break_rounds.max(1) {
            let (it, m) = self.equilibrate(model, p, info)?;
            iters += it;
            let st = model.commit_history();
            if st.newly_broken == 0 {
                let kind = PhaseKind::Implicit;
                let record = StepRecord::of(model, lam, iters, st.max_stretch, m, kind);
                info.steps.push(record);
                return Ok(iters);
            }
        }
        Err(PdError::NoConvergence {
            solver: "implicit (bond breaking)",
            iterations: p.max_break_rounds,
            load: lam,
            measure: f64::NAN,
            tolerance: 0.0,
        })
    }
}

/// Solve by Newton-Raphson from the current state to `params.target_load`.
pub fn solve(model: &mut PdModel, params: &ImplicitParams) -> Result<SolveInfo, PdError> {
    let t0 = Instant::now();
    let mut info = SolveInfo::default();
    let mut newton = Newton::new(model)?;
    let lam0 = model.load;
    let broken0 = model.broken_bonds();
    let steps = params.steps.max(1);
    for k in 1..=steps {
        let lam = lam0 + (params.target_load - lam0) * k as f64 / steps as f64;
        info.iterations += newton.load_step(model, lam, params, &mut info)?;
    }
    let dt = t0.elapsed().as_secs_f64();
    let broken = model.broken_bonds() - broken0;
    info.finish_single_phase(PhaseKind::Implicit, lam0, params.target_load, dt, broken);
    Ok(info)
}

#[cfg(test)]
#[path = "implicit_tests.rs"]
mod tests;
