//! Tests of the frozen-history solver (`super`): Newton, the chord iteration and ADR reach
//! the same equilibria, and the fallbacks take over where one fails.

use super::*;
use crate::cases::bar_tension;

fn loaded_bar() -> PdModel {
    let case = bar_tension(0.005);
    let mut m = PdModel::new(&case.problem).unwrap();
    m.set_load_factor(case.target_load);
    m
}

#[test]
fn adr_takes_over_a_failed_newton_solve_and_finds_the_same_equilibrium() {
    let params = ImplicitParams::default();
    let mut by_newton = loaded_bar();
    let start = by_newton.displacements().to_vec();
    let mut solver = FrozenSolver::new(&by_newton).unwrap();
    assert!(!solver.has_chord(), "elastic bonds: Newton alone");
    let mut info = SolveInfo::default();
    let solved = solver
        .equilibrate(&mut by_newton, &params, &start, &mut info)
        .unwrap();
    assert!(
        matches!(solved, Solved::Newton(it) if it > 0 && it < 10),
        "Newton converges by itself: {solved:?}"
    );
    // No Newton iteration allowed: Newton reports no convergence and ADR takes over.
    let mut by_adr = loaded_bar();
    let starved = ImplicitParams {
        max_iters: 0,
        ..params
    };
    let solved = FrozenSolver::new(&by_adr)
        .unwrap()
        .equilibrate(&mut by_adr, &starved, &start, &mut info)
        .unwrap();
    assert!(matches!(solved, Solved::Adr(it) if it > 100), "{solved:?}");
    let (a, b) = (by_newton.displacements(), by_adr.displacements());
    let scale = a.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
    assert!(scale > 0.0);
    let diff = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x[0] - y[0]).hypot(x[1] - y[1]))
        .fold(0.0, f64::max);
    assert!(
        diff < 1e-6 * scale,
        "ADR vs Newton: {diff:.3e} of {scale:.3e}"
    );
}

/// Seed 001's edge-cracked plate (brittle bonds), 30 x 30 nodes, at `load` MPa.
fn edge_plate(load: f64) -> PdModel {
    use crate::cases::{seed001_crack, CrackKind};
    let mut m = PdModel::new(&seed001_crack(CrackKind::Edge, 30).problem).unwrap();
    m.set_load_factor(load);
    m
}

/// Newton's equilibrium of `model` from its state, with a fresh solver.
fn by_newton(mut model: PdModel, params: &ImplicitParams) -> PdModel {
    let start = model.displacements().to_vec();
    let mut info = SolveInfo::default();
    let solved = FrozenSolver::new(&model)
        .unwrap()
        .without_chord()
        .equilibrate(&mut model, params, &start, &mut info)
        .unwrap();
    assert!(matches!(solved, Solved::Newton(_)), "{solved:?}");
    model
}

/// Equilibrium of `m` by the slot's solver, which must be the chord iteration's.
fn by_chord(
    slot: &mut SolverSlot,
    m: &mut PdModel,
    params: &ImplicitParams,
    start: &[[f64; 2]],
    info: &mut SolveInfo,
) {
    let solved = slot
        .get(m)
        .unwrap()
        .equilibrate(m, params, start, info)
        .unwrap();
    assert!(matches!(solved, Solved::Chord(_)), "{solved:?}");
}

/// Newton settings converging to a residual of 1e-9.
fn tight() -> ImplicitParams {
    ImplicitParams {
        convergence: Convergence::Residual { tol: 1e-9 },
        residual_tol: 1e-9,
        ..Default::default()
    }
}

#[test]
fn a_window_out_of_refactorisations_goes_to_adr_and_tries_less_the_next_time() {
    let params = ImplicitParams {
        convergence: Convergence::Residual { tol: 1e-13 },
        residual_tol: 1e-13,
        ..Default::default()
    };
    // A threshold every iteration misses: each one after the first asks to refactorise.
    let fb = Fallbacks {
        refactor_contraction: -1.0,
        chord_refactors: Some(3),
        ..Fallbacks::default()
    };
    let reference = by_newton(edge_plate(6.0), &params);
    let mut m = edge_plate(6.0);
    let start = m.displacements().to_vec();
    let mut solver = FrozenSolver::new(&m).unwrap().with_fallbacks(fb);
    let mut info = SolveInfo::default();
    let solved = solver
        .equilibrate(&mut m, &params, &start, &mut info)
        .unwrap();
    assert!(matches!(solved, Solved::Adr(_)), "{solved:?}");
    let d = reference.relative_displacement_gap(&m);
    assert!(d < 1e-6, "ADR vs Newton: {d:.2e}");
    // The first factor and the 3 refactorisations allowed.
    assert_eq!(info.factorizations, 4);
    // The same equilibrium again: after the failure the chord iteration gets one.
    m.set_displacements(&start).unwrap();
    let mut again = SolveInfo::default();
    let solved = solver
        .equilibrate(&mut m, &params, &start, &mut again)
        .unwrap();
    assert!(matches!(solved, Solved::Adr(_)), "{solved:?}");
    assert_eq!(again.factorizations, 2);
}

#[test]
fn the_kept_solver_finds_newtons_equilibria_without_refactorising_for_a_new_load() {
    let params = tight();
    let mut m = edge_plate(4.0);
    let mut slot = SolverSlot::default();
    let mut info = SolveInfo::default();
    let start = m.displacements().to_vec();
    by_chord(&mut slot, &mut m, &params, &start, &mut info);
    assert_eq!(
        info.factorizations, 1,
        "one factorisation for the first solve"
    );
    // A new load: the kept factor serves.
    m.set_load_factor(6.0);
    by_chord(&mut slot, &mut m, &params, &start, &mut info);
    assert_eq!(info.factorizations, 1, "no factorisation for the new load");
    let d = by_newton(edge_plate(6.0), &params).relative_displacement_gap(&m);
    assert!(d < 1e-7, "kept solver vs Newton at 6 MPa: {d:.2e}");
    // Bonds break: the change is picked up by comparison, Newton's state is found.
    m.set_load_factor(20.0);
    by_chord(&mut slot, &mut m, &params, &start, &mut info);
    let broken = m.commit_history().newly_broken;
    assert!(broken > 0, "bonds break at the tip at 20 MPa on this grid");
    let mut reference = m.clone();
    reference.set_displacements(&start).unwrap();
    let reference = by_newton(reference, &params);
    by_chord(&mut slot, &mut m, &params, &start, &mut info);
    let d = reference.relative_displacement_gap(&m);
    assert!(
        d < 1e-7,
        "kept solver vs Newton after {broken} bonds broke: {d:.2e}"
    );

    // A clone starts empty; a model of another size gets new solvers.
    assert!(format!("{:?}", slot.clone()).contains("empty"));
    let other = edge_plate(1.0);
    let mut small =
        PdModel::new(&crate::cases::seed001_crack(crate::cases::CrackKind::Edge, 20).problem)
            .unwrap();
    small.set_load_factor(1.0);
    assert!(slot.get(&m).unwrap().fits(&other));
    assert!(!slot.get(&m).unwrap().fits(&small));
    slot.get(&small).unwrap();
    assert!(slot.get(&small).unwrap().fits(&small));
}

#[test]
fn after_a_failed_chord_iteration_adr_comes_before_newton_in_the_windows() {
    let params = tight();
    let reference = by_newton(edge_plate(6.0), &params);
    let mut info = SolveInfo::default();
    // The chord iteration gets no iteration: ADR takes over (the windows' order).
    let starved = |m: &PdModel, fb: Fallbacks| {
        FrozenSolver::new(m).unwrap().with_fallbacks(Fallbacks {
            chord_iters: 0,
            ..fb
        })
    };
    let mut m = edge_plate(6.0);
    let start = m.displacements().to_vec();
    let solved = starved(&m, Fallbacks::default())
        .equilibrate(&mut m, &params, &start, &mut info)
        .unwrap();
    assert!(matches!(solved, Solved::Adr(it) if it > 0), "{solved:?}");
    let d = reference.relative_displacement_gap(&m);
    assert!(d < 1e-6, "ADR vs Newton: {d:.2e}");
    // ADR starved too: Newton from the same start.
    let mut m = edge_plate(6.0);
    let no_adr = Fallbacks {
        adr_max_iters: 0,
        ..Fallbacks::default()
    };
    let solved = starved(&m, no_adr)
        .equilibrate(&mut m, &params, &start, &mut info)
        .unwrap();
    assert!(matches!(solved, Solved::Newton(_)), "{solved:?}");
    let d = reference.relative_displacement_gap(&m);
    assert!(d < 1e-9, "Newton after ADR failed vs Newton: {d:.2e}");
    // Newton first (the full-PD order): Newton succeeds, ADR is not needed.
    let mut m = edge_plate(6.0);
    let newton_first = Fallbacks {
        adr_before_newton: false,
        ..Fallbacks::default()
    };
    let solved = starved(&m, newton_first)
        .equilibrate(&mut m, &params, &start, &mut info)
        .unwrap();
    assert!(matches!(solved, Solved::Newton(_)), "{solved:?}");
}

#[test]
fn an_adr_trial_that_runs_out_hands_over_to_newton_which_then_comes_first() {
    let params = tight();
    let reference = by_newton(edge_plate(6.0), &params);
    // No chord iteration, and an ADR trial of one step per row: too short to converge.
    let mut m = edge_plate(6.0);
    let start = m.displacements().to_vec();
    let mut solver = FrozenSolver::new(&m).unwrap().with_fallbacks(Fallbacks {
        chord_iters: 0,
        adr_trial_steps_per_row: 1,
        ..Fallbacks::default()
    });
    let mut info = SolveInfo::default();
    let mut solve = |solver: &mut FrozenSolver, m: &mut PdModel, params: &ImplicitParams| {
        m.set_displacements(&start).unwrap();
        solver.equilibrate(m, params, &start, &mut info).unwrap()
    };
    let solved = solve(&mut solver, &mut m, &params);
    assert!(matches!(solved, Solved::Newton(_)), "{solved:?}");
    let d = reference.relative_displacement_gap(&m);
    assert!(d < 1e-9, "Newton after the ADR trial vs Newton: {d:.2e}");
    // A trial ADR would pass is skipped while Newton keeps converging.
    solver.fallbacks.adr_trial_steps_per_row = 10_000;
    let solved = solve(&mut solver, &mut m, &params);
    assert!(matches!(solved, Solved::Newton(_)), "{solved:?}");
    // Newton fails: ADR with its full budget, and the next fallback tries ADR first again.
    let starved = ImplicitParams {
        max_iters: 0,
        ..params.clone()
    };
    let solved = solve(&mut solver, &mut m, &starved);
    assert!(matches!(solved, Solved::Adr(it) if it > 30), "{solved:?}");
    let d = reference.relative_displacement_gap(&m);
    assert!(d < 1e-6, "ADR after Newton failed vs Newton: {d:.2e}");
    let solved = solve(&mut solver, &mut m, &params);
    assert!(matches!(solved, Solved::Adr(_)), "{solved:?}");
}

#[test]
fn a_slot_tallies_the_equilibria_of_its_solvers_across_rebuilds() {
    let params = tight();
    let mut m = edge_plate(6.0);
    let start = m.displacements().to_vec();
    let mut slot = SolverSlot::default();
    let mut info = SolveInfo::default();
    by_chord(&mut slot, &mut m, &params, &start, &mut info);
    by_chord(&mut slot, &mut m, &params, &start, &mut info);
    // The solvers are dropped; their count stays with the slot.
    slot.clear();
    // A starved chord iteration: ADR's trial (one step per row) runs out, Newton finds it.
    slot.get(&m).unwrap().fallbacks = Fallbacks {
        chord_iters: 0,
        adr_trial_steps_per_row: 1,
        ..Fallbacks::default()
    };
    m.set_displacements(&start).unwrap();
    let solved = slot
        .get(&m)
        .unwrap()
        .equilibrate(&mut m, &params, &start, &mut info)
        .unwrap();
    assert!(matches!(solved, Solved::Newton(_)), "{solved:?}");
    let t = slot.take_tally();
    let expected = Tally {
        chord: 2,
        newton: 1,
        adr_trials_run_out: 1,
        ..Tally::default()
    };
    assert_eq!(t, expected);
    assert_eq!(t.fallbacks(), 1);
    // Taken: the next count starts from zero.
    assert_eq!(slot.take_tally(), Tally::default());
}

#[test]
fn a_non_finite_newton_state_restarts_adr_from_the_given_start() {
    let mut m = loaded_bar();
    let start = m.displacements().to_vec();
    let mut bad = start.clone();
    bad[3] = [f64::NAN, 0.0];
    m.set_displacements(&bad).unwrap();
    let mut info = SolveInfo::default();
    let solved = FrozenSolver::new(&m)
        .unwrap()
        .equilibrate(&mut m, &ImplicitParams::default(), &start, &mut info)
        .unwrap();
    assert!(matches!(solved, Solved::Adr(_)), "{solved:?}");
    assert!(m
        .displacements()
        .iter()
        .all(|u| u[0].is_finite() && u[1].is_finite()));
}
