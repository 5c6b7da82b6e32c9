//! Tests of the trade bench's variants and comparisons (`super`).

use super::*;

#[test]
fn the_full_bench_has_the_issue_grid_and_its_finest_run_is_n60() {
    let v = variants(2.0, 20, 1e-4, false);
    let labels: Vec<_> = v.iter().map(|x| x.label.as_str()).collect();
    assert_eq!(
        labels,
        ["n20", "n30", "n40", "n60", "side3", "side4", "aitken", "psi1e-3", "psi1e-5"]
    );
    assert_eq!(v[finest(&v)].label, "n60");
    // Side at fixed dx keeps dx = 0.1 m.
    for x in v.iter().filter(|x| x.series == "side") {
        assert!((x.dx() - 0.1).abs() < 1e-12, "{x:?}");
    }
    let q = variants(2.0, 20, 1e-4, true);
    assert_eq!(q[finest(&q)].label, "n24");
}

fn path(pts: &[(f64, f64)]) -> TipPath {
    TipPath {
        name: "crack.end".into(),
        points: pts
            .iter()
            .map(|&(x, y)| crate::growth::PathPoint {
                x,
                y,
                step: 0,
                load: 3.3,
            })
            .collect(),
        ended: None,
    }
}

fn run_with(label: &str, pts: &[(f64, f64)], failure_load: Option<f64>) -> TradeRun {
    TradeRun {
        label: label.into(),
        failure: failure_load.is_some(),
        failure_load,
        paths: vec![path(pts)],
        ..Default::default()
    }
}

#[test]
fn runs_are_compared_with_the_reference_by_distance_and_failure_load() {
    // Three straight 4 m paths down from (10, 8): the reference, one shifted 0.1 m and
    // one tilted to end 0.3 m aside. Hausdorff: 0.1, 0.3 and between them 0.2.
    let mut runs = vec![
        run_with("fine", &[(10.0, 8.0), (10.0, 4.0)], Some(3.3)),
        run_with(
            "shift",
            &[(10.0, 8.0), (10.1, 7.9), (10.1, 4.0)],
            Some(3.35),
        ),
        run_with("tilt", &[(10.0, 8.0), (10.3, 4.0)], None),
    ];
    compare_to(&mut runs, 0);
    assert!(runs[0].deviation_m.expect("ran") < 1e-12);
    assert_eq!(runs[0].failure_load_err, Some(0.0));
    let d1 = runs[1].deviation_m.expect("ran");
    assert!((d1 - 0.1).abs() < 1e-3, "{d1}");
    let e = runs[1].failure_load_err.expect("both failed");
    assert!((e - 0.05 / 3.3).abs() < 1e-12, "{e}");
    // No failure: no load error, but a path deviation.
    assert_eq!(runs[2].failure_load_err, None);
    let d2 = runs[2].deviation_m.expect("ran");
    assert!(d2 > 0.29 && d2 < 0.301, "{d2}");
    // Symmetric, and the triangle inequality through the reference.
    let (a, b) = (&runs[1].paths, &runs[2].paths);
    let (ab, ba) = (run_deviation(a, b), run_deviation(b, a));
    assert_eq!(ab.map(|x| x.0), ba.map(|x| x.0));
    assert!(ab.expect("same tip").0 <= d1 + d2 + 1e-12);
    // A run that ended early is not compared (its path stops where its coupling gave
    // up).
    let mut early = runs.clone();
    early[1].failure_reason = Some("load step 0 could not be solved".into());
    compare_to(&mut early, 0);
    assert_eq!(
        (early[1].deviation_m, early[1].failure_load_err),
        (None, None)
    );
    assert!(early[2].deviation_m.is_some());
    // A reference that did not run leaves every comparison empty.
    let mut failed = runs.clone();
    failed[0].error = Some("x".into());
    compare_to(&mut failed, 0);
    assert!(failed.iter().all(|r| r.deviation_m.is_none()));
}

/// A path whose points are reached at `loads`.
fn path_at(pts: &[(f64, f64)], loads: &[f64]) -> TipPath {
    let mut p = path(pts);
    for (q, &l) in p.points.iter_mut().zip(loads) {
        q.load = l;
    }
    p
}

#[test]
fn paths_are_compared_below_the_first_overstrain_for_runs_that_got_there() {
    // The reference runs straight down; the run follows it to load 0.2, then turns 1 m
    // aside. The reference overstrained the body at 0.25, the run at 0.3.
    let loads = [0.1, 0.1, 0.2, 0.3];
    let mut reference = run_with("fine", &[], None);
    reference.paths = vec![path_at(
        &[(10.0, 8.0), (10.0, 7.0), (10.0, 6.0), (10.0, 5.0)],
        &loads,
    )];
    reference.overstrain_load = Some(0.25);
    reference.end_load = Some(0.4);
    let mut run = reference.clone();
    run.label = "coarse".into();
    run.paths = vec![path_at(
        &[(10.0, 8.0), (10.05, 7.0), (10.05, 6.0), (11.0, 5.0)],
        &loads,
    )];
    run.overstrain_load = Some(0.3);
    // It ended early past the overstrain: no whole-path deviation, but the part below.
    run.failure_reason = Some("load step 7 could not be solved".into());
    let mut short = run.clone();
    short.label = "short".into();
    short.end_load = Some(0.2);
    let mut runs = vec![reference, run, short];
    compare_to(&mut runs, 0);
    assert_eq!(runs[0].before_overstrain.map(|b| b[0]), Some(0.0));
    assert_eq!(runs[1].deviation_m, None);
    let [d, common, load] = runs[1].before_overstrain.expect("got past 0.25");
    assert_eq!(load, 0.25);
    // 0.05 aside; the cut at the common reach adds 4e-6.
    assert!((d - 0.05).abs() < 1e-5, "{d}");
    assert!((common - 2.0).abs() < 0.01, "{common}");
    // A run that stopped below the load is not compared there.
    assert_eq!(runs[2].before_overstrain, None);
    // Without an overstrain in either run, nothing.
    for r in runs.iter_mut() {
        r.overstrain_load = None;
    }
    compare_to(&mut runs, 0);
    assert!(runs.iter().all(|r| r.before_overstrain.is_none()));
}
