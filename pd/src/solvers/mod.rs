//! Quasi-static solvers, one interface: a params struct in,
//! `Result<SolveInfo, PdError>` out (faer / argmin style).
//!
//! - [`adr`]: adaptive dynamic relaxation (seed 002 Eqs. 9-15, Kilic & Madenci).
//! - [`implicit`]: Newton-Raphson on the full nonlinear equilibrium with the
//!   analytic tangent (seed 000 section 2).
//! - [`switching`]: implicit while no bond passes the damage onset, the
//!   failure increments by the secant re-commit rounds (ADR if those fail),
//!   implicit again once failure stops (seed 000 section 4).
//! - [`frozen`]: equilibrium with the bond history frozen (chord iteration on a
//!   kept [`secant`] factor, Newton and ADR fallbacks), for the coupling's
//!   windows and full-PD growth.
//! - [`secant`]: the secant equilibria of the re-commit rounds with one
//!   Cholesky factor and Woodbury low-rank updates (used by [`switching`]).
//!
//! All three measure convergence the same way ([`Convergence`]): the relative
//! whole-field displacement change of seed 000 Eq. 16,
//! $e_u = \|u_n - u_{n-1}\|_2 / \|u_{n-1}\|_2 < e_0$, or the relative force
//! residual $\|R_{free}\|_2 / \|R_{ref}\|_2$ with $R_{ref}$ the larger of the
//! applied body forces and the support reactions. Each solver drives the
//! load factor from its current value to `target_load` in equal steps.

pub mod adr;
pub mod anderson;
pub mod frozen;
pub mod implicit;
pub mod limit;
pub mod limit_solvers;
pub mod secant;
pub mod switching;

use serde::Serialize;

use crate::error::PdError;
use crate::geometry::P2;
use crate::model::PdModel;

/// Iterations between two [`Iterating`] reports of a long equilibrium search.
pub const PROGRESS_EVERY: usize = 1000;

/// How far an iterative equilibrium search has got at one load: sent every
/// [`PROGRESS_EVERY`] iterations of ADR and after every secant re-commit round, so an
/// observer can show a solve that crawls, a softened body's for one, while it crawls
/// rather than only when it ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Iterating {
    /// The solver iterating.
    pub solver: &'static str,
    /// The load factor of the equilibrium searched for.
    pub load: f64,
    /// Iterations of this equilibrium so far, over all its bond-breaking rounds.
    pub iterations: usize,
    /// The bond-breaking round (1 first) and the most the equilibrium may take.
    pub round: (usize, usize),
    /// The iterations a round may take.
    pub max_iterations: usize,
    /// The convergence measure now (the last round's, between rounds).
    pub measure: f64,
    /// The tolerance of [`Self::measure`].
    pub tolerance: f64,
    /// Bonds broken at this load so far, where the rounds commit them (none while ADR
    /// breaks bonds inside its iterations).
    pub broken: Option<usize>,
}

/// Convergence measure shared by all solvers.
#[derive(Clone, Copy, Debug, PartialEq, serde::Deserialize, Serialize)]
pub enum Convergence {
    /// Relative displacement change per iteration below `e0` (seed 000 Eq. 16).
    Displacement {
        /// Tolerance (seed 000 uses 1e-9).
        e0: f64,
    },
    /// Relative force residual below `tol`.
    Residual {
        /// Tolerance.
        tol: f64,
    },
}

impl Convergence {
    /// The tolerance its measure must fall below.
    pub fn tolerance(self) -> f64 {
        match self {
            Convergence::Displacement { e0 } => e0,
            Convergence::Residual { tol } => tol,
        }
    }
}

impl Default for Convergence {
    /// Seed 000 section 3: `e0 = 1e-9`.
    fn default() -> Self {
        Convergence::Displacement { e0: 1e-9 }
    }
}

/// Solver phase kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum PhaseKind {
    /// Newton-Raphson.
    Implicit,
    /// Adaptive dynamic relaxation.
    Explicit,
    /// Secant re-commit rounds solved implicitly ([`secant`]): the
    /// switching solver's failure increments.
    Secant,
}

/// One contiguous run of one solver kind.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Phase {
    /// Solver kind.
    pub kind: PhaseKind,
    /// Load factor at the start.
    pub load_start: f64,
    /// Load factor at the end.
    pub load_end: f64,
    /// Iterations (Newton or secant iterations, or ADR steps).
    pub iterations: usize,
    /// Wall time (s).
    pub time_s: f64,
}

/// Where the switching solver changed phase.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SwitchPoint {
    /// Load factor at the switch.
    pub load: f64,
    /// Total iterations done before the switch.
    pub iteration: usize,
    /// Phase entered.
    pub to: PhaseKind,
    /// Why.
    pub reason: String,
}

/// Result of one load step.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StepRecord {
    /// Load factor.
    pub load: f64,
    /// Iterations in the step.
    pub iterations: usize,
    /// Broken bond pairs after the step (cumulative, pre-cracks excluded).
    pub broken_bonds: usize,
    /// Largest stretch of an intact bond.
    pub max_stretch: f64,
    /// Final convergence measure of the step.
    pub measure: f64,
    /// Solver kind of the step.
    pub kind: PhaseKind,
    /// Force and displacement of every boundary condition at the end of the step
    /// ([`crate::reaction`]): the load-displacement record.
    pub resultants: Vec<crate::reaction::BcResultant>,
}

impl StepRecord {
    /// The record of a load step that converged at load factor `load` in `iterations`,
    /// with the model's broken bonds and boundary resultants now.
    pub(crate) fn of(
        model: &mut PdModel,
        load: f64,
        iterations: usize,
        max_stretch: f64,
        measure: f64,
        kind: PhaseKind,
    ) -> StepRecord {
        StepRecord {
            load,
            iterations,
            broken_bonds: model.broken_bonds(),
            max_stretch,
            measure,
            kind,
            resultants: model.bc_resultants(),
        }
    }
}

/// What a solve did.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SolveInfo {
    /// Total iterations (Newton and secant iterations + ADR steps).
    pub iterations: usize,
    /// Convergence measure per Newton iteration, and per 100 ADR steps plus
    /// the last one of each step.
    pub residual_history: Vec<f64>,
    /// Bond pairs broken during this solve.
    pub bonds_broken: usize,
    /// Load factor reached.
    pub final_load: f64,
    /// Load steps.
    pub steps: Vec<StepRecord>,
    /// Solver phases in order.
    pub phases: Vec<Phase>,
    /// Switch points (switching solver).
    pub switch_points: Vec<SwitchPoint>,
    /// Time in implicit phases, secant rounds included (s).
    pub time_implicit_s: f64,
    /// Time in explicit phases (s).
    pub time_explicit_s: f64,
    /// Of the implicit time, tangent assembly (s).
    pub time_assembly_s: f64,
    /// Of the implicit time, factorisation and solve (s).
    pub time_factorization_s: f64,
    /// Number of numeric factorisations.
    pub factorizations: usize,
    /// Newton steps solved on a kept factor instead of a new one
    /// ([`implicit::Newton`]).
    pub kept_factor_solves: usize,
    /// Factorisations that fell back to LU.
    pub lu_fallbacks: usize,
    /// Switching solver: secant equilibria solved by Newton in damage
    /// increments (re-commit rounds).
    pub secant_rounds: usize,
    /// Switching solver: damage increments handed to ADR because Newton
    /// failed.
    pub adr_fallbacks: usize,
    /// Total wall time (s).
    pub wall_time_s: f64,
}

impl SolveInfo {
    /// Closes a single-phase solve that drove the load from `lam0` to `target` in `dt`
    /// seconds: records the phase, the final load, the bonds broken since `broken0` and the
    /// wall time.
    pub(crate) fn finish_single_phase(
        &mut self,
        kind: PhaseKind,
        lam0: f64,
        target: f64,
        dt: f64,
        bonds_broken: usize,
    ) {
        self.push_phase(kind, lam0, target, self.iterations, dt);
        self.final_load = target;
        self.bonds_broken = bonds_broken;
        self.wall_time_s = dt;
    }

    /// Adds the record of a later solve from this one's end state: its counters and
    /// times, its steps, switch points and phases (a phase continuing this one's last of
    /// the same kind joins it). The final load is the later solve's.
    pub fn absorb(&mut self, later: SolveInfo) {
        self.iterations += later.iterations;
        self.residual_history.extend(later.residual_history);
        self.bonds_broken += later.bonds_broken;
        self.final_load = later.final_load;
        self.steps.extend(later.steps);
        self.switch_points.extend(later.switch_points);
        for ph in later.phases {
            self.join_phase(ph);
        }
        self.time_implicit_s += later.time_implicit_s;
        self.time_explicit_s += later.time_explicit_s;
        self.time_assembly_s += later.time_assembly_s;
        self.time_factorization_s += later.time_factorization_s;
        self.factorizations += later.factorizations;
        self.kept_factor_solves += later.kept_factor_solves;
        self.lu_fallbacks += later.lu_fallbacks;
        self.secant_rounds += later.secant_rounds;
        self.adr_fallbacks += later.adr_fallbacks;
        self.wall_time_s += later.wall_time_s;
    }

    pub(crate) fn push_phase(
        &mut self,
        kind: PhaseKind,
        load_start: f64,
        load_end: f64,
        iterations: usize,
        time_s: f64,
    ) {
        match kind {
            PhaseKind::Implicit | PhaseKind::Secant => self.time_implicit_s += time_s,
            PhaseKind::Explicit => self.time_explicit_s += time_s,
        }
        self.join_phase(Phase {
            kind,
            load_start,
            load_end,
            iterations,
            time_s,
        });
    }

    /// Appends `phase`, or extends the last phase when it is of the same kind (the
    /// totals of time are the caller's).
    fn join_phase(&mut self, phase: Phase) {
        if let Some(last) = self.phases.last_mut() {
            if last.kind == phase.kind {
                last.load_end = phase.load_end;
                last.iterations += phase.iterations;
                last.time_s += phase.time_s;
                return;
            }
        }
        self.phases.push(phase);
    }
}

/// Residual norms at the current state, from the force densities already in
/// `model.force`: (free-DOF residual, reference). The reference is the larger
/// of the applied body force and the reaction at prescribed DOFs.
pub(crate) fn residual_norms(model: &PdModel) -> (f64, f64) {
    let (mut r2, mut b2, mut re2) = (0.0, 0.0, 0.0);
    let lam = model.load;
    for i in 0..model.force.len() {
        let f = model.force[i];
        let b = model.bc.body[i];
        for c in 0..2 {
            let bi = lam * b[c];
            b2 += bi * bi;
            if model.bc.fixed[i][c] {
                re2 += f[c] * f[c];
            } else {
                let r = f[c] + bi;
                r2 += r * r;
            }
        }
    }
    (r2.sqrt(), b2.sqrt().max(re2.sqrt()))
}

/// Squared norm of a displacement field over the free DOFs.
pub(crate) fn norm2_free(u: &[P2], fixed: &[[bool; 2]]) -> f64 {
    let mut s = 0.0;
    for (x, f) in u.iter().zip(fixed) {
        for c in 0..2 {
            if !f[c] {
                s += x[c] * x[c];
            }
        }
    }
    s
}

/// Refuses a state with a real node displaced by more than the body's size (the diagonal
/// of the nodes' bounding box) beyond the largest prescribed displacement
/// ([`PdError::Runaway`]). Loads below a strain of 1 (what `pdbem check` allows) move no
/// node that far at an equilibrium; a solver that reaches such a state has found nodes
/// held by bonds that carry no force, not an equilibrium of the body.
pub fn check_bounded(model: &PdModel, solver: &'static str) -> Result<(), PdError> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for x in &model.grid.pos {
        for c in 0..2 {
            lo[c] = lo[c].min(x[c]);
            hi[c] = hi[c].max(x[c]);
        }
    }
    let size = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let norm = |u: &P2| u[0].hypot(u[1]);
    let prescribed = (0..model.n_nodes())
        .filter(|&i| model.bc.fixed[i][0] || model.bc.fixed[i][1])
        .map(|i| norm(&model.u[i]))
        .fold(0.0, f64::max);
    let displacement = model.u[..model.n_real()]
        .iter()
        .map(norm)
        .fold(0.0, f64::max);
    if displacement > prescribed + size {
        return Err(PdError::Runaway {
            solver,
            load: model.load,
            displacement,
            prescribed,
            size,
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{BoundaryCondition, Layer, PdProblem, Region, Selection};

    #[test]
    fn a_node_beyond_the_body_size_is_a_runaway_state() {
        let mut m = PdModel::new(&PdProblem {
            region: Region::rectangle([0.0, 0.0], [3.0, 4.0]),
            dx: 0.5,
            youngs_modulus: 1.0,
            boundary: vec![BoundaryCondition::Displacement {
                on: Selection::Box {
                    min: [-1.0, -1.0],
                    max: [0.0, 5.0],
                },
                ux: Some(0.0),
                uy: Some(0.0),
                layer: Layer::Fictitious,
            }],
            ..Default::default()
        })
        .unwrap();
        // A strain of 0.5 moves the far edge by 1.5 m, within the box's diagonal (about
        // 6 m with the layer): accepted.
        let strained: Vec<P2> = m.positions().iter().map(|x| [0.5 * x[0], 0.0]).collect();
        m.set_displacements(&strained).unwrap();
        check_bounded(&m, "test").unwrap();
        // One node 100 m away: refused, with the sizes named.
        let mut far = strained.clone();
        far[m.n_real() / 2] = [0.0, 100.0];
        m.set_displacements(&far).unwrap();
        let e = check_bounded(&m, "test").unwrap_err();
        assert!(matches!(e, PdError::Runaway { .. }), "{e}");
        let text = e.to_string();
        assert!(
            text.contains("1.000e2 m") && text.contains("runaway"),
            "{text}"
        );
    }
}
