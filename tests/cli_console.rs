//! The command line as a user meets it: `--quiet` hides progress but prints the results
//! (with units), progress on a stderr that is not a terminal comes as lines, and
//! `bench --case` looks for cases under the current folder.

use std::process::Command;

fn pdbem() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pdbem"))
}

fn temp(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("pdbem-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

const CASE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/cases/first_scene.ron");

#[test]
fn quiet_prints_results_with_units_and_no_progress() {
    let out = temp("quiet");
    let o = pdbem()
        .args(["run", CASE, "--quiet", "--out"])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{o:?}");
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("first_scene: BEM, "), "{stdout}");
    assert!(stdout.contains("K_I 3.113e7 Pa m^0.5"), "{stdout}");
    assert!(stdout.contains("outputs in"), "{stdout}");
    // No progress: stderr holds the scene's note only (its reference is the infinite
    // plate's).
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.lines().all(|l| l.starts_with("note: ")) && stderr.contains("finite size"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn progress_comes_as_lines_when_stderr_is_not_a_terminal() {
    let out = temp("sweep");
    let o = pdbem()
        .args(["sweep", CASE, "--vary", "cracks.0.angle_deg=20,40", "--out"])
        .arg(&out)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{o:?}");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(stderr.lines().any(|l| l.starts_with("2/2")), "{stderr}");
    assert!(
        !stderr.contains('\r') && !stderr.contains('\u{1b}'),
        "{stderr:?}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bench_case_is_looked_up_under_the_current_folder() {
    let here = temp("bench");
    std::fs::create_dir_all(&here).expect("dir");
    let o = pdbem()
        .current_dir(&here)
        .args([
            "bench",
            "growth",
            "--case",
            "growth_tension_edge",
            "--out",
            "b",
        ])
        .output()
        .expect("runs");
    assert!(!o.status.success());
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("no file cases/growth_tension_edge.ron under the current folder"),
        "{stderr}"
    );
    let _ = std::fs::remove_dir_all(&here);
}

/// `pdbem check CASE | head -0`: a reader that closed the pipe ends the output quietly
/// (exit 0, nothing on stderr), where `println!` panicked with "failed printing to
/// stdout: Broken pipe".
#[test]
fn a_closed_stdout_pipe_is_not_a_panic() {
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    let o = pdbem()
        .args(["check", CASE])
        .stdout(writer)
        .stderr(std::process::Stdio::piped())
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{o:?}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
