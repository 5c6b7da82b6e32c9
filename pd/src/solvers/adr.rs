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
//! (Eqs. 13-14).
//!
//! Bond history: by default (`break_during_iterations = false`) the bonds
//! act with their committed secant factor $T(s_{hist})$ during the
//! iterations of a load step ([`History::Secant`]), so each equilibrium
//! search is a stable elastic problem with a unique solution. At the
//! converged state the history is committed (every bond past `s0`/`s_c`
//! breaks at once, Jacobi-style; $s_{hist}$ rises to the converged
//! stretch), and the step is re-converged until no bond broke and no
//! stretch exceeds its history by more than `growth_tol (s_c - s_m)`: a
//! monotone fixed-point iteration whose limit satisfies $s = s_{hist}$ for
//! every loading bond, i.e. the softening equilibrium of seed 000 Eq. 12.
//! The damage then depends only on the sequence of load steps, not on the
//! transient overshoot of the fictitious dynamics (seed 000 section 3.3
//! shows how that overshoot makes explicit results rate dependent), so ADR
//! and the switching solver agree bond for bond. With
//! `break_during_iterations = true` (and in the rate mode
//! `iters_per_step = Some(_)`) bonds break inside the iterations, the
//! classical explicit PD practice (seed 002 section 2.2).

use std::time::Instant;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::{
    residual_norms, Convergence, Iterating, PhaseKind, SolveInfo, StepRecord, PROGRESS_EVERY,
};
use crate::bonds::group_sum;
use crate::error::PdError;
use crate::forces::{ForceStats, History};
use crate::geometry::P2;
use crate::model::PdModel;

/// Gershgorin bound of the linearised stiffness per node: the absolute row sums
/// $\sum_m \sum_q |K_{(i,p),(m,q)}|$ (force density per displacement, N/m^4) of both
/// components `p`, in the reference configuration. PMB bond by bond (each bond's block
/// $k/|\xi|\, n n^T$ counted on the diagonal and off it); the state-based model from
/// its tangent rows. ADR's fictitious density and the explicit time step
/// ([`crate::dynamics`]) both use it.
pub fn row_bounds(model: &PdModel) -> Vec<[f64; 2]> {
    let b = &model.bonds;
    if let Some(rows) = model.stiffness_row_sums() {
        return rows;
    }
    (0..model.n_nodes())
        .map(|i| {
            // Group-ordered sum: mirror nodes get bitwise equal bounds.
            group_sum(&b.meta, b.row(i), |bb| {
                let kl = b.k[bb] * b.inv_len[bb];
                let ex = b.xi[bb][0] * b.inv_len[bb];
                let ey = b.xi[bb][1] * b.inv_len[bb];
                [
                    2.0 * kl * (ex * ex + (ex * ey).abs()),
                    2.0 * kl * (ey * ey + (ex * ey).abs()),
                ]
            })
        })
        .collect()
}

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
    /// Break bonds and raise the history inside the iterations instead of
    /// at converged states (always the case in the rate mode
    /// `iters_per_step = Some(_)`).
    pub break_during_iterations: bool,
    /// Degrading bonds: an equilibrium is settled once no stretch exceeds
    /// its committed history by more than `growth_tol (s_c - s_m)`.
    pub growth_tol: f64,
    /// Re-convergence rounds per load step after bonds broke.
    pub max_break_rounds: usize,
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
            break_during_iterations: false,
            growth_tol: 1e-3,
            max_break_rounds: 100,
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
    /// Directed bonds broken with these buffers.
    pub broken_directed: usize,
    /// Whether [`Adr::step`] updates the bond history ([`History::Update`],
    /// the default of [`Adr::new`]) or leaves it to [`Adr::equilibrate`].
    pub history: History,
    c_last: f64,
    rref_max: f64,
    /// [`History::Secant`]: the equilibrium is settled once no bond's
    /// stretch exceeds its committed history by more than this.
    pub growth_tol: f64,
}

/// Nodes per parallel chunk of the per-DOF loops.
const CHUNK: usize = 1024;

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
        let mass = row_bounds(model)
            .iter()
            .map(|[rx, ry]| (0.25 * safety * rx.max(*ry)).max(f64::MIN_POSITIVE))
            .collect();
        Adr {
            mass,
            vel: vec![[0.0; 2]; n],
            f_prev: vec![[0.0; 2]; n],
            fresh: true,
            since_growth: 0,
            total_iters: 0,
            broken_directed: 0,
            history: History::Update,
            c_last: 0.0,
            rref_max: 0.0,
            growth_tol: 0.0,
        }
    }

    /// Restart from rest (zero velocity) at the current state.
    pub fn reset(&mut self) {
        self.fresh = true;
        self.c_last = 0.0;
        self.vel.iter_mut().for_each(|v| *v = [0.0; 2]);
    }

    /// One ADR step at the model's current load factor. The bond history
    /// is updated in this pass only in [`History::Update`] mode
    /// ([`Adr::history`]). The per-DOF loops run in parallel over fixed
    /// chunks whose partial sums are added in chunk order, so a run is
    /// bitwise reproducible for any number of threads.
    pub fn step(&mut self, model: &mut PdModel) -> StepOut {
        let stats = model.compute_forces(self.history);
        self.total_iters += 1;
        self.broken_directed += stats.newly_broken;
        if stats.growing > 0 {
            self.since_growth = 0;
        } else {
            self.since_growth += 1;
        }
        let (r, rref) = residual_norms(model);
        let lam = model.load;
        let fixed = &model.bc.fixed[..];
        let body = &model.bc.body[..];
        let force = &model.force[..];
        let mass = &self.mass[..];
        // Damping from the local Rayleigh quotient (Eqs. 13-14).
        let mut c = 0.0;
        if !self.fresh {
            let (vel, f_prev, u) = (&self.vel[..], &self.f_prev[..], &model.u[..]);
            let parts: Vec<(f64, f64)> = (0..u.len().div_ceil(CHUNK))
                .into_par_iter()
                .map(|ch| {
                    let (mut num, mut den) = (0.0, 0.0);
                    for i in ch * CHUNK..((ch + 1) * CHUNK).min(u.len()) {
                        for d in 0..2 {
                            if fixed[i][d] {
                                continue;
                            }
                            let v = vel[i][d];
                            let ui = u[i][d];
                            den += ui * ui;
                            if v != 0.0 {
                                let f = force[i][d] + lam * body[i][d];
                                let kii = -(f - f_prev[i][d]) / (mass[i] * v);
                                num += ui * kii * ui;
                            }
                        }
                    }
                    (num, den)
                })
                .collect();
            let (num, den) = parts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
            if num > 0.0 && den > 0.0 {
                c = (2.0 * (num / den).sqrt()).min(1.9);
            } else if self.history == History::Frozen {
                // Softening bonds make the Rayleigh quotient negative; with
                // a frozen history nothing else dissipates, so keep the last
                // damping instead of running undamped.
                c = self.c_last;
            }
            self.c_last = c;
        }
        let fresh = self.fresh;
        let parts: Vec<(f64, f64)> = self
            .vel
            .par_chunks_mut(CHUNK)
            .zip(self.f_prev.par_chunks_mut(CHUNK))
            .zip(model.u.par_chunks_mut(CHUNK))
            .enumerate()
            .map(|(ch, ((vel, f_prev), u))| {
                let (mut du2, mut u2) = (0.0, 0.0);
                let base = ch * CHUNK;
                for k in 0..vel.len() {
                    let i = base + k;
                    for d in 0..2 {
                        if fixed[i][d] {
                            continue;
                        }
                        let f = force[i][d] + lam * body[i][d];
                        let a = f / mass[i];
                        let v = if fresh {
                            0.5 * a
                        } else {
                            ((2.0 - c) * vel[k][d] + 2.0 * a) / (2.0 + c)
                        };
                        vel[k][d] = v;
                        f_prev[k][d] = f;
                        u2 += u[k][d] * u[k][d];
                        u[k][d] += v;
                        du2 += v * v;
                    }
                }
                (du2, u2)
            })
            .collect();
        let (du2, u2) = parts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
        self.fresh = false;
        let du_rel = if u2 > 0.0 {
            (du2 / u2).sqrt()
        } else {
            f64::INFINITY
        };
        // Reference: the largest applied force or reaction seen by these
        // buffers, so a body that separates from its supports (reaction
        // near zero) does not inflate the relative residual.
        self.rref_max = self.rref_max.max(rref);
        let rref = self.rref_max;
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

    /// Equilibrium at the current load with the bond history of
    /// [`Adr::history`]: in [`History::Update`] mode one [`Self::converge`];
    /// otherwise converge with the history frozen (or secant), commit
    /// it at the converged state (every bond past its limit breaks at once,
    /// Jacobi-style), and converge again while bonds broke, up to
    /// `max_rounds` rounds. Returns (steps, measure, statistics of the last
    /// pass, whether any bond was damaged). `progress` hears how far it has got
    /// ([`Iterating`], over all rounds).
    #[allow(clippy::too_many_arguments)]
    pub fn equilibrate(
        &mut self,
        model: &mut PdModel,
        conv: Convergence,
        min_iters: usize,
        max_iters: usize,
        max_rounds: usize,
        history: &mut Vec<f64>,
        progress: &mut dyn FnMut(&Iterating),
    ) -> Result<(usize, f64, ForceStats, bool), PdError> {
        let it0 = self.total_iters;
        if self.history == History::Update {
            let (it, m, st) =
                self.converge(model, conv, min_iters, max_iters, history, progress)?;
            let grew = self.since_growth < self.total_iters - it0;
            return Ok((it, m, st, grew));
        }
        let mut grew = false;
        let mut iters = 0;
        let mut last = (0, 0.0);
        let rounds = max_rounds.max(1);
        let (broken0, mut broken) = (model.broken_bonds(), 0);
        for round in 0..rounds {
            // Every increment starts at rest, so the result depends on the
            // start state only (not on the velocity a previous increment
            // left behind).
            if round == 0 || self.history != History::Secant {
                self.reset();
            }
            let mut in_round = |e: &Iterating| {
                progress(&Iterating {
                    iterations: iters + e.iterations,
                    round: (round + 1, rounds),
                    broken: Some(broken),
                    ..*e
                })
            };
            let (it, m, _) =
                self.converge(model, conv, min_iters, max_iters, history, &mut in_round)?;
            iters += it;
            let st = model.commit_history();
            self.broken_directed += st.newly_broken;
            broken = model.broken_bonds() - broken0;
            last = (st.newly_broken, st.max_growth);
            grew |= st.growing > 0;
            let settled = match self.history {
                History::Secant => st.max_growth <= self.growth_tol,
                _ => true,
            };
            if st.newly_broken == 0 && settled {
                return Ok((iters, m, st, grew));
            }
        }
        Err(PdError::Unsettled {
            solver: "adr (bond breaking)",
            rounds: max_rounds.max(1),
            load: model.load,
            broken: last.0,
            growth: last.1,
            allowed: self.growth_tol,
        })
    }

    /// Iterate at the current load until `conv` is met (after `min_iters`),
    /// or fail after `max_iters`. Returns (steps, final measure). `progress` hears
    /// every [`PROGRESS_EVERY`] iterations how far it has got.
    pub fn converge(
        &mut self,
        model: &mut PdModel,
        conv: Convergence,
        min_iters: usize,
        max_iters: usize,
        history: &mut Vec<f64>,
        progress: &mut dyn FnMut(&Iterating),
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
            if it % PROGRESS_EVERY == 0 {
                progress(&Iterating {
                    solver: "adr",
                    load: model.load,
                    iterations: it,
                    round: (1, 1),
                    max_iterations: max_iters,
                    measure: m,
                    tolerance: conv.tolerance(),
                    broken: None,
                });
            }
        }
        let (m, _) = last.unwrap_or((f64::NAN, ForceStats::default()));
        Err(PdError::NoConvergence {
            solver: "adr",
            iterations: max_iters,
            load: model.load,
            measure: m,
            tolerance: conv.tolerance(),
        })
    }
}

impl Adr {
    /// The solver of [`solve`] for `params`: the bond history secant between converged
    /// states (committed at them) unless `params` step a fixed number of iterations or
    /// break bonds inside the iterations.
    pub fn for_params(model: &PdModel, params: &AdrParams) -> Self {
        let mut adr = Adr::new(model, params.safety);
        if params.iters_per_step.is_none() && !params.break_during_iterations {
            adr.history = History::Secant;
            adr.growth_tol = params.growth_tol * model.law().softening_range();
        }
        adr
    }

    /// One load step of [`solve`] at load factor `lam`: equilibrium with the breaking
    /// rounds, recorded in `info.steps`; `progress` as [`Adr::equilibrate`]. Returns the
    /// iterations.
    pub fn load_step(
        &mut self,
        model: &mut PdModel,
        lam: f64,
        params: &AdrParams,
        info: &mut SolveInfo,
        progress: &mut dyn FnMut(&Iterating),
    ) -> Result<usize, PdError> {
        model.set_load_factor(lam);
        let (iters, m, st, _) = self.equilibrate(
            model,
            params.convergence,
            params.min_iters,
            params.max_iters,
            params.max_break_rounds,
            &mut info.residual_history,
            progress,
        )?;
        let record = StepRecord::of(model, lam, iters, st.max_stretch, m, PhaseKind::Explicit);
        info.steps.push(record);
        Ok(iters)
    }
}

/// Solve by ADR from the model's current state to `params.target_load`.
pub fn solve(model: &mut PdModel, params: &AdrParams) -> Result<SolveInfo, PdError> {
    let t0 = Instant::now();
    let mut info = SolveInfo::default();
    let mut adr = Adr::for_params(model, params);
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
                    &mut |_| {},
                )?;
                (it + n.max(1), m, st)
            }
            None => {
                info.iterations += adr.load_step(model, lam, params, &mut info, &mut |_| {})?;
                continue;
            }
        };
        info.iterations += iters;
        if k == steps {
            let record = StepRecord::of(model, lam, iters, st.max_stretch, m, PhaseKind::Explicit);
            info.steps.push(record);
        }
    }
    let dt = t0.elapsed().as_secs_f64();
    let broken = model.broken_bonds() - broken0;
    info.finish_single_phase(PhaseKind::Explicit, lam0, params.target_load, dt, broken);
    Ok(info)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::plate_hole;

    #[test]
    fn breaking_rounds_that_run_out_say_so() {
        // The seed 000 plate with a hole on a 12 x 12 grid, pulled to 4 times its
        // target in one step with one re-convergence round: bonds break in that round,
        // so the step has not settled, and the error says why instead of reporting a NaN
        // measure against a zero tolerance.
        let case = plate_hole(12);
        let mut m = PdModel::new(&case.problem).unwrap();
        let params = AdrParams {
            target_load: 4.0 * case.target_load,
            steps: 1,
            max_break_rounds: 1,
            ..Default::default()
        };
        match solve(&mut m, &params) {
            Err(PdError::Unsettled {
                rounds,
                broken,
                growth,
                allowed,
                ..
            }) => {
                assert_eq!(rounds, 1);
                assert!(
                    broken > 0 || growth > allowed,
                    "{broken} {growth} {allowed}"
                );
            }
            other => panic!("expected Unsettled, got {other:?}"),
        }
    }
}
