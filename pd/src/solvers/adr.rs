//! Adaptive dynamic relaxation (seed 002 Eqs. 9-15; Kilic & Madenci 2010).
//!
//! $\Lambda \ddot u + c_n \Lambda \dot u = F(u)$ with central differences and
//! $\Delta t = 1$:
//! $$\dot u^{n+1/2} = \frac{(2 - c_n\Delta t)\dot u^{n-1/2} + 2\Delta t\,\Lambda^{-1}F^n}{2 + c_n\Delta t},\quad
//!   u^{n+1} = u^n + \Delta t\,\dot u^{n+1/2}$$
//! started by $\dot u^{1/2} = \Delta t\,\Lambda^{-1}F^0/2$ (Eq. 12). The
//! fictitious density is the Gershgorin bound of the linearised stiffness,
//! $\Lambda_{ii} = \tfrac14\Delta t^2 \sum_j |K_{ij}|$ times a safety factor
//! (REFERENCES.md), and the damping comes from the local Rayleigh quotient
//! $c_n = 2\sqrt{u^T K^n u / u^T u}$ with the diagonal
//! $K^n_{ii} = -(F^n_i - F^{n-1}_i)/(\Lambda_{ii}\Delta t\,\dot u_i^{n-1/2})$
//! (Eqs. 13-14). Bonds break during the iterations (history `Update`).

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::{residual_norms, Convergence, PhaseKind, SolveInfo, StepRecord};
use crate::error::PdError;
use crate::forces::{ForceStats, History};
use crate::geometry::P2;
use crate::model::PdModel;

/// ADR parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AdrParams {
    /// Load factor to reach.
    pub target_load: f64,
    /// Number of equal load increments from the current load factor.
    pub steps: usize,
    /// `Some(n)`: exactly `n` steps per increment (loading rate per iteration,
    /// seed 000 section 3.3), converging only at the target; `None`: converge
    /// every increment.
    pub iters_per_step: Option<usize>,
    /// Convergence measure; default seed 000 Eq. 16 with `e0 = 1e-9`.
    pub convergence: Convergence,
    /// Minimum steps before convergence may be declared in a converge phase.
    pub min_iters: usize,
    /// Cap on the steps of one converge phase.
    pub max_iters: usize,
    /// Safety factor on the Gershgorin density (1 = the bound itself).
    pub safety: f64,
}

impl Default for AdrParams {
    fn default() -> Self {
        AdrParams {
            target_load: 1.0,
            steps: 1,
            iters_per_step: None,
            convergence: Convergence::default(),
            min_iters: 10,
            max_iters: 200_000,
            safety: 1.5,
        }
    }
}

/// Reusable ADR buffers (no allocation inside the iterations).
pub struct Adr {
    mass: Vec<f64>,
    vel: Vec<P2>,
    f_prev: Vec<P2>,
    fresh: bool,
    /// Steps since the last damage growth (used by the switching solver).
    pub since_growth: usize,
    /// Total steps taken with these buffers.
    pub total_iters: usize,
    /// Bond pairs broken (directed count / 2) with these buffers.
    pub broken_directed: usize,
}

/// Outcome of one ADR step.
#[derive(Clone, Copy, Debug)]
pub struct StepOut {
    /// Relative displacement change (Eq. 16).
    pub du_rel: f64,
    /// Relative force residual.
    pub res_rel: f64,
    /// Force pass statistics.
    pub stats: ForceStats,
}

impl StepOut {
    /// The measure selected by `conv` and whether it is met.
    pub fn measure(&self, conv: Convergence) -> (f64, bool) {
        match conv {
            Convergence::Displacement { e0 } => (self.du_rel, self.du_rel < e0),
            Convergence::Residual { tol } => (self.res_rel, self.res_rel < tol),
        }
    }
}

impl Adr {
    /// Buffers for `model`, with the fictitious density (safety factor `safety`).
    pub fn new(model: &PdModel, safety: f64) -> Self {
        let n = model.n_nodes();
        let b = &model.bonds;
        let mass = (0..n)
            .map(|i| {
                let (mut rx, mut ry) = (0.0, 0.0);
                for bb in b.row(i) {
                    let kl = b.k[bb] * b.inv_len[bb];
                    let ex = b.xi[bb][0] * b.inv_len[bb];
                    let ey = b.xi[bb][1] * b.inv_len[bb];
                    rx += 2.0 * kl * (ex * ex + (ex * ey).abs());
                    ry += 2.0 * kl * (ey * ey + (ex * ey).abs());
                }
                (0.25 * safety * rx.max(ry)).max(f64::MIN_POSITIVE)
            })
            .collect();
        Adr {
            mass,
            vel: vec![[0.0; 2]; n],
            f_prev: vec![[0.0; 2]; n],
            fresh: true,
            since_growth: 0,
            total_iters: 0,
            broken_directed: 0,
        }
    }

    /// Restart from rest (zero velocity) at the current state.
    pub fn reset(&mut self) {
        self.fresh = true;
        self.vel.iter_mut().for_each(|v| *v = [0.0; 2]);
    }

    /// One ADR step at the model's current load factor.
    pub fn step(&mut self, model: &mut PdModel) -> StepOut {
        let stats = model.compute_forces(History::Update);
        self.total_iters += 1;
        self.broken_directed += stats.newly_broken;
        if stats.growing > 0 {
            self.since_growth = 0;
        } else {
            self.since_growth += 1;
        }
        let (r, rref) = residual_norms(model);
        let lam = model.load;
        let fixed = &model.bc.fixed;
        let body = &model.bc.body;
        // Damping from the local Rayleigh quotient (Eqs. 13-14).
        let mut c = 0.0;
        if !self.fresh {
            let (mut num, mut den) = (0.0, 0.0);
            for i in 0..self.vel.len() {
                for d in 0..2 {
                    if fixed[i][d] {
                        continue;
                    }
                    let v = self.vel[i][d];
                    let ui = model.u[i][d];
                    den += ui * ui;
                    if v != 0.0 {
                        let f = model.force[i][d] + lam * body[i][d];
                        let kii = -(f - self.f_prev[i][d]) / (self.mass[i] * v);
                        num += ui * kii * ui;
                    }
                }
            }
            if num > 0.0 && den > 0.0 {
                c = (2.0 * (num / den).sqrt()).min(1.9);
            }
        }
        let (mut du2, mut u2) = (0.0, 0.0);
        for i in 0..self.vel.len() {
            for d in 0..2 {
                if fixed[i][d] {
                    continue;
                }
                let f = model.force[i][d] + lam * body[i][d];
                let a = f / self.mass[i];
                let v = if self.fresh {
                    0.5 * a
                } else {
                    ((2.0 - c) * self.vel[i][d] + 2.0 * a) / (2.0 + c)
                };
                self.vel[i][d] = v;
                self.f_prev[i][d] = f;
                u2 += model.u[i][d] * model.u[i][d];
                model.u[i][d] += v;
                du2 += v * v;
            }
        }
        self.fresh = false;
        let du_rel = if u2 > 0.0 {
            (du2 / u2).sqrt()
        } else {
            f64::INFINITY
        };
        let res_rel = if rref > 0.0 {
            r / rref
        } else if r == 0.0 {
            0.0
        } else {
            f64::INFINITY
        };
        StepOut {
            du_rel,
            res_rel,
            stats,
        }
    }

    /// Iterate at the current load until `conv` is met (after `min_iters`),
    /// or fail after `max_iters`. Returns (steps, final measure).
    pub fn converge(
        &mut self,
        model: &mut PdModel,
        conv: Convergence,
        min_iters: usize,
        max_iters: usize,
        history: &mut Vec<f64>,
    ) -> Result<(usize, f64, ForceStats), PdError> {
        let mut best = f64::INFINITY;
        let mut last = None;
        for it in 1..=max_iters {
            let out = self.step(model);
            let (m, ok) = out.measure(conv);
            if m.is_nan() {
                return Err(PdError::NonFinite {
                    solver: "adr",
                    iteration: it,
                    load: model.load,
                });
            }
            if model
                .u
                .iter()
                .any(|x| !x[0].is_finite() || !x[1].is_finite())
            {
                return Err(PdError::NonFinite {
                    solver: "adr",
                    iteration: it,
                    load: model.load,
                });
            }
            if it > 100 {
                best = best.min(out.res_rel);
                if out.res_rel > 1e12 * best.max(1e-300) && out.res_rel > 1.0 {
                    return Err(PdError::Diverged {
                        solver: "adr",
                        iteration: it,
                        load: model.load,
                        residual: out.res_rel,
                        initial: best,
                    });
                }
            }
            if it % 100 == 0 {
                history.push(m);
            }
            last = Some((m, out.stats));
            if ok && it >= min_iters {
                history.push(m);
                return Ok((it, m, out.stats));
            }
        }
        let (m, _) = last.unwrap_or((f64::NAN, ForceStats::default()));
        Err(PdError::NoConvergence {
            solver: "adr",
            iterations: max_iters,
            load: model.load,
            measure: m,
            tolerance: match conv {
                Convergence::Displacement { e0 } => e0,
                Convergence::Residual { tol } => tol,
            },
        })
    }
}

/// Solve by ADR from the model's current state to `params.target_load`.
pub fn solve(model: &mut PdModel, params: &AdrParams) -> Result<SolveInfo, PdError> {
    let t0 = Instant::now();
    let mut info = SolveInfo::default();
    let mut adr = Adr::new(model, params.safety);
    let lam0 = model.load;
    let steps = params.steps.max(1);
    let broken0 = model.broken_bonds();
    for k in 1..=steps {
        let lam = lam0 + (params.target_load - lam0) * k as f64 / steps as f64;
        model.set_load_factor(lam);
        let (iters, m, st) = match params.iters_per_step {
            Some(n) if k < steps => {
                let mut out = None;
                for _ in 0..n.max(1) {
                    out = Some(adr.step(model));
                }
                let o = out.unwrap();
                (n.max(1), o.measure(params.convergence).0, o.stats)
            }
            Some(n) => {
                for _ in 0..n.max(1) {
                    adr.step(model);
                }
                let (it, m, st) = adr.converge(
                    model,
                    params.convergence,
                    params.min_iters,
                    params.max_iters,
                    &mut info.residual_history,
                )?;
                (it + n.max(1), m, st)
            }
            None => adr.converge(
                model,
                params.convergence,
                params.min_iters,
                params.max_iters,
                &mut info.residual_history,
            )?,
        };
        info.iterations += iters;
        if params.iters_per_step.is_none() || k == steps {
            info.steps.push(StepRecord {
                load: lam,
                iterations: iters,
                broken_bonds: model.broken_bonds(),
                max_stretch: st.max_stretch,
                measure: m,
                kind: PhaseKind::Explicit,
            });
        }
    }
    let dt = t0.elapsed().as_secs_f64();
    info.push_phase(
        PhaseKind::Explicit,
        lam0,
        params.target_load,
        info.iterations,
        dt,
    );
    info.final_load = params.target_load;
    info.bonds_broken = model.broken_bonds() - broken0;
    info.wall_time_s = dt;
    Ok(info)
}
