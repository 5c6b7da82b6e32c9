use super::*;
use crate::relaxation::test_maps::{iterations, Rotated};

/// Aitken without the jump safeguard (the scheme before the restart and fallback).
fn unguarded(w0: f64) -> Aitken {
    let mut a = Aitken::new(w0);
    a.jump_factor = f64::INFINITY;
    a
}

#[test]
fn aitken_weight_is_exact_for_a_scalar_linear_map() {
    let mut a = Aitken::new(0.5);
    a.w_max = 10.0;
    let h = |x: f64| -3.0 * x + 2.0; // fixed point 0.5, optimal w = 1/(1+3)
    let x0 = 0.0;
    let x1 = a.next(&[x0], &[h(x0)])[0];
    let x2 = a.next(&[x1], &[h(x1)])[0];
    assert!((a.last_weight().unwrap() - 0.25).abs() < 1e-12);
    assert!((x2 - 0.5).abs() < 1e-12);
}

#[test]
fn aitken_keeps_its_weight_when_the_secant_weight_is_not_positive() {
    // Two steps whose residual grew along the step: the secant weight is negative.
    let mut a = unguarded(0.4);
    a.next(&[0.0, 0.0], &[1.0, 0.0]);
    let w_before = a.last_weight().unwrap();
    // x moved by 0.4 in the first component; the residual grew from 1 to 2 there.
    a.next(&[0.4, 0.0], &[2.4, 0.0]);
    assert_eq!(a.last_weight(), Some(w_before));
    // A positive secant weight is taken.
    let mut b = Aitken::new(0.4);
    b.next(&[0.0], &[1.0]);
    b.next(&[0.4], &[0.6]); // H(x) = 1 - x: optimal w = 1/2
    assert!((b.last_weight().unwrap() - 0.5).abs() < 1e-12);
}

#[test]
fn aitken_weight_is_clamped_at_w_max() {
    // H(x) = 0.9 x + 1: the secant weight is 1 / (1 - 0.9) = 10, clamped to w_max = 1.
    let mut a = Aitken::new(0.5);
    let h = |x: f64| 0.9 * x + 1.0;
    let x1 = a.next(&[0.0], &[h(0.0)])[0];
    let x2 = a.next(&[x1], &[h(x1)])[0];
    assert_eq!(a.last_weight(), Some(1.0));
    assert!((x2 - h(x1)).abs() < 1e-15);
}

#[test]
fn a_jump_restarts_from_the_best_iterate_with_w0() {
    let mut a = Aitken::new(0.2);
    a.next(&[0.0, 0.0], &[1.0, 0.0]); // |r| = 1, the best
    a.next(&[0.2, 0.0], &[0.9, 0.0]); // |r| = 0.7, the best now
    assert!(a.take_events().is_empty());
    // |r| = 3 > 4 * 0.7: a jump.
    let x = a.next(&[1.0, 0.0], &[4.0, 0.0]);
    let ev = a.take_events();
    assert_eq!(ev.len(), 1, "{ev:?}");
    assert!(
        matches!(ev[0], RelaxationEvent::Restart { count: 1, ratio } if (ratio - 3.0 / 0.7).abs() < 1e-12)
    );
    // From the best iterate (0.2 -> 0.9) with w0 = 0.2.
    assert!(
        (x[0] - (0.2 + 0.2 * 0.7)).abs() < 1e-15 && x[1] == 0.0,
        "{x:?}"
    );
    assert_eq!(a.last_weight(), Some(0.2));
    assert_eq!(a.restarts(), 1);
    assert!(!a.fell_back());
}

#[test]
fn a_jump_after_the_last_restart_hands_over_to_iqn_ils() {
    let mut a = Aitken::new(0.5);
    a.max_restarts = 0;
    a.next(&[0.0], &[1.0]);
    a.next(&[0.5], &[0.8]);
    a.next(&[0.6], &[10.0]); // |r| = 9.4 > 4 * 0.3
    let ev = a.take_events();
    assert!(
        matches!(ev[..], [RelaxationEvent::Fallback { restarts: 0, pairs: 3, ratio }] if (ratio - 9.4 / 0.3).abs() < 1e-9),
        "{ev:?}"
    );
    assert!(a.fell_back());
    // The step is IQN-ILS's (a quasi-Newton step, no weight).
    assert_eq!(a.last_weight(), None);
    assert!(a.take_events().is_empty());
}

#[test]
fn a_jump_right_after_a_first_weight_step_hands_over_at_once() {
    // A restart would take the same w0 step from the same best iterate again.
    let mut a = Aitken::new(1.0);
    a.next(&[0.0], &[1.0]);
    a.next(&[1.0], &[-30.0]); // |r| = 31 > 4 * 1 right after the first step
    let ev = a.take_events();
    assert!(
        matches!(
            ev[..],
            [RelaxationEvent::Fallback {
                restarts: 0,
                pairs: 2,
                ..
            }]
        ),
        "{ev:?}"
    );
    assert_eq!(a.restarts(), 0);
}

#[test]
fn the_hand_over_reaches_the_fixed_point_of_an_affine_map() {
    // H(x) = -30 x + 31 (fixed point 1): Aitken's first step with w0 = 1 jumps.
    let h = |x: f64| -30.0 * x + 31.0;
    let mut a = Aitken::new(1.0);
    a.max_restarts = 0;
    let mut x = 0.0;
    for _ in 0..4 {
        x = a.next(&[x], &[h(x)])[0];
    }
    assert!(a.fell_back());
    assert!((x - 1.0).abs() < 1e-12, "{x}");
}

#[test]
fn the_safeguard_pays_on_the_spectrum_of_the_deep_crack() {
    // The Ritz values of coupled_sent_a8 (two stiff modes -38.4, -19.5 over a bulk in
    // [-5.4, 0]) on an affine map with 42 unknowns, relative residual 1e-4. Measured
    // iterations for w0 = 0.05 / 0.1 / 0.3 / 0.5 / 0.7 / 1: unguarded Aitken 36 / 39 /
    // 35 / 38 / 44 / 43, safeguarded 25 / 28 / 20 / 18 / 18 / 16 (22 / 18 / 19 / 16 /
    // 16 / 16 with max_restarts = 0), IQN-ILS 16 each.
    let map = Rotated::stiff(40);
    for w0 in [0.05, 0.1, 0.3, 0.5, 0.7, 1.0] {
        let plain = iterations(&map, unguarded(w0), 1e-4, 50).unwrap_or(usize::MAX);
        let guarded = iterations(&map, Aitken::new(w0), 1e-4, 50).unwrap_or(usize::MAX);
        assert!(plain > 33, "w0 {w0}: unguarded {plain}");
        assert!(guarded <= 30, "w0 {w0}: safeguarded {guarded}");
    }
}
