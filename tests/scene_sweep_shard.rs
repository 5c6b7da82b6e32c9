//! Sharded sweeps (issue 22): the shards of a grid, run apart and joined with
//! `--collect`, give the table of the sweep run in one piece (wall times aside), failed
//! runs included; a missing shard or a shard of another sweep is refused by name.

use pdbem::cli::{execute, Command, FailedRuns};
use pdbem::sweep::shard::Shard;

const SRC: &str = r#"(
    name: "shard",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (outline: Rectangle(x0: 0, y0: 0, width: 1, height: 4)),
    cracks: [(name: "c", start: (0, 2), angle_deg: 0, length: 0.5)],
    boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
    bem: (element_size: 0.2, group_sizes: {"c": 0.01}),
    reference: SentTada(width: 1, sigma: 1),
    outputs: (formats: [Svg]),
)"#;

/// A crack of 1.5 m does not fit the 1 m strip: that run fails and is a row too.
const VARY: [&str; 2] = ["cracks.0.length=0.3,0.5,1.5", "bem.element_size=0.2,0.1"];

fn sweep(
    scene: &std::path::Path,
    out: &std::path::Path,
    shard: Option<Shard>,
    collect: bool,
) -> anyhow::Result<()> {
    execute(Command::Sweep {
        scene: scene.to_path_buf(),
        vary: VARY.iter().map(|v| v.to_string()).collect(),
        out: Some(out.to_path_buf()),
        quiet: true,
        max_memory: None,
        shard,
        collect,
    })
}

/// The failed runs of a sweep or shard whose failures are rows (the error of exit code 3,
/// [`FailedRuns`]); any other error fails the test.
fn failed(r: anyhow::Result<()>, what: &str) -> usize {
    match r {
        Ok(()) => 0,
        Err(e) => {
            e.downcast_ref::<FailedRuns>()
                .unwrap_or_else(|| panic!("{what}: {e:#}"))
                .failed
        }
    }
}

/// sweep.csv without its wall-time column.
fn table(dir: &std::path::Path) -> Vec<Vec<String>> {
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

#[test]
fn shards_joined_equal_the_serial_sweep() {
    let root = std::env::temp_dir().join(format!("pdbem_shard_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let scene = root.join("shard.ron");
    std::fs::write(&scene, SRC).unwrap();

    let serial = sweep(&scene, &root.join("serial"), None, false);
    assert_eq!(failed(serial, "serial sweep"), 2, "the 1.5 m cracks fail");
    let sharded = root.join("sharded");
    // A shard's failed runs are rows, not its exit: `--collect` reports them.
    for i in [3, 1] {
        sweep(&scene, &sharded, Some(Shard { index: i, count: 3 }), false).expect("shard");
    }
    let missing = sweep(&scene, &sharded, None, true).expect_err("shard 2 missing");
    assert!(format!("{missing:#}").contains("shards 2/3"), "{missing:#}");
    assert!(!sharded.join("sweep.csv").exists());
    sweep(&scene, &sharded, Some(Shard { index: 2, count: 3 }), false).expect("shard");
    assert_eq!(failed(sweep(&scene, &sharded, None, true), "collect"), 2);

    let (a, b) = (table(&root.join("serial")), table(&sharded));
    assert_eq!(a.len(), 7, "6 runs and a header");
    assert_eq!(a, b);
    assert_eq!(
        a.iter()
            .filter(|r| r.contains(&"failed".to_string()))
            .count(),
        2
    );
    for k in 0..6 {
        let run = format!("run_{k:03}");
        assert_eq!(
            root.join("serial").join(&run).exists(),
            sharded.join(&run).exists(),
            "{run}"
        );
    }
    assert!(sharded.join("sweep_k.svg").exists());

    // A shard of another split, or of another sweep, is refused.
    let other = root.join("other");
    sweep(&scene, &other, Some(Shard { index: 1, count: 2 }), false).expect("shard");
    std::fs::rename(other.join("shard-1-of-2"), sharded.join("shard-1-of-2")).unwrap();
    let mixed = sweep(&scene, &sharded, None, true).expect_err("two splits");
    assert!(format!("{mixed:#}").contains("shards"), "{mixed:#}");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn shard_arguments_are_checked() {
    assert_eq!(
        Shard::parse("2/16"),
        Ok(Shard {
            index: 2,
            count: 16
        })
    );
    for bad in ["0/3", "4/3", "1/0", "a/b", "3", "-1/2", "1/2000000"] {
        let e = Shard::parse(bad).expect_err(bad);
        assert!(e.contains("--shard"), "{e}");
    }
    assert_eq!(Shard { index: 2, count: 3 }.indices(8), vec![1, 4, 7]);
    let all: Vec<usize> = (1..=3)
        .flat_map(|i| Shard { index: i, count: 3 }.indices(8))
        .collect();
    let mut sorted = all.clone();
    sorted.sort();
    assert_eq!(sorted, (0..8).collect::<Vec<_>>(), "disjoint and complete");
}
