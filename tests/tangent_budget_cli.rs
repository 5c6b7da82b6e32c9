//! Sparse tangent factors against `--max-memory`, through the binary (the budget is
//! process-wide). A stand-alone state-based implicit or switching run factors a tangent
//! whose Cholesky factor is several times the model (154.4 MiB for the 100 x 100 plate
//! below, whose nodes and bonds take about 20 MiB): `pdbem check` reports the factor
//! from its symbolic analysis and refuses it over the budget, naming `pd.solver`; `pdbem
//! run` refuses it before the first solve instead of treating the failure as softening
//! (the switching solver then spent its damage increments on a 10 000-node body for
//! more than 10 minutes).

mod cli_common;

use std::time::Duration;

use cli_common::{pdbem, temp};

/// A 1 m plate on a 0.01 m grid, state-based, held on its left side and pulled on its
/// right, solved by `solver`.
fn scene(dir: &std::path::Path, solver: &str) -> std::path::PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let path = dir.join(format!("plate_{solver}.ron"));
    let text = format!(
        r#"(
    name: "plate",
    material: (E: 2e11, nu: 0.3, plane: Stress, thickness: 1e-3),
    body: (
        outline: Rectangle(x0: 0, y0: 0, width: 1, height: 1),
        patches: [(name: "pin", from: (0, 0.45), to: (0, 0.55))],
    ),
    boundary: [
        (on: "left", x: Displacement(0)),
        (on: "pin", y: Displacement(0)),
        (on: "right", x: Traction(1e8)),
    ],
    pd: (dx: 0.01, model: StateBased, solver: {solver}(), surface_correction: true),
)"#
    );
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn check_reports_the_factor_and_refuses_it_over_the_budget() {
    let dir = temp("budget", "check");
    let s = scene(&dir, "Implicit");
    let o = pdbem(&["check".as_ref(), s.as_os_str()], Duration::from_secs(120));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{o:?}");
    assert!(
        stdout.contains("PD tangent: sparse Cholesky factor of 20235306 entries (154.383 MiB)"),
        "{stdout}"
    );
    let o = pdbem(
        &[
            "check".as_ref(),
            s.as_os_str(),
            "--max-memory".as_ref(),
            "100M".as_ref(),
        ],
        Duration::from_secs(120),
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{stderr}");
    for part in [
        "pd.solver: the sparse Cholesky factor of 20316 unknowns",
        "would need 154.383 MiB, over the budget of 100.000 MiB",
        "use pd.solver: Adr",
    ] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_refuses_the_factor_before_the_first_solve() {
    let dir = temp("budget", "run");
    for solver in ["Implicit", "Switching"] {
        let s = scene(&dir, solver);
        let out = dir.join(format!("out_{solver}"));
        let o = pdbem(
            &[
                "run".as_ref(),
                s.as_os_str(),
                "--max-memory".as_ref(),
                "100M".as_ref(),
                "--out".as_ref(),
                out.as_os_str(),
            ],
            Duration::from_secs(120),
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{solver}: {stderr}");
        assert!(
            stderr.contains("would need 154.383 MiB, over the budget of 100.000 MiB"),
            "{solver}: {stderr}"
        );
        assert!(!out.exists(), "{solver}: {} left behind", out.display());
    }
    let _ = std::fs::remove_dir_all(&dir);
}
