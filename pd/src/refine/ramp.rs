//! Quasi-static brittle load ramp on a refined body: the crack-initiation ramp of
//! [`crate::measure::ramp_to_initiation`] (seed 000 section 2, seed 001 section 6.1) with
//! seed 004's adaptive refinement (section 3, Fig. 5 steps 3-5 at every equilibrium).
//!
//! At each load factor $\lambda$ (from `start` by `step`, the start moved up to just below
//! the first-break load predicted by one elastic solve at $\lambda = 1$, as the uniform
//! ramp does) the driver repeats, up to `max_rounds` times:
//! 1. the elastic equilibrium $K(\text{intact})\,u = \lambda f$ of the linearised
//!    dual-horizon energy ([`super::linear`]) by conjugate gradients preconditioned with
//!    a sparse Cholesky factor of $K$ kept while only bonds break ([`super::direct`],
//!    warm-started);
//! 2. the criteria (Eq. 15, $\varphi_k > \varphi_c$; Eq. 16, $\min_i\varepsilon_{ii} >
//!    \alpha s_c$; level below `max_level`): if any particle fires, it splits
//!    ([`Body::split`], children inheriting their ancestors' broken bonds) and the round
//!    re-solves before any bond breaks, so a bond breaks only where the body has been
//!    refined as far as the criteria ask (with $\alpha < 1$, Eq. 16 fires before the
//!    stretch reaches $s_c$);
//! 3. every intact bond whose linearised stretch $n\cdot(u_j-u_k)/|\xi|$ passes its
//!    owner's critical stretch breaks (seed 004 Eq. 11 with the owner's horizon, as in
//!    adaptive dynamics); none: the load step is done.
//!
//! The initiation load is the first $\lambda$ at which the crack extension
//! ([`crate::measure::crack_extension_of`]) grows by more than `run_length`; the ramp
//! keeps breaking at that load until the extension reaches `grow_to` (for the kink
//! angle), then stops. A solve that fails after bonds have broken is unstable growth under
//! load control (a piece came loose: its loads have no equilibrium, and the solve stalls
//! on a fresh factor, [`super::direct::FRESH_CAP`]): the load is the initiation load and
//! `unstable` is set, as in the uniform ramp. The body is geometrically linear (small
//! strains), so the stretch is the linearised one: the nonlinear stretch would count a
//! large rigid rotation of a piece about its last bonds as stretch and break the whole
//! piece. The uniform ramp's Newton solves the nonlinear stretch, which differs at the
//! critical stretch by its square, about 1e-3 relative.

use std::time::Instant;

use serde::Serialize;

use super::direct::Solver;
use super::run::flagged;
use super::{Body, Refinement};
use crate::error::PdError;
use crate::measure::{crack_extension_of, RampParams, Tip};
use crate::problem::PdProblem;

/// Most load steps a ramp may take (the scenes' `load.count` bound).
const MAX_STEPS: f64 = 1e5;

/// One load step of the ramp.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RampStep {
    /// Load factor.
    pub load: f64,
    /// Particles at the end of the step.
    pub particles: usize,
    /// Particles split during the step.
    pub split: usize,
    /// Directed bonds broken during the step.
    pub broken: usize,
    /// Crack extension at the end of the step (m).
    pub extension: f64,
    /// The step ended with no bond left to break (or at `grow_to`, or in unstable growth);
    /// false when it used up `max_rounds` with bonds still breaking.
    pub settled: bool,
}

/// Result of [`ramp`]: the body in its final state and the ramp's record.
#[derive(Clone, Debug)]
pub struct RefinedRamp {
    /// The body in its final state.
    pub body: Body,
    /// The ramp's record.
    pub record: RampRecord,
}

/// The record of a [`ramp`].
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RampRecord {
    /// Load factor at which the first bond broke.
    pub first_break_load: Option<f64>,
    /// Load factor at which the crack ran (extension past `run_length`).
    pub initiation_load: Option<f64>,
    /// Crack extension at the end (m).
    pub extension: f64,
    /// The equilibrium was lost after bonds broke (unstable growth): the ramp stopped.
    pub unstable: bool,
    /// Particles split before the ramp (static regions, Eq. 15 on the pre-cracks).
    pub setup_split: usize,
    /// The load steps.
    pub steps: Vec<RampStep>,
    /// Preconditioned conjugate-gradient iterations, all solves.
    pub iterations: usize,
    /// Wall time of the splits (s).
    pub split_s: f64,
    /// Wall time of the solves (s).
    pub solve_s: f64,
    /// Why the solves ran as plain conjugate gradients (the preconditioner's factor over
    /// the memory budget, [`super::direct::Solver::plain`]); `None`: preconditioned.
    pub plain_cg: Option<String>,
}

/// Ramp `p` (loads at factor 1) with brittle breaking and adaptive refinement `r` until
/// the crack from `tips` runs (module docs). The problem needs a failure law with a
/// critical stretch; prescribed displacements (fictitious layers included) scale with the
/// load factor, as tractions do.
pub fn ramp(
    p: &PdProblem,
    r: &Refinement,
    tips: &[Tip],
    rp: &RampParams,
) -> Result<RefinedRamp, PdError> {
    ramp_with(p, r, tips, rp, Solver::default())
}

/// [`ramp`] with the given solver (a [`Solver`] with a budget of one byte runs plain
/// conjugate gradients: the benchmark's baseline).
pub fn ramp_with(
    p: &PdProblem,
    r: &Refinement,
    tips: &[Tip],
    rp: &RampParams,
    solver: Solver,
) -> Result<RefinedRamp, PdError> {
    ramp_observed(p, r, tips, rp, solver, &mut |_| {})
}

/// [`ramp_with`], telling `observe` every load step as it ends.
pub fn ramp_observed(
    p: &PdProblem,
    r: &Refinement,
    tips: &[Tip],
    rp: &RampParams,
    mut solver: Solver,
    observe: &mut dyn FnMut(&RampStep),
) -> Result<RefinedRamp, PdError> {
    check_params(rp)?;
    r.validate()?;
    let mut body = Body::from_problem(p)?;
    body.keep_horizon = r.keep_horizon;
    critical_stretches(&body)?;
    let mut out = RampRecord::default();
    let t = Instant::now();
    out.setup_split += super::run::set_up(&mut body, r)?;
    out.split_s += t.elapsed().as_secs_f64();
    let mut lam = first_load(&mut body, r, rp, &mut solver, &mut out)?;
    let ext0 = extension(&body, tips);
    out.extension = ext0;
    while lam <= rp.max_load * (1.0 + 1e-12) {
        let step = load_step(&mut body, r, tips, rp, lam, ext0, &mut solver, &mut out)?;
        observe(&step);
        out.steps.push(step);
        if out.initiation_load.is_some() {
            break;
        }
        lam += rp.step;
    }
    out.plain_cg = solver.plain.clone();
    Ok(RefinedRamp { body, record: out })
}

/// The ramp's numbers must mean a ramp: finite, positive step, start at most the end.
fn check_params(rp: &RampParams) -> Result<(), PdError> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(rp.start) && ok(rp.step) && ok(rp.max_load) && rp.start <= rp.max_load) {
        return Err(PdError::invalid(
            "load",
            format!(
                "the ramp needs 0 < start <= end and a positive step, got start {}, step {}, end {}",
                rp.start, rp.step, rp.max_load
            ),
        ));
    }
    if (rp.max_load - rp.start) / rp.step > MAX_STEPS {
        return Err(PdError::invalid(
            "load",
            format!(
                "the ramp from {} to {} by {} takes more than {MAX_STEPS} load steps",
                rp.start, rp.max_load, rp.step
            ),
        ));
    }
    if !(rp.run_length.is_finite() && rp.run_length > 0.0 && rp.grow_to.is_finite()) {
        return Err(PdError::invalid(
            "run_length",
            format!("must be positive and finite, got {}", rp.run_length),
        ));
    }
    Ok(())
}

/// Every particle's critical stretch; an error without a breaking law.
fn critical_stretches(body: &Body) -> Result<Vec<f64>, PdError> {
    (0..body.len())
        .map(|k| body.critical_stretch(k))
        .collect::<Option<Vec<f64>>>()
        .ok_or_else(|| {
            PdError::invalid(
                "failure",
                "the refined load ramp breaks bonds at a critical stretch: give a failure law (CriticalStretch or FromGc)",
            )
        })
}

fn extension(body: &Body, tips: &[Tip]) -> f64 {
    crack_extension_of(body.positions(), &body.damage(), tips)
}

/// Timed solve at load `lam` (conjugate gradients preconditioned by a kept Cholesky
/// factor, [`super::direct`]).
fn solve(
    body: &mut Body,
    r: &Refinement,
    lam: f64,
    solver: &mut Solver,
    out: &mut RampRecord,
) -> Result<(), PdError> {
    let t = Instant::now();
    let it = solver.solve(body, lam, r.tolerance);
    out.solve_s += t.elapsed().as_secs_f64();
    out.iterations += it?;
    Ok(())
}

/// The first load of the ramp: `start`, moved up by whole steps to just below the load at
/// which the largest stretch of an elastic solve at factor 1 reaches its critical
/// stretch (the response is linear). The body is left at zero displacement.
fn first_load(
    body: &mut Body,
    r: &Refinement,
    rp: &RampParams,
    solver: &mut Solver,
    out: &mut RampRecord,
) -> Result<f64, PdError> {
    solve(body, r, 1.0, solver, out)?;
    let sc = critical_stretches(body)?;
    let owner = body.dh.owners();
    let ratio = linear_stretches(body, &owner)
        .iter()
        .enumerate()
        .filter(|&(b, _)| body.dh.intact[b] != 0)
        .map(|(b, s)| s / sc[owner[b] as usize])
        .fold(0.0f64, f64::max);
    body.u.iter_mut().for_each(|u| *u = [0.0; 2]);
    let mut lam = rp.start;
    if ratio > 0.0 {
        let fb = 1.0 / ratio;
        if fb > lam {
            lam += ((fb - lam) / rp.step).floor() * rp.step;
        }
    }
    Ok(lam)
}

/// The linearised stretch `n . (u_j - u_k) / |xi|` of every bond (the solve's own
/// measure: a rigid rotation does not stretch it).
fn linear_stretches(body: &Body, owner: &[u32]) -> Vec<f64> {
    let bonds = &body.dh.bonds;
    (0..bonds.len())
        .map(|b| {
            let (k, j) = (owner[b] as usize, bonds.nbr[b] as usize);
            let xi = bonds.xi[b];
            let il = bonds.inv_len[b];
            let du = [body.u[j][0] - body.u[k][0], body.u[j][1] - body.u[k][1]];
            (du[0] * xi[0] + du[1] * xi[1]) * il * il
        })
        .collect()
}

/// Breaks every intact bond whose linearised stretch passes its owner's critical stretch
/// (seed 004 Eq. 11 with the owner's horizon, as in adaptive dynamics); returns the
/// directed bonds broken.
fn break_bonds(body: &mut Body) -> Result<usize, PdError> {
    let sc = critical_stretches(body)?;
    let owner = body.dh.owners();
    let s = linear_stretches(body, &owner);
    let mut broken = 0;
    for (b, flag) in body.dh.intact.iter_mut().enumerate() {
        if *flag != 0 && s[b] > sc[owner[b] as usize] {
            *flag = 0;
            broken += 1;
        }
    }
    Ok(broken)
}

/// One load step (module docs): solve, split while the criteria fire, break, repeat.
fn load_step(
    body: &mut Body,
    r: &Refinement,
    tips: &[Tip],
    rp: &RampParams,
    lam: f64,
    ext0: f64,
    solver: &mut Solver,
    out: &mut RampRecord,
) -> Result<RampStep, PdError> {
    let mut step = RampStep {
        load: lam,
        particles: body.len(),
        split: 0,
        broken: 0,
        extension: out.extension,
        settled: false,
    };
    for _round in 0..rp.max_rounds {
        if let Err(e) = solve(body, r, lam, solver, out) {
            if out.first_break_load.is_none() {
                return Err(e);
            }
            out.unstable = true;
            out.initiation_load.get_or_insert(lam);
            step.settled = true;
            break;
        }
        let t = Instant::now();
        let f = flagged(body, r, false, true);
        if !f.is_empty() {
            step.split += body.split(&f)?;
            out.split_s += t.elapsed().as_secs_f64();
            continue;
        }
        let broken = break_bonds(body)?;
        step.broken += broken;
        if broken > 0 && out.first_break_load.is_none() {
            out.first_break_load = Some(lam);
        }
        let ext = extension(body, tips);
        out.extension = ext;
        if ext - ext0 > rp.run_length && out.initiation_load.is_none() {
            out.initiation_load = Some(lam);
        }
        if broken == 0 || (out.initiation_load.is_some() && ext - ext0 >= rp.grow_to) {
            step.settled = true;
            break;
        }
    }
    step.particles = body.len();
    step.extension = out.extension;
    Ok(step)
}
