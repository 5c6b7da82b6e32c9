//! Seed 001 section 6.1: 50 mm square, E = 30 GPa, G_c = 110 J/m^2, 10 mm
//! central crack under uniaxial tension; the crack runs at 14.6 MPa. The
//! 45-degree crack kinks towards the direction perpendicular to the load
//! (seed 001: 56 degrees; maximum circumferential stress: 53.1 degrees).
//! The edge crack runs straight, perpendicular to the load.
//!
//! Grids: 80 x 80 (dx = 0.625 mm, delta = 1.88 mm, s0 = 0.0034) for the
//! central and inclined cracks, 60 x 60 (dx = 0.833 mm) for the edge crack
//! (seed: 200 x 200), to keep the suite fast; the measured values below
//! are for these grids.

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
    // Bonds breaking at the ramp's first load would make every load found an upper
    // bound (the ramp's start), not a result.
    if let Some(f) = r.first_break_load {
        assert!(
            f > start,
            "{kind:?}: bonds broke at the ramp's start {start}"
        );
    }
    (m, r)
}

#[test]
fn central_crack_initiation_load_near_14_6_mpa() {
    let (_, r) = run(CrackKind::Central, 80, 10.0, 0.0);
    eprintln!(
        "central: first break {:?} MPa, initiation {:?} MPa, {:.1} s",
        r.first_break_load, r.initiation_load, r.info.time_factorization_s
    );
    // Measured (80 x 80): first bond breaks at 12.5 MPa, the crack runs
    // at 13.25 MPa (-9.2 % of 14.6; LEFM with the finite-width factor gives
    // 14.1 MPa). Before the crack ends were made open (bonds crossing exactly
    // at a tip are not cut), 12.25 / 13.5 MPa.
    let s = r.initiation_load.expect("crack did not run");
    assert!((s / 14.6 - 1.0).abs() < 0.10, "initiation at {s} MPa");
}

#[test]
fn inclined_crack_kinks_towards_horizontal() {
    let (m, r) = run(CrackKind::Inclined, 80, 8.0, 6e-3);
    let case = seed001_crack(CrackKind::Inclined, 80);
    let delta = case.problem.horizon();
    let tips = crack_tips(&case.problem.cracks[0], false);
    let a = kink_angle(&m, tips[0], 1.5 * delta, 4.0 * delta).expect("no kink measured");
    eprintln!(
        "inclined: initiation {:?} MPa, kink {a:.1} deg (seed 001: 56, MTS: {:.1})",
        r.initiation_load,
        mts_kink_deg(1.0)
    );
    // Measured (80 x 80): kink -41.1 degrees from the crack line at the
    // upper tip (seed 001: 56; maximum circumferential stress: 53.1), i.e.
    // the new path runs about 4 degrees from horizontal, nearly
    // perpendicular to the load; initiation 14.25 MPa (seed 001: 15.9).
    // (100 x 100 gave -44.5 degrees and 13.75 MPa.)
    assert!(a < -30.0 && a > -70.0, "kink {a}");
}

/// LEFM initiation stress (MPa) of an edge crack of length `a` in a strip
/// of width `w` under remote tension: $\sigma_c = K_{Ic}/(F\sqrt{\pi a})$ with
/// $K_{Ic} = \sqrt{E G_c}$ (plane stress) and the single-edge-notch factor
/// $F = 1.12 - 0.231 r + 10.55 r^2 - 21.72 r^3 + 30.39 r^4$, $r = a/w$
/// (Tada's handbook, accurate to 0.5 % for r < 0.6).
fn lefm_edge_mpa(a: f64, w: f64) -> f64 {
    let k_ic = (30e9_f64 * 110.0).sqrt();
    let r = a / w;
    let f = 1.12 - 0.231 * r + 10.55 * r * r - 21.72 * r.powi(3) + 30.39 * r.powi(4);
    k_ic / (f * (std::f64::consts::PI * a).sqrt()) / 1e6
}

#[test]
fn edge_crack_runs_straight_near_lefm_load() {
    // Seed 001 section 6.1, Fig. 10: "Under the tension of 8.5 MPa, the
    // crack propagates in a straight line and quickly penetrates the whole
    // plate." The text gives no crack length; cases::seed001_crack assumes
    // 10 mm (the length of its central and inclined cracks), for which
    // LEFM gives 7.48 MPa (8.5 MPa would fit a = 8.2 mm).
    let n = 60;
    let (m, r) = run(CrackKind::Edge, n, 4.0, 3e-3);
    let case = seed001_crack(CrackKind::Edge, n);
    let delta = case.problem.horizon();
    let tips = crack_tips(&case.problem.cracks[0], true);
    assert_eq!(tips.len(), 1);
    let lefm = lefm_edge_mpa(0.010, 0.050);
    let s = r.initiation_load.expect("edge crack did not run");
    let a = kink_angle(&m, tips[0], 1.5 * delta, 4.0 * delta).expect("no kink measured");
    eprintln!(
        "edge: first break {:?} MPa, initiation {s} MPa (LEFM {lefm:.2}, seed 001 8.5), kink {a:.1} deg, extension {:.2} mm",
        r.first_break_load,
        r.extension * 1e3
    );
    // Measured (60 x 60): first break 5.75 MPa, initiation 6.75 MPa, -9.8 %
    // of LEFM (the central crack on 80 x 80 is -4.5 % of its LEFM value;
    // coarser grids run earlier); bound 15 %.
    assert!(
        (s / lefm - 1.0).abs() < 0.15,
        "initiation {s} MPa vs LEFM {lefm}"
    );
    // Mode I: the crack continues along its own line, perpendicular to
    // the load. Measured 0.0 degrees; bound 10.
    assert!(a.abs() < 10.0, "kink {a} deg");
    // It ran at least the requested 3 mm (measured 5.4 mm).
    assert!(r.extension >= 3e-3, "extension {}", r.extension);
}
