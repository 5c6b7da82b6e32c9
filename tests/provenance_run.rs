//! Every run folder records what made it: `scene.ron` (the resolved scene) runs again
//! to the same numbers, and `summary.json` carries the version, commit, thread count,
//! command line and start time.

use std::path::PathBuf;

use pdbem::runner::run_scene;
use pdbem::scene::path::{parse_value, with_overrides};
use pdbem::scene::Scene;

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdbem-prov-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn written_scene_runs_again_to_the_same_numbers() {
    let case = concat!(env!("CARGO_MANIFEST_DIR"), "/cases/first_scene.ron");
    let base = Scene::load(case).expect("case");
    // A sweep-like override must reach scene.ron.
    let scene = with_overrides(&base, &[("cracks.0.angle_deg".into(), parse_value("40"))])
        .expect("override");
    let (a, b) = (temp("a"), temp("b"));
    let first = run_scene(&scene, &a, true).expect("first run");
    let text = std::fs::read_to_string(a.join("scene.ron")).expect("scene.ron");
    assert!(text.starts_with("// The resolved scene"), "{text}");
    let again = Scene::load(a.join("scene.ron")).expect("scene.ron loads");
    assert_eq!(again.cracks[0].angle_deg, Some(40.0));
    assert_eq!(again.to_json(), scene.to_json());
    let second = run_scene(&again, &b, true).expect("second run");
    assert_eq!(first.tips.len(), second.tips.len());
    for (x, y) in first.tips.iter().zip(&second.tips) {
        // Same scene, same machine: the same numbers to round-off of the parallel assembly.
        assert!(
            (x.k1 - y.k1).abs() <= 1e-10 * x.k1.abs(),
            "{} vs {}",
            x.k1,
            y.k1
        );
        assert!(
            (x.k2 - y.k2).abs() <= 1e-10 * x.k1.abs(),
            "{} vs {}",
            x.k2,
            y.k2
        );
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(a.join("summary.json")).expect("summary"))
            .expect("json");
    let p = &json["provenance"];
    assert_eq!(p["version"], env!("CARGO_PKG_VERSION"));
    assert!(p["threads"].as_u64().is_some_and(|t| t >= 1), "{p}");
    assert!(!p["git_commit"].as_str().unwrap_or("").is_empty(), "{p}");
    assert!(
        p["command_line"].as_array().is_some_and(|c| !c.is_empty()),
        "{p}"
    );
    let t = p["start_time"].as_str().unwrap_or("");
    let shape = t.len() == 20
        && t.ends_with('Z')
        && t.chars().enumerate().all(|(i, c)| match i {
            4 | 7 => c == '-',
            10 => c == 'T',
            13 | 16 => c == ':',
            19 => c == 'Z',
            _ => c.is_ascii_digit(),
        });
    assert!(shape, "start_time {t}");
    let _ = std::fs::remove_dir_all(&a);
    let _ = std::fs::remove_dir_all(&b);
}
