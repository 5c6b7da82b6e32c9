//! Infinite-plate scenes by superposition: `inclined_crack_45` (K_I = K_II =
//! sigma sqrt(pi a)/2, kink -53.13 deg), `kirsch_hole` (peak hoop stress 3 sigma) and
//! `colinear_cracks_infinite` (two colinear cracks, Tada's closed form in elliptic
//! integrals).
mod common_scene;

use common_scene::*;
use pdbem_bem::analytic::colinear_cracks_k1;
use std::f64::consts::PI;

/// Issue bounds 0.5 % and 0.2 deg. Measured -0.004 % (both), kink -53.13.
#[test]
fn inclined_crack_45_infinite_plate() {
    let s = solve_bem(&case("inclined_crack_45", &[]));
    let k = (PI * 1.0_f64).sqrt() / 2.0;
    assert_eq!(s.tips.len(), 2);
    for t in &s.tips {
        println!(
            "{}: K_I {:+.4} % K_II {:+.4} % kink {:.3}",
            t.name,
            pct(t.k1, k),
            pct(t.k2.abs(), k),
            t.kink_deg
        );
        assert!(pct(t.k1, k).abs() < 0.5 && pct(t.k2.abs(), k).abs() < 0.5);
        assert!(pct(t.k1_j.unwrap(), k).abs() < 0.5 && pct(t.k2_j.unwrap().abs(), k).abs() < 0.5);
        assert!((t.kink_deg.abs() - 53.130).abs() < 0.2);
    }
}

/// Two equal colinear cracks 0.2 < |x| < 1.2 m, sigma_yy = 1 Pa, 200 elements per face
/// (issue 17 bound 1 %). Measured against [`colinear_cracks_k1`] (K_inner 1.43311,
/// K_outer 1.32941): crack-opening fit +0.049 % inner, +0.031 % outer; interaction
/// integral +0.087 %, +0.065 %; K_II below 3e-15.
#[test]
fn colinear_cracks_tada() {
    let s = solve_bem(&case("colinear_cracks_infinite", &[]));
    let (inner, outer) = colinear_cracks_k1(1.0, 0.2, 1.2);
    assert_eq!(s.tips.len(), 4);
    for t in &s.tips {
        let x = t.position[0].abs();
        let k = if x < 0.7 { inner } else { outer };
        println!(
            "{} at |x| = {x}: K_I {:+.4} % (fit), {:+.4} % (integral), K_II {:.2e}",
            t.name,
            pct(t.k1, k),
            pct(t.k1_j.unwrap(), k),
            t.k2
        );
        assert!(pct(t.k1, k).abs() < 1.0 && pct(t.k1_j.unwrap(), k).abs() < 1.0);
        assert!(t.k2.abs() < 1e-6 * k);
    }
}

/// Issue bound 1 %. Measured peak 3.00009 sigma with 256 elements.
#[test]
fn kirsch_hole_peak_hoop_stress() {
    let scene = case("kirsch_hole", &[]);
    let ctxdir = std::env::temp_dir().join(format!("pdbem-kirsch-{}", std::process::id()));
    let s = pdbem::runner::run_scene(&scene, &ctxdir, true).unwrap();
    let peak = s.extra["hoop_peak"].as_f64().unwrap();
    println!("peak hoop stress {peak:.5}");
    assert!((peak - 3.0).abs() < 0.03);
    assert!(ctxdir.join("hoop_hole.csv").exists() && ctxdir.join("summary.json").exists());
    let est = s.extra["hoop_peak_err_est"].as_f64().unwrap();
    assert!(
        (peak - 3.0).abs() <= est,
        "{peak} against its estimate {est}"
    );
    let _ = std::fs::remove_dir_all(&ctxdir);
}

/// The peak's error estimate, |peak(h) - peak(2h)|, bounds its error on coarse circles:
/// measured errors 0.52, 0.083, 2.5e-4 Pa against estimates 1.47, 0.44, 8.5e-3 with 8,
/// 16, 64 elements (before, the 8-element peak was 17 % low with no estimate).
#[test]
fn kirsch_peak_estimate_bounds_its_error() {
    for n in ["8", "16", "64"] {
        let scene = case(
            "kirsch_hole",
            &[
                ("bem.elements_per_circle", n),
                ("outputs.grids", "[]"),
                ("outputs.lines", "[]"),
            ],
        );
        let (s, _) = pdbem::run_bem::solve(&scene).unwrap();
        let peak = s.extra["hoop_peak_hole"].as_f64().unwrap();
        let est = s.extra["hoop_peak_hole_err_est"].as_f64().unwrap();
        println!("{n} elements: peak {peak:.5}, estimate {est:.3e}");
        assert!((peak - 3.0).abs() <= est, "{n}: {peak} against {est}");
        assert!(est < 1.0 || n == "8", "{n}: {est}");
    }
}

/// Interior stresses around the Kirsch hole against the analytic field on a ring of points
/// at r = 1.1 to 3 (issue: displacements and stresses at interior points). Measured max
/// error 1.4e-4 sigma over a 61 x 61 grid outside r = 1.05.
#[test]
fn kirsch_interior_stress_field() {
    let scene = case("kirsch_hole", &[]);
    let (_, level) = pdbem::run_bem::solve(&scene).unwrap();
    let ev = pdbem_bem::post::FieldEvaluator::new(
        &level.setup.mesh,
        &level.setup.material,
        &level.solution,
        level.setup.background,
    );
    let mut worst: f64 = 0.0;
    for r in [1.1, 1.5, 2.0, 3.0] {
        for k in 0..24 {
            let t = 2.0 * PI * k as f64 / 24.0 + 0.01;
            let (c, s) = (t.cos(), t.sin());
            let a2 = 1.0 / (r * r);
            let srr = 0.5 * (1.0 - a2) + 0.5 * (1.0 - 4.0 * a2 + 3.0 * a2 * a2) * (2.0 * t).cos();
            let stt = 0.5 * (1.0 + a2) - 0.5 * (1.0 + 3.0 * a2 * a2) * (2.0 * t).cos();
            let srt = -0.5 * (1.0 + 2.0 * a2 - 3.0 * a2 * a2) * (2.0 * t).sin();
            let exact = [
                srr * c * c + stt * s * s - 2.0 * srt * s * c,
                srr * s * s + stt * c * c + 2.0 * srt * s * c,
                (srr - stt) * s * c + srt * (c * c - s * s),
            ];
            let got = ev.stress(pdbem_bem::V2::new(r * c, r * s));
            for i in 0..3 {
                worst = worst.max((got[i] - exact[i]).abs());
            }
        }
    }
    println!("max stress error {worst:.3e} sigma");
    assert!(worst < 1e-3);
}

/// `interior.csv` carries stress estimates from the level below, max(|s(h) - s(2h)|,
/// 2e-4 |s|), which bound the error of points a fair distance from the boundary; points
/// nearer an element than 0.3 of its length get a note (constant elements' near-field
/// error, which the two levels share: Kirsch's hole with 256 elements, off the middle of
/// an element, sigma_xx -0.43 % at 0.007 element lengths with an estimate of 0.02 %).
#[test]
fn interior_points_carry_estimates_and_near_boundary_points_a_note() {
    let mid = PI / 2.0 - PI / 256.0;
    let h = 2.0 * (PI / 256.0).sin();
    let ring = |d: f64| ((1.0 + d) * mid.cos(), (1.0 + d) * mid.sin());
    let far = [ring(4.0 * h), ring(1.2 * h), ring(0.41 * h)];
    let points = |pts: &[(f64, f64)]| {
        let list: Vec<String> = pts.iter().map(|p| format!("[{}, {}]", p.0, p.1)).collect();
        list.join(", ")
    };
    let run = |pts: &[(f64, f64)], tag: &str| {
        let scene = case(
            "kirsch_hole",
            &[("bem.interior_points", &format!("[{}]", points(pts)))],
        );
        let out = std::env::temp_dir().join(format!("pdbem-interior-{}-{tag}", std::process::id()));
        let s = pdbem::runner::run_scene(&scene, &out, true).expect("runs");
        let text = std::fs::read_to_string(out.join("interior.csv")).expect("interior.csv");
        let _ = std::fs::remove_dir_all(&out);
        let rows: Vec<Vec<f64>> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect();
        (s.notes, rows)
    };
    let (notes, rows) = run(&far, "far");
    assert!(text_has(&notes, "interior.csv:").is_none(), "{notes:?}");
    for r in &rows {
        let (x, y) = (r[0], r[1]);
        let (rr, t) = (x.hypot(y), y.atan2(x));
        let a2 = 1.0 / (rr * rr);
        let srr = 0.5 * (1.0 - a2) + 0.5 * (1.0 - 4.0 * a2 + 3.0 * a2 * a2) * (2.0 * t).cos();
        let stt = 0.5 * (1.0 + a2) - 0.5 * (1.0 + 3.0 * a2 * a2) * (2.0 * t).cos();
        let srt = -0.5 * (1.0 + 2.0 * a2 - 3.0 * a2 * a2) * (2.0 * t).sin();
        let (c, s) = (t.cos(), t.sin());
        let sxx = srr * c * c + stt * s * s - 2.0 * srt * s * c;
        println!(
            "r {rr:.5}: sxx {:.6} exact {sxx:.6} estimate {:.2e}",
            r[4], r[7]
        );
        assert!((r[4] - sxx).abs() <= r[7], "{r:?} against {sxx}");
    }
    let (notes, _) = run(&[ring(4.0 * h), ring(0.015 * h)], "near");
    let note = text_has(
        &notes,
        "interior.csv: 1 of 2 points lie nearer the boundary",
    );
    assert!(note.is_some(), "{notes:?}");
}

fn text_has<'a>(notes: &'a [String], part: &str) -> Option<&'a String> {
    notes.iter().find(|n| n.contains(part))
}
