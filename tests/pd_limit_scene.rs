//! A stand-alone PD ramp with tanh bonds under prescribed loads past the body's capacity
//! (`pdbem_pd::solvers::limit` through `src/run_pd.rs`): `pdbem run` halves the failed
//! step 4 times, stops at the last converged load with its outputs written,
//! `complete: false`, `failure_reason` and `limit` in `summary.json`, and exit code 3;
//! `pdbem sweep` marks such a run `incomplete` and exits 3 as for a failed run; the same
//! bar pulled by its end's displacement stops at its snap-back with the force load
//! control stopped at, and the reason names the snap-back, not a peak load. The
//! physics of the stop (that it is the capacity displacement control shows) is tested
//! in `pd/src/solvers/limit_tests.rs`.

use std::path::{Path, PathBuf};
use std::process::Command;

/// A 0.2 x 0.02 m bar on a 4 mm grid, notched at mid-length from both sides (5 mm deep),
/// its left end held and its right end pulled by 5 MPa times the load factor, in steps of
/// 0.25 to `last`; tanh bonds.
fn scene(last_steps: usize) -> String {
    scene_loaded(last_steps, "Traction(5e6)")
}

/// [`scene`] with the right end's x component `right`.
fn scene_loaded(last_steps: usize, right: &str) -> String {
    format!(
        r#"(
    name: "pd_notched_bar_limit",
    material: (E: 2e11, nu: 0.3333333333333333, plane: Stress, thickness: 0.02),
    body: (
        outline: Rectangle(x0: 0, y0: 0, width: 0.2, height: 0.02),
        patches: [(name: "pin", from: (0, 0.008), to: (0, 0.012))],
    ),
    cracks: [
        (name: "lower", start: (0.1, 0), angle_deg: 90, length: 0.005),
        (name: "upper", start: (0.1, 0.02), angle_deg: -90, length: 0.005),
    ],
    boundary: [
        (on: "left", x: Displacement(0)),
        (on: "pin", y: Displacement(0)),
        (on: "right", x: {right}),
    ],
    load: (initial: 0.25, step: 0.25, count: {last_steps}),
    pd: (
        dx: 0.004,
        surface_correction: true,
        solver: Implicit(max_iter: 25),
        failure: Degradation(s_m: 4e-5, s_c: 4e-4, beta: 3),
    ),
)"#
    )
}

fn dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdbem-limit-{tag}-{}", std::process::id()));
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
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn a_ramp_past_the_capacity_stops_at_its_last_converged_load_with_exit_code_3() {
    let d = dir("run");
    std::fs::write(d.join("bar.ron"), scene(20)).unwrap();
    let (code, err) = pdbem(&["run", "bar.ron", "--out", "out", "--quiet"], &d);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("no equilibrium at load factor"), "{err}");
    let out = d.join("out");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["complete"], false);
    let limit = &summary["limit"];
    let (last, failed) = (
        limit["last_converged_load"].as_f64().unwrap(),
        limit["failed_load"].as_f64().unwrap(),
    );
    assert_eq!(limit["load_unit"], "Pa");
    assert_eq!(limit["cutbacks"], 4);
    // The bracket: a sixteenth of the 1.25 MPa step; the stop within the ramp (the bar
    // carries 4.19 times 5 MPa in the library's Newton test of the same body).
    assert!(
        (failed - last - 1.25e6 / 16.0).abs() < 1.0,
        "{last} {failed}"
    );
    assert!(last > 15e6 && last < 25e6, "{last}");
    let reason = summary["failure_reason"].as_str().unwrap();
    assert!(
        reason.contains("the outputs hold the last converged state")
            && reason.contains("past its peak load"),
        "{reason}"
    );
    // The outputs are those of the last converged state.
    for f in ["nodes.csv", "damage.png", "load_displacement.csv"] {
        assert!(out.join(f).exists(), "{f}");
    }
    let table = std::fs::read_to_string(out.join("load_displacement.csv")).unwrap();
    let last_row = table.lines().last().unwrap();
    let factor: f64 = last_row.split(',').nth(1).unwrap().parse().unwrap();
    assert!((factor * 5e6 - last).abs() < 1e-3, "{last_row}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_sweep_marks_a_stopped_ramp_incomplete_and_exits_3() {
    let d = dir("sweep");
    std::fs::write(d.join("bar.ron"), scene(20)).unwrap();
    // 12 steps end at 3 x 5 MPa, below the capacity: complete; 20 steps pass it.
    let (code, err) = pdbem(
        &[
            "sweep",
            "bar.ron",
            "--vary",
            "load.count=12,20",
            "--out",
            "sw",
            "--quiet",
        ],
        &d,
    );
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("1 of 2 runs failed or ended early"), "{err}");
    let table = std::fs::read_to_string(d.join("sw/sweep.csv")).unwrap();
    let rows: Vec<Vec<&str>> = table.lines().map(|l| l.split(',').collect()).collect();
    let status = rows[0].iter().position(|c| *c == "status").unwrap();
    assert_eq!(rows[1][status], "ok", "{table}");
    assert_eq!(rows[2][status], "incomplete", "{table}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The stop of a run of `text` in a fresh folder: exit code, summary, last row of
/// `load_displacement.csv`.
fn stopped(text: &str, tag: &str) -> (serde_json::Value, Vec<String>) {
    let d = dir(tag);
    std::fs::write(d.join("bar.ron"), text).unwrap();
    let (code, err) = pdbem(&["run", "bar.ron", "--out", "out", "--quiet"], &d);
    assert_eq!(code, Some(3), "{tag}: {err}");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("out/summary.json")).unwrap())
            .unwrap();
    let table = std::fs::read_to_string(d.join("out/load_displacement.csv")).unwrap();
    let last = table.lines().last().unwrap().split(',').map(String::from);
    let last = last.collect();
    let _ = std::fs::remove_dir_all(&d);
    (summary, last)
}

#[test]
fn a_displacement_controlled_ramp_stops_at_the_snap_back_with_the_load_controlled_force() {
    // The end pulled by 1e-5 m per load factor, in steps of 0.1 to 4: Newton follows the
    // bar to the notch's snap-back and loses the path there. Measured: the last converged
    // state at 2.175 carries 8401 N; under load control the bar stops between 8375 and
    // 8406 N (the same body's capacity both ways).
    let text = scene_loaded(40, "Displacement(1e-5)")
        .replace("initial: 0.25, step: 0.25", "initial: 0.1, step: 0.1");
    let (summary, row) = stopped(&text, "displacement");
    let reason = summary["failure_reason"].as_str().unwrap();
    assert!(
        reason.contains("snap-back") && !reason.contains("peak load"),
        "{reason}"
    );
    assert_eq!(summary["limit"]["load_unit"], "-");
    // `right.support.fx` of the last converged state: the force the pulled end carries.
    let pulled: f64 = row[10].parse().unwrap();
    let (load_summary, _) = stopped(&scene(20), "load");
    let capacity = load_summary["limit"]["last_converged_load"]
        .as_f64()
        .unwrap()
        * 0.02
        * 0.02;
    assert!(
        (pulled / capacity - 1.0).abs() < 0.02,
        "displacement control ends at {pulled} N, load control at {capacity} N"
    );
}
