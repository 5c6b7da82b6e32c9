//! Implicit Newton-Raphson on the full nonlinear equilibrium (seed 000
//! section 2).
//!
//! Each iteration solves $K_m \Delta u_m = -E(u_m)$ (Eq. 5) over the free DOFs
//! with the analytic tangent of Eqs. 8-10 and 14-15 ([`crate::tangent`]),
//! prescribed DOFs removed (section 2.3). The bond history is frozen during
//! the iterations and committed once a step converges; brittle bonds that
//! pass `s0` then break and the step is re-solved until no bond breaks.
//! Convergence: Eq. 16 on the Newton update, or the relative residual
//! (checked before factorising, which saves the last solve). A backtracking
//! line search halves the update while the residual grows; NaN, a residual
//! growing past `1e6` times its start, or the iteration cap are errors.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{norm2_free, residual_norms, Convergence, PhaseKind, SolveInfo, StepRecord};
use crate::error::PdError;
use crate::forces::{History, TangentKind};
use crate::geometry::P2;
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
    /// Newton iteration cap per solve.
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

/// Reusable Newton buffers: tangent pattern, symbolic factorisation, vectors.
pub struct Newton {
    /// Tangent pattern and values.
    pub tangent: Tangent,
    rhs: Vec<f64>,
    u_save: Vec<P2>,
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
        })
    }

    /// Newton iterations to equilibrium at the model's current load (history
    /// frozen). Returns (iterations, final measure).
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
        for it in 1..=p.max_iters {
            let rref = rref0.max(residual_norms(model).1);
            if !r.is_finite() {
                return Err(PdError::NonFinite {
                    solver: "implicit",
                    iteration: it,
                    load: model.load,
                });
            }
            let rel = if rref > 0.0 { r / rref } else { r };
            if rel < p.residual_tol || r == 0.0 {
                info.residual_history.push(rel);
                return Ok((it - 1, rel));
            }
            if r > 1e6 * r0.max(f64::MIN_POSITIVE) {
                return Err(PdError::Diverged {
                    solver: "implicit",
                    iteration: it,
                    load: model.load,
                    residual: r,
                    initial: r0,
                });
            }
            let ta = Instant::now();
            model.assemble_tangent(&mut self.tangent, TangentKind::Consistent);
            let tf = Instant::now();
            info.time_assembly_s += (tf - ta).as_secs_f64();
            // Right-hand side: residual F + lambda b at the free DOFs.
            let lam = model.load;
            for i in 0..model.n_nodes() {
                for c in 0..2 {
                    let d = self.tangent.dof[2 * i + c];
                    if d != usize::MAX {
                        self.rhs[d] = model.force[i][c] + lam * model.bc.body[i][c];
                    }
                }
            }
            let fact = self.tangent.solve(&mut self.rhs)?;
            info.time_factorization_s += tf.elapsed().as_secs_f64();
            info.factorizations += 1;
            if fact == Factorization::Lu {
                info.lu_fallbacks += 1;
            }
            // Update with backtracking while the residual grows.
            self.u_save.copy_from_slice(&model.u);
            let mut alpha = 1.0;
            let mut du2 = 0.0;
            for _ in 0..6 {
                du2 = 0.0;
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
                model.compute_forces(History::Frozen);
                let (rn, _) = residual_norms(model);
                if rn.is_finite() && (rn <= 1.5 * r || alpha < 0.05) {
                    r = rn;
                    break;
                }
                alpha *= 0.5;
            }
            let u2 = norm2_free(&model.u, &model.bc.fixed);
            measure = if u2 > 0.0 { (du2 / u2).sqrt() } else { 0.0 };
            if it == 1 {
                r0 = r0.max(r);
            }
            let rref = rref0.max(residual_norms(model).1);
            let rel = if rref > 0.0 { r / rref } else { r };
            info.residual_history.push(rel);
            last_rel = rel;
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
            iterations: p.max_iters,
            load: model.load,
            // The quantity the criterion tests (the relative residual for `Residual`, not
            // the displacement change).
            measure: match p.convergence {
                Convergence::Displacement { .. } => measure,
                Convergence::Residual { .. } => last_rel,
            },
            tolerance: match p.convergence {
                Convergence::Displacement { e0 } => e0,
                Convergence::Residual { tol } => tol,
            },
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
        let tf = Instant::now();
        let fact = self.tangent.solve(&mut self.rhs)?;
        info.time_factorization_s += tf.elapsed().as_secs_f64();
        info.factorizations += 1;
        if fact == Factorization::Lu {
            info.lu_fallbacks += 1;
        }
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
