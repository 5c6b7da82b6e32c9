//! `pdbem bench {bem|pd|coupling|growth} --out DIR [--quick]`: timing tables
//! and `DIR/bench.json` (schemas in docs/outputs.md). Each benchmark is wired
//! by the issue that brings its solver; until then the command says so.

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

/// Runs a benchmark into `out` (`quick`: smaller sizes for CI).
pub fn run(kind: BenchKind, out: &Path, quick: bool) -> anyhow::Result<()> {
    let _ = (out, quick);
    let issue = match kind {
        BenchKind::Bem => 2,
        BenchKind::Pd => 3,
        BenchKind::Coupling => 4,
        BenchKind::Growth => 5,
    };
    anyhow::bail!("bench {kind:?} is not wired yet (it arrives with issue {issue})")
}
