//! Explicit-implicit switching (seed 000 section 4, Figs. 10-11).
//!
//! Implicit load steps of size $\Delta u_i = (\lambda_{target}-\lambda_0)/N_i$
//! while no intact bond would pass the damage onset (`s_m`, or `s0` for
//! brittle bonds) beyond its history. A step that would is rolled back and
//! the solver switches to ADR, which carries the load in steps of
//! $\Delta u_e = (\lambda_{target}-\lambda)/N_e$ (a fixed number of ADR
//! iterations per step: the seed's loading rate). Once no bond has been
//! damaged for `quiet_iters` ADR iterations (and the load has passed the
//! point where damage was detected), the solver returns to implicit steps.
//! At the target load ADR converges fully, then a final implicit polish
//! runs if it causes no new damage. Both phases use the same convergence
//! measure; every switch is recorded.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::adr::Adr;
use super::implicit::{ImplicitParams, Newton};
use super::{Convergence, PhaseKind, SolveInfo, StepRecord, SwitchPoint};
use crate::error::PdError;
use crate::model::{ModelState, PdModel};

/// Switching-solver parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SwitchingParams {
    /// Load factor to reach.
    pub target_load: f64,
    /// `N_i`: implicit steps over the whole load (seed 000: 3 or 5).
    pub implicit_steps: usize,
    /// `N_e`: explicit steps over the load remaining at the first switch
    /// (seed 000: 180 or 1000).
    pub explicit_steps: usize,
    /// ADR iterations per explicit step (1 = the seed's loading rate).
    pub iters_per_explicit_step: usize,
    /// ADR iterations without damage growth before returning to implicit.
    pub quiet_iters: usize,
    /// Convergence measure of both phases (seed 000 Eq. 16, `e0 = 1e-9`).
    pub convergence: Convergence,
    /// ADR density safety factor.
    pub safety: f64,
    /// ADR iteration cap for the final convergence.
    pub max_adr_iters: usize,
    /// Newton iteration cap per step.
    pub max_newton_iters: usize,
}

impl Default for SwitchingParams {
    fn default() -> Self {
        SwitchingParams {
            target_load: 1.0,
            implicit_steps: 3,
            explicit_steps: 180,
            iters_per_explicit_step: 1,
            quiet_iters: 2000,
            convergence: Convergence::default(),
            safety: 1.5,
            max_adr_iters: 200_000,
            max_newton_iters: 15,
        }
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
    let mut adr = Adr::new(model, p.safety);
    let ip = ImplicitParams {
        target_load: target,
        steps: p.implicit_steps,
        convergence: p.convergence,
        max_iters: p.max_newton_iters,
        ..Default::default()
    };
    let d_imp = (target - lam0) / p.implicit_steps.max(1) as f64;
    let mut d_exp: Option<f64> = None;
    let mut saved = ModelState::default();
    let mut phase = PhaseKind::Implicit;
    let mut lam = lam0;
    let mut detect_load = lam0;
    let eps = 1e-12 * (target - lam0).abs().max(1e-300);
    let onset = model.law.damage_onset();
    while (target - lam).abs() > eps {
        match phase {
            PhaseKind::Implicit => {
                let ts = Instant::now();
                let next = if (target - lam).abs() <= d_imp.abs() * (1.0 + 1e-9) {
                    target
                } else {
                    lam + d_imp
                };
                model.save_into(&mut saved);
                let it0 = info.iterations;
                // The linear predictor already shows whether damage would
                // start: then Newton is not even tried.
                let res = newton.predict_to(model, next, &mut info).and_then(|_| {
                    if model.stretch_stats().growing > 0 {
                        Ok((0, f64::NAN))
                    } else {
                        newton.equilibrate(model, &ip, &mut info)
                    }
                });
                let growing = match &res {
                    Ok((it, _)) => {
                        info.iterations += it;
                        let st = model.stretch_stats();
                        st.growing > 0 || (onset.is_finite() && st.max_stretch.is_nan())
                    }
                    Err(_) => true,
                };
                if growing {
                    model.restore(&saved);
                    detect_load = next;
                    let reason = match res {
                        Ok(_) => {
                            format!("a bond would pass the damage onset {onset} at load {next}")
                        }
                        Err(e) => format!("Newton failed at load {next}: {e}"),
                    };
                    info.push_phase(
                        PhaseKind::Implicit,
                        lam,
                        lam,
                        info.iterations - it0,
                        ts.elapsed().as_secs_f64(),
                    );
                    phase = PhaseKind::Explicit;
                    info.switch_points.push(SwitchPoint {
                        load: lam,
                        iteration: info.iterations,
                        to: PhaseKind::Explicit,
                        reason,
                    });
                    if d_exp.is_none() {
                        d_exp = Some((target - lam) / p.explicit_steps.max(1) as f64);
                    }
                    adr.reset();
                } else {
                    let (_, m) = res.unwrap();
                    let st = model.commit_history();
                    info.steps.push(StepRecord {
                        load: next,
                        iterations: info.iterations - it0,
                        broken_bonds: model.broken_bonds(),
                        max_stretch: st.max_stretch,
                        measure: m,
                        kind: PhaseKind::Implicit,
                    });
                    info.push_phase(
                        PhaseKind::Implicit,
                        lam,
                        next,
                        info.iterations - it0,
                        ts.elapsed().as_secs_f64(),
                    );
                    lam = next;
                }
            }
            PhaseKind::Explicit => {
                let ts = Instant::now();
                let de = d_exp.unwrap();
                let it0 = info.iterations;
                let start = lam;
                adr.since_growth = 0;
                let mut back = false;
                while (target - lam).abs() > eps {
                    lam = if (target - lam).abs() <= de.abs() * (1.0 + 1e-9) {
                        target
                    } else {
                        lam + de
                    };
                    model.set_load_factor(lam);
                    let mut last = None;
                    for _ in 0..p.iters_per_explicit_step.max(1) {
                        last = Some(adr.step(model));
                    }
                    info.iterations += p.iters_per_explicit_step.max(1);
                    let o = last.unwrap();
                    if !o.du_rel.is_finite() && o.du_rel.is_nan() {
                        return Err(PdError::NonFinite {
                            solver: "switching/adr",
                            iteration: info.iterations,
                            load: lam,
                        });
                    }
                    if (lam - detect_load) * de.signum() >= 0.0
                        && adr.since_growth >= p.quiet_iters
                        && (target - lam).abs() > eps
                    {
                        back = true;
                        break;
                    }
                }
                if back {
                    // Settle the state at this load before Newton takes over.
                    let (it, m, st) = adr.converge(
                        model,
                        p.convergence,
                        10,
                        p.max_adr_iters,
                        &mut info.residual_history,
                    )?;
                    info.iterations += it;
                    info.steps.push(StepRecord {
                        load: lam,
                        iterations: info.iterations - it0,
                        broken_bonds: model.broken_bonds(),
                        max_stretch: st.max_stretch,
                        measure: m,
                        kind: PhaseKind::Explicit,
                    });
                    info.push_phase(
                        PhaseKind::Explicit,
                        start,
                        lam,
                        info.iterations - it0,
                        ts.elapsed().as_secs_f64(),
                    );
                    info.switch_points.push(SwitchPoint {
                        load: lam,
                        iteration: info.iterations,
                        to: PhaseKind::Implicit,
                        reason: format!("no bond damaged for {} ADR iterations", adr.since_growth),
                    });
                    phase = PhaseKind::Implicit;
                } else {
                    let (it, m, st) = adr.converge(
                        model,
                        p.convergence,
                        10,
                        p.max_adr_iters,
                        &mut info.residual_history,
                    )?;
                    info.iterations += it;
                    info.steps.push(StepRecord {
                        load: lam,
                        iterations: info.iterations - it0,
                        broken_bonds: model.broken_bonds(),
                        max_stretch: st.max_stretch,
                        measure: m,
                        kind: PhaseKind::Explicit,
                    });
                    info.push_phase(
                        PhaseKind::Explicit,
                        start,
                        lam,
                        info.iterations - it0,
                        ts.elapsed().as_secs_f64(),
                    );
                    // Final implicit polish at the target, kept only if it
                    // damages nothing.
                    let ts = Instant::now();
                    model.save_into(&mut saved);
                    let it1 = info.iterations;
                    let ok = match newton.equilibrate(model, &ip, &mut info) {
                        Ok((it, _)) => {
                            info.iterations += it;
                            model.stretch_stats().growing == 0
                        }
                        Err(_) => false,
                    };
                    if !ok {
                        model.restore(&saved);
                    } else {
                        info.switch_points.push(SwitchPoint {
                            load: lam,
                            iteration: it1,
                            to: PhaseKind::Implicit,
                            reason: "final implicit equilibrium at the target".into(),
                        });
                    }
                    info.push_phase(
                        PhaseKind::Implicit,
                        lam,
                        lam,
                        info.iterations - it1,
                        ts.elapsed().as_secs_f64(),
                    );
                }
            }
        }
    }
    info.final_load = target;
    info.bonds_broken = model.broken_bonds() - broken0;
    info.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(info)
}
