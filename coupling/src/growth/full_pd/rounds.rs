//! The load steps of full-PD growth: equilibria with the bond history frozen, and the
//! break rounds between them.
//!
//! Equilibrium ([`Equilibrium::solve`]): brittle bonds take the secant chord iteration of
//! [`pdbem_pd::solvers::secant`] (one factorised tangent $K_0$ kept over many rounds, the
//! bonds broken since corrected by Woodbury updates, Anderson mixing); for brittle bonds
//! the secant and the frozen-history forces are the same, so it converges to the same
//! equilibrium as Newton. Newton (seed 000 Eq. 5) takes over where the chord iteration
//! fails, and ADR where Newton fails: `pdbem_pd::solvers::frozen::FrozenSolver`, the solvers
//! of the PD-BEM windows, with the whole-body settings of [`Equilibrium::new`].
//! Degrading bonds go to Newton directly (their secant force, at the committed
//! history, is not the frozen-history force Newton balances).
//!
//! Why the chord iteration: each break round changes some ten bond pairs, a rank-ten
//! change of the tangent. Newton refactorised the 160 000-DOF tangent of the shear plate
//! at dx = 0.05 m two or three times per round; the chord iteration solves with the kept
//! factor (see the module note of `pdbem_pd::solvers::secant` for the cost model).

use crate::error::CouplingError;
use crate::growth::checkpoint::SolverWork;

use pdbem_pd::material::BondLaw;
use pdbem_pd::solvers::frozen::{Fallbacks, FrozenSolver, Solved};
use pdbem_pd::solvers::implicit::ImplicitParams;
use pdbem_pd::solvers::{Convergence, SolveInfo};
use pdbem_pd::{PdError, PdModel};

/// A full-PD growth error with `message`; [`message_of`] gives the message back.
pub(super) fn fail(message: String) -> CouplingError {
    CouplingError::Growth {
        mode: "full-PD",
        message,
    }
}

/// The message of a full-PD growth error, without the mode prefix (for notes).
pub(super) fn message_of(e: &CouplingError) -> String {
    match e {
        CouplingError::Growth { message, .. } => message.clone(),
        other => other.to_string(),
    }
}

/// A PD error of the whole-body model as a full-PD growth error.
pub(super) fn pd_fail(e: PdError) -> CouplingError {
    fail(e.to_string())
}

/// Outcome of tracking after a break round.
pub(super) enum Tracked {
    /// Keep going.
    Continue,
    /// The body came apart: stop the step.
    Separated,
}

/// Newton equilibria that stall above the tolerance but below this displacement-change
/// measure after 10 iterations are accepted: a node that lost all its bonds has no
/// stiffness and its update does not settle (measured 2.3e-5 half way through the
/// 200 x 100 node edge-cracked plate, where Newton had converged to 1e-6 before; with 50
/// iterations per stalled round the run took over 10 minutes).
pub(super) const LOOSE_MEASURE: f64 = 1e-3;

/// ADR steps per node row of the grid allowed to the ADR fallback. Measured on
/// `growth_shear_edge` at dx = 0.1 m (200 x 100 nodes): four fallbacks, all converged,
/// in the step where the crack ran to the clamped edge; that step took 617 s of the run's
/// 836 s (Newton alone had stopped there and called it collapse, 492 s in all).
const ADR_STEPS_PER_ROW: usize = 200;

/// Contraction per chord iteration above which the factor is renewed. Higher than the
/// windows' 0.1 (`pdbem_pd::solvers::secant::CONTRACTION_REFACTOR`): the factorisations
/// here are of the whole body. Measured on `growth_tension_edge` at dx = 0.1 m (40 000
/// DOFs, 2 cores, identical paths): 0.1: 327 factorisations and 3255 solves, 246 s;
/// 0.3: 223 and 3394, 181 s; 0.6: 175 and 3566, 170 s (Newton: 618 s).
const REFACTOR_CONTRACTION: f64 = 0.6;

/// Chord iterations per equilibrium before Newton takes over.
const CHORD_ITERS: usize = 50;

/// Equilibria not found by the first solver.
#[derive(Debug, Default)]
pub(super) struct Counts {
    /// Left by the chord iteration to Newton (and ADR).
    pub newton: usize,
    /// Newton stalled below [`LOOSE_MEASURE`].
    pub loose: usize,
    /// Found by ADR after Newton failed.
    pub adr: usize,
}

/// The solvers of the frozen-history equilibria ([`FrozenSolver`]) and their bookkeeping.
pub(super) struct Equilibrium {
    solver: FrozenSolver,
    ip: ImplicitParams,
    pub counts: Counts,
    pub info: SolveInfo,
    /// Chord solves of the solvers dropped by [`Equilibrium::renew`].
    chord_solves_done: usize,
    /// The scene's iteration budgets ([`Equilibrium::set_effort`] scales them).
    base: (ImplicitParams, Fallbacks),
}

impl Equilibrium {
    /// Solvers for `model`: tolerances 1e-6 as in [`pdbem_pd::measure::ramp_to_initiation`];
    /// ADR to a residual of 1e-6 within [`ADR_STEPS_PER_ROW`] steps per node row; Newton
    /// stalls below [`LOOSE_MEASURE`] accepted.
    pub fn new(model: &PdModel) -> Result<Self, PdError> {
        let rows = (model.n_real() as f64).sqrt().ceil() as usize;
        let fallbacks = Fallbacks {
            refactor_contraction: REFACTOR_CONTRACTION,
            chord_iters: CHORD_ITERS,
            // No limit: with the windows' 8 the failed chord iterations went to Newton on the
            // whole body, and `growth_tension_edge` took 186 s instead of 115 s.
            chord_refactors: None,
            adr_before_newton: false,
            loose_measure: LOOSE_MEASURE,
            adr_tol: 1e-6,
            adr_max_iters: ADR_STEPS_PER_ROW * rows,
            // Newton comes before ADR here.
            adr_trial_steps_per_row: 0,
        };
        let ip = ImplicitParams {
            residual_tol: 1e-6,
            convergence: Convergence::Displacement { e0: 1e-6 },
            max_iters: 10,
            ..Default::default()
        };
        Ok(Equilibrium {
            solver: FrozenSolver::new(model)?.with_fallbacks(fallbacks),
            ip: ip.clone(),
            counts: Counts::default(),
            info: SolveInfo::default(),
            chord_solves_done: 0,
            base: (ip, fallbacks),
        })
    }

    /// Drops the kept factorisations (new solvers for `model`, same settings and
    /// counters): done at the end of every load step, so that a run resumed from a
    /// checkpoint repeats an uninterrupted one bit for bit.
    pub fn renew(&mut self, model: &PdModel) -> Result<(), PdError> {
        self.chord_solves_done += self.solver.chord_solves();
        let fallbacks = self.solver.fallbacks;
        let chord = self.solver.has_chord();
        let mut solver = FrozenSolver::new(model)?.with_fallbacks(fallbacks);
        if !chord {
            solver = solver.without_chord();
        }
        self.solver = solver;
        Ok(())
    }

    /// Iteration budgets of Newton, the chord iteration and ADR at `factor` times the
    /// scene's (1: the scene's; the back-off of a step raises them).
    pub fn set_effort(&mut self, factor: usize) {
        let (ip, fb) = &self.base;
        self.ip.max_iters = ip.max_iters * factor;
        self.solver.fallbacks.chord_iters = fb.chord_iters * factor;
        self.solver.fallbacks.adr_max_iters = fb.adr_max_iters * factor;
    }

    /// The counters of the `solver` log event, for a checkpoint.
    pub fn work_done(&self) -> SolverWork {
        SolverWork {
            factorizations: self.info.factorizations,
            chord_solves: self.chord_solves_done + self.solver.chord_solves(),
            assembly_s: self.info.time_assembly_s,
            factor_and_solve_s: self.info.time_factorization_s,
            newton: self.counts.newton,
            loose: self.counts.loose,
            adr: self.counts.adr,
        }
    }

    /// Takes the counters of a checkpoint.
    pub fn set_work(&mut self, w: &SolverWork) {
        self.info.factorizations = w.factorizations;
        self.chord_solves_done = w.chord_solves - self.solver.chord_solves();
        self.info.time_assembly_s = w.assembly_s;
        self.info.time_factorization_s = w.factor_and_solve_s;
        self.counts = Counts {
            newton: w.newton,
            loose: w.loose,
            adr: w.adr,
        };
    }

    /// The solver work so far, for the run log: factorisations of the tangent (Newton,
    /// predictor and chord iteration), the chord iteration's triangular solves, the
    /// seconds spent assembling and in factorisations and solves, the fallbacks.
    pub fn work(&self) -> serde_json::Value {
        serde_json::json!({
            "factorizations": self.info.factorizations,
            "chord_solves": self.chord_solves_done + self.solver.chord_solves(),
            "assembly_s": self.info.time_assembly_s,
            "factor_and_solve_s": self.info.time_factorization_s,
            "newton_fallbacks": self.counts.newton,
            "loose": self.counts.loose,
            "adr_fallbacks": self.counts.adr,
        })
    }

    /// Moves the model to load `f` ([`FrozenSolver::predict_to`]).
    pub fn predict_to(&mut self, model: &mut PdModel, f: f64) -> Result<(), PdError> {
        self.solver.predict_to(model, f, &mut self.info)
    }

    /// Equilibrium at the model's load with the bond history frozen
    /// ([`FrozenSolver::equilibrate`]: the chord iteration, Newton, ADR), counting the
    /// fallbacks; the failure of all is the error.
    pub fn solve(&mut self, model: &mut PdModel) -> Result<(), CouplingError> {
        let start = model.displacements().to_vec();
        let solved = self
            .solver
            .equilibrate(model, &self.ip, &start, &mut self.info)
            .map_err(|e| {
                fail(format!(
                    "no frozen-bond equilibrium (chord iteration, Newton, ADR): {e}"
                ))
            })?;
        if self.solver.has_chord() && !matches!(solved, Solved::Chord(_)) {
            self.counts.newton += 1;
        }
        match solved {
            Solved::Loose(_) => self.counts.loose += 1,
            Solved::Adr(_) => self.counts.adr += 1,
            Solved::Chord(_) | Solved::Newton(_) => {}
        }
        Ok(())
    }
}

/// Directed bonds broken together in a sequentially linear round: the most stretched ones,
/// about half a grid spacing of crack advance at m = 3 (some 20 directed bonds cross a
/// crack segment of length dx). Fewer means more equilibrium solves for the same path
/// (one bond pair per round took minutes on a 100 x 100 grid).
const BONDS_PER_ROUND: usize = 20;

/// One load step. Brittle bonds (PMB with s0): sequentially linear rounds (sequentially
/// linear analysis, Rots, Belletti & Invernizzi 2008, Eng. Fract. Mech. 75:590):
/// equilibrium at the step's load f; if the largest stretch passes s0, the state is
/// scaled down to the load at which only the most stretched bonds pass s0 (the response
/// is nearly linear for a fixed set of bonds),
/// those bonds break (`commit_history` at the scaled state), and equilibrium at f is
/// sought again. Breaking every bond past s0 at once (Jacobi rounds) instead smears the
/// damage over a wide zone as soon as growth turns unstable under load control (measured on
/// a 40 x 40 node edge-cracked plate: a 15 mm wide damaged blob instead of a crack).
/// Degrading bonds: Jacobi rounds as in `pdbem_pd::solvers::implicit::Newton::load_step`. `after` runs after every
/// round that broke bonds (tracking) and may end the step.
///
/// `first_round`: 0 for a fresh step (the state is moved to load f first), else the
/// round to go on from at load f (a run resumed inside the step). Every
/// [`RENEW_ROUNDS`]-th round ends with new solvers ([`Equilibrium::renew`]); `after`
/// gets the model, the solvers and the round index.
pub(super) fn load_step(
    model: &mut PdModel,
    eq: &mut Equilibrium,
    (f, first_round): (f64, usize),
    max_rounds: usize,
    mut after: impl FnMut(&PdModel, &Equilibrium, usize) -> Result<Tracked, CouplingError>,
) -> Result<(), CouplingError> {
    let brittle = matches!(model.law(), BondLaw::Brittle { .. });
    let s0 = model.law().damage_onset();
    if first_round == 0 {
        eq.predict_to(model, f).map_err(pd_fail)?;
    }
    for round in first_round..max_rounds {
        eq.solve(model)?;
        let broken = if brittle {
            break_most_stretched(model, f, s0)?
        } else {
            model.commit_history().newly_broken
        };
        if broken == 0 {
            return Ok(());
        }
        if renews_after(round) {
            eq.renew(model).map_err(pd_fail)?;
        }
        if let Tracked::Separated = after(model, eq, round)? {
            return Ok(());
        }
    }
    Err(fail(format!(
        "bonds still breaking after {max_rounds} equilibrium rounds at load {f}"
    )))
}

/// Break rounds of a load step after which the solvers are renewed: a checkpoint taken
/// there ([`crate::growth::events::EngineObserver::round_checkpoint`]) is resumed bit for
/// bit by a run that starts with new solvers. Measured on the 40 x 40 node edge plate of
/// `tests/growth_resume.rs` (57 rounds in its last step): 92 factorisations without the
/// renewal; the chord iteration refactorises every few rounds anyway.
pub const RENEW_ROUNDS: usize = 25;

/// Whether the solvers are renewed after round `round` (0-based) of a step.
pub(super) fn renews_after(round: usize) -> bool {
    (round + 1).is_multiple_of(RENEW_ROUNDS)
}

/// One sequentially linear round at the equilibrium of load `f`: when the largest stretch
/// passes `s0`, scales the state down until only the [`BONDS_PER_ROUND`] most stretched
/// bonds pass s0 and breaks them (`commit_history` at the scaled state); returns the
/// directed bonds broken (0: the state holds at `f`). The displacements are restored to
/// the load-f state.
fn break_most_stretched(model: &mut PdModel, f: f64, s0: f64) -> Result<usize, CouplingError> {
    let st = model.stretch_stats();
    // NaN stretches (a diverged state) break nothing either.
    if st.max_stretch.is_nan() || st.max_stretch <= s0 {
        return Ok(0);
    }
    let u: Vec<[f64; 2]> = model.displacements().to_vec();
    let scale = if st.growing <= 2 * BONDS_PER_ROUND {
        1.0
    } else {
        critical_scale(model, &u, f, s0 / st.max_stretch)?
    };
    set_scaled(model, &u, f, scale)?;
    let broken = model.commit_history().newly_broken;
    set_scaled(model, &u, f, 1.0)?;
    Ok(broken)
}

/// The state `scale u` at load `scale f`.
fn set_scaled(
    model: &mut PdModel,
    u: &[[f64; 2]],
    f: f64,
    scale: f64,
) -> Result<(), CouplingError> {
    let v: Vec<[f64; 2]> = u.iter().map(|p| [p[0] * scale, p[1] * scale]).collect();
    model.set_load_factor(f * scale);
    model.set_displacements(&v).map_err(pd_fail)?;
    Ok(())
}

/// Scale in (0, 1] of the load-f state at which between [`BONDS_PER_ROUND`] and twice as
/// many directed bonds pass s0, by bisection on the count (monotone in the scale); `lo` is
/// a scale at which at most the most stretched bond passes (s0 / s_max). The stretch is
/// linear in the displacements only for small rotations (a nearly cut plate reached
/// 0.96 s0 instead of 1.02 s0 by linear scaling), hence the count rather than a formula.
fn critical_scale(
    model: &mut PdModel,
    u: &[[f64; 2]],
    f: f64,
    lo: f64,
) -> Result<f64, CouplingError> {
    let (mut lo, mut hi) = (lo.min(1.0), 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        set_scaled(model, u, f, mid)?;
        let n = model.stretch_stats().growing;
        if n < BONDS_PER_ROUND {
            lo = mid;
        } else if n > 2 * BONDS_PER_ROUND {
            hi = mid;
        } else {
            return Ok(mid);
        }
        if hi - lo < 1e-12 {
            break;
        }
    }
    Ok(hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pdbem_pd::cases::{seed001_crack, CrackKind};

    /// Seed 001's edge-cracked plate, 40 x 40 nodes, brittle bonds, at rest.
    fn edge_plate() -> PdModel {
        PdModel::new(&seed001_crack(CrackKind::Edge, 40).problem).unwrap()
    }

    /// Newton alone, as for degrading bonds.
    fn newton_only(model: &PdModel) -> Equilibrium {
        let mut eq = Equilibrium::new(model).unwrap();
        let fallbacks = eq.solver.fallbacks;
        eq.solver = FrozenSolver::new(model)
            .unwrap()
            .without_chord()
            .with_fallbacks(fallbacks);
        eq
    }

    #[test]
    fn chord_iteration_breaks_the_same_bonds_as_newton_with_fewer_factorisations() {
        // 12 MPa: above the plate's LEFM load at this resolution, so bonds break in many
        // rounds (the crack runs), and the chord iteration must follow every round.
        let load = 12.0;
        let rounds = 40;
        let mut by_chord = edge_plate();
        let mut chord = Equilibrium::new(&by_chord).unwrap();
        assert!(
            chord.solver.has_chord(),
            "brittle bonds take the chord iteration"
        );
        let chord_done = load_step(&mut by_chord, &mut chord, (load, 0), rounds, |_, _, _| {
            Ok(Tracked::Continue)
        })
        .is_ok();
        let mut by_newton = edge_plate();
        let mut newton = newton_only(&by_newton);
        let newton_done = load_step(&mut by_newton, &mut newton, (load, 0), rounds, |_, _, _| {
            Ok(Tracked::Continue)
        })
        .is_ok();
        // Both settle within the rounds or both still break bonds after them.
        assert_eq!(chord_done, newton_done);
        let broken = by_chord.broken_bonds();
        assert!(broken > 200, "the crack runs: {broken} broken bonds");
        assert_eq!(broken, by_newton.broken_bonds(), "same bonds broken");
        assert!(
            by_chord.bond_intact() == by_newton.bond_intact(),
            "same bonds broken"
        );
        let gap = by_newton.relative_displacement_gap(&by_chord);
        assert!(gap < 1e-4, "chord vs Newton: {gap:.3e}");
        let (fc, fn_) = (chord.info.factorizations, newton.info.factorizations);
        assert!(2 * fc < fn_, "factorisations: chord {fc}, Newton {fn_}");
        assert_eq!(chord.counts.newton + chord.counts.adr, 0, "no fallback");
    }

    #[test]
    fn newton_then_adr_take_over_where_the_chord_iteration_fails() {
        let load = 5.0;
        let mut reference = edge_plate();
        reference.set_load_factor(load);
        let mut eq = Equilibrium::new(&reference).unwrap();
        eq.solve(&mut reference).unwrap();
        assert_eq!(eq.counts.newton + eq.counts.adr, 0);

        // No chord iteration and no Newton iteration allowed: ADR must find it.
        let mut starved = edge_plate();
        starved.set_load_factor(load);
        let mut eq = Equilibrium::new(&starved).unwrap();
        eq.solver.fallbacks.chord_iters = 0;
        eq.ip.max_iters = 0;
        eq.solve(&mut starved).unwrap();
        assert_eq!((eq.counts.newton, eq.counts.adr), (1, 1));
        let gap = reference.relative_displacement_gap(&starved);
        assert!(gap < 1e-4, "ADR vs chord: {gap:.3e}");

        // Newton alone after a failed chord iteration.
        let mut by_newton = edge_plate();
        by_newton.set_load_factor(load);
        let mut eq = Equilibrium::new(&by_newton).unwrap();
        eq.solver.fallbacks.chord_iters = 0;
        eq.solve(&mut by_newton).unwrap();
        assert_eq!((eq.counts.newton, eq.counts.adr), (1, 0));
        let gap = reference.relative_displacement_gap(&by_newton);
        assert!(gap < 1e-5, "Newton vs chord: {gap:.3e}");
    }

    /// Displacements after every round of a 12 MPa step on [`edge_plate`] (bonds break
    /// in every round), from round `from` of a run stopped after round `from - 1` and
    /// resumed with new solvers from the model state there (`from` 0: the whole step).
    fn rounds_from(from: usize) -> Vec<Vec<[f64; 2]>> {
        let (load, rounds) = (12.0, 40);
        let mut model = edge_plate();
        if from > 0 {
            let mut eq = Equilibrium::new(&model).unwrap();
            let stop = |_: &PdModel, _: &Equilibrium, round: usize| {
                Ok(if round + 1 == from {
                    Tracked::Separated
                } else {
                    Tracked::Continue
                })
            };
            load_step(&mut model, &mut eq, (load, 0), rounds, stop).unwrap();
            let state = model.state();
            model = edge_plate();
            model.try_restore(&state).unwrap();
        }
        let mut eq = Equilibrium::new(&model).unwrap();
        let mut out = Vec::new();
        let _ = load_step(&mut model, &mut eq, (load, from), rounds, |m, _, _| {
            out.push(m.displacements().to_vec());
            Ok(Tracked::Continue)
        });
        out
    }

    #[test]
    fn a_step_resumed_after_a_renewal_round_repeats_it_bit_for_bit() {
        let whole = rounds_from(0);
        assert!(whole.len() > RENEW_ROUNDS + 5, "{} rounds", whole.len());
        // After round 24 the solvers were renewed: the resumed rounds are the same bits.
        let from = RENEW_ROUNDS;
        assert!(
            rounds_from(from) == whole[from..],
            "resumed after a renewal"
        );
        // After other rounds the kept factorisation carries over and the bits differ
        // (measured at every one of these).
        let differ: Vec<usize> = [6, 12, 18]
            .into_iter()
            .filter(|&r| rounds_from(r) != whole[r..])
            .collect();
        assert_eq!(
            differ,
            [6, 12, 18],
            "rounds without renewal whose resume differs"
        );
    }
}
