//! Seed 001 section 6.1: 50 mm square, E = 30 GPa, G_c = 110 J/m^2, 10 mm
//! central crack under uniaxial tension; the crack runs at 14.6 MPa. The
//! 45-degree crack kinks towards the direction perpendicular to the load
//! (seed 001: 56 degrees; maximum circumferential stress: 53.1 degrees).

use pdbem_pd::cases::{seed001_crack, CrackKind};
use pdbem_pd::measure::{crack_tips, kink_angle, mts_kink_deg, ramp_to_initiation, RampParams};
use pdbem_pd::PdModel;

fn run(
    kind: CrackKind,
    n: usize,
    start: f64,
    grow_to: f64,
) -> (PdModel, pdbem_pd::measure::Initiation) {
    let case = seed001_crack(kind, n);
    let delta = case.problem.horizon();
    let mut m = PdModel::new(&case.problem).unwrap();
    let tips = crack_tips(&case.problem.cracks[0], kind == CrackKind::Edge);
    let p = RampParams {
        start,
        step: 0.25,
        max_load: 25.0,
        run_length: 2.0 * delta,
        grow_to,
        max_rounds: 400,
    };
    let r = ramp_to_initiation(&mut m, &tips, &p)
        .map_err(|e| format!("{e}"))
        .unwrap();
    (m, r)
}

#[test]
fn central_crack_initiation_load_near_14_6_mpa() {
    let (_, r) = run(CrackKind::Central, 100, 10.0, 0.0);
    eprintln!(
        "central: first break {:?} MPa, initiation {:?} MPa, {:.1} s",
        r.first_break_load, r.initiation_load, r.info.time_factorization_s
    );
    // Measured (100 x 100 grid, dx = 0.5 mm, delta = 1.51 mm): first bond
    // breaks at 12.5 MPa, the crack runs at 13.5 MPa (-7.5 % of 14.6; LEFM
    // with the finite-width factor gives about 14.1 MPa).
    let s = r.initiation_load.expect("crack did not run");
    assert!((s / 14.6 - 1.0).abs() < 0.10, "initiation at {s} MPa");
}

#[test]
fn inclined_crack_kinks_towards_horizontal() {
    let (m, r) = run(CrackKind::Inclined, 100, 12.0, 6e-3);
    let case = seed001_crack(CrackKind::Inclined, 100);
    let delta = case.problem.horizon();
    let tips = crack_tips(&case.problem.cracks[0], false);
    let a = kink_angle(&m, tips[0], 1.5 * delta, 4.0 * delta).expect("no kink measured");
    eprintln!(
        "inclined: initiation {:?} MPa, kink {a:.1} deg (seed 001: 56, MTS: {:.1})",
        r.initiation_load,
        mts_kink_deg(1.0)
    );
    // Measured: kink -44.5 degrees from the crack line at the upper tip
    // (seed 001: 56; maximum circumferential stress: 53.1), i.e. the new
    // path runs about 0.5 degrees from horizontal, perpendicular to the load;
    // initiation 13.75 MPa (seed 001: 15.9).
    assert!(a < -30.0 && a > -70.0, "kink {a}");
}
