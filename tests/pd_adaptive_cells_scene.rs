//! `pd.refinement` on the grid's cells (the tanh law under a quasi-static solver,
//! `pdbem_pd::adapt` through `src/run_pd.rs`): the shipped case runs to its last load
//! with the notch tips' cells split and reported; a plain-PMB scene is accepted (the
//! particle path needs the state-based model); settings the cells cannot take are
//! refused by `pdbem check` naming the field. The physics (the finer grid's peak force)
//! is tested in `pd/src/adapt/tests.rs`.

use std::path::{Path, PathBuf};
use std::process::Command;

const CASE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/cases/pd_notched_bar_adaptive.ron"
);

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdbem-cells-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn pdbem(args: &[&str], at: &Path) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_pdbem"))
        .args(args)
        .current_dir(at)
        .output()
        .expect("pdbem runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr),
    )
}

#[test]
fn the_case_splits_its_notch_tips_and_reports_the_cells() {
    let d = dir("run");
    let (code, text) = pdbem(&["run", CASE, "--out", "out", "--quiet"], &d);
    assert_eq!(code, Some(0), "{text}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("out/summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["complete"], true);
    let r = &summary["refinement"];
    assert_eq!(r["on"], "cells");
    let cells = r["cells_level_1"].as_u64().unwrap();
    assert!(cells >= 4, "{r}");
    // Each split coarse cell holds four children.
    assert_eq!(summary["refined_nodes"].as_u64().unwrap(), 4 * cells);
    let rounds = r["rounds"].as_array().unwrap();
    assert!(!rounds.is_empty());
    let last_nodes = rounds.last().unwrap()["nodes"].as_u64().unwrap();
    assert_eq!(summary["nodes"].as_u64().unwrap(), last_nodes);
    // 300 coarse nodes, each split cell adding three.
    assert_eq!(last_nodes, 300 + 3 * cells);
    let (code, text) = pdbem(&["check", CASE], &d);
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("the set-up splits"), "{text}");
}

#[test]
fn cells_refuse_a_third_level_and_kept_horizons() {
    let scene = std::fs::read_to_string(CASE).unwrap();
    let d = dir("refuse");
    for (with, field) in [
        (
            "refinement: (critical_damage: 0.25, max_level: 3)",
            "pd.refinement.max_level",
        ),
        (
            "refinement: (critical_damage: 0.25, keep_horizon: true)",
            "pd.refinement.keep_horizon",
        ),
    ] {
        let s = scene.replace("refinement: (critical_damage: 0.25)", with);
        assert_ne!(s, scene);
        std::fs::write(d.join("bar.ron"), s).unwrap();
        let (code, text) = pdbem(&["check", "bar.ron"], &d);
        assert_ne!(code, Some(0), "{with}: {text}");
        assert!(text.contains(field), "{with}: {text}");
    }
}
