//! `pdbem bench {bem|pd|coupling|growth|sweep-mpi|trade} --out DIR [--quick]`: timing tables and
//! `DIR/bench.json` (schemas in docs/outputs.md). Speed targets live here, never in tests.
//!
//! `bench pd` (issue 3): bond-force throughput at about 1e4, 1e5 and 1e6 bonds, bytes per
//! bond, tangent factorisation and solve times, and the switching solver against pure ADR on
//! `pd_plate_hole` and `pd_three_point_bend` in one run (`switching_speedup`, damage and
//! displacement agreement), and seed 004's dynamic branching plate, cases 1 and 2, timed on
//! the coarse grid, the fine grid and the adaptively refined coarse grid over 80 us (2 us
//! with `--quick`) with the fine/coarse and adaptive/coarse ratios next to the seed's
//! Tables 5 and 6 (`branching`); schema in `pdbem_pd::bench`.
//!
//! `bench trade` (issue 18): [`crate::bench_trade`], path deviation and failure-load
//! error of PD-BEM growth against wall time over window resolution, side, relaxation and
//! coupling tolerance.
//!
//! `bench growth` (issue 5): [`crate::growth::bench`], PD-BEM against BEM-only and full PD
//! on `cases/growth_tension_edge.ron`.
//!
//! `bench coupling` (issue 4): the coupled SENT cases with each acceleration scheme
//! (constant 0.3, Aitken from 0.3, IQN-ILS from 0.5): iterations, CMOD error, time per phase.
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
    /// A growth sweep over `mpirun -np 2` against one process of 2 threads (issue 22;
    /// needs `--features mpi`).
    SweepMpi,
    /// Speed against accuracy of PD-BEM growth over window and coupling settings
    /// (issue 18; [`crate::bench_trade`]).
    Trade,
    /// Seed 001 section 6: the eleven crack plates by PD against the seed and LEFM
    /// (issue 21; [`crate::bench_seed001`]).
    Seed001,
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
pub fn run(kind: BenchKind, out: &Path, quick: bool, case: Option<&str>) -> Result<()> {
    if case.is_some() && !matches!(kind, BenchKind::Growth | BenchKind::Seed001) {
        anyhow::bail!("--case applies to `bench growth` and `bench seed001` only");
    }
    match kind {
        BenchKind::Bem => bench_bem(out, quick),
        BenchKind::Pd => bench_pd(out, quick),
        BenchKind::Coupling => bench_coupling(out, quick),
        BenchKind::Growth => crate::growth::bench::run(out, quick, case),
        BenchKind::SweepMpi => crate::sweep::bench::run(out, quick),
        BenchKind::Trade => crate::bench_trade::run(out, quick).map(|_| ()),
        BenchKind::Seed001 => crate::bench_seed001::run(out, quick, case).map(|_| ()),
    }
}

/// `bench KIND --collect`: rebuilds a benchmark's report from the run folders of an earlier
/// run in `out` (`trade` only).
pub fn collect(kind: BenchKind, out: &Path) -> Result<()> {
    if kind != BenchKind::Trade {
        anyhow::bail!("--collect applies to `bench trade` only");
    }
    crate::bench_trade::collect(out).map(|_| ())
}

/// One coupled run of `bench coupling`.
#[derive(Debug, Serialize)]
pub struct CouplingBenchEntry {
    /// Case file stem.
    pub case: String,
    /// Acceleration scheme.
    pub scheme: String,
    /// BEM elements.
    pub elements: usize,
    /// PD real nodes in all windows.
    pub pd_nodes: usize,
    /// Coupling iterations.
    pub iterations: usize,
    /// Converged within the scene's cap.
    pub converged: bool,
    /// CMOD relative error against the formula (when the case has a mouth and a reference).
    pub cmod_err: Option<f64>,
    /// Time per phase and total (s).
    pub timings: pdbem_coupling::iteration::Timings,
    /// Wall time of the whole run including setup (s).
    pub wall_time_s: f64,
    /// Why the run failed (non-convergence, ...), first line only.
    pub error: Option<String>,
}

/// `bench coupling`: the coupled SENT cases (seed 002 section 3.2.1) with each acceleration
/// scheme, in one process (`--quick`: a/W = 0.5 only).
fn bench_coupling(out: &Path, quick: bool) -> Result<()> {
    use crate::scene::path::{parse_value, with_overrides};
    let cases: &[&str] = if quick {
        &["coupled_sent_a5"]
    } else {
        &["coupled_sent_a2", "coupled_sent_a5", "coupled_sent_a8"]
    };
    let schemes = [
        ("constant", "{\"Constant\": 0.3}"),
        ("aitken", "{\"Aitken\": 0.3}"),
        ("iqn-ils", "{\"IqnIls\": {\"w0\": 0.5}}"),
    ];
    let mut entries = Vec::new();
    for case in cases {
        let base = load_case(case)?;
        for (name, value) in schemes {
            let scene = with_overrides(
                &base,
                &[("coupling.relaxation".to_string(), parse_value(value))],
            )?;
            entries.push(coupling_entry(case, name, &scene));
        }
    }
    if !quick {
        // Seed 002 Table 5 case 3 size: about 3680 elements and 1600 PD points (seed: 862 s).
        let scene = with_overrides(
            &load_case("coupled_sent_a8")?,
            &[
                // Finer outline, crack faces at the window's dx (the interface rows).
                (
                    "bem.group_sizes".to_string(),
                    parse_value(
                        r#"{"left": 0.0186, "right": 0.0186, "top": 0.0186, "bottom": 0.0186}"#,
                    ),
                ),
                ("coupling.relaxation".to_string(), parse_value(schemes[2].1)),
            ],
        )?;
        entries.push(coupling_entry("a8_seed_mesh", schemes[2].0, &scene));
    }
    let mut text = String::new();
    let _ = writeln!(
        text,
        "coupling benchmark ({} threads): seed 002 SENT cases",
        rayon::current_num_threads()
    );
    let _ = writeln!(
        text,
        "{:<16} {:<9} {:>8} {:>8} {:>5} {:>5} {:>9} {:>8} {:>8} {:>7} {:>8} {:>8}",
        "case",
        "scheme",
        "elements",
        "pd_nodes",
        "iter",
        "conv",
        "cmod_err%",
        "bem_s",
        "subst_s",
        "pd_s",
        "map_s",
        "wall_s"
    );
    for e in &entries {
        if let Some(err) = &e.error {
            let _ = writeln!(
                text,
                "{:<16} {:<9} failed after {:.2} s: {err}",
                e.case, e.scheme, e.wall_time_s
            );
            continue;
        }
        let t = &e.timings;
        let _ =
            writeln!(
            text,
            "{:<16} {:<9} {:>8} {:>8} {:>5} {:>5} {:>9} {:>8.3} {:>8.4} {:>7.3} {:>8.4} {:>8.3}",
            e.case,
            e.scheme,
            e.elements,
            e.pd_nodes,
            e.iterations,
            e.converged,
            e.cmod_err.map(|v| format!("{:+.2}", 100.0 * v)).unwrap_or_else(|| "-".into()),
            t.bem_assembly_s + t.bem_factor_s,
            t.bem_substitution_s,
            t.pd_s,
            t.mapping_s,
            e.wall_time_s
        );
    }
    crate::console::out(&text);
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    write_atomic(&out.join("bench.txt"), text.as_bytes())?;
    let json = serde_json::json!({"bench": "coupling", "threads": rayon::current_num_threads(), "runs": entries});
    write_atomic(
        &out.join("bench.json"),
        serde_json::to_string_pretty(&json)?.as_bytes(),
    )?;
    Ok(())
}

/// `bench pd`: the PD crate's benchmark as a table on stdout, `bench.txt` and `bench.json`.
fn bench_pd(out: &Path, quick: bool) -> Result<()> {
    eprintln!(
        "bench pd: force kernel, factorisation, switching vs ADR, seed 004 branching plate (cases 1 and 2) coarse, fine, adaptive, refined initiation ramp plain vs preconditioned ({})",
        if quick {
            "quick"
        } else {
            "full: several minutes"
        }
    );
    let report = pdbem_pd::bench::run_bench(pdbem_pd::bench::BenchOptions { quick });
    let text = pdbem_pd::bench::table(&report);
    crate::console::out(&text);
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    write_atomic(&out.join("bench.txt"), text.as_bytes())?;
    write_atomic(
        &out.join("bench.json"),
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    eprintln!("bench pd: wrote {}", out.join("bench.json").display());
    Ok(())
}

fn load_case(case: &str) -> Result<crate::scene::Scene> {
    Ok(crate::scene::Scene::load(crate::cases::case_path(case)?)?)
}

/// One coupled solve of `scene` timed as a bench row (a failed solve becomes a row too).
fn coupling_entry(case: &str, scheme: &str, scene: &crate::scene::Scene) -> CouplingBenchEntry {
    let t0 = std::time::Instant::now();
    let result = crate::run_coupled::solve(scene);
    let wall = t0.elapsed().as_secs_f64();
    let (mut summary, outcome) = match result {
        Ok(r) => r,
        Err(e) => {
            let msg = format!("{e:#}");
            let short = msg.split("; history").next().unwrap_or(&msg).to_string();
            return CouplingBenchEntry {
                case: case.to_string(),
                scheme: scheme.to_string(),
                elements: 0,
                pd_nodes: 0,
                iterations: 0,
                converged: false,
                cmod_err: None,
                timings: Default::default(),
                wall_time_s: wall,
                error: Some(short),
            };
        }
    };
    crate::runner::reference::apply(scene, &mut summary);
    CouplingBenchEntry {
        case: case.to_string(),
        scheme: scheme.to_string(),
        elements: summary.elements.unwrap_or(0),
        pd_nodes: outcome
            .setup
            .problem
            .windows
            .iter()
            .map(|w| w.model.n_real())
            .sum(),
        iterations: outcome.info.iterations,
        converged: outcome.info.converged,
        cmod_err: summary.cracks.first().and_then(|c| c.cmod_err),
        timings: outcome.info.timings.clone(),
        wall_time_s: wall,
        error: None,
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
    crate::console::out(&table);
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
