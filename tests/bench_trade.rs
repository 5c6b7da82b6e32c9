//! `pdbem bench trade --quick` (issue 18 item 7) on its smoke-test settings: the tension
//! plate of seed 002 section 3.2.2 with a 6 m crack (a/W = 0.6), PD-BEM with windows of 20
//! and 24 nodes per side and a looser coupling tolerance.
//!
//! Checks the report's structure (report.md tables, bench.json, the plot, the same
//! comparison again from the run folders by `--collect`) and physics:
//! - LEFM: K_I = F(a/W) sigma sqrt(pi a) with F(0.6) about 3 (edge-crack table) gives about
//!   43 Pa m^0.5 at a = 6 m and 3.3 Pa, far above K_c = 9.3 Pa m^0.5 (the case file), and
//!   K_I grows with a: every run fails in its first load step, at the initial load 3.3, so
//!   the failure-load errors are 0;
//! - mode I: the path stays on the crack line x = 10 m within one node spacing;
//! - the deviation measure is a metric on paths of one reach: the finest run deviates from
//!   itself by 0; on the three paths cut at their common reach it is symmetric and obeys
//!   the triangle inequality up to its sampling (8 points per segment: half a sample
//!   spacing, 1/16 of the longest segment).

use std::path::PathBuf;

use pdbem::bench_trade::{self, TradeRun};
use pdbem::growth::TipPath;
use pdbem_coupling::growth::compare::{cut_at_reach, path_deviation, reach};
use pdbem_geometry::P2;

fn out_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdbem-bench-trade-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn points(p: &TipPath) -> Vec<P2> {
    p.points.iter().map(|q| P2::new(q.x, q.y)).collect()
}

/// A path cut at reach `r` (same name, loads dropped).
fn cut(p: &TipPath, r: f64) -> TipPath {
    let mut c = p.clone();
    c.points = cut_at_reach(&points(p), r)
        .into_iter()
        .map(|q| pdbem::growth::PathPoint {
            x: q.x,
            y: q.y,
            step: 0,
            load: 0.0,
        })
        .collect();
    c
}

fn longest_segment(p: &TipPath) -> f64 {
    points(p)
        .windows(2)
        .map(|w| (w[1] - w[0]).norm())
        .fold(0.0, f64::max)
}

fn check_metric(runs: &[TradeRun]) {
    let paths: Vec<&TipPath> = runs.iter().map(|r| &r.paths[0]).collect();
    let common = paths
        .iter()
        .map(|p| reach(&points(p)))
        .fold(f64::INFINITY, f64::min);
    assert!(common > 2.0, "the tips grew at least 2 m: {common}");
    let cuts: Vec<TipPath> = paths.iter().map(|p| cut(p, common)).collect();
    let slack = cuts.iter().map(longest_segment).fold(0.0, f64::max) / 16.0;
    let d = |i: usize, j: usize| path_deviation(&cuts[i], &cuts[j]).0;
    for i in 0..3 {
        assert!(d(i, i) < 1e-9, "d({i}, {i}) = {}", d(i, i));
        for j in 0..3 {
            assert!((d(i, j) - d(j, i)).abs() < 1e-12, "symmetry {i} {j}");
            for k in 0..3 {
                assert!(
                    d(i, k) <= d(i, j) + d(j, k) + slack,
                    "triangle {i} {j} {k}: {} > {} + {} (+ {slack})",
                    d(i, k),
                    d(i, j),
                    d(j, k)
                );
            }
        }
    }
}

#[test]
fn quick_trade_bench_writes_its_report_and_measures_what_it_says() {
    let out = out_dir();
    let report = bench_trade::run(&out, true).expect("bench trade --quick");
    assert_eq!(report.cases.len(), 1);
    let case = &report.cases[0];
    assert_eq!(case.case, "growth_tension_edge");
    assert_eq!(case.reference, "n24");
    let labels: Vec<_> = case.runs.iter().map(|r| r.label.as_str()).collect();
    assert_eq!(labels, ["n20", "n24", "psi1e-3"]);

    // Structure: report.md, bench.json, the deviation plot.
    let md = std::fs::read_to_string(out.join("report.md")).expect("report.md");
    assert!(
        md.contains("## growth_tension_edge (reference: n24)"),
        "{md}"
    );
    let head = format!("| {} |", bench_trade::report::COLUMNS.join(" | "));
    assert!(md.contains(&head), "{md}");
    for l in labels {
        assert!(md.contains(&format!("\n| {l} |")), "row {l}: {md}");
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("bench.json")).expect("json"))
            .expect("bench.json parses");
    assert_eq!(json["bench"], "trade");
    let rows = json["cases"][0]["runs"].as_array().expect("runs");
    assert_eq!(rows.len(), 3);
    for ext in ["png", "svg"] {
        assert!(
            out.join(format!("trade_deviation.{ext}")).is_file(),
            "{ext}"
        );
    }

    // Physics.
    for r in &case.runs {
        assert!(r.error.is_none() && r.complete, "{r:?}");
        assert!(r.wall_time_s > 0.0 && r.coupling_iterations > 0, "{r:?}");
        assert!(r.failure, "{}: K_I is far above K_c", r.label);
        assert_eq!(r.failure_load, Some(3.3), "{}", r.label);
        assert_eq!(r.failure_load_err, Some(0.0), "{}", r.label);
        assert_eq!(r.paths.len(), 1);
        let p = &r.paths[0];
        assert_eq!(
            (p.points[0].x, p.points[0].y),
            (10.0, 4.0),
            "starts at the tip"
        );
        for q in &p.points {
            assert!(
                (q.x - 10.0).abs() < r.dx,
                "{}: mode I path at {q:?}",
                r.label
            );
        }
        assert!(r.deviation_m.expect("compared") < r.dx, "{r:?}");
    }
    let finest = &case.runs[1];
    assert!(finest.deviation_m.expect("compared") < 1e-9);
    check_metric(&case.runs);

    // `--collect` rebuilds the same comparison from the run folders.
    let again = bench_trade::collect(&out).expect("bench trade --collect");
    for (a, b) in case.runs.iter().zip(&again.cases[0].runs) {
        assert_eq!(a.deviation_m, b.deviation_m, "{}", a.label);
        assert_eq!(a.failure_load_err, b.failure_load_err, "{}", a.label);
    }
    let _ = std::fs::remove_dir_all(&out);
}
