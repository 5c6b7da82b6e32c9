//! Error estimates and tolerance-driven refinement of a static BEM solve (issue 17).
//!
//! Every static BEM run solves its scene at two levels of the one sizing rule
//! ([`crate::setup::sizing`]): the primary level (refinement r, every element size and
//! every grading of the local size field divided by r) and the level below it (r / 2,
//! sizes twice as large: about 1/8 of the primary's cost). The error of a quantity q at
//! the primary level is estimated by
//! $$ e(q_h) = \max\big( |q_h - q_{2h}|,\; |K_\text{cod} - K_J|,\; \epsilon_0 |q_h| \big):$$
//! the first term is exact for the O(h) rate of constant elements (REFERENCES.md) and
//! over-estimates by 2^p - 1 at a faster rate p; the second is the disagreement of the
//! two K extractions (crack-opening fit and interaction integral; K only, and not where
//! K is the integral's because the fit is biased, a crack loaded on one face); the floor
//! $\epsilon_0$ = [`RESOLUTION_FLOOR`] covers biases no refinement removes (measured up
//! to 6e-4 on SENT a/W = 0.1 against the FEM table, the same at every h). An observed
//! order from a third level (h, 2h, 4h) was tried and dropped: it under-estimated SENT
//! a/W = 0.8 by a factor 6 (estimate / true error 0.16), where this estimate gives 0.7.
//! For a Richardson pair ([`crate::scene::BemSettings::richardson`]) the reported value
//! is $2 q_h - q_{2h}$ and the same estimate bounds its error from above.
//!
//! `bem.tolerance` (or `pdbem run --tol`) asks for
//! $S \max_\text{tips} \max(e(K_I), e(K_{II})) / K_{eq} \le \text{tol}$ and
//! $S\, e(\text{CMOD}) \le \text{tol} |\text{CMOD}|$ with the safety factor
//! S = [`SAFETY`] = 2: the estimate has been measured down to 0.6-0.7 of the true error
//! where convergence is slower than O(h) (SENT a/W = 0.5 to 0.8 against the FEM table,
//! `tests/verification_error_estimate.rs`), and a tolerance reported as met must bound
//! the true error, not only the estimate. While it is not met, r doubles (the
//! primary becomes the level below), as long as the next level fits the memory budget
//! ([`crate::setup::estimate`]) and r stays at most [`MAX_REFINE`]. A tolerance the
//! budget cannot reach ends with the best level and a note that says so, never with a
//! claim of convergence; so does an estimate that stops decreasing ([`STAGNATION`]).
//! Since every estimate has the floor, the smallest tolerance is S times the floor.
//!
//! A level whose crack meshes leave a tip's crack-opening fit with fewer than
//! [`pdbem_bem::post::sif::MIN_FIT_STATIONS`] stations has a K error the estimate cannot
//! see ([`crate::setup::fit_stations`]): it never meets a tolerance (refinement goes on),
//! and a run whose reported level (or the coarse level of a Richardson pair) is such a
//! level is refused with the size that would do.

use anyhow::Result;
use serde::Serialize;
use std::time::Instant;

use crate::run_bem::level::{solve_level, Level};
use crate::scene::Scene;
use crate::setup::fit_stations;

/// Largest refinement the tolerance loop tries (sizes / 64 of the scene's).
pub const MAX_REFINE: f64 = 64.0;
/// Relative floor of every estimate (module docs); the smallest `bem.tolerance` is twice it.
pub const RESOLUTION_FLOOR: f64 = crate::scene::bem::ESTIMATE_FLOOR;
/// Safety factor of the tolerance test (module docs).
pub const SAFETY: f64 = 2.0;
/// The tolerance test as `summary.json` states it.
pub const CRITERION: &str = "2 max(e(K_I), e(K_II)) <= tol |K| and 2 e(CMOD) <= tol |CMOD|";
/// Refinement stops when a level's estimate is above this fraction of the previous
/// level's: the estimate is held up by something refinement does not remove (the
/// disagreement of the two K extractions, or the floor).
pub const STAGNATION: f64 = 0.95;

/// One solved level, for `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct LevelRecord {
    /// Refinement r (element sizes divided by r).
    pub refine: f64,
    /// Elements.
    pub elements: usize,
    /// Wall time of the level (s): meshing, assembly, factorization, post-processing.
    pub seconds: f64,
    /// Largest relative error estimate of the level (against the level below it), if it
    /// has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_rel_estimate: Option<f64>,
}

/// Error estimates of one level: per tip (K_I, K_II), per crack CMOD.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Estimates {
    /// |K_I(h) - K_I(2h)|, |K_II(h) - K_II(2h)| per tip, in the primary's tip order.
    pub tips: Vec<(f64, f64)>,
    /// |CMOD(h) - CMOD(2h)| per crack (None without a mouth).
    pub cracks: Vec<Option<f64>>,
}

impl Estimates {
    /// The estimates of `fine` from `coarse` (module docs; tips and cracks matched by
    /// name; a tip missing from the coarse level gets an infinite estimate).
    pub fn of(fine: &Level, coarse: &Level) -> Self {
        let tips = fine
            .tips
            .iter()
            .map(|t| {
                let Some(c) = coarse.tips.iter().find(|c| c.name == t.name) else {
                    return (f64::INFINITY, f64::INFINITY);
                };
                let keq = t.k1.hypot(t.k2);
                let floor = RESOLUTION_FLOOR * keq;
                // A K from the integral because the fit is biased (a crack loaded on one
                // face) is not bounded by its distance to the fit.
                let fit_primary = t.k_source.is_none();
                let extraction = |cod: Option<f64>, j: Option<f64>| match (cod, j) {
                    (Some(a), Some(b)) if fit_primary && a.is_finite() && b.is_finite() => {
                        (a - b).abs()
                    }
                    _ => 0.0,
                };
                let e1 = (t.k1 - c.k1)
                    .abs()
                    .max(extraction(t.k1_cod, t.k1_j))
                    .max(floor);
                let e2 = (t.k2 - c.k2)
                    .abs()
                    .max(extraction(t.k2_cod, t.k2_j))
                    .max(floor);
                (e1, e2)
            })
            .collect();
        let cracks = fine
            .cracks
            .iter()
            .map(|f| {
                let v = f.cmod?;
                let c = coarse.cracks.iter().find(|c| c.name == f.name)?.cmod?;
                Some((v - c).abs().max(RESOLUTION_FLOOR * v.abs()))
            })
            .collect();
        Estimates { tips, cracks }
    }

    /// The largest relative estimate over every K (against K_eq) and CMOD of `level`.
    pub fn worst_relative(&self, level: &Level) -> f64 {
        let mut worst: f64 = 0.0;
        for (t, (e1, e2)) in level.tips.iter().zip(&self.tips) {
            let k = t.k1.hypot(t.k2);
            worst = worst.max(relative(e1.max(*e2), k));
        }
        for (c, e) in level.cracks.iter().zip(&self.cracks) {
            if let (Some(v), Some(e)) = (c.cmod, e) {
                worst = worst.max(relative(*e, v.abs()));
            }
        }
        worst
    }
}

/// e / |v|, infinite when v is zero and e is not.
fn relative(e: f64, v: f64) -> f64 {
    if e == 0.0 {
        0.0
    } else if v > 0.0 {
        e / v
    } else {
        f64::INFINITY
    }
}

/// The levels of a static solve.
pub struct Refined {
    /// The primary (finest) level.
    pub fine: Level,
    /// The level below it, when it could be solved.
    pub coarse: Option<Level>,
    /// Why the level below could not be solved.
    pub coarse_failure: Option<String>,
    /// Every level solved, coarsest first.
    pub levels: Vec<LevelRecord>,
    /// Whether `bem.tolerance` was met (None without a tolerance).
    pub reached: Option<bool>,
    /// Why refinement stopped short of the tolerance.
    pub stop_reason: Option<String>,
}

/// Solves `scene` at load `factor`: the primary level `start` (1, or 2 for a Richardson
/// pair), the level below it for the estimate, and finer levels while `bem.tolerance`
/// asks for them (module docs).
pub fn solve(scene: &Scene, factor: f64, start: f64) -> Result<Refined> {
    let mut levels = Vec::new();
    let timed = |r: f64, levels: &mut Vec<LevelRecord>| -> Result<Level> {
        let t0 = Instant::now();
        let level = solve_level(scene, factor, r)?;
        levels.push(LevelRecord {
            refine: r,
            elements: level.setup.mesh.len(),
            seconds: t0.elapsed().as_secs_f64(),
            max_rel_estimate: None,
        });
        Ok(level)
    };
    let (mut coarse, mut coarse_failure) = match timed(0.5 * start, &mut levels) {
        Ok(l) => (Some(l), None),
        Err(e) => (None, Some(format!("{e:#}"))),
    };
    let mut r = start;
    let mut fine = timed(r, &mut levels)?;
    let tol = scene.bem.tolerance;
    let (mut reached, mut stop_reason) = (None, None);
    let mut previous: Option<f64> = None;
    loop {
        let worst = coarse
            .as_ref()
            .map(|c| Estimates::of(&fine, c).worst_relative(&fine));
        if let (Some(w), Some(rec)) = (worst, levels.last_mut()) {
            rec.max_rel_estimate = Some(w);
        }
        let Some(tol) = tol else { break };
        let w = worst.unwrap_or(f64::INFINITY);
        let resolved = fit_stations::unresolved(scene, &fine.setup.mesh).is_empty();
        if resolved && SAFETY * w <= tol {
            reached = Some(true);
            break;
        }
        reached = Some(false);
        if resolved {
            if let Some(why) = stagnation(previous, w, tol, fine.setup.mesh.len()) {
                stop_reason = Some(why);
                break;
            }
            previous = Some(w);
        }
        if let Some(why) = next_level_refused(scene, 2.0 * r, w, tol, fine.setup.mesh.len()) {
            stop_reason = Some(why);
            break;
        }
        r *= 2.0;
        let next = timed(r, &mut levels)?;
        coarse = Some(std::mem::replace(&mut fine, next));
        coarse_failure = None;
    }
    fit_stations::require(
        scene,
        &fine.setup.mesh,
        &level_name(r, stop_reason.as_deref()),
    )?;
    if let (true, Some(c)) = (scene.bem.richardson, &coarse) {
        fit_stations::require(scene, &c.setup.mesh, &level_name(0.5 * r, None))?;
    }
    Ok(Refined {
        fine,
        coarse,
        coarse_failure,
        levels,
        reached,
        stop_reason,
    })
}

/// The BEM level at refinement `r` for a message, with why refinement stopped there.
fn level_name(r: f64, stopped: Option<&str>) -> String {
    let level = if r == 1.0 {
        "the BEM mesh at the scene's sizes".to_string()
    } else {
        format!("the BEM mesh at the scene's sizes / {r}")
    };
    match stopped {
        Some(why) => format!("{level} ({why})"),
        None => level,
    }
}

/// Why refinement stops although the tolerance is not met: the estimate `worst` of the
/// last level is not below [`STAGNATION`] times that of the level before (`previous`).
fn stagnation(previous: Option<f64>, worst: f64, tol: f64, n: usize) -> Option<String> {
    let p = previous?;
    (worst > STAGNATION * p).then(|| {
        format!(
            "bem.tolerance = {tol:e} not reached: the largest relative error estimate went \
             from {p:.3e} to {worst:.3e} with {n} elements (the test asks for {SAFETY} x \
             estimate <= tolerance); refinement no longer reduces it \
             (it is held up by the disagreement of the crack-opening fit and the \
             interaction integral, or by the floor {RESOLUTION_FLOOR:e})"
        )
    })
}

/// Why the level at refinement `r` is not tried: past [`MAX_REFINE`], or over the memory
/// budget by the exact count of the mesh ([`crate::setup::estimate`]).
fn next_level_refused(scene: &Scene, r: f64, worst: f64, tol: f64, n: usize) -> Option<String> {
    let reason = |what: String| {
        format!(
            "bem.tolerance = {tol:e} not reached: the largest relative error estimate is {worst:.3e} with {n} elements (the test asks for {SAFETY} x estimate <= tolerance); {what}"
        )
    };
    if r > MAX_REFINE {
        return Some(reason(format!(
            "refinement stops at element sizes / {MAX_REFINE} of the scene's"
        )));
    }
    let mut s = scene.clone();
    s.bem.richardson = false;
    match crate::setup::estimate::level(&s, r) {
        Ok(bytes) if bytes <= crate::setup::estimate::budget() as f64 => None,
        Ok(bytes) => Some(reason(format!(
            "the next level (sizes / {r}) needs {} > budget {} (--max-memory)",
            crate::setup::estimate::bytes_text(bytes),
            crate::setup::estimate::bytes_text(crate::setup::estimate::budget() as f64)
        ))),
        Err(e) => Some(reason(format!("the next level cannot be meshed: {e:#}"))),
    }
}
