//! Seed 004 section 4.3 (Kalthoff-Winkler) from a scene: the impact's region velocities
//! are validated, and a cheap coarse run (dx = 2 mm, the automatic time step instead of
//! the seed's 1e-8 s, 60 us) grows the primary cracks from the pre-crack tips at the
//! angle band of the seed's Table 8.

use std::path::{Path, PathBuf};

use pdbem::runner::run_scene;
use pdbem::scene::Scene;

fn case_text(name: &str) -> String {
    let f = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name);
    std::fs::read_to_string(f).expect("case file")
}

fn parse(text: &str) -> Result<Scene, String> {
    Scene::from_ron_str(text, Path::new("kw.ron")).map_err(|e| format!("{e}"))
}

const IMPACT: &str = "(min: (0, 0.075), max: (0.006, 0.125), velocity: (16.5, 0), hold: true)";

/// The three cases parse; a box turned inside out, a box outside the body, a non-finite
/// or a zero velocity that is not held are refused with the field named; the impact
/// alone loads the body (no boundary condition needed).
#[test]
fn impact_boxes_are_validated() {
    let text = case_text("seed004_kalthoff_coarse.ron");
    for c in ["coarse", "fine", "adaptive"] {
        parse(&case_text(&format!("seed004_kalthoff_{c}.ron"))).expect(c);
    }
    assert!(text.contains(IMPACT));
    let refused = |to: &str, field: &str| {
        let e = parse(&text.replace(IMPACT, to)).expect_err(to);
        assert!(e.contains(field), "{to}: {e}");
    };
    refused(
        "(min: (0.006, 0.075), max: (0, 0.125), velocity: (16.5, 0))",
        "pd.solver.velocities.0.max",
    );
    refused(
        "(min: (0.2, 0.075), max: (0.3, 0.125), velocity: (16.5, 0))",
        "pd.solver.velocities.0.min",
    );
    refused(
        "(min: (0, 0.075), max: (0.006, 0.125), velocity: (0, 0))",
        "pd.solver.velocities.0.velocity",
    );
    refused(
        "(min: (0, 0.075), max: (0.006, 0.125), velocity: (inf, 0))",
        "pd.solver.velocities.0.velocity",
    );
    let e = parse(&text.replace(&format!("velocities: [{IMPACT}],"), "")).expect_err("no load");
    assert!(e.contains("nothing to solve"), "{e}");
}

/// The coarse plate (dx = 2 mm, 5000 particles) for 60 us at the automatic dt
/// (0.8 dt_c = 4.35e-7 s: 138 steps): both primary cracks leave their pre-crack tips at
/// 50 to 70 degrees from the pre-crack direction (measured 58.9; with the seed's
/// dt = 1e-8 s for 100 us 59.2; seed Table 8: coarse 61.8, adaptive 60.9, fine 66.1,
/// experiment about 70; a mode-I crack would run at 0 degrees), the upper one up and the
/// lower one down by the same angle (the set-up is symmetric about y = 100 mm, to 0.5
/// degrees); every damaged particle ahead of the pre-cracks lies within 3 dx of the two
/// lines from the tips at the measured angles or is part of the secondary cracks that
/// grow from the right edge between the pre-crack lines (x >= 70 mm, 74 < y < 126 mm; the
/// seed's "secondary fracture generated at the right side"); the energies are finite and
/// the dissipation positive.
#[test]
fn coarse_impact_deflects_the_cracks_at_the_seed_angle() {
    let text = case_text("seed004_kalthoff_coarse.ron")
        .replace("dt: Some(1e-8),", "")
        .replace("end_time: 1e-4", "end_time: 6e-5")
        .replace("snapshots: [2.4e-5, 5e-5, 8e-5, 1e-4]", "snapshots: [6e-5]");
    let scene = parse(&text).expect("valid");
    let dir = std::env::temp_dir().join(format!("pdbem_kw_scene_{}", std::process::id()));
    let s = run_scene(&scene, &dir, true).unwrap_or_else(|e| panic!("{e:#}"));
    let a = &s.extra["deflection_deg"];
    let (lower, upper) = (a[0].as_f64().unwrap(), a[1].as_f64().unwrap());
    assert!((50.0..=70.0).contains(&upper), "{a}");
    assert!((upper + lower).abs() < 0.5, "{a}");
    let f = &s.extra["dynamics"]["final"];
    for k in ["kinetic_J", "strain_J", "external_work_J", "fracture_J"] {
        assert!(f[k].as_f64().unwrap().is_finite(), "{f}");
    }
    assert!(f["fracture_J"].as_f64().unwrap() > 0.0, "{f}");
    let nodes = std::fs::read_to_string(dir.join("nodes.csv")).expect("nodes.csv");
    let dx = 0.002;
    let tips = [([0.05, 0.074], lower), ([0.05, 0.126], upper)];
    let mut on_ray = [0usize; 2];
    for l in nodes.lines().skip(1) {
        let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        let secondary = v[0] >= 0.07 && v[1] > 0.074 && v[1] < 0.126;
        if v[4] <= 0.4 || v[0] <= 0.05 + 3.0 * dx || secondary {
            continue;
        }
        let near = tips.iter().position(|(t, ang)| {
            let (c, s) = (ang.to_radians().cos(), ang.to_radians().sin());
            ((v[0] - t[0]) * s - (v[1] - t[1]) * c).abs() <= 3.0 * dx
        });
        let k = near.unwrap_or_else(|| panic!("damage off the primary cracks at {v:?}"));
        on_ray[k] += 1;
    }
    assert!(on_ray.iter().all(|&n| n >= 10), "{on_ray:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
