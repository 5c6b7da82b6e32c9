use super::*;
use crate::cases::{bar_tension, BAR_FORCE};
use crate::problem::{BoundaryCondition, Failure, Layer, PdProblem, Selection};
use crate::solvers::implicit::{ImplicitParams, Newton};

/// The bar of [`bar_tension`] (0.2 x 0.02 m, 2000 N at load factor 1) on a grid of
/// spacing `dx` with tanh bonds and a notch at mid-length (cracks `depth` deep from both
/// sides), so that it softens at the notch, away from both ends.
pub(crate) fn notched_bar(dx: f64, depth: f64) -> PdProblem {
    let mut p = bar_tension(dx).problem;
    p.failure = Failure::Degradation {
        s_m: 4e-5,
        s_c: 4e-4,
        beta: 3.0,
    };
    p.cracks = vec![
        vec![[0.1, -0.001], [0.1, depth]],
        vec![[0.1, 0.02 - depth], [0.1, 0.021]],
    ];
    p
}

/// [`notched_bar`] on a 2 mm grid with 6 mm notches (an 8 mm ligament).
fn notched_softening_bar() -> PdProblem {
    notched_bar(0.002, 0.006)
}

fn newton_params() -> ImplicitParams {
    ImplicitParams {
        max_iters: 25,
        ..Default::default()
    }
}

fn ramp(last: f64, n: usize) -> Vec<f64> {
    (1..=n).map(|k| last * k as f64 / n as f64).collect()
}

/// [`notched_bar`] (2 mm grid, 6 mm notches) with its end column pulled by
/// `ux = lambda 1e-5 m` instead of the force.
pub(crate) fn pulled_notched_bar() -> PdProblem {
    let mut p = notched_softening_bar();
    p.boundary[1] = BoundaryCondition::Displacement {
        on: Selection::Box {
            min: [0.2 - p.dx, -1.0],
            max: [0.2, 1.0],
        },
        ux: Some(1e-5),
        uy: None,
        layer: Layer::Real,
    };
    p
}

/// The largest force [`pulled_notched_bar`] carries, ramped in steps of 0.05 until Newton
/// fails (past the peak the bar snaps back) or the force falls: a load the bar is shown
/// to carry.
fn displacement_controlled_peak() -> f64 {
    let mut m = PdModel::new(&pulled_notched_bar()).unwrap();
    let mut newton = Newton::new(&m).unwrap();
    let mut info = SolveInfo::default();
    let mut peak: f64 = 0.0;
    for lam in ramp(3.0, 60) {
        if newton
            .load_step(&mut m, lam, &newton_params(), &mut info)
            .is_err()
        {
            break;
        }
        // The force the pulled column puts on the bar.
        let f = info.steps.last().unwrap().resultants[1].force[0];
        if f < peak {
            break;
        }
        peak = f;
    }
    peak
}

#[test]
fn a_load_controlled_ramp_stops_at_the_capacity_the_displacement_controlled_bar_shows() {
    let carried = displacement_controlled_peak();
    // Load control: 2000 N times the load factor, in steps of 0.25 up to 10 (20 000 N,
    // well past the capacity), halved up to 4 times.
    let mut m = PdModel::new(&notched_softening_bar()).unwrap();
    let mut newton = Newton::new(&m).unwrap();
    let p = newton_params();
    let out = to_limit(
        &mut m,
        &ramp(10.0, 40),
        4,
        "implicit",
        &mut |_| {},
        |m, s, info| {
            newton.load_step(m, s.target, &p, info)?;
            Ok(())
        },
    )
    .unwrap();
    let stop = out.stop.expect("the ramp passes the bar's capacity");
    let (last, failed) = (stop.last_load * BAR_FORCE, stop.failed_load * BAR_FORCE);
    // Measured: the displacement-controlled bar carries 5622 N before its Newton fails
    // (force increments shrinking to 74 N per 0.05); load control converges to 5750 N
    // and fails at 5781 N.
    assert!(
        failed > carried,
        "stopped at {last}-{failed} N below a load the bar carries ({carried} N)"
    );
    assert!(
        last < 1.05 * carried,
        "converged to {last} N, 5 % past the {carried} N of displacement control"
    );
    assert_eq!(stop.cutbacks, 4);
    assert_eq!(out.retries, 4);
    assert!(failed - last <= 0.25 / 16.0 * BAR_FORCE * (1.0 + 1e-9));
    assert!(matches!(stop.error, PdError::NoConvergence { .. }));
    // The model holds the last converged state, the record ends with it.
    assert_eq!(m.load_factor(), stop.last_load);
    assert_eq!(out.info.steps.last().unwrap().load, stop.last_load);
    assert_eq!(out.info.final_load, stop.last_load);
}

/// A model whose state a fake segment moves: the elastic bar on a coarse grid.
fn small_model() -> PdModel {
    PdModel::new(&bar_tension(0.01).problem).unwrap()
}

fn no_convergence(load: f64) -> PdError {
    PdError::NoConvergence {
        solver: "fake",
        iterations: 1,
        load,
        measure: 1.0,
        tolerance: 0.0,
    }
}

#[test]
fn a_failed_segment_is_halved_from_the_kept_state_until_the_limit_is_bracketed() {
    // A fake body with its limit at load factor 3.3: a segment past it fails after
    // moving the model, which the ramp undoes.
    let mut m = small_model();
    let mut asked = Vec::new();
    let mut events = Vec::new();
    let mut observe = |e: &RampEvent| events.push(e.clone());
    let out = to_limit(
        &mut m,
        &ramp(5.0, 5),
        3,
        "fake",
        &mut observe,
        |m, s, info| {
            asked.push((s.target, s.level, s.restored));
            m.set_load_factor(s.target);
            if s.target > 3.3 {
                m.set_displacements(&vec![[1.0, 0.0]; m.n_nodes()]).unwrap();
                return Err(no_convergence(s.target).into());
            }
            info.steps.push(crate::solvers::StepRecord {
                load: s.target,
                iterations: 1,
                broken_bonds: 0,
                max_stretch: 0.0,
                measure: 0.0,
                kind: crate::solvers::PhaseKind::Implicit,
                resultants: Vec::new(),
            });
            Ok(())
        },
    )
    .unwrap();
    let stop = out.stop.unwrap();
    // 1, 2, 3 converge; 4 fails; 3.5 (half the step) fails; 3.25 (a quarter)
    // converges; 3.5 fails; 3.375 (an eighth, the last halving) fails: the limit lies in
    // (3.25, 3.375].
    let targets: Vec<f64> = asked.iter().map(|a| a.0).collect();
    assert_eq!(targets, [1.0, 2.0, 3.0, 4.0, 3.5, 3.25, 3.5, 3.375]);
    assert_eq!(
        asked.iter().map(|a| (a.1, a.2)).collect::<Vec<_>>(),
        [
            (0, false),
            (0, false),
            (0, false),
            (0, false),
            (1, true),
            (2, true),
            (2, false),
            (3, true)
        ]
    );
    assert_eq!(
        (stop.last_load, stop.failed_load, stop.cutbacks),
        (3.25, 3.375, 3)
    );
    assert_eq!(m.load_factor(), 3.25);
    // Every converged segment and every halving is reported, in order.
    let halving = |failed_load, level| RampEvent::Halving {
        failed_load,
        level,
        max: 3,
    };
    let converged = |load| RampEvent::Converged { load };
    assert_eq!(
        events,
        [
            converged(1.0),
            converged(2.0),
            converged(3.0),
            halving(4.0, 1),
            halving(3.5, 2),
            converged(3.25),
            halving(3.5, 3),
        ]
    );
    assert!(m.displacements().iter().all(|u| *u == [0.0, 0.0]));
    assert_eq!(out.info.steps.len(), 4);
}

#[test]
fn a_segment_that_failed_part_way_keeps_what_it_reached() {
    // A solver of several increments that fails at 2.5 after converging at 2.0.
    let mut m = small_model();
    let mut asked = Vec::new();
    let out = to_limit(&mut m, &[4.0], 1, "fake", &mut |_| {}, |m, s, _| {
        asked.push(s.target);
        if s.target > 2.5 {
            m.set_load_factor(2.0);
            return Err(SegmentFailure {
                error: no_convergence(2.5),
                reached: Some(2.0),
                failed_at: Some(2.5),
            });
        }
        m.set_load_factor(s.target);
        Ok(())
    })
    .unwrap();
    // The first try reaches 2.0; the second goes on from there with half the
    // increment (to 4.0 at most), fails again at 2.5 and is the last.
    assert_eq!(asked, [4.0, 4.0]);
    let stop = out.stop.unwrap();
    assert_eq!((stop.last_load, stop.failed_load), (2.0, 2.5));
    assert_eq!(m.load_factor(), 2.0);
}

#[test]
fn errors_that_are_not_a_failed_equilibrium_end_the_ramp_as_errors() {
    let mut m = small_model();
    let e = to_limit(&mut m, &[1.0, 2.0], 4, "fake", &mut |_| {}, |_, _, _| {
        Err(PdError::invalid("failure.s_c", "test").into())
    })
    .unwrap_err();
    assert!(matches!(e, PdError::InvalidInput { .. }), "{e}");
    // A converged runaway state is a failed equilibrium: halved, then the stop; the step
    // it recorded is dropped with it.
    let mut m = small_model();
    let out = to_limit(&mut m, &[1.0], 1, "fake", &mut |_| {}, |m, s, info| {
        m.set_load_factor(s.target);
        m.set_displacements(&vec![[100.0, 0.0]; m.n_nodes()])
            .unwrap();
        let kind = crate::solvers::PhaseKind::Implicit;
        let record = crate::solvers::StepRecord::of(m, s.target, 1, 0.0, 0.0, kind);
        info.steps.push(record);
        Ok(())
    })
    .unwrap();
    let stop = out.stop.unwrap();
    assert!(
        matches!(stop.error, PdError::Runaway { .. }),
        "{:?}",
        stop.error
    );
    assert_eq!(stop.last_load, 0.0);
    assert!(out.info.steps.is_empty());
    // Halvings beyond MAX_CUTBACKS are MAX_CUTBACKS (no shift past the integer's width).
    let mut m = small_model();
    let out = to_limit(&mut m, &[1.0], 100, "fake", &mut |_| {}, |_, s, _| {
        Err(no_convergence(s.target).into())
    })
    .unwrap();
    assert_eq!(out.stop.unwrap().cutbacks, MAX_CUTBACKS);
}

#[test]
fn a_falling_ramp_is_driven_and_halved_like_a_rising_one() {
    // Compression: load factors 0 -> -1 -> -2, the fake limit at -1.3.
    let mut m = small_model();
    let mut asked = Vec::new();
    let out = to_limit(&mut m, &[-1.0, -2.0], 2, "fake", &mut |_| {}, |m, s, _| {
        asked.push(s.target);
        m.set_load_factor(s.target);
        if s.target < -1.3 {
            return Err(no_convergence(s.target).into());
        }
        Ok(())
    })
    .unwrap();
    assert_eq!(asked, [-1.0, -2.0, -1.5, -1.25, -1.5]);
    let stop = out.stop.unwrap();
    assert_eq!((stop.last_load, stop.failed_load), (-1.25, -1.5));
    assert_eq!(m.load_factor(), -1.25);
}
