//! `pd.refinement` against `--max-memory`, through the binary (the budget is
//! process-wide). Static regions multiply the particles up to 4^max_level inside them:
//! `pdbem check` estimates what they add and refuses a refinement over the budget naming
//! `pd.refinement`; splits the criteria make during a run are checked against the budget
//! before the refined body is allocated, so a run is refused instead of aborting on
//! allocation.

use std::path::{Path, PathBuf};
mod cli_common;

use std::time::Duration;

use cli_common::{pdbem, temp};

fn case(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(name)
}

/// `case` with its `refinement: (...)` line replaced by `refinement`, written to `dir`.
fn variant(dir: &Path, case_name: &str, refinement: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let text = std::fs::read_to_string(case(case_name)).unwrap();
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with("refinement:"))
        .expect("a refinement line");
    let path = dir.join(case_name);
    std::fs::write(
        &path,
        text.replace(line, &format!("        refinement: {refinement},")),
    )
    .unwrap();
    path
}

/// The path-refined branching case: `check` reports the body the run starts from (the
/// run's own count: 9976 particles, `docs/seed004.md`), and the size estimate of its
/// circle ([`pdbem::setup::refined_size::refined_children`], which the budget check uses
/// before anything is built) is within 5 % of what the circle splits (the set-up's 1992
/// splits, 3 particles each: 5976; estimated 5973; a dynamic run's set-up splits the
/// static regions only).
#[test]
fn check_reports_the_refined_start_and_the_estimate_holds() {
    let path = case("seed004_branching_case1_path_refined.ron");
    let o = pdbem(
        &["check".as_ref(), path.as_os_str()],
        Duration::from_secs(120),
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{o:?}");
    assert!(
        stdout.contains("note: pd.refinement: the set-up splits 1992 particles: 9976 particles and 272998 directed bonds at the start"),
        "{stdout}"
    );
    let scene = pdbem::scene::Scene::load(&path).unwrap();
    let r = scene
        .pd
        .as_ref()
        .and_then(|pd| pd.refinement.as_ref())
        .unwrap();
    let geo = pdbem::scene::shapes::SceneGeometry::of(&scene);
    let (n, _) = pdbem::setup::refined_size::refined_children(r, &geo, 1e-3, 3.015);
    let split = 3.0 * 1992.0;
    assert!((n / split - 1.0).abs() < 0.05, "{n} against {split}");
}

/// A circle over the whole branching plate split 4 times (about 1e6 particles, 2.9e7
/// bonds): `check` and `run` refuse it at 3 GiB naming `pd.refinement`, and `run` leaves
/// no output folder.
#[test]
fn a_refinement_over_the_budget_is_refused_by_check_and_run() {
    let dir = temp("refbudget", "deep");
    let s = variant(
        &dir,
        "seed004_branching_case1_path_refined.ron",
        "(circles: [(centre: (0.05, 0.02), radius: 0.2)], max_level: 4)",
    );
    let budget = ["--max-memory".as_ref(), "3G".as_ref()];
    let o = pdbem(
        &[&["check".as_ref(), s.as_os_str()][..], &budget[..]].concat(),
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{stderr}");
    assert!(
        stderr.contains(
            "pd.refinement (max_level 4, its circles and near_cracks) gives about 1.025e6 PD nodes"
        ),
        "{stderr}"
    );
    let out = dir.join("out");
    let o = pdbem(
        &[
            &[
                "run".as_ref(),
                s.as_os_str(),
                "--out".as_ref(),
                out.as_os_str(),
            ][..],
            &budget[..],
        ]
        .concat(),
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success() && stderr.contains("pd.refinement"),
        "{stderr}"
    );
    assert!(!out.exists(), "{} left behind", out.display());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The adaptive branching case has no static region, so its size estimate (about 18 MB)
/// passes a budget of 20 MB and its set-up splits nothing. But a split builds the refined
/// body beside the one it splits, so the first split during the run would need twice the
/// 4000-particle body (24.8 MiB): `check` and `run` refuse the scene at its set-up,
/// before the first step, naming `pd.refinement`, and `run` leaves no output folder.
#[test]
fn a_split_over_the_budget_ends_the_run_before_it_allocates() {
    let dir = temp("refbudget", "split");
    let adaptive = case("seed004_branching_case1_adaptive.ron");
    let o = pdbem(
        &[
            "check".as_ref(),
            adaptive.as_os_str(),
            "--max-memory".as_ref(),
            "20M".as_ref(),
        ],
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        !o.status.success()
            && stderr.contains(
                "pd.refinement: a split during the run builds the refined body beside the body it splits (4000 particles"
            )
            && stderr.contains("over the budget of 20.000 MiB"),
        "{stderr}"
    );
    let out = dir.join("out");
    let o = pdbem(
        &[
            "run".as_ref(),
            adaptive.as_os_str(),
            "--max-memory".as_ref(),
            "20M".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{stderr}");
    for part in [
        "pd.refinement: a split during the run builds the refined body beside the body it splits (4000 particles",
        "over the budget of 20.000 MiB",
    ] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    assert!(!out.exists(), "{} left behind", out.display());
    let _ = std::fs::remove_dir_all(&dir);
}
