//! Bad problems get a clear error naming the field and the reason.

use pdbem_pd::cases::{plate_hole, seed001_crack, CrackKind};
use pdbem_pd::{Failure, PdError, PdModel, PdProblem, Region};

fn field_of(p: &PdProblem) -> (String, String) {
    match PdModel::new(p) {
        Err(PdError::InvalidInput { field, reason }) => (field, reason),
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("accepted a bad problem"),
    }
}

#[test]
fn horizon_smaller_than_dx() {
    let mut p = plate_hole(20).problem;
    p.horizon_factor = 0.8;
    let (f, r) = field_of(&p);
    assert_eq!(f, "horizon_factor");
    assert!(r.contains("smaller than dx"), "{r}");
}

#[test]
fn empty_region() {
    let mut p = plate_hole(20).problem;
    p.region = Region::default();
    assert_eq!(field_of(&p).0, "region.outline");
    // A region smaller than one cell holds no node.
    let mut p = plate_hole(20).problem;
    p.region = Region::rectangle([0.0, 0.0], [1e-5, 1e-5]);
    p.boundary.clear();
    let (f, r) = field_of(&p);
    assert_eq!(f, "region");
    assert!(r.contains("empty region"), "{r}");
}

#[test]
fn crack_outside_the_region() {
    let mut p = seed001_crack(CrackKind::Central, 40).problem;
    p.cracks = vec![vec![[0.1, 0.1], [0.12, 0.1]]];
    let (f, r) = field_of(&p);
    assert_eq!(f, "cracks[0][0]");
    assert!(r.contains("outside"), "{r}");
}

#[test]
fn negative_fracture_energy() {
    let mut p = seed001_crack(CrackKind::Central, 40).problem;
    p.failure = Failure::FractureEnergy { g_c: -110.0 };
    let (f, r) = field_of(&p);
    assert_eq!(f, "failure.g_c");
    assert!(r.contains("-110"), "{r}");
}

#[test]
fn degradation_onset_not_below_critical() {
    let mut p = plate_hole(20).problem;
    p.failure = Failure::Degradation {
        s_m: 0.02,
        s_c: 0.02,
        beta: 3.0,
    };
    let (f, r) = field_of(&p);
    assert_eq!(f, "failure.s_m");
    assert!(r.contains("smaller than s_c"), "{r}");
}
