//! Seed 004 Table 2 on uniform grids: the crack-mouth opening of the edge-crack plate
//! (`pdbem_pd::edge_crack`) with state-based PD against Irwin's formula, one row per
//! crack depth a/L = 0.1..0.5. Arguments: `dx` (m, default 1e-3) and the plate height
//! (m, default `HEIGHT` = 0.1). The numbers are in docs/seed004.md.
//!
//! `cargo run --release -p pdbem-pd --example seed004_table2 -- 5e-4`

use pdbem_pd::edge_crack::{
    error_vs_irwin, irwin_cod, mouth_opening, problem, HEIGHT, RATIOS, SIDE,
};
use pdbem_pd::solvers::implicit::{solve, ImplicitParams};
use pdbem_pd::{PdModel, TractionLoad};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let dx: f64 = args.get(1).map_or(Ok(1e-3), |s| s.parse())?;
    let h: f64 = args.get(2).map_or(Ok(HEIGHT), |s| s.parse())?;
    println!("| a/L | Irwin (um) | PD (um) | error | nodes | wall (s) |");
    println!("|---|---|---|---|---|---|");
    for r in RATIOS {
        let t = std::time::Instant::now();
        let mut m = PdModel::new(&problem(dx, r, h, TractionLoad::TransferFunction))?;
        solve(&mut m, &ImplicitParams::default())?;
        let cod = mouth_opening(&m.positions()[..m.n_real()], m.displacements(), h)
            .ok_or("no node at the crack mouth")?;
        println!(
            "| {r} | {:.4} | {:.4} | {:+.2} % | {} | {:.1} |",
            irwin_cod(r * SIDE) * 1e6,
            cod * 1e6,
            100.0 * error_vs_irwin(cod, r),
            m.n_real(),
            t.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
