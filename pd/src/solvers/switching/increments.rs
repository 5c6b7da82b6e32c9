//! The damage increments of the switching solver: the secant re-commit rounds on one
//! kept factor, and ADR where they fail (or by choice, [`super::DamageSolver`]).

use std::time::Instant;

use super::{Increment, Switcher};
use crate::error::PdError;
use crate::model::PdModel;
use crate::solvers::{Iterating, PhaseKind, StepRecord};

impl<'p> Switcher<'p> {
    /// Increment `k -> k + 1` with bond failure: the secant rounds, or ADR
    /// if they fail (or by choice), whose progress goes to `progress`. Returns whether
    /// any bond's damage grew.
    pub(super) fn damage_increment(
        &mut self,
        model: &mut PdModel,
        k: usize,
        progress: &mut dyn FnMut(&Iterating),
    ) -> Result<bool, PdError> {
        let ts = Instant::now();
        let (lam, next) = (self.load_at(k), self.load_at(k + 1));
        let mut inc = None;
        // The state the increment starts from: the secant rounds' fallback, and where
        // a failed increment leaves the model ([`super::solve_partial`]).
        model.save_into(&mut self.saved);
        if self.secant_enabled() {
            match self.secant_rounds(model, next, progress) {
                Ok(out) => inc = Some(out),
                Err(e) => {
                    model.restore(&self.saved);
                    self.info.adr_fallbacks += 1;
                    self.switch(
                        PhaseKind::Explicit,
                        lam,
                        format!("the secant rounds failed at load {next}: {e}"),
                    );
                }
            }
        }
        let inc = match inc {
            Some(out) => out,
            None => self.adr_increment(model, next, progress)?,
        };
        self.adr_warm = inc.kind == PhaseKind::Explicit;
        self.info.iterations += inc.iterations;
        self.info.steps.push(StepRecord {
            load: next,
            iterations: inc.iterations,
            broken_bonds: model.broken_bonds(),
            max_stretch: inc.stats.max_stretch,
            measure: inc.measure,
            kind: inc.kind,
            resultants: model.bc_resultants(),
        });
        self.info.push_phase(
            inc.kind,
            lam,
            next,
            inc.iterations,
            ts.elapsed().as_secs_f64(),
        );
        Ok(inc.grew)
    }

    /// The secant re-commit rounds at load `lam`, each equilibrium by the
    /// chord iteration of [`SecantSolver`] (the first one also carries the
    /// load increment, as a linear predictor would). `progress` hears of every round.
    fn secant_rounds(
        &mut self,
        model: &mut PdModel,
        lam: f64,
        progress: &mut dyn FnMut(&Iterating),
    ) -> Result<Increment, PdError> {
        model.set_load_factor(lam);
        let (mut iterations, mut grew) = (0, false);
        let tangent = &mut self.newton.tangent;
        // Bonds may have changed since the last round (an ADR increment).
        self.secant.track_changes(model, tangent, &mut self.info)?;
        let rounds = self.p.max_break_rounds.max(1);
        let broken0 = model.broken_bonds();
        for round in 1..=rounds {
            let (it, measure) =
                self.secant
                    .equilibrate(model, tangent, &self.sp, &mut self.info)?;
            iterations += it;
            self.info.secant_rounds += 1;
            let stats = model.commit_history();
            self.secant.track_changes(model, tangent, &mut self.info)?;
            grew |= stats.growing > 0;
            progress(&Iterating {
                solver: "secant re-commit rounds",
                load: lam,
                iterations,
                round: (round, rounds),
                max_iterations: self.sp.max_iters,
                measure,
                tolerance: self.sp.convergence.tolerance(),
                broken: Some(model.broken_bonds() - broken0),
            });
            if stats.newly_broken == 0 && stats.max_growth <= self.growth_tol {
                return Ok(Increment {
                    iterations,
                    measure,
                    stats,
                    grew,
                    kind: PhaseKind::Secant,
                });
            }
        }
        Err(PdError::NoConvergence {
            solver: "switching (secant re-commit rounds)",
            iterations: self.p.max_break_rounds,
            load: lam,
            measure: f64::NAN,
            tolerance: self.growth_tol,
        })
    }

    /// One increment to load `lam` by ADR with the re-commit rounds.
    fn adr_increment(
        &mut self,
        model: &mut PdModel,
        lam: f64,
        progress: &mut dyn FnMut(&Iterating),
    ) -> Result<Increment, PdError> {
        model.set_load_factor(lam);
        if !self.adr_warm {
            self.adr.reset();
        }
        let (iterations, measure, stats, grew) = self.adr.equilibrate(
            model,
            self.p.convergence,
            self.p.iters_per_explicit_step.max(1),
            self.p.max_adr_iters,
            self.p.max_break_rounds,
            &mut self.info.residual_history,
            progress,
        )?;
        Ok(Increment {
            iterations,
            measure,
            stats,
            grew,
            kind: PhaseKind::Explicit,
        })
    }
}
