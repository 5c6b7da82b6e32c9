//! Eq. 15 at a tie (`run::flagged`, `run::DAMAGE_TIE`; seed 004 Eq. 15 is strict).

use super::*;

/// Eq. 15 is strict (`phi > phi_c`) and a damage that ties `phi_c` up to round-off is not
/// past it: on seed 004's branching plate, after the set-up split of the pre-crack's
/// mouth, two particles by the pre-crack have damage 0.4 to within 1e-15 (measured
/// 0.4 + 3.3e-16 and 0.4 + 5.6e-16); they are not flagged, and they are once `phi_c`
/// is lowered by 1e-9.
#[test]
fn a_damage_tied_with_the_critical_damage_does_not_refine() {
    let case = crate::cases::branching_plate(1e-3, 1e6);
    let mut b = Body::from_problem(&case.problem).unwrap();
    let r = Refinement::default();
    let first = run::flagged(&b, &r, true, false);
    assert!(!first.is_empty());
    b.split(&first).unwrap();
    let phi = b.damage();
    let ties: Vec<usize> = (0..b.len())
        .filter(|&k| b.level[k] == 0 && (phi[k] - 0.4).abs() < 1e-15)
        .collect();
    assert!(!ties.is_empty());
    let flagged = run::flagged(&b, &r, true, false);
    assert!(ties.iter().all(|k| !flagged.contains(k)), "{ties:?}");
    let lower = Refinement {
        critical_damage: Some(0.4 - 1e-9),
        ..Default::default()
    };
    let flagged = run::flagged(&b, &lower, true, false);
    assert!(ties.iter().all(|k| flagged.contains(k)), "{ties:?}");
}
