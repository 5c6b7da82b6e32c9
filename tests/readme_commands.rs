//! The README's commands run as written (issue 18 item 1): every line of a README.md code
//! block that starts with `pdbem` or `cargo run --release --` is parsed by the command
//! line ([`pdbem::cli::Cli`]), every scene it names exists, and every `check`, `run`,
//! `sweep` and `plot-paths` command runs through [`pdbem::cli::execute`] in README order,
//! its `runs/...` folders in a scratch folder. Heavy scenes run on a smaller copy
//! ([`smaller`]: coarser elements, a sparser K record), which exercises the same code
//! paths; the tolerance sweep leaves out tolerances below 3e-3. `bench` commands are parsed only: each takes minutes (`bench growth` runs full
//! PD), and their quick forms have their own tests (`src/bench.rs`, `src/growth/bench.rs`).

use std::path::{Path, PathBuf};

use clap::Parser;
use pdbem::cli::{execute, Cli, Command};
use pdbem::scene::path::{parse_value, with_overrides};
use pdbem::scene::Scene;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// The command lines of README.md's code blocks, as `pdbem` argument lists.
fn readme_commands() -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(Path::new(ROOT).join("README.md")).expect("README.md");
    let mut out = Vec::new();
    let mut in_block = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if !in_block {
            continue;
        }
        let cmd = line.split(" #").next().unwrap_or("").trim();
        let rest = if let Some(r) = cmd.strip_prefix("cargo run --release --") {
            r
        } else if let Some(r) = cmd.strip_prefix("pdbem ") {
            r
        } else {
            continue;
        };
        let mut args = vec!["pdbem".to_string()];
        args.extend(rest.split_whitespace().map(String::from));
        out.push(args);
    }
    out
}

/// Overrides that make a heavy README scene quick (scene stem, whether the command asks
/// for BEM-only growth).
fn smaller(stem: &str, bem_only: bool) -> Vec<(&'static str, &'static str)> {
    match (stem, bem_only) {
        // BEM-only growth through the plate: 80 re-meshes at 0.1 m, 20 at 0.4 m.
        ("growth_tension_edge", true) => vec![("bem.element_size", "0.4"), ("growth.da", "0.4")],
        // PD-BEM: the K record every 4 m instead of 0.25 m (BEM solves of the path).
        ("growth_tension_edge", false) => vec![("growth.sif_spacing", "4")],
        // Eight lengths on a 1000-element strip.
        ("sent_tall", _) => vec![("bem.element_size", "0.4")],
        _ => Vec::new(),
    }
}

/// The argument list with `cases/...` pointing at the repository (or at a smaller copy
/// written to `scratch`) and `runs/...` into `scratch`.
fn localise(args: &[String], scratch: &Path) -> Vec<String> {
    let bem_only = args.iter().any(|a| a == "bem-only");
    args.iter()
        .map(|a| {
            if let Some(file) = a.strip_prefix("cases/") {
                let stem = file.trim_end_matches(".ron");
                let path = Path::new(ROOT).join(a);
                let ov = smaller(stem, bem_only);
                if ov.is_empty() {
                    return path.display().to_string();
                }
                small_copy(&path, stem, &ov, scratch).display().to_string()
            } else if a.starts_with("runs/") {
                scratch.join(a).display().to_string()
            } else if let Some(list) = a.strip_prefix("bem.tolerance=") {
                // The tolerance sweep without its finest value (1e-3 refines to about
                // 7000 elements, a minute of CPU; README quotes that run).
                let kept: Vec<&str> = list
                    .split(',')
                    .filter(|v| v.parse::<f64>().is_ok_and(|t| t >= 3e-3))
                    .collect();
                format!("bem.tolerance={}", kept.join(","))
            } else {
                a.clone()
            }
        })
        .collect()
}

/// Writes the scene at `path` with `ov` applied to `scratch/cases/<stem>_small<k>.ron`.
fn small_copy(path: &Path, stem: &str, ov: &[(&str, &str)], scratch: &Path) -> PathBuf {
    let scene = Scene::load(path).unwrap_or_else(|e| panic!("{e}"));
    let ov: Vec<(String, serde_json::Value)> = ov
        .iter()
        .map(|(p, v)| (p.to_string(), parse_value(v)))
        .collect();
    let s = with_overrides(&scene, &ov).unwrap_or_else(|e| panic!("{e}"));
    let dir = scratch.join("cases");
    std::fs::create_dir_all(&dir).expect("scratch");
    let k = std::fs::read_dir(&dir).map(|d| d.count()).unwrap_or(0);
    let file = dir.join(format!("{stem}_small{k}.ron"));
    let text = pdbem::scene::ron_options()
        .to_string(&s)
        .expect("scene as RON");
    std::fs::write(&file, text).expect("write scene");
    Scene::load(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    file
}

#[test]
fn every_readme_command_parses_and_runs() {
    let commands = readme_commands();
    // README lists 21 command lines today (one cargo run, twenty pdbem).
    assert!(commands.len() >= 21, "{} commands found", commands.len());
    let scratch = std::env::temp_dir().join(format!("pdbem-readme-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    std::fs::create_dir_all(&scratch).expect("scratch");
    let mut ran = 0;
    for args in &commands {
        let line = args[1..].join(" ");
        for a in args.iter().filter(|a| a.starts_with("cases/")) {
            assert!(
                Path::new(ROOT).join(a).exists(),
                "{line}: {a} does not exist"
            );
        }
        let cli = Cli::try_parse_from(args).unwrap_or_else(|e| panic!("{line}: {e}"));
        if matches!(cli.command, Command::Bench { .. }) {
            continue;
        }
        let local = localise(args, &scratch);
        let cli = Cli::try_parse_from(&local).unwrap_or_else(|e| panic!("{line}: {e}"));
        let t0 = std::time::Instant::now();
        execute(cli.command).unwrap_or_else(|e| panic!("{line}: {e:#}"));
        eprintln!("{line}: {:.1} s", t0.elapsed().as_secs_f64());
        ran += 1;
    }
    // Both growth runs and their overlay ran; the BEM-only run went through the plate.
    let grow_bem = scratch.join("runs/grow-bem/summary.json");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&grow_bem).expect("grow-bem summary"))
            .expect("json");
    assert_eq!(summary["failure"], true, "{summary}");
    assert_eq!(summary["tips_final"][0]["ended"], "outline");
    assert!(scratch.join("runs/grow-pdbem/sif_path.csv").exists());
    assert!(scratch.join("runs/paths.svg").exists());
    assert!(ran >= 11, "{ran} commands ran");
    let _ = std::fs::remove_dir_all(&scratch);
}
