//! Seed 001 section 6 with transfer-function tractions (`pd.traction:
//! TransferFunction`): the `cases/seed001_*.ron` scenes solved by `pdbem`'s
//! stand-alone PD runner on coarse grids (the cases carry the seed's 200 x 200),
//! initiation loads against seed 001 and against LEFM; and the validation of
//! the field.
//!
//! LEFM: K from this engine's BEM on the same square plate (the cases without
//! their `pd` section), K_Ic = sqrt(E G_0) = 1.8166 MPa m^0.5 (plane stress),
//! initiation where the largest maximum-circumferential-stress K_eq reaches
//! K_Ic.

use std::path::Path;

use pdbem::scene::{PdTraction, Scene};

fn case(name: &str, nx: usize) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("cases/seed001_{name}.ron"));
    let mut s = Scene::load(&path).unwrap();
    s.pd.as_mut().unwrap().nx = Some(nx);
    s
}

fn solve(s: &Scene) -> (Option<f64>, Vec<Option<f64>>) {
    let (summary, _) = pdbem::run_pd::solve(s).unwrap();
    // No bond may break at the ramp's first load: the loads found would be its start.
    let bounded = |n: &String| n.contains("already broke at the ramp's first load");
    assert!(
        !summary.notes.iter().any(bounded),
        "{}: {:?}",
        s.name,
        summary.notes
    );
    let load = summary.extra["initiation_load"].as_f64().map(|v| v / 1e6);
    let kinks = summary.extra["kink_deg_per_tip"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64())
        .collect();
    (load, kinks)
}

#[test]
fn every_seed001_case_uses_the_transfer_functions() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases");
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        if name.starts_with("seed001_") && name.ends_with(".ron") {
            let s = Scene::load(&p).unwrap();
            let pd = s.pd.as_ref().unwrap();
            assert_eq!(pd.traction, PdTraction::TransferFunction, "{name}");
            assert_eq!(pd.nx, Some(200), "{name}: the seed's grid");
            n += 1;
        }
    }
    // Seed 001 section 6: 3 single-crack, 4 two-crack and 4 three-crack plates.
    assert_eq!(n, 11);
}

/// Seed 001 section 6.1: the central crack runs at 14.6 MPa (LEFM for the square
/// plate, BEM K: 13.7 MPa).
#[test]
fn central_crack_runs_near_the_seed_load() {
    let (load, kinks) = solve(&case("central_crack", 80));
    let s = load.expect("the crack did not run");
    eprintln!("central, 80 x 80: initiation {s} MPa, kinks {kinks:?}");
    // Measured 13.2 MPa on 80 x 80 (-9.6 % of the seed's 14.6, -3.9 % of
    // LEFM's 13.73; 100 x 100 also 13.2). Bounds: 10 % of the seed, 5 % of LEFM.
    assert!((s / 14.6 - 1.0).abs() < 0.10, "{s}");
    assert!((s / 13.73 - 1.0).abs() < 0.05, "{s}");
    // Mode I: both tips run along the crack line (measured 0 and 0 degrees).
    for k in kinks {
        assert!(k.expect("no kink measured").abs() < 5.0);
    }
}

/// Seed 001 section 6.2: two parallel cracks 25 mm apart run at 13.7 MPa along
/// paths that bend away from each other. Before the extension of
/// `pdbem_pd::measure` counted each damaged node for its nearest tip only, the
/// first broken row of one crack "ran" the other crack's tips (at the full 25 mm
/// between them).
#[test]
fn two_parallel_cracks_run_and_bend_apart() {
    let (load, kinks) = solve(&case("two_parallel_cracks", 80));
    let s = load.expect("the cracks did not run");
    eprintln!("two parallel, 80 x 80: initiation {s} MPa, kinks {kinks:?}");
    // Measured 12.2 MPa on 80 x 80 (-11 % of the seed's 13.7; 12.4 on 100 x 100,
    // LEFM 13.2). Bound: 12 % of the seed (the coarse grid runs early), 10 % of LEFM.
    assert!((s / 13.7 - 1.0).abs() < 0.12, "{s}");
    assert!((s / 13.2 - 1.0).abs() < 0.10, "{s}");
    // Tips: lower crack (right, left), upper crack (right, left); counter-clockwise
    // from each tip's direction. Away from each other: lower tips turn down, upper
    // tips up. Measured -22.1, 22.1, 22.1, -22.1 degrees (100 x 100: +-18.1).
    let k: Vec<f64> = kinks.iter().map(|k| k.expect("no kink measured")).collect();
    assert!(
        k[0] < -5.0 && k[1] > 5.0 && k[2] > 5.0 && k[3] < -5.0,
        "{k:?}"
    );
}

#[test]
fn transfer_function_traction_with_coupling_is_an_error() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/coupled_sent_a2.ron");
    let text = std::fs::read_to_string(path).unwrap();
    let text = text.replace(
        "pd: (failure: Elastic)",
        "pd: (failure: Elastic, traction: TransferFunction)",
    );
    let e = Scene::from_ron_str(&text, Path::new("x.ron"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("pd.traction"), "{e}");
}

/// Seed 001 section 6.1, Fig. 8: the 10 mm crack at 45 degrees. LEFM (this engine's
/// BEM, maximum circumferential stress) turns both tips by -52.9 degrees
/// (Erdogan-Sih for K_I = K_II in an infinite plate: -53.13); the seed reports 56.
#[test]
fn inclined_crack_kinks_towards_the_perpendicular_of_the_load() {
    let s = case("inclined_crack", 80);
    let (load, kinks) = solve(&s);
    let (lefm, lefm_kink) = pdbem::bench_seed001::lefm(&s).unwrap();
    let (lefm, lefm_kink) = (lefm.unwrap(), lefm_kink.unwrap());
    eprintln!("inclined, 80 x 80: initiation {load:?} MPa, kinks {kinks:?}; LEFM {lefm} MPa, {lefm_kink} deg");
    // The BEM's kink against Erdogan-Sih's for K_II / K_I = 1: the finite plate
    // changes the ratio a little (measured -52.94 against -53.13).
    let erdogan_sih = pdbem_pd::measure::mts_kink_deg(1.0);
    assert!((erdogan_sih + 53.13).abs() < 0.01, "{erdogan_sih}");
    assert!((lefm_kink - erdogan_sih).abs() < 0.5, "{lefm_kink}");
    // Measured 14.0 MPa on 80 x 80 (-9.9 % of LEFM's 15.54, -12 % of the seed's
    // 15.9; 200 x 200: 14.6, -6 % of LEFM). Bound: 12 % of LEFM.
    let p = load.expect("the crack did not run");
    assert!((p / lefm - 1.0).abs() < 0.12, "{p} MPa");
    // Both tips turn clockwise from their own direction (the crack rises to the
    // right, the load is vertical). Measured -43.3 on 80 x 80. The measured kink does
    // not converge with the grid: 100 x 100 -45.0, 140 x 140 -45.7, 200 x 200 -51.0,
    // 280 x 280 -43.3 (the 80 x 80 value to 1e-4: on both grids the damage ahead of
    // the tips runs 1.7 degrees from the grid's x axis), while the load does
    // (14.0, 13.6, 14.8, 14.6, 15.4 MPa against LEFM's 15.54; docs/seed001_traction.md).
    // Bound: 35 to 60 degrees, the grid's spread around LEFM's 52.9.
    for k in &kinks {
        let k = k.expect("no kink measured");
        assert!(k < -35.0 && k > -60.0, "{kinks:?}");
    }
}

/// Seed 001 section 6.2, Fig. 14: two colinear 5 mm edge cracks. The handbook's
/// double-edge-notched strip (Tada: F(a/b) = (1.122 - 0.561 r - 0.205 r^2 +
/// 0.471 r^3 - 0.190 r^4) / sqrt(1 - r), r = a/b, b the half width) gives 12.9 MPa; this
/// engine's BEM for the square plate 12.3 MPa; PD 12.2. The seed reports 8.5 MPa,
/// its load for the single edge crack: a K 1.45 times the handbook's, which no
/// 5 mm crack pair in a 50 mm plate has (docs/seed001_traction.md).
#[test]
fn colinear_edge_cracks_run_at_the_handbook_load() {
    let s = case("colinear_edge_cracks", 80);
    let (load, kinks) = solve(&s);
    let lefm = pdbem::bench_seed001::lefm(&s).unwrap().0.unwrap();
    eprintln!("colinear edge, 80 x 80: initiation {load:?} MPa, kinks {kinks:?}; LEFM {lefm} MPa");
    let r: f64 = 0.005 / 0.025;
    let f = (1.122 - 0.561 * r - 0.205 * r * r + 0.471 * r.powi(3) - 0.190 * r.powi(4))
        / (1.0 - r).sqrt();
    let k_ic = (30e9_f64 * 110.0).sqrt();
    let tada = k_ic / (f * (std::f64::consts::PI * 0.005).sqrt()) / 1e6;
    // The square plate's finite height raises K over the infinite strip's (as for
    // the central crack, -2.9 %): measured 12.32 against 12.90 MPa (-4.5 %).
    assert!(
        lefm < tada && lefm > 0.93 * tada,
        "LEFM {lefm}, Tada {tada}"
    );
    // Measured 12.2 MPa on 80 x 80 (-1 % of LEFM). Bound 8 %.
    let p = load.expect("the cracks did not run");
    assert!((p / lefm - 1.0).abs() < 0.08, "{p} MPa");
    // Mode I by symmetry: both run along their line (measured 0, 0).
    for k in kinks {
        assert!(k.expect("no kink measured").abs() < 5.0);
    }
}
