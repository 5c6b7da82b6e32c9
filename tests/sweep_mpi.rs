//! MPI sweeps (issue 22). With `--features mpi` (`.ci/run` installs OpenMPI and runs
//! this file so): `mpirun --oversubscribe -np 2 pdbem sweep ...` gives the serial sweep's
//! table (wall times aside), failed runs included (exit code 3 on both), with every run
//! done exactly once and both ranks working; a sweep folder in use stops every rank before
//! any run; the README's mpirun command runs as written. Without the feature: a pdbem
//! started as one of several MPI ranks refuses the sweep instead of letting every rank
//! run all of it.

use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_pdbem");

/// The scene of `tests/scene_sweep_shard.rs`: a 1 m strip, coarse elements.
const SRC: &str = r#"(
    name: "mpi",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (outline: Rectangle(x0: 0, y0: 0, width: 1, height: 4)),
    cracks: [(name: "c", start: (0, 2), angle_deg: 0, length: 0.5)],
    boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
    bem: (element_size: 0.2, group_sizes: {"c": 0.01}),
    reference: SentTada(width: 1, sigma: 1),
    outputs: (formats: [Svg]),
)"#;

/// A crack of 1.5 m does not fit the 1 m strip: those two runs fail and are rows.
const VARY: [&str; 2] = [
    "cracks.0.length=0.2,0.3,0.4,0.5,1.5",
    "bem.element_size=0.2,0.1",
];

fn scratch(name: &str) -> PathBuf {
    let root = std::env::temp_dir().join(format!("pdbem_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).expect("scratch folder");
    root
}

fn sweep_args(scene: &Path, out: &Path) -> Vec<String> {
    let mut args = vec!["sweep".to_string(), scene.display().to_string()];
    for v in VARY {
        args.extend(["--vary".to_string(), v.to_string()]);
    }
    args.extend(["--out".into(), out.display().to_string(), "--quiet".into()]);
    args
}

#[cfg(not(feature = "mpi"))]
#[test]
fn without_the_feature_a_rank_refuses_the_sweep() {
    let root = scratch("mpi_refuse");
    let scene = root.join("mpi.ron");
    std::fs::write(&scene, SRC).unwrap();
    let out = Command::new(BIN)
        .args(sweep_args(&scene, &root.join("out")))
        .env("OMPI_COMM_WORLD_SIZE", "2")
        .output()
        .expect("pdbem starts");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("built without the `mpi` feature"), "{err}");
    assert!(!root.join("out/sweep.csv").exists());
    // One rank is a plain sweep: its two failed runs are rows, and exit code 3 says so.
    let one = Command::new(BIN)
        .args(sweep_args(&scene, &root.join("one")))
        .env("OMPI_COMM_WORLD_SIZE", "1")
        .output()
        .expect("pdbem starts");
    let err = String::from_utf8_lossy(&one.stderr);
    assert!(
        one.status.code() == Some(3) && err.contains("2 of 10 runs failed"),
        "{:?}: {err}",
        one.status
    );
    assert!(root.join("one/sweep.csv").exists());
    let _ = std::fs::remove_dir_all(&root);
}

#[cfg(feature = "mpi")]
mod with_mpi {
    use super::*;

    /// mpirun, allowed to run as root (CI runs as root; OpenMPI refuses otherwise).
    pub(super) fn mpirun() -> Command {
        let mut c = Command::new("mpirun");
        c.env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
        c
    }

    /// sweep.csv without its wall-time column.
    fn table(dir: &Path) -> Vec<Vec<String>> {
        let text = std::fs::read_to_string(dir.join("sweep.csv")).expect("sweep.csv");
        let rows: Vec<Vec<String>> = text
            .lines()
            .map(|l| l.split(',').map(String::from).collect())
            .collect();
        let col = rows[0]
            .iter()
            .position(|c| c == "wall_time_s")
            .expect("wall time column");
        rows.into_iter()
            .map(|mut r| {
                r.remove(col);
                r
            })
            .collect()
    }

    fn check_ok(out: std::process::Output, what: &str) {
        assert!(
            out.status.success(),
            "{what}: {}\n{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }

    /// A sweep whose two failed runs are rows: exit code 3 (`pdbem::cli::EXIT_INCOMPLETE`;
    /// under mpirun, rank 0's), with the count in the message.
    fn check_two_failed(out: std::process::Output, what: &str) {
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            out.status.code() == Some(3) && err.contains("2 of 10 runs failed"),
            "{what}: {:?}\n{}\n{err}",
            out.status,
            String::from_utf8_lossy(&out.stdout),
        );
    }

    #[test]
    fn mpirun_two_ranks_equals_the_serial_sweep() {
        let root = scratch("mpi_sweep");
        let scene = root.join("mpi.ron");
        std::fs::write(&scene, SRC).unwrap();
        let serial = Command::new(BIN)
            .args(sweep_args(&scene, &root.join("serial")))
            .output()
            .expect("pdbem starts");
        check_two_failed(serial, "serial sweep");
        let par = mpirun()
            .args(["--oversubscribe", "-np", "2", BIN])
            .args(sweep_args(&scene, &root.join("mpi")))
            .output()
            .expect("mpirun starts (OpenMPI installed?)");
        check_two_failed(par, "mpirun sweep");

        let (a, b) = (table(&root.join("serial")), table(&root.join("mpi")));
        assert_eq!(a.len(), 11, "10 runs and a header");
        assert_eq!(a, b);
        let failed = a
            .iter()
            .filter(|r| r.contains(&"failed".to_string()))
            .count();
        assert_eq!(failed, 2, "the 1.5 m cracks");
        for k in 0..10 {
            let dir = root.join(format!("mpi/run_{k:03}"));
            assert_eq!(
                dir.join("summary.json").exists(),
                k < 8,
                "{}",
                dir.display()
            );
        }

        let rec: pdbem::sweep::schedule::MpiRecord = serde_json::from_str(
            &std::fs::read_to_string(root.join("mpi/sweep_mpi.json")).expect("sweep_mpi.json"),
        )
        .expect("record parses");
        assert_eq!(rec.ranks, 2);
        let mut done: Vec<usize> = rec.runs.iter().map(|r| r.run).collect();
        done.sort();
        assert_eq!(done, (0..10).collect::<Vec<_>>(), "every run exactly once");
        for rank in 0..2 {
            assert!(
                rec.runs.iter().any(|r| r.rank == rank),
                "rank {rank} ran nothing: {:?}",
                rec.runs
            );
        }
        let busy: f64 = rec.runs.iter().map(|r| r.run_s).sum();
        let e = busy / (2.0 * rec.makespan_s);
        assert!(
            (rec.efficiency - e).abs() < 1e-12 && e > 0.0 && e <= 1.0,
            "{e}"
        );
        for r in &rec.runs {
            assert!(r.start_s <= r.end_s && r.end_s <= rec.makespan_s, "{r:?}");
        }

        // A folder another live pdbem holds (pid 1 stands for it): every rank stops
        // before any run, and mpirun fails.
        let locked = root.join("locked");
        std::fs::create_dir_all(&locked).unwrap();
        std::fs::write(locked.join(".pdbem-lock"), "1").unwrap();
        let refused = mpirun()
            .args(["--oversubscribe", "-np", "2", BIN])
            .args(sweep_args(&scene, &locked))
            .output()
            .expect("mpirun starts");
        let err = String::from_utf8_lossy(&refused.stderr);
        assert!(!refused.status.success(), "{err}");
        assert!(err.contains("in use by pdbem process 1"), "{err}");
        assert!(!locked.join("run_000").exists() && !locked.join("sweep.csv").exists());
        let _ = std::fs::remove_dir_all(&root);
    }

    /// The README's `mpirun` line, with `pdbem` the test binary and `runs/` a scratch folder.
    #[test]
    fn readme_mpirun_command_runs() {
        let root_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
        let readme = std::fs::read_to_string(root_dir.join("README.md")).expect("README.md");
        let line = readme
            .lines()
            .map(|l| l.split(" #").next().unwrap_or("").trim())
            .find(|l| l.starts_with("mpirun "))
            .expect("README shows an mpirun command");
        let scratch = scratch("mpi_readme");
        let args: Vec<String> = line
            .split_whitespace()
            .skip(1)
            .map(|a| match a {
                "pdbem" => BIN.to_string(),
                _ if a.starts_with("runs/") => scratch.join(a).display().to_string(),
                _ => a.to_string(),
            })
            .collect();
        let out = mpirun()
            .args(&args)
            .current_dir(root_dir)
            .output()
            .expect("mpirun starts");
        check_ok(out, line);
        let out_dir = args
            .iter()
            .position(|a| a == "--out")
            .map(|i| PathBuf::from(&args[i + 1]))
            .expect("the README command names --out");
        assert!(out_dir.join("sweep.csv").exists() && out_dir.join("sweep_mpi.json").exists());
        let _ = std::fs::remove_dir_all(&scratch);
    }
}
