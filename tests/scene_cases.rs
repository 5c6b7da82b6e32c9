//! Every scene in `cases/` loads and validates, and opens with a comment
//! saying what it exercises and where its numbers come from.

use std::path::PathBuf;

use pdbem::scene::Scene;

mod common_scene;

fn cases() -> Vec<PathBuf> {
    common_scene::case_files()
}

#[test]
fn every_case_loads_and_validates() {
    let files = cases();
    assert!(
        files.len() >= 7,
        "expected the issue-2 cases, found {files:?}"
    );
    let failures: Vec<String> = files
        .iter()
        .filter_map(|f| Scene::load(f).err().map(|e| e.to_string()))
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn every_case_starts_with_a_comment() {
    for f in cases() {
        let text = std::fs::read_to_string(&f).expect("readable");
        assert!(
            text.trim_start().starts_with("//"),
            "{} must open with a comment",
            f.display()
        );
    }
}

#[test]
fn case_names_match_file_names() {
    for f in cases() {
        let s = Scene::load(&f).expect("valid");
        let stem = f.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
        assert_eq!(s.name, stem, "{}", f.display());
    }
}

#[test]
fn seed002_sent_cases_reproduce_the_exact_cmod_column() {
    // Seed 002 Table 3 "exact": 7.20e-4, 4.92e-3, 6.41e-2 m.
    for (a, exact) in [(2, 7.20e-4), (5, 4.92e-3), (8, 6.41e-2)] {
        let f = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("cases/sent_bem_a{a}.ron"));
        let s = Scene::load(&f).expect("valid");
        let (_, cmod) = pdbem::runner::reference::cmod_reference(&s).expect("SENT reference");
        assert!(((cmod - exact) / exact).abs() < 2e-3, "a = {a}: {cmod}");
    }
}
