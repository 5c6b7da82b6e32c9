//! The PD benchmark report as a text table for the terminal ([`table`]).

use super::BenchReport;

/// The report as a text table.
pub fn table(r: &BenchReport) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let _ = writeln!(s, "PD benchmark ({} threads)", r.threads);
    let _ = writeln!(
        s,
        "{:<10} {:>8} {:>9} {:>15} {:>10} {:>10} {:>10} {:>9} {:>12}",
        "model",
        "nodes",
        "bonds",
        "bond_evals/s",
        "bytes/bond",
        "assembly_s",
        "factor_s",
        "solve_s",
        "factor_nnz"
    );
    for k in &r.kernel {
        let _ = writeln!(
            s,
            "{:<10} {:>8} {:>9} {:>15.3e} {:>10.1} {:>10.4} {:>10.4} {:>9.5} {:>12}",
            k.model,
            k.nodes,
            k.bonds,
            k.bond_evals_per_s,
            k.bytes_per_bond,
            k.assembly_s,
            k.factorization_s,
            k.solve_s,
            k.factor_entries
        );
    }
    let _ = writeln!(s, "\nswitching vs pure ADR:");
    for line in wrap(&r.protocol, 100) {
        let _ = writeln!(s, "  {line}");
    }
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "{:<20} {:>7} {:>4} {:>5} {:>8} {:>8} {:>8} {:>8} {:>22} {:>7} {:>5} {:>9} {:>6} {:>9} {:>9}",
        "case",
        "grid",
        "N_i",
        "N_e",
        "adr_s",
        "switch_s",
        "speedup",
        "adr_it",
        "newton/secant/adr_it",
        "rounds",
        "fact",
        "broken",
        "differ",
        "du_field",
        "du_line"
    );
    for c in &r.switching {
        let _ = writeln!(
            s,
            "{:<20} {:>7} {:>4} {:>5} {:>8.2} {:>8.2} {:>8.2} {:>8} {:>22} {:>7} {:>5} {:>9} {:>6} {:>9.2e} {:>9.2e}",
            c.case,
            format!("{}x{}", c.grid[0], c.grid[1]),
            c.implicit_steps,
            c.increments,
            c.adr.time_s,
            c.switching.time_s,
            c.switching_speedup,
            c.adr.adr_iterations,
            format!(
                "{}/{}/{}",
                c.switching.newton_iterations,
                c.switching.secant_iterations,
                c.switching.adr_iterations
            ),
            c.switching.secant_rounds,
            c.switching.factorizations,
            format!("{}/{}", c.adr.broken_pairs, c.switching.broken_pairs),
            c.differing_pairs,
            c.displacement_difference,
            c.profile_difference
        );
        if let Some(e) = &c.error {
            let _ = writeln!(s, "  error: {e}");
        }
        let _ = writeln!(
            s,
            "  speed-up per repeat: {}",
            c.speedups
                .iter()
                .map(|v| format!("{v:.2}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let _ = writeln!(
        s,
        "seed 000 Table 1 (Julia, one core, its own ADR baseline): plate 10.7x, three-point bend 6.4x"
    );
    for b in &r.branching {
        s.push_str(&crate::dynamics::bench::table(b));
    }
    if let Some(b) = &r.refined_ramp {
        s.push_str(&crate::refine::bench::table(b));
    }
    s
}

/// `text` cut into lines of at most `width` characters at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split_whitespace() {
        let last = lines.last_mut().expect("one line");
        if !last.is_empty() && last.len() + 1 + word.len() > width {
            lines.push(word.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}
