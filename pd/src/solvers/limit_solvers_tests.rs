use super::*;
use crate::cases::{plate_hole, BAR_FORCE};
use crate::solvers::limit::LimitedSolve;
use crate::solvers::limit::RampEvent;
use crate::solvers::{adr, implicit, Convergence, PROGRESS_EVERY};

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
    let mut events = Vec::new();
    let out = solve_to_limit(&mut m, &solver, 4, &mut |e| events.push(e.clone())).unwrap();
    let heard: Vec<f64> = events
        .iter()
        .filter_map(|e| match e {
            RampEvent::Converged { load } => Some(*load),
            _ => None,
        })
        .collect();
    let stop = out
        .stop
        .clone()
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
    // Every accepted step or increment was reported as it converged, and the damage
    // increments' rounds as they went.
    assert!(
        out.info.steps.iter().all(|st| heard.contains(&st.load)),
        "{heard:?}"
    );
    let (reports, by_adr) = check_reports("switching", &events, &out);
    eprintln!("switching: {reports} progress reports, {by_adr} of ADR");
    assert!(reports > 0);
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
    let mut events = Vec::new();
    let out = solve_to_limit(&mut m, &adr, 4, &mut |e| events.push(e.clone())).unwrap();
    let (reports, by_adr) = check_reports("adr", &events, &out);
    eprintln!("adr: {reports} progress reports");
    assert!(by_adr > 0 && by_adr == reports);
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

/// Checks the progress reports among a ramp's `events` against its record `out` and
/// returns how many there were and how many came from ADR: reported while a step iterated
/// (between the events that end the steps before and it, at its load), iterations and
/// rounds growing within the step's count and budget; a secant increment once per round,
/// the last report being the step's (its iterations and the bonds it broke); ADR every
/// [`PROGRESS_EVERY`] iterations of a round, with the bonds the rounds before broke.
fn check_reports(name: &str, events: &[RampEvent], out: &LimitedSolve) -> (usize, usize) {
    let (mut pending, mut total, mut by_adr) = (Vec::new(), 0, 0);
    for e in events {
        let load = match e {
            RampEvent::Iterating(r) => {
                pending.push(*r);
                continue;
            }
            RampEvent::Converged { load } => *load,
            RampEvent::Halving { failed_load, .. } => *failed_load,
        };
        let at = std::mem::take(&mut pending);
        total += at.len();
        by_adr += at.iter().filter(|r| r.solver == "adr").count();
        assert!(
            at.iter().all(|r| r.load == load),
            "{name}: {at:?} at {load}"
        );
        // Within one solver (a secant increment that fails goes on by ADR from its start).
        assert!(at.windows(2).all(|w| w[0].solver != w[1].solver
            || (w[0].iterations < w[1].iterations && w[0].round.0 <= w[1].round.0)));
        assert!(at
            .iter()
            .all(|r| r.round.0 <= r.round.1 && r.measure.is_finite()));
        let RampEvent::Converged { .. } = e else {
            continue;
        };
        let k = out.info.steps.iter().rposition(|s| s.load == load).unwrap();
        let step = &out.info.steps[k];
        let before = k
            .checked_sub(1)
            .map_or(0, |j| out.info.steps[j].broken_bonds);
        let broken_here = step.broken_bonds - before;
        let of_kind: Vec<_> = at
            .iter()
            .filter(|r| (r.solver == "adr") == (step.kind == PhaseKind::Explicit))
            .collect();
        assert!(of_kind.iter().all(|r| r.iterations <= step.iterations));
        match step.kind {
            PhaseKind::Explicit => {
                assert!(of_kind.len() * PROGRESS_EVERY <= step.iterations, "{name}");
                assert!(of_kind
                    .iter()
                    .all(|r| r.broken.is_some_and(|b| b <= broken_here)));
            }
            PhaseKind::Secant => {
                let last = of_kind
                    .last()
                    .expect("a secant increment reports its rounds");
                assert_eq!(of_kind.len(), last.round.0, "{name}");
                assert_eq!(last.iterations, step.iterations, "{name}");
                assert_eq!(last.broken, Some(broken_here), "{name}");
            }
            PhaseKind::Implicit => assert!(at.is_empty(), "{name}: Newton reports none"),
        }
    }
    (total, by_adr)
}
