//! Seed 004 Table 2 with dual-horizon particles (`pdbem_pd::refine`): coarse (dx = 1 mm,
//! no refinement), adaptive (dx = 1 mm, refined by Eq. 15 on the pre-crack, phi_c =
//! 0.4, with `adaptive-keep` the children keep the parent's horizon as in the seed's
//! Table 3, or a static region: the particles within `r` of the crack line and tip), fine
//! (dx = 0.5 mm). Argument: `coarse`, `adaptive`, `region R` (m) or `fine`. Numbers in
//! docs/seed004.md.
//!
//! `cargo run --release -p pdbem-pd --example seed004_adaptive -- adaptive`

use pdbem_pd::edge_crack::{crack, error_vs_irwin, mouth_opening, problem, HEIGHT, RATIOS, SIDE};
use pdbem_pd::refine::{run, Refinement};
use pdbem_pd::{Selection, TractionLoad};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let mode = args.get(1).map_or("adaptive", |s| s.as_str());
    let radius: f64 = args.get(2).map_or(Ok(4e-3), |s| s.parse())?;
    let dx = if mode == "fine" { 5e-4 } else { 1e-3 };
    println!("| a/L | PD (um) | error | particles | split | CG iterations | wall (s) |");
    println!("|---|---|---|---|---|---|---|");
    for r in RATIOS {
        let p = problem(dx, r, HEIGHT, TractionLoad::TransferFunction);
        let settings = match mode {
            "adaptive" => Refinement::default(),
            "adaptive-keep" => Refinement {
                keep_horizon: true,
                ..Default::default()
            },
            "region" => Refinement {
                critical_damage: None,
                regions: vec![Selection::NearPolyline {
                    points: crack(r * SIDE, HEIGHT),
                    distance: Some(radius),
                }],
                ..Default::default()
            },
            _ => Refinement {
                critical_damage: None,
                ..Default::default()
            },
        };
        let t = std::time::Instant::now();
        let out = run(&p, &settings, 1.0)?;
        let b = &out.body;
        let cod = mouth_opening(b.positions(), &b.u, HEIGHT).ok_or("no mouth particle")?;
        println!(
            "| {r} | {:.4} | {:+.2} % | {} | {} | {} | {:.1} |",
            cod * 1e6,
            100.0 * error_vs_irwin(cod, r),
            b.len(),
            out.rounds.iter().map(|x| x.split).sum::<usize>(),
            out.rounds.iter().map(|x| x.iterations).sum::<usize>(),
            t.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
