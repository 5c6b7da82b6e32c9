//! Explicit-implicit switching (seed 000 section 4, Figs. 10-11).
//!
//! The load path $[\lambda_0, \lambda_{target}]$ is cut into $N_e$ equal
//! explicit increments $\Delta\lambda_e = (\lambda_{target}-\lambda_0)/N_e$
//! (the load steps of the pure-ADR reference, [`super::adr::solve`] with
//! `steps = N_e`). Every equilibrium the solver reaches lies on this grid,
//! so the two solvers can be compared state by state.
//!
//! - **Implicit** (Newton, [`super::implicit`]): a step of
//!   $m\,\Delta\lambda_e$ with $m \le m_{max} = N_e/N_i$, i.e. at most the
//!   seed's $\Delta u_i = u_{total}/N_i$. The linear predictor and then the
//!   converged state are checked: if any intact bond would pass the damage
//!   onset (`s_m`, or `s0` for brittle bonds) beyond its history, the step
//!   is rolled back and retried with $m/2$. While no bond is damaged the
//!   response is elastic with a fixed bond state, so a converged implicit
//!   step reaches the same equilibrium as the ADR increments it replaces.
//! - **Explicit** (ADR, [`super::adr`]): when even $m = 1$ would damage a
//!   bond, one increment $\Delta\lambda_e$ is carried by ADR, converged to
//!   the same measure as the implicit steps (seed 000 Eq. 16 by default)
//!   with the secant re-commit loop of [`super::adr`] (bonds break only at
//!   converged states). After an increment in which no bond broke, the
//!   solver tries implicit steps of $m_{max}$ increments again (halving on
//!   damage; a rejected try costs one predictor solve). Newton runs with
//!   Cholesky only: a tangent that is not positive definite (softening)
//!   rejects the implicit step.
//!
//! Differences from the seed: the seed uses $N_e$ increments over the load
//! remaining at the switch and a fixed loading rate (one ADR iteration per
//! increment, convergence only at the end); here $N_e$ counts increments
//! over the whole load and every increment is converged, so the switching
//! solver and the pure-ADR reference follow the same quasi-static path
//! (the seed's fast loading rate makes the damage depend on the rate,
//! seed 000 section 3.3). Every switch is recorded.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::adr::Adr;
use super::implicit::{ImplicitParams, Newton};
use super::{Convergence, PhaseKind, SolveInfo, StepRecord, SwitchPoint};
use crate::error::PdError;
use crate::forces::History;
use crate::model::{ModelState, PdModel};

/// Switching-solver parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SwitchingParams {
    /// Load factor to reach.
    pub target_load: f64,
    /// `N_i`: the largest implicit step is `(target - lambda_0) / N_i`
    /// (seed 000: 3 or 5).
    pub implicit_steps: usize,
    /// `N_e`: explicit increments over the whole load; the pure-ADR
    /// reference with `steps = N_e` takes the same increments. Rounded up
    /// to a multiple of `N_i`.
    pub explicit_steps: usize,
    /// Minimum ADR iterations per explicit increment before convergence
    /// may be declared.
    pub iters_per_explicit_step: usize,
    /// Convergence measure of both phases (seed 000 Eq. 16, `e0 = 1e-9`).
    pub convergence: Convergence,
    /// ADR density safety factor.
    pub safety: f64,
    /// ADR iteration cap per explicit increment.
    pub max_adr_iters: usize,
    /// Newton iteration cap per step.
    pub max_newton_iters: usize,
    /// ADR: break bonds inside the iterations instead of at converged
    /// states (see [`super::adr`]); keep equal to the reference's setting.
    pub break_during_iterations: bool,
    /// Degrading bonds: an equilibrium is settled once no stretch exceeds
    /// its committed history by more than `growth_tol (s_c - s_m)`.
    pub growth_tol: f64,
    /// ADR re-convergence rounds per increment after bonds broke.
    pub max_break_rounds: usize,
}

impl Default for SwitchingParams {
    fn default() -> Self {
        SwitchingParams {
            target_load: 1.0,
            implicit_steps: 3,
            explicit_steps: 180,
            iters_per_explicit_step: 10,
            convergence: Convergence::default(),
            safety: 1.5,
            max_adr_iters: 200_000,
            max_newton_iters: 15,
            break_during_iterations: false,
            growth_tol: 1e-3,
            max_break_rounds: 100,
        }
    }
}

impl SwitchingParams {
    /// The number of explicit increments actually used: `explicit_steps`
    /// rounded up to a multiple of `implicit_steps` (both at least 1).
    pub fn increments(&self) -> usize {
        let ni = self.implicit_steps.max(1);
        self.explicit_steps.max(1).div_ceil(ni) * ni
    }
}

/// Solve with the explicit-implicit switch from the current state.
pub fn solve(model: &mut PdModel, p: &SwitchingParams) -> Result<SolveInfo, PdError> {
    let t0 = Instant::now();
    let mut info = SolveInfo::default();
    let target = p.target_load;
    let lam0 = model.load;
    let broken0 = model.broken_bonds();
    let mut newton = Newton::new(model)?;
    // A tangent that is not positive definite means softening: leave that
    // step to ADR instead of an LU solve.
    newton.tangent.allow_lu = false;
    let mut adr = Adr::new(model, p.safety);
    if !p.break_during_iterations {
        adr.history = History::Secant;
        adr.growth_tol = p.growth_tol * model.law().softening_range();
    }
    let ip = ImplicitParams {
        target_load: target,
        steps: p.implicit_steps,
        convergence: p.convergence,
        max_iters: p.max_newton_iters,
        ..Default::default()
    };
    let n_inc = p.increments();
    let m_max = n_inc / p.implicit_steps.max(1);
    let load_at = |k: usize| {
        if k >= n_inc {
            target
        } else {
            lam0 + (target - lam0) * k as f64 / n_inc as f64
        }
    };
    let onset = model.law.damage_onset();
    let mut saved = ModelState::default();
    let mut phase = PhaseKind::Implicit;
    let mut k = 0usize;
    let mut m = m_max;
    while k < n_inc {
        let lam = load_at(k);
        match phase {
            PhaseKind::Implicit => {
                let ts = Instant::now();
                let m_eff = m.min(n_inc - k);
                let next = load_at(k + m_eff);
                model.save_into(&mut saved);
                let it0 = info.iterations;
                // The linear predictor already shows whether damage would
                // start: then Newton is not even tried.
                // An implicit step may not damage any bond (seed 000: the
                // implicit phase ends at s_m). Letting Newton degrade bonds
                // in large steps after the first failure was tried: it
                // changes the damage history of bonds that load and unload
                // within a step (measured 4 of 330 pairs different on the
                // 20 x 20 plate with a hole, profile 3.4 % off).
                let bad = |st: crate::forces::ForceStats| st.growing > 0 || st.max_stretch.is_nan();
                let res = newton.predict_to(model, next, &mut info).and_then(|_| {
                    if bad(model.stretch_stats()) {
                        Ok((0, f64::NAN))
                    } else {
                        newton.equilibrate(model, &ip, &mut info)
                    }
                });
                let growing = match &res {
                    Ok((it, _)) => {
                        info.iterations += it;
                        bad(model.stretch_stats())
                    }
                    Err(_) => true,
                };
                if growing {
                    model.restore(&saved);
                    info.push_phase(
                        PhaseKind::Implicit,
                        lam,
                        lam,
                        info.iterations - it0,
                        ts.elapsed().as_secs_f64(),
                    );
                    if m_eff > 1 {
                        m = m_eff / 2;
                        continue;
                    }
                    let reason = match res {
                        Ok(_) => format!(
                            "a bond would pass the damage onset {onset} within one increment, at load {next}"
                        ),
                        Err(e) => format!("Newton failed at load {next}: {e}"),
                    };
                    phase = PhaseKind::Explicit;
                    info.switch_points.push(SwitchPoint {
                        load: lam,
                        iteration: info.iterations,
                        to: PhaseKind::Explicit,
                        reason,
                    });
                    adr.reset();
                } else {
                    let (_, meas) = res.unwrap();
                    let st = model.commit_history();
                    info.steps.push(StepRecord {
                        load: next,
                        iterations: info.iterations - it0,
                        broken_bonds: model.broken_bonds(),
                        max_stretch: st.max_stretch,
                        measure: meas,
                        kind: PhaseKind::Implicit,
                    });
                    info.push_phase(
                        PhaseKind::Implicit,
                        lam,
                        next,
                        info.iterations - it0,
                        ts.elapsed().as_secs_f64(),
                    );
                    k += m_eff;
                }
            }
            PhaseKind::Explicit => {
                let ts = Instant::now();
                let next = load_at(k + 1);
                model.set_load_factor(next);
                let broken_before = model.broken_bonds();
                let (it, meas, st, _) = adr.equilibrate(
                    model,
                    p.convergence,
                    p.iters_per_explicit_step.max(1),
                    p.max_adr_iters,
                    p.max_break_rounds,
                    &mut info.residual_history,
                )?;
                info.iterations += it;
                info.steps.push(StepRecord {
                    load: next,
                    iterations: it,
                    broken_bonds: model.broken_bonds(),
                    max_stretch: st.max_stretch,
                    measure: meas,
                    kind: PhaseKind::Explicit,
                });
                info.push_phase(
                    PhaseKind::Explicit,
                    lam,
                    next,
                    it,
                    ts.elapsed().as_secs_f64(),
                );
                k += 1;
                if model.broken_bonds() == broken_before && k < n_inc {
                    phase = PhaseKind::Implicit;
                    m = m_max;
                    info.switch_points.push(SwitchPoint {
                        load: next,
                        iteration: info.iterations,
                        to: PhaseKind::Implicit,
                        reason: "no bond broke during the last ADR increment".into(),
                    });
                }
            }
        }
    }
    info.final_load = target;
    info.bonds_broken = model.broken_bonds() - broken0;
    info.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(info)
}
