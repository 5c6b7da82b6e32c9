//! PD-BEM growth's growing BEM mesh against `--max-memory`, through the binary (the
//! budget is process-wide). Every window relocation adds 2 `growth.elements_per_extension`
//! elements per tip; the dense system of N elements takes 8 (2N)^2 bytes. Before, nothing
//! bounded it: `growth_tension_edge` with 10000 elements per extension grew to 24 GB in
//! 90 s and was killed by the machine. Now `check` refuses a scene whose first relocation
//! would pass the budget, notes one whose budget ends the path before it can cross the
//! body, and every BEM system is checked before it is allocated, so the run ends with the
//! reason (`complete: false`, exit 3).

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::time::Duration;

mod cli_common;
use cli_common::{pdbem, temp};

/// `growth_tension_edge` with `elements_per_extension`, written to `dir`.
fn variant(dir: &Path, elements: usize) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let case = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/growth_tension_edge.ron");
    let text = std::fs::read_to_string(case).unwrap().replace(
        "elements_per_extension: 5)",
        &format!("elements_per_extension: {elements})"),
    );
    let path = dir.join(format!("epe{elements}.ron"));
    std::fs::write(&path, text).unwrap();
    path
}

fn text(out: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

#[test]
fn a_growing_mesh_is_held_to_the_memory_budget() {
    let dir = temp("mesh-budget", "scenes");
    let check = |scene: &Path, budget: &str| {
        let args: Vec<&OsStr> = vec![
            OsStr::new("check"),
            scene.as_os_str(),
            OsStr::new("--max-memory"),
            OsStr::new(budget),
        ];
        pdbem(&args, Duration::from_secs(60))
    };
    // 700 elements at the start; 4 GiB hold 11585.
    let out = check(&variant(&dir, 10000), "4G");
    let t = text(&out);
    assert!(!out.status.success(), "{t}");
    assert!(
        t.contains("growth.elements_per_extension = 10000: the first window relocation would take the BEM mesh from 700 to 20700 elements"),
        "{t}"
    );
    let out = check(&variant(&dir, 500), "4G");
    let t = text(&out);
    assert!(out.status.success(), "{t}");
    assert!(
        t.contains(
            "holds 11585 (the first mesh has 700): about 10 relocations, 5.000e0 m of crack"
        ),
        "{t}"
    );
    let out = check(&variant(&dir, 5), "4G");
    assert!(
        !text(&out).contains("elements_per_extension"),
        "{}",
        text(&out)
    );

    // 40 MiB hold 1145 elements: 11 relocations of 40; the crack needs about 16.
    let scene = variant(&dir, 20);
    let run = temp("mesh-budget", "run");
    let args: Vec<&OsStr> = vec![
        OsStr::new("run"),
        scene.as_os_str(),
        OsStr::new("--out"),
        run.as_os_str(),
        OsStr::new("--quiet"),
        OsStr::new("--max-memory"),
        OsStr::new("40M"),
    ];
    let out = pdbem(&args, Duration::from_secs(300));
    let t = text(&out);
    assert_eq!(out.status.code(), Some(3), "{t}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["complete"], false);
    let reason = summary["failure_reason"].as_str().unwrap();
    assert!(
        reason.contains("elements (2360 unknowns) need 0.042 GiB for the dense system, over the memory budget of 0.039 GiB"),
        "{reason}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&run);
}
