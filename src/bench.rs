//! `pdbem bench {bem|pd|coupling|growth} --out DIR [--quick]`: timing tables and
//! `DIR/bench.json` (schemas in docs/outputs.md). Speed targets live here, never in tests.
//!
//! `bench bem` (issue 2): the seed-002 edge-cracked plate (a/W = 0.8) at about 500, 1000,
//! 2000 and 4000 elements plus the 3680-element mesh of seed 002 Table 5 case 3; per mesh
//! assembly, factorization, one further right-hand side (median of 5) and memory, and the
//! least-squares scaling exponents of each time in the element count.

use crate::output::atomic::write_atomic;
use anyhow::{Context, Result};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// Which benchmark.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum BenchKind {
    /// BEM assembly / factorisation / solve times and memory (issue 2).
    Bem,
    /// PD bond-force throughput and switching speed-up (issue 3).
    Pd,
    /// PD-BEM coupling on the SENT cases (issue 4).
    Coupling,
    /// Growth: PD-BEM against BEM-only and full PD (issue 5).
    Growth,
}

/// `bench.json` of `bench bem`.
#[derive(Debug, Serialize)]
pub struct BemBenchReport {
    /// Benchmark name ("bem").
    pub bench: &'static str,
    /// Threads rayon used.
    pub threads: usize,
    /// One entry per mesh.
    pub meshes: Vec<pdbem_bem::bench::BenchEntry>,
    /// Fitted exponents p of time ~ elements^p: assembly, factor, solve.
    pub exponents: Exponents,
    /// The seed-002 Table 5 case 3 mesh (about 3680 elements): assembly + factor (s).
    pub table5_case3_assemble_factor_s: Option<f64>,
    /// Its further right-hand side by substitution (s).
    pub table5_case3_solve_s: Option<f64>,
    /// Its further right-hand side through the precomputed response (s).
    pub table5_case3_solve_response_s: Option<f64>,
}

/// Scaling exponents.
#[derive(Debug, Serialize)]
pub struct Exponents {
    /// Assembly time exponent (expected 2).
    pub assembly: Option<f64>,
    /// Factorization exponent (expected 3 asymptotically).
    pub factor: Option<f64>,
    /// Further right-hand side exponent (expected 2).
    pub solve: Option<f64>,
}

/// Runs a benchmark into `out` (`quick`: smaller sizes for CI).
pub fn run(kind: BenchKind, out: &Path, quick: bool) -> Result<()> {
    match kind {
        BenchKind::Bem => bench_bem(out, quick),
        BenchKind::Pd => crate::run_pd::bench(out, quick),
        BenchKind::Coupling => {
            anyhow::bail!("bench coupling is not wired yet (it arrives with issue 4)")
        }
        BenchKind::Growth => {
            anyhow::bail!("bench growth is not wired yet (it arrives with issue 5)")
        }
    }
}

fn bench_bem(out: &Path, quick: bool) -> Result<()> {
    let sizes: &[usize] = if quick {
        &[250, 500]
    } else {
        &[500, 1000, 2000, 3680, 4000]
    };
    eprintln!("bench bem: meshes of about {sizes:?} elements");
    let meshes = pdbem_bem::bench::run(sizes, 5).context("bench bem")?;
    let fit = |f: &dyn Fn(&pdbem_bem::bench::BenchEntry) -> f64| {
        pdbem_bem::bench::fit_exponent(
            &meshes
                .iter()
                .map(|m| (m.elements as f64, f(m)))
                .collect::<Vec<_>>(),
        )
    };
    let case3 = meshes.iter().find(|m| (3600..3800).contains(&m.elements));
    let report = BemBenchReport {
        bench: "bem",
        threads: rayon::current_num_threads(),
        exponents: Exponents {
            assembly: fit(&|m| m.assembly_s),
            factor: fit(&|m| m.factor_s),
            solve: fit(&|m| m.solve_s),
        },
        table5_case3_assemble_factor_s: case3.map(|m| m.assembly_s + m.factor_s),
        table5_case3_solve_s: case3.map(|m| m.solve_s),
        table5_case3_solve_response_s: case3.map(|m| m.solve_response_s),
        meshes,
    };
    let table = bem_table(&report);
    print!("{table}");
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    write_atomic(&out.join("bench.txt"), table.as_bytes())?;
    write_atomic(
        &out.join("bench.json"),
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    eprintln!("bench bem: wrote {}", out.join("bench.json").display());
    Ok(())
}

fn bem_table(r: &BemBenchReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "BEM benchmark ({} threads): seed-002 plate, a/W = 0.8",
        r.threads
    );
    let _ = writeln!(
        s,
        "{:>9} {:>9} {:>11} {:>10} {:>10} {:>11} {:>12} {:>11}",
        "elements",
        "unknowns",
        "assembly_s",
        "factor_s",
        "solve_s",
        "response_s",
        "solve_resp_s",
        "memory_MB"
    );
    for m in &r.meshes {
        let _ = writeln!(
            s,
            "{:>9} {:>9} {:>11.3} {:>10.3} {:>10.4} {:>11.3} {:>12.5} {:>11.1}",
            m.elements,
            m.unknowns,
            m.assembly_s,
            m.factor_s,
            m.solve_s,
            m.response_s,
            m.solve_response_s,
            m.memory_bytes as f64 / 1e6
        );
    }
    let e = |x: Option<f64>| x.map(|v| format!("{v:.2}")).unwrap_or_else(|| "-".into());
    let _ = writeln!(
        s,
        "exponents (time ~ N^p): assembly {}, factor {}, solve {}",
        e(r.exponents.assembly),
        e(r.exponents.factor),
        e(r.exponents.solve)
    );
    if let (Some(af), Some(sv), Some(sr)) = (
        r.table5_case3_assemble_factor_s,
        r.table5_case3_solve_s,
        r.table5_case3_solve_response_s,
    ) {
        let _ = writeln!(
            s,
            "seed 002 Table 5 case 3 mesh: assemble + factor {af:.2} s (target < 10 s); further RHS {:.1} ms by substitution, {:.2} ms through the precomputed response (target < 50 ms)",
            sv * 1e3,
            sr * 1e3
        );
    }
    s
}
