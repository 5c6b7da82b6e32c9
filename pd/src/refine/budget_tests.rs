//! A split against the memory budget ([`Body::budget`], `split::within_budget`).

use super::*;
use crate::error::PdError;

/// The budget a split checks is the bytes of the body it makes beside the body it
/// splits, at [`PARTICLE_BYTES`] and [`BOND_BYTES`]: the split of every particle of seed
/// 004's plate on a 4 mm grid passes at exactly those bytes and is refused one byte
/// below them, before anything is allocated (the body is unchanged).
#[test]
fn a_split_over_the_budget_is_refused_before_it_allocates() {
    let case = crate::cases::branching_plate(4e-3, 1e6);
    let body = Body::from_problem(&case.problem).unwrap();
    let all: Vec<usize> = (0..body.len()).collect();
    let bytes = |b: &Body| b.len() as f64 * PARTICLE_BYTES + b.dh.bonds.len() as f64 * BOND_BYTES;
    let mut split = body.clone();
    split.split(&all).unwrap();
    let need = bytes(&split) + bytes(&body);
    let mut at = body.clone();
    at.budget = Some(need as u64);
    assert_eq!(at.split(&all).unwrap(), body.len());
    let mut below = body.clone();
    below.budget = Some(need as u64 - 1);
    match below.split(&all) {
        Err(PdError::TooLarge { what, bytes, .. }) => {
            assert_eq!(bytes, need);
            assert!(what.contains("pd.refinement"), "{what}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(below.len(), body.len());
    assert_eq!(below.dh.bonds.len(), body.dh.bonds.len());
}

/// A start body the criteria may split must fit the budget twice over (the refined body
/// lives beside it): `room_to_split` passes at exactly twice its bytes and refuses one
/// byte below, naming `pd.refinement`; without criteria nothing will split and any
/// budget passes; `set_up_static` refuses what `room_to_split` refuses.
#[test]
fn a_body_without_room_for_its_first_split_is_refused_at_set_up() {
    let case = crate::cases::branching_plate(4e-3, 1e6);
    let body = Body::from_problem(&case.problem).unwrap();
    let need = 2.0 * (body.len() as f64 * PARTICLE_BYTES + body.dh.bonds.len() as f64 * BOND_BYTES);
    let r = crate::refine::Refinement::default();
    let mut at = body.clone();
    at.budget = Some(need as u64);
    assert!(crate::refine::run::room_to_split(&at, &r).is_ok());
    let mut below = body.clone();
    below.budget = Some(need as u64 - 1);
    match crate::refine::run::room_to_split(&below, &r) {
        Err(PdError::TooLarge { what, bytes, .. }) => {
            assert_eq!(bytes, need);
            assert!(what.contains("pd.refinement"), "{what}");
        }
        other => panic!("{other:?}"),
    }
    let none = crate::refine::Refinement {
        critical_damage: None,
        strain_factor: None,
        ..Default::default()
    };
    assert!(crate::refine::run::room_to_split(&below, &none).is_ok());
    assert!(matches!(
        crate::refine::run::set_up_static(&mut below.clone(), &r),
        Err(PdError::TooLarge { .. })
    ));
}
