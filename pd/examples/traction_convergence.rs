//! Seed 001 section 5 convergence study: the 50 mm plate under 200 MPa at
//! both ends, dx = 1, 0.5, 0.25, 0.125 mm at m = 3.015, loaded through the
//! transfer functions and through the body-force layer
//! ([`pdbem_pd::traction::study`]). Writes `traction_convergence.json` and
//! `traction_convergence.md` into the directory given as the first argument
//! (default `.`).
//!
//! `cargo run --release -p pdbem-pd --example traction_convergence -- OUT_DIR`
//! (about 3 minutes CPU on one core; the 0.125 mm grid has 160 000 nodes).

use std::fmt::Write as _;

use pdbem_pd::traction::study::{elastic, study_row, StudyRow, MONITOR};
use pdbem_pd::TractionLoad;

fn table(rows: &[StudyRow]) -> String {
    let e = elastic(MONITOR);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Seed 001 section 5: convergence of the traction plate\n\n\
         Elastic displacement at (-12.25, -12.25) mm: u_x = {:.4e} m, u_y = {:.4e} m.\n\
         PD at m = 3.015 is 1.1616 times softer in bulk than the continuum (discrete horizon sum).\n",
        e[0], e[1]
    );
    let _ = writeln!(
        s,
        "| dx (mm) | traction | k | u_x (m) | u_y (m) | u_x/elastic | u_y/elastic | E eps_yy/p interior | mid flux mean/p | mid dev (2 delta inside) | mid dev (all) | dev at ceil(m) dx below edge | edge excess | edge unevenness | time (s) |"
    );
    let _ = writeln!(s, "|{}", "---|".repeat(15));
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {:?} | {} | {:.5e} | {:.5e} | {:.4} | {:.4} | {:.4} | {:.6} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.1} |",
            r.dx * 1e3,
            r.mode,
            r.k,
            r.u_monitor[0],
            r.u_monitor[1],
            r.u_over_elastic[0],
            r.u_over_elastic[1],
            r.interior_strain_ratio,
            r.mid_flux_mean,
            r.mid_flux_dev_interior,
            r.mid_flux_dev_all,
            r.edge_flux_dev_interior,
            r.edge_excess,
            r.edge_unevenness,
            r.time_s
        );
    }
    s
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| ".".into()));
    std::fs::create_dir_all(&out)?;
    let mut rows = Vec::new();
    for dx in [1e-3, 0.5e-3, 0.25e-3, 0.125e-3] {
        for mode in [TractionLoad::TransferFunction, TractionLoad::BodyForceLayer] {
            let r = study_row(dx, 3.015, mode)?;
            eprintln!("dx {dx:e} {mode:?}: {:.1} s", r.time_s);
            rows.push(r);
        }
    }
    std::fs::write(
        out.join("traction_convergence.json"),
        serde_json::to_string_pretty(&rows)?,
    )?;
    let md = table(&rows);
    std::fs::write(out.join("traction_convergence.md"), &md)?;
    print!("{md}");
    Ok(())
}
