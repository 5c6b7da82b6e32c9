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
