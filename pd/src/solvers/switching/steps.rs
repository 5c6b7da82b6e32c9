//! The switching loop (`Switcher::run`): the solver state, the switches between
//! elastic steps and damage increments, and the elastic Newton steps.

use std::time::Instant;

use super::{elastic_fraction, DamageSolver, Mode, Rejection, Switcher, SwitchingParams};
use crate::error::PdError;
use crate::forces::{ForceStats, History};
use crate::model::{ModelState, PdModel};
use crate::solvers::adr::Adr;
use crate::solvers::implicit::{ImplicitParams, Newton};
use crate::solvers::limit::RampEvent;
use crate::solvers::secant::{SecantParams, SecantSolver};
use crate::solvers::{PhaseKind, SolveInfo, StepRecord, SwitchPoint};

impl<'p> Switcher<'p> {
    pub(super) fn new(model: &PdModel, p: &'p SwitchingParams) -> Result<Self, PdError> {
        let mut newton = Newton::new(model)?;
        // A tangent that is not positive definite means softening: leave
        // that step to the damage increments instead of an LU solve.
        newton.tangent.allow_lu = false;
        let secant = SecantSolver::new(
            model,
            newton.tangent.n_free,
            p.max_secant_columns,
            p.anderson_depth,
        );
        let mut adr = Adr::new(model, p.safety);
        let growth_tol = p.growth_tol * model.law().softening_range();
        if !p.break_during_iterations {
            adr.history = History::Secant;
            adr.growth_tol = growth_tol;
        }
        let n_inc = p.increments();
        Ok(Switcher {
            p,
            ip: ImplicitParams {
                target_load: p.target_load,
                steps: p.implicit_steps,
                convergence: p.convergence,
                max_iters: p.max_newton_iters,
                ..Default::default()
            },
            sp: SecantParams {
                convergence: p.convergence,
                residual_tol: 1e-10,
                max_iters: p.max_secant_iters,
                max_columns: p.max_secant_columns,
                anderson_depth: p.anderson_depth,
                refactor_contraction: crate::solvers::secant::CONTRACTION_REFACTOR,
                max_refactors: None,
            },
            newton,
            secant,
            adr,
            saved: ModelState::default(),
            info: SolveInfo::default(),
            lam0: model.load,
            n_inc,
            m_max: n_inc / p.implicit_steps.max(1),
            growth_tol,
            adr_warm: false,
        })
    }

    /// Load factor after `k` increments.
    pub(super) fn load_at(&self, k: usize) -> f64 {
        if k >= self.n_inc {
            self.p.target_load
        } else {
            self.lam0 + (self.p.target_load - self.lam0) * k as f64 / self.n_inc as f64
        }
    }

    /// The switching loop from increment 0 to the last; `observe` hears the load factor
    /// of every accepted elastic step and damage increment, and the progress of long ADR
    /// increments.
    pub(super) fn run(
        &mut self,
        model: &mut PdModel,
        observe: &mut dyn FnMut(&RampEvent),
    ) -> Result<(), PdError> {
        let mut mode = Mode::Elastic;
        let mut k = 0usize;
        let mut m = self.m_max;
        while k < self.n_inc {
            match mode {
                Mode::Elastic => {
                    let m_eff = m.min(self.n_inc - k);
                    match self.elastic_step(model, k, m_eff) {
                        Ok(()) => {
                            k += m_eff;
                            observe(&RampEvent::Converged {
                                load: self.load_at(k),
                            });
                        }
                        Err(rejection) => {
                            // Retry with the increments that stay elastic
                            // by linear interpolation (at most m - 1);
                            // none: the next increment damages bonds.
                            let safe = (rejection.elastic_fraction * m_eff as f64).floor();
                            m = (safe as usize).min(m_eff - 1);
                            if m == 0 {
                                mode = Mode::Damage;
                                let to = self.damage_kind();
                                self.switch(to, self.load_at(k), rejection.reason);
                            }
                        }
                    }
                }
                Mode::Damage => {
                    let grew = self
                        .damage_increment(model, k, &mut |e| observe(&RampEvent::Iterating(*e)))?;
                    k += 1;
                    observe(&RampEvent::Converged {
                        load: self.load_at(k),
                    });
                    if !grew && k < self.n_inc {
                        mode = Mode::Elastic;
                        m = self.m_max;
                        self.switch(
                            PhaseKind::Implicit,
                            self.load_at(k),
                            "no bond's damage grew during the last increment".into(),
                        );
                    }
                }
            }
        }
        Ok(())
    }

    /// Whether damage increments use the secant rounds (else ADR).
    pub(super) fn secant_enabled(&self) -> bool {
        self.p.damage_solver == DamageSolver::Secant && !self.p.break_during_iterations
    }

    /// Phase kind of the damage increments.
    fn damage_kind(&self) -> PhaseKind {
        if self.secant_enabled() {
            PhaseKind::Secant
        } else {
            PhaseKind::Explicit
        }
    }

    pub(super) fn switch(&mut self, to: PhaseKind, load: f64, reason: String) {
        self.info.switch_points.push(SwitchPoint {
            load,
            iteration: self.info.iterations,
            to,
            reason,
        });
    }

    /// One Newton step over `m` increments from increment `k`, accepted only
    /// if no bond's damage grows; otherwise rolled back.
    fn elastic_step(&mut self, model: &mut PdModel, k: usize, m: usize) -> Result<(), Rejection> {
        let ts = Instant::now();
        let (lam, next) = (self.load_at(k), self.load_at(k + m));
        self.adr_warm = false;
        // The Newton solves below replace the factor the secant solver uses.
        self.secant.invalidate();
        model.save_into(&mut self.saved);
        let it0 = self.info.iterations;
        // An elastic step may not damage any bond (seed 000: the implicit
        // phase ends at s_m). The linear predictor already shows whether
        // damage would start: then Newton is not even tried.
        let damaging = |st: ForceStats| st.growing > 0 || st.max_stretch.is_nan();
        let info = &mut self.info;
        let res = self.newton.predict_to(model, next, info).and_then(|_| {
            if damaging(model.stretch_stats()) {
                Ok(None)
            } else {
                self.newton.equilibrate(model, &self.ip, info).map(Some)
            }
        });
        let onset = model.law().damage_onset();
        let outcome = match res {
            Ok(Some((it, meas))) => {
                info.iterations += it;
                if damaging(model.stretch_stats()) {
                    Err(Rejection {
                        reason: format!(
                            "a bond passes the damage onset {onset} within {m} increments, at load {next}"
                        ),
                        elastic_fraction: elastic_fraction(model, &self.saved.u),
                    })
                } else {
                    Ok(meas)
                }
            }
            Ok(None) => Err(Rejection {
                reason: format!(
                    "the predictor passes the damage onset {onset} within {m} increments, at load {next}"
                ),
                elastic_fraction: elastic_fraction(model, &self.saved.u),
            }),
            Err(e) => Err(Rejection {
                reason: format!("Newton failed at load {next}: {e}"),
                elastic_fraction: 0.5,
            }),
        };
        let iters = info.iterations - it0;
        match outcome {
            Ok(meas) => {
                let st = model.commit_history();
                info.steps.push(StepRecord {
                    load: next,
                    iterations: iters,
                    broken_bonds: model.broken_bonds(),
                    max_stretch: st.max_stretch,
                    measure: meas,
                    kind: PhaseKind::Implicit,
                    resultants: model.bc_resultants(),
                });
                info.push_phase(
                    PhaseKind::Implicit,
                    lam,
                    next,
                    iters,
                    ts.elapsed().as_secs_f64(),
                );
                Ok(())
            }
            Err(rejection) => {
                model.restore(&self.saved);
                info.push_phase(
                    PhaseKind::Implicit,
                    lam,
                    lam,
                    iters,
                    ts.elapsed().as_secs_f64(),
                );
                Err(rejection)
            }
        }
    }
}
