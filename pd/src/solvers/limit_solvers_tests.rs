use super::*;
use crate::cases::{plate_hole, BAR_FORCE};
use crate::solvers::limit::RampEvent;
use crate::solvers::{adr, implicit, Convergence};

/// Seed 000's plate with a hole on a 12 x 12 grid, pulled to 0.8 of the seed's end
/// displacement in steps of 0.1 (bonds degrading past s_m; Newton in steps of 1/6 stops
/// converging at 0.83), each solver through its own `solve` and through
/// [`solve_to_limit`].
#[test]
fn without_a_failure_every_solver_does_what_its_solve_does() {
    let case = plate_hole(12);
    let conv = Convergence::Displacement { e0: 1e-9 };
    let solvers = [
        QuasiStatic::Implicit(ImplicitParams {
            target_load: 0.8,
            steps: 8,
            convergence: conv,
            ..Default::default()
        }),
        QuasiStatic::Adr(AdrParams {
            target_load: 0.8,
            steps: 8,
            convergence: conv,
            ..Default::default()
        }),
        QuasiStatic::Switching(SwitchingParams {
            target_load: 0.8,
            implicit_steps: case.implicit_steps,
            explicit_steps: 30,
            convergence: conv,
            ..Default::default()
        }),
    ];
    for solver in &solvers {
        let mut plain = PdModel::new(&case.problem).unwrap();
        let info = match solver {
            QuasiStatic::Implicit(p) => implicit::solve(&mut plain, p),
            QuasiStatic::Adr(p) => adr::solve(&mut plain, p),
            QuasiStatic::Switching(p) => switching::solve(&mut plain, p),
        }
        .unwrap();
        let mut ramped = PdModel::new(&case.problem).unwrap();
        let out = solve_to_limit(&mut ramped, solver, 4, &mut |_| {}).unwrap();
        let name = solver.name();
        assert!(out.stop.is_none() && out.retries == 0, "{name}");
        let s_max = info.steps.last().unwrap().max_stretch;
        assert!(s_max > 0.015, "{name}: the bonds degrade ({s_max})");
        assert_eq!(ramped.displacements(), plain.displacements(), "{name}");
        assert_eq!(ramped.broken_bonds(), plain.broken_bonds(), "{name}");
        let loads = |i: &SolveInfo| i.steps.iter().map(|s| s.load).collect::<Vec<_>>();
        assert_eq!(loads(&out.info), loads(&info), "{name}");
        assert_eq!(out.info.iterations, info.iterations, "{name}");
        assert_eq!(out.info.phases.len(), info.phases.len(), "{name}");
        assert_eq!(out.info.final_load, info.final_load, "{name}");
    }
}

/// The notched tanh bar of the ramp's tests on a 4 mm grid with 5 mm notches (a 10 mm
/// ligament), pulled by its end load.
fn notched_bar() -> crate::PdProblem {
    crate::solvers::limit::tests::notched_bar(0.004, 0.005)
}

#[test]
fn the_switching_solver_stops_where_newton_brackets_the_capacity() {
    // Newton's bracket of the bar's capacity, in load steps of 0.25 halved 4 times.
    let mut m = PdModel::new(&notched_bar()).unwrap();
    let newton = QuasiStatic::Implicit(ImplicitParams {
        target_load: 5.0,
        steps: 20,
        max_iters: 25,
        ..Default::default()
    });
    let n = solve_to_limit(&mut m, &newton, 4, &mut |_| {})
        .unwrap()
        .stop
        .unwrap();
    // The switching solver from 0.25 increments, with smaller ADR budgets than its
    // defaults (ADR fails past the limit only at its caps).
    let mut m = PdModel::new(&notched_bar()).unwrap();
    let solver = QuasiStatic::Switching(SwitchingParams {
        target_load: 5.0,
        implicit_steps: 5,
        explicit_steps: 20,
        max_adr_iters: 20_000,
        max_break_rounds: 10,
        ..Default::default()
    });
    let mut heard = Vec::new();
    let mut observe = |e: &RampEvent| {
        if let RampEvent::Converged { load } = e {
            heard.push(*load);
        }
    };
    let out = solve_to_limit(&mut m, &solver, 4, &mut observe).unwrap();
    let stop = out
        .stop
        .expect("5 times the bar's 2000 N is past its capacity");
    let (last, failed) = (stop.last_load * BAR_FORCE, stop.failed_load * BAR_FORCE);
    let (n_last, n_failed) = (n.last_load * BAR_FORCE, n.failed_load * BAR_FORCE);
    // Measured: both stop between 8375 and 8406 N (load factors 4.1875 and 4.203125).
    let width = 0.25 / 16.0 * BAR_FORCE;
    assert!(
        (last - n_last).abs() <= width * (1.0 + 1e-9) && n_failed > n_last,
        "switching stopped at {last}-{failed} N, Newton at {n_last}-{n_failed} N"
    );
    // Halved 4 times from increments of 0.25: the bracket is a sixteenth of one.
    assert!(failed - last <= width * (1.0 + 1e-9));
    assert_eq!(m.load_factor(), stop.last_load);
    assert_eq!(out.info.final_load, stop.last_load);
    assert_eq!(out.info.steps.last().unwrap().load, stop.last_load);
    // The record of the segments reads as one solve's: the steps in order.
    assert!(out.info.steps.windows(2).all(|w| w[0].load < w[1].load));
    // Every accepted step or increment was reported as it converged.
    assert!(
        out.info.steps.iter().all(|st| heard.contains(&st.load)),
        "{heard:?}"
    );
}

/// ADR through the ramp: equilibria at every step (rest restarts after a restore), and
/// the stop where Newton brackets the capacity.
#[test]
fn adr_stops_where_newton_brackets_the_capacity() {
    let newton = QuasiStatic::Implicit(ImplicitParams {
        target_load: 5.0,
        steps: 20,
        max_iters: 25,
        ..Default::default()
    });
    let mut m = PdModel::new(&notched_bar()).unwrap();
    let n = solve_to_limit(&mut m, &newton, 4, &mut |_| {})
        .unwrap()
        .stop
        .unwrap();
    // Steps of 1.0 halved 4 times: a bracket of 0.0625 (125 N).
    let adr = QuasiStatic::Adr(AdrParams {
        target_load: 5.0,
        steps: 5,
        max_iters: 20_000,
        max_break_rounds: 10,
        ..Default::default()
    });
    let mut m = PdModel::new(&notched_bar()).unwrap();
    let out = solve_to_limit(&mut m, &adr, 4, &mut |_| {}).unwrap();
    let stop = out.stop.expect("past the capacity");
    eprintln!("{n:?}\n{stop:?} {}", out.retries);
    // Measured: Newton 4.1875-4.203125, ADR 4.1875-4.25 (a converged state at 4.1875
    // from rest after the restore, where Newton converged too).
    assert!(stop.failed_load - stop.last_load <= 1.0 / 16.0 + 1e-12);
    assert!(
        stop.last_load <= n.failed_load + 1e-12 && stop.failed_load >= n.last_load,
        "ADR {:?}, Newton {:?}",
        (stop.last_load, stop.failed_load),
        (n.last_load, n.failed_load)
    );
    assert_eq!(m.load_factor(), stop.last_load);
    assert_eq!(out.info.steps.last().unwrap().load, stop.last_load);
}

#[test]
fn a_failed_switching_increment_is_placed_in_the_ramp_direction() {
    // Rising from 1 to 2 in increments of 0.25, failed from 1.5: reached 1.5, failed 1.75.
    assert_eq!(failed_increment(1.0, 1.5, 0.25, 2.0), (Some(1.5), 1.75));
    // Failed in the first increment: nothing reached; the last increment ends at the
    // target.
    assert_eq!(failed_increment(1.0, 1.0, 0.25, 2.0), (None, 1.25));
    assert_eq!(failed_increment(1.0, 1.9, 0.25, 2.0), (Some(1.9), 2.0));
    // Falling (compression) from -1 to -2.
    assert_eq!(
        failed_increment(-1.0, -1.5, -0.25, -2.0),
        (Some(-1.5), -1.75)
    );
    assert_eq!(failed_increment(-1.0, -1.0, -0.25, -2.0), (None, -1.25));
    assert_eq!(
        failed_increment(-1.0, -1.9, -0.25, -2.0),
        (Some(-1.9), -2.0)
    );
}
