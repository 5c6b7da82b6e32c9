//! Shared helpers of the scene-level verification tests.
#![allow(dead_code)]

use std::path::PathBuf;

use pdbem::run_bem;
use pdbem::runner::RunSummary;
use pdbem::scene::path::{parse_value, with_overrides};
use pdbem::scene::Scene;

/// Loads a case with dotted-path overrides (`("cracks.0.length", "3")`).
pub fn case(name: &str, overrides: &[(&str, &str)]) -> Scene {
    let scene = Scene::load(format!("{}/cases/{name}.ron", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let ov: Vec<(String, serde_json::Value)> = overrides
        .iter()
        .map(|(p, v)| (p.to_string(), parse_value(v)))
        .collect();
    with_overrides(&scene, &ov).unwrap()
}

/// Solves a BEM scene and fills the reference errors.
pub fn solve_bem(scene: &Scene) -> RunSummary {
    let (mut s, _) = run_bem::solve(scene).unwrap();
    pdbem::runner::reference::apply(scene, &mut s);
    s
}

/// Relative error in percent.
pub fn pct(v: f64, r: f64) -> f64 {
    100.0 * (v / r - 1.0)
}

/// Every scene file of `cases/`, sorted.
pub fn case_files() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("cases/ exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    files.sort();
    files
}
