//! Equilibrium of a PD model (a window, or the whole body in full-PD growth) with the
//! bond history frozen: the secant chord iteration on a kept factorisation for brittle
//! bonds ([`FrozenSolver`], [`crate::solvers::secant`]), Newton-Raphson (seed 000
//! section 2, Eq. 5) for degrading bonds, and where the first solver fails adaptive
//! dynamic relaxation (seed 002 Eqs. 9-15) and Newton in the order [`Fallbacks`] sets
//! (windows: ADR on a trial budget, Newton, ADR on its full budget; full PD: Newton
//! first).
//!
//! Why a kept factorisation: between two coupling iterations only the prescribed
//! displacements of the coupled virtual nodes change, and between two break rounds only
//! a few bonds; Newton refactorised the window's tangent two or three times for each
//! (a third of a PD-BEM run's time on `growth_tension_edge`, measured with perf). For
//! brittle bonds the secant and the frozen-history forces are the same, so the chord
//! iteration converges to Newton's equilibrium.
//!
//! Newton stalls once the bonds left make the tangent nearly singular: a fragment held
//! by one bond, a node whose remaining bonds are collinear. Measured on the seed 001
//! two-crack plate (`cases/growth_two_parallel_cracks.ron`): the relative residual stopped
//! at 5e-5 after 50 iterations, in the step where the cracks ran through. ADR needs only
//! the forces, so such a state still equilibrates. No bond breaks in either solver; the
//! caller commits the history.

use std::fmt;
use std::ops::AddAssign;

use serde::{Deserialize, Serialize};

use crate::forces::History;
use crate::material::BondLaw;
use crate::solvers::implicit::{ImplicitParams, Newton};
use crate::solvers::secant::{SecantParams, SecantSolver, CONTRACTION_REFACTOR};
use crate::solvers::{adr, Convergence};
use crate::{PdError, PdModel, SolveInfo};

/// Low-rank columns (changed bond pairs) kept before the chord iteration refactorises
/// (the explicit-implicit switch's default).
const CHORD_COLUMNS: usize = 256;
/// Anderson depth of the chord iteration (the switch's default).
const CHORD_ANDERSON: usize = 3;
/// Chord iterations per equilibrium before a fallback takes over.
const CHORD_ITERS: usize = 50;

/// Refactorisations for poor contraction a window's chord iteration may make per
/// equilibrium before ADR takes over ([`Fallbacks::chord_refactors`]). Where the chord
/// iteration fails, a window is nearly cut and its contraction stalls near 1: without a
/// limit every iteration asked for a refactorisation (about 96 factorisations and 0.15 s
/// per failed equilibrium of a 20 x 20 window) while ADR converged in 0.03-0.08 s.
/// `growth_tension_edge` over seven interface tolerances psi = (0.94-1.06) 1e-4 (each a
/// different but equally valid sequence of break rounds), wall time on 2 cores: no limit
/// median 6.07 s; 8, 5.21 s; 4 with [`STALLED_CHORD_REFACTORS`], 4.65 s; 2 with it,
/// 5.26 s. The paths are the same node for node.
const CHORD_REFACTORS: usize = 4;

/// [`CHORD_REFACTORS`] after a failed chord iteration of the same window. Failures come
/// in runs (a nearly cut window fails at every coupling iteration until its state moves
/// on: 30 in a row measured), and each tried refactorisation is lost.
const STALLED_CHORD_REFACTORS: usize = 1;

/// What [`FrozenSolver`] does where its first solvers fail.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fallbacks {
    /// Contraction per chord iteration above which the kept factor is renewed.
    pub refactor_contraction: f64,
    /// Chord iterations before a fallback takes over.
    pub chord_iters: usize,
    /// Refactorisations for poor contraction within one chord iteration before a fallback
    /// takes over ([`SecantParams::max_refactors`]); `None`: no limit.
    pub chord_refactors: Option<usize>,
    /// After a failed chord iteration, ADR on a trial budget before Newton
    /// ([`Self::adr_trial_steps_per_row`]; ADR on its full budget where Newton fails too).
    /// The windows' choice: where the chord iteration fails a window is nearly cut, and
    /// there Newton (LU on an indefinite tangent) failed too in every case measured on
    /// `growth_tension_edge` (0.8 s for 50 iterations each) while ADR converged in 250-810
    /// steps (0.02-0.06 s). Without the chord iteration (degrading bonds) Newton is tried
    /// first regardless.
    pub adr_before_newton: bool,
    /// A Newton stall ([`PdError::NoConvergence`]) below this measure is accepted as the
    /// equilibrium ([`Solved::Loose`]); 0 accepts none.
    pub loose_measure: f64,
    /// Relative residual of the ADR fallback.
    pub adr_tol: f64,
    /// ADR steps allowed to the fallback.
    pub adr_max_iters: usize,
    /// With `adr_before_newton`: ADR steps per node row of the model (the square root of
    /// its node count) tried before Newton; ADR gets the rest of `adr_max_iters` only
    /// where Newton fails too ([`ADR_TRIAL_STEPS_PER_ROW`]).
    pub adr_trial_steps_per_row: usize,
}

impl Default for Fallbacks {
    /// The windows' settings: the switch's refactorisation threshold, at most
    /// [`CHORD_REFACTORS`] refactorisations per chord iteration (fewer after a failed
    /// one), ADR on a trial of [`ADR_TRIAL_STEPS_PER_ROW`] before Newton after a failed
    /// chord iteration, no loose Newton stalls, ADR to `ADR_FALLBACK_TOL` within
    /// `ADR_FALLBACK_MAX_ITERS` steps.
    fn default() -> Self {
        Fallbacks {
            refactor_contraction: CONTRACTION_REFACTOR,
            chord_iters: CHORD_ITERS,
            chord_refactors: Some(CHORD_REFACTORS),
            adr_before_newton: true,
            loose_measure: 0.0,
            adr_tol: ADR_FALLBACK_TOL,
            adr_max_iters: ADR_FALLBACK_MAX_ITERS,
            adr_trial_steps_per_row: ADR_TRIAL_STEPS_PER_ROW,
        }
    }
}

/// The solver that found an equilibrium, with its iterations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solved {
    /// The chord iteration on the kept factor.
    Chord(usize),
    /// Newton.
    Newton(usize),
    /// A Newton stall below [`Fallbacks::loose_measure`].
    Loose(usize),
    /// ADR after Newton failed.
    Adr(usize),
}

/// Equilibria of [`FrozenSolver`]s by the solver that found them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Tally {
    /// By the chord iteration.
    pub chord: usize,
    /// By Newton (first for degrading bonds, else after a failed chord iteration).
    pub newton: usize,
    /// Newton stalls accepted ([`Solved::Loose`]).
    pub loose: usize,
    /// By ADR.
    pub adr: usize,
    /// ADR trials that ran out before Newton ([`Fallbacks::adr_trial_steps_per_row`]).
    pub adr_trials_run_out: usize,
    /// Equilibria no solver found (errors).
    pub failed: usize,
}

impl Tally {
    /// Equilibria the chord iteration did not find: by Newton, a loose Newton stall or
    /// ADR. These are fallbacks for a solver with a chord iteration (brittle bonds, as in
    /// every growth window); without one (degrading bonds) Newton comes first and its
    /// equilibria count here too.
    pub fn fallbacks(&self) -> usize {
        self.newton + self.loose + self.adr
    }

    /// Counts one outcome.
    fn record(&mut self, solved: &Result<Solved, PdError>) {
        match solved {
            Ok(Solved::Chord(_)) => self.chord += 1,
            Ok(Solved::Newton(_)) => self.newton += 1,
            Ok(Solved::Loose(_)) => self.loose += 1,
            Ok(Solved::Adr(_)) => self.adr += 1,
            Err(_) => self.failed += 1,
        }
    }
}

impl AddAssign for Tally {
    fn add_assign(&mut self, o: Tally) {
        self.chord += o.chord;
        self.newton += o.newton;
        self.loose += o.loose;
        self.adr += o.adr;
        self.adr_trials_run_out += o.adr_trials_run_out;
        self.failed += o.failed;
    }
}

impl std::iter::Sum for Tally {
    fn sum<I: Iterator<Item = Tally>>(iter: I) -> Tally {
        iter.fold(Tally::default(), |mut a, b| {
            a += b;
            a
        })
    }
}

impl Solved {
    /// Iterations of the solver that succeeded.
    pub fn iterations(self) -> usize {
        match self {
            Solved::Chord(n) | Solved::Newton(n) | Solved::Loose(n) | Solved::Adr(n) => n,
        }
    }
}

/// The frozen-history solvers of one PD model, kept between equilibria: Newton's tangent
/// pattern and symbolic factorisation, and for brittle bonds the chord iteration with its
/// kept factor. Bonds broken since the last equilibrium are picked up by comparing every
/// bond's stiffness with the factorised one, so the caller may commit between calls.
pub struct FrozenSolver {
    /// `None` when the tangent's pattern is over the memory budget
    /// ([`PdError::TooLarge`]): ADR alone then.
    newton: Option<Newton>,
    chord: Option<SecantSolver>,
    /// Nodes and bonds of the model it was built for.
    shape: (usize, usize),
    /// Its fallback settings.
    pub fallbacks: Fallbacks,
    /// The last chord iteration failed: with a refactorisation limit the next one gets
    /// at most [`STALLED_CHORD_REFACTORS`].
    stalled: bool,
    /// In the windows' order, the last fallback ran out of its ADR trial and Newton
    /// converged: the next one starts with Newton ([`Self::adr_then_newton`]).
    newton_won: bool,
    /// Its equilibria so far, by solver.
    tally: Tally,
}

impl FrozenSolver {
    /// Solvers for `model` with the windows' [`Fallbacks`]. A tangent pattern over the
    /// memory budget leaves ADR alone ([`Self::has_newton`]).
    pub fn new(model: &PdModel) -> Result<Self, PdError> {
        let newton = match Newton::new(model) {
            Ok(n) => Some(n),
            Err(PdError::TooLarge { .. }) => None,
            Err(e) => return Err(e),
        };
        let chord = newton
            .as_ref()
            .filter(|_| matches!(model.law(), BondLaw::Brittle { .. }))
            .map(|n| SecantSolver::new(model, n.tangent.n_free, CHORD_COLUMNS, CHORD_ANDERSON));
        Ok(FrozenSolver {
            newton,
            chord,
            shape: (model.n_nodes(), model.n_bonds()),
            fallbacks: Fallbacks::default(),
            stalled: false,
            newton_won: false,
            tally: Tally::default(),
        })
    }

    /// The same with other fallbacks.
    pub fn with_fallbacks(mut self, fallbacks: Fallbacks) -> Self {
        self.fallbacks = fallbacks;
        self
    }

    /// Newton only (no chord iteration), as for degrading bonds.
    pub fn without_chord(mut self) -> Self {
        self.chord = None;
        self
    }

    /// Whether Newton is available (its tangent pattern within the memory budget).
    pub fn has_newton(&self) -> bool {
        self.newton.is_some()
    }

    /// Whether the chord iteration is used (brittle bonds).
    pub fn has_chord(&self) -> bool {
        self.chord.is_some()
    }

    /// Triangular solve pairs of the chord iteration so far.
    pub fn chord_solves(&self) -> usize {
        self.chord.as_ref().map_or(0, |c| c.solves)
    }

    /// Whether it was built for a model of this size (a window rebuilt after a
    /// relocation needs new solvers).
    pub fn fits(&self, model: &PdModel) -> bool {
        self.shape == (model.n_nodes(), model.n_bonds())
    }

    /// Moves the model to load factor `lam`. With the chord iteration the load is only
    /// set: its first update from the state with the prescribed displacements at `lam`
    /// solves the predictor's linear system with the kept factor. Newton alone starts
    /// from its linear predictor ([`Newton::predict_to`]).
    pub fn predict_to(
        &mut self,
        model: &mut PdModel,
        lam: f64,
        info: &mut SolveInfo,
    ) -> Result<(), PdError> {
        match self.newton.as_mut() {
            Some(newton) if self.chord.is_none() && model.load_factor() != lam => {
                newton.predict_to(model, lam, info)
            }
            _ => {
                model.set_load_factor(lam);
                Ok(())
            }
        }
    }

    /// Its equilibria so far, by solver.
    pub fn tally(&self) -> Tally {
        self.tally
    }

    /// Equilibrium at the model's load with the bond history frozen: the chord iteration
    /// to `params`' tolerances; where it fails Newton and ADR from the same state, in the
    /// order and with the settings of [`Self::fallbacks`] (ADR from Newton's last finite
    /// state, or from `start` if the state is not finite). Returns the solver that
    /// succeeded, and counts it ([`Self::tally`]).
    pub fn equilibrate(
        &mut self,
        model: &mut PdModel,
        params: &ImplicitParams,
        start: &[[f64; 2]],
        info: &mut SolveInfo,
    ) -> Result<Solved, PdError> {
        let solved = self.solve(model, params, start, info);
        self.tally.record(&solved);
        solved
    }

    /// [`Self::equilibrate`] without the count.
    fn solve(
        &mut self,
        model: &mut PdModel,
        params: &ImplicitParams,
        start: &[[f64; 2]],
        info: &mut SolveInfo,
    ) -> Result<Solved, PdError> {
        let fb = self.fallbacks;
        // The state this call starts from: the fallbacks restart from it, ADR from
        // `start` if it is not finite.
        let before = model.displacements().to_vec();
        let from = if all_finite(&before) {
            &before[..]
        } else {
            start
        };
        if self.newton.is_none() {
            return equilibrate_adr(model, from, fb.adr_tol, fb.adr_max_iters, info)
                .map(Solved::Adr);
        }
        if let (Some(chord), Some(newton)) = (self.chord.as_mut(), self.newton.as_mut()) {
            let tangent = &mut newton.tangent;
            let sp = SecantParams {
                convergence: params.convergence,
                residual_tol: params.residual_tol,
                max_iters: fb.chord_iters,
                max_columns: CHORD_COLUMNS,
                anderson_depth: CHORD_ANDERSON,
                refactor_contraction: fb.refactor_contraction,
                max_refactors: fb.chord_refactors.map(|m| {
                    if self.stalled {
                        m.min(STALLED_CHORD_REFACTORS)
                    } else {
                        m
                    }
                }),
            };
            let solved = chord
                .track_changes(model, tangent, info)
                .and_then(|_| chord.equilibrate(model, tangent, &sp, info));
            self.stalled = solved.is_err();
            match solved {
                Ok((iters, _)) => return Ok(Solved::Chord(iters)),
                Err(_) => {
                    // Newton's factorisations replace the kept factor.
                    chord.invalidate();
                    model.set_displacements(&before)?;
                }
            }
            if fb.adr_before_newton {
                return self.adr_then_newton(model, params, (&before, from), info);
            }
        }
        match self.newton_alone(model, params, info) {
            // A tangent whose factor is over the memory budget (`PdError::TooLarge`):
            // ADR needs no factor and reaches the same equilibrium, only slower.
            Err(
                PdError::NoConvergence { .. }
                | PdError::Diverged { .. }
                | PdError::NonFinite { .. }
                | PdError::TooLarge { .. },
            ) => equilibrate_adr(model, from, fb.adr_tol, fb.adr_max_iters, info).map(Solved::Adr),
            other => other,
        }
    }

    /// The windows' order after a failed chord iteration, each solver from the state
    /// `before` (ADR from `from` where that is not finite): ADR on a trial budget
    /// ([`Fallbacks::adr_trial_steps_per_row`]), Newton, then ADR with its full budget.
    /// Failures come in runs (a nearly cut window fails at every coupling iteration until
    /// its state moves on), so after a trial that ran out and a Newton that converged the
    /// next fallback skips the trial, until Newton fails. Errors with the last solver's
    /// error.
    fn adr_then_newton(
        &mut self,
        model: &mut PdModel,
        params: &ImplicitParams,
        (before, from): (&[[f64; 2]], &[[f64; 2]]),
        info: &mut SolveInfo,
    ) -> Result<Solved, PdError> {
        let fb = self.fallbacks;
        let rows = (model.n_nodes() as f64).sqrt().ceil() as usize;
        let trial = if self.newton_won {
            0
        } else {
            fb.adr_trial_steps_per_row
                .saturating_mul(rows)
                .min(fb.adr_max_iters)
        };
        if trial > 0 {
            match equilibrate_adr(model, from, fb.adr_tol, trial, info) {
                Ok(iters) => return Ok(Solved::Adr(iters)),
                Err(_) => {
                    self.tally.adr_trials_run_out += 1;
                    model.set_displacements(before)?;
                }
            }
        }
        let newton = self.newton_alone(model, params, info);
        self.newton_won = newton.is_ok();
        if newton.is_ok() || trial == fb.adr_max_iters {
            return newton;
        }
        model.set_displacements(before)?;
        equilibrate_adr(model, from, fb.adr_tol, fb.adr_max_iters, info).map(Solved::Adr)
    }

    /// Newton from the model's state; a stall below [`Fallbacks::loose_measure`] is
    /// accepted ([`Solved::Loose`]).
    fn newton_alone(
        &mut self,
        model: &mut PdModel,
        params: &ImplicitParams,
        info: &mut SolveInfo,
    ) -> Result<Solved, PdError> {
        let Some(newton) = self.newton.as_mut() else {
            // `equilibrate` gives a solver without Newton to ADR before it gets here.
            return Err(PdError::LinearSolve {
                dofs: 0,
                reason: "no tangent: its pattern or factor is over the memory budget".into(),
            });
        };
        match newton.equilibrate(model, params, info) {
            Ok((iters, _)) => Ok(Solved::Newton(iters)),
            Err(PdError::NoConvergence {
                measure,
                iterations,
                ..
            }) if measure < self.fallbacks.loose_measure => Ok(Solved::Loose(iterations)),
            Err(e) => Err(e),
        }
    }
}

/// Whether every displacement is finite.
fn all_finite(u: &[[f64; 2]]) -> bool {
    u.iter().all(|p| p[0].is_finite() && p[1].is_finite())
}

/// A window's [`FrozenSolver`], built on first use; a clone starts empty. The tally of
/// the solvers it dropped is kept until [`Self::take_tally`].
#[derive(Default)]
pub struct SolverSlot {
    solver: Option<Box<FrozenSolver>>,
    dropped: Tally,
}

impl SolverSlot {
    /// The solvers of `model`, built if there are none or they belong to a model of
    /// another size.
    pub fn get(&mut self, model: &PdModel) -> Result<&mut FrozenSolver, PdError> {
        if !self.solver.as_ref().is_some_and(|s| s.fits(model)) {
            self.clear();
            self.solver = Some(Box::new(FrozenSolver::new(model)?));
        }
        Ok(self.solver.as_mut().expect("just built"))
    }

    /// Drops the solvers (the model was replaced).
    pub fn clear(&mut self) {
        if let Some(s) = self.solver.take() {
            self.dropped += s.tally;
        }
    }

    /// The equilibria of its solvers since the last call, by solver.
    pub fn take_tally(&mut self) -> Tally {
        let mut t = std::mem::take(&mut self.dropped);
        if let Some(s) = self.solver.as_mut() {
            t += std::mem::take(&mut s.tally);
        }
        t
    }
}

impl Clone for SolverSlot {
    fn clone(&self) -> Self {
        SolverSlot::default()
    }
}

impl fmt::Debug for SolverSlot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "SolverSlot({})",
            if self.solver.is_some() {
                "built"
            } else {
                "empty"
            }
        )
    }
}

/// Relative residual of the windows' ADR fallback ([`Fallbacks`]): far below the interface
/// tolerance psi (1e-4 by default) at which the windows' forces are used.
const ADR_FALLBACK_TOL: f64 = 1e-8;

/// ADR steps allowed to the fallback (about a second for a 20 x 20 window).
const ADR_FALLBACK_MAX_ITERS: usize = 200_000;

/// ADR steps per node row tried before Newton ([`Fallbacks::adr_trial_steps_per_row`]).
/// Over the ten shipped growth cases the windows' ADR fallbacks converged in 7-33 steps
/// per row, one in 244 (`growth_inclined_crack`: 6344 steps on 672 nodes). A window that
/// needs far more has a soft mode, a piece nearly cut free, where the chord iteration
/// failed for the same reason; there Newton converged in 2-39 iterations: on
/// `growth_shear_edge_refined` with `growth.damage_threshold: 0.3` (1724 nodes, 42 rows)
/// ADR took 18 700-63 000 steps (7-23 s, 0.35 ms a step), or ran out of its 200 000 (70 s),
/// where Newton took 0.3 s. That run had not ended after 10 minutes with ADR's full budget
/// first; with this trial and [`FrozenSolver`]'s memory of Newton's success it takes 23.5 s
/// (docs/growth_modes.md).
pub const ADR_TRIAL_STEPS_PER_ROW: usize = 100;

/// ADR equilibrium at the model's load with the bond history frozen (no bond breaks),
/// from the current state if it is finite, else from `start`, to the relative residual
/// `tol` within `max_iters` steps. Returns the steps taken.
pub fn equilibrate_adr(
    model: &mut PdModel,
    start: &[[f64; 2]],
    tol: f64,
    max_iters: usize,
    info: &mut SolveInfo,
) -> Result<usize, PdError> {
    if !all_finite(model.displacements()) {
        model.set_displacements(start)?;
    }
    let mut adr = adr::Adr::new(model, 1.5);
    adr.history = History::Frozen;
    let (iters, _, _) = adr.converge(
        model,
        Convergence::Residual { tol },
        1,
        max_iters,
        &mut info.residual_history,
        &mut |_| {},
    )?;
    Ok(iters)
}

#[cfg(test)]
#[path = "frozen_tests.rs"]
mod tests;
