//! `pdbem bench seed001`: seed 001 section 6 (Zhou et al.), the eleven crack
//! configurations of `cases/seed001_*.ron`, each solved by stand-alone PD on its own grid
//! (the seed's 200 x 200; `--quick`: 40 x 40) and set against the seed's initiation load
//! and kink angle and against LEFM for the same geometry.
//!
//! **LEFM column.** The case without its `pd` section is solved by the BEM at the scene's
//! last load factor `f`; every tip's maximum-circumferential-stress kink `theta` and
//! equivalent factor `K_eq = K_I cos^3(theta/2) - 3/2 K_II cos(theta/2) sin(theta)` scale
//! with the load, so the crack initiates at
//! `sigma_c = f sigma_1 K_Ic / max_tips K_eq`, with `sigma_1` the largest traction at
//! load factor 1 and `K_Ic = sqrt(E G_c)` (plane stress) or `sqrt(E G_c / (1 - nu^2))`
//! (plane strain).
//!
//! **PD column.** [`crate::run_pd::solve`]: the load ramp of the case until the crack runs
//! two horizons ([`pdbem_pd::measure::ramp_to_initiation`]), the kink per tip measured
//! from the damaged nodes 1 to 4 horizons ahead of the tip.
//!
//! Outputs: `bench.json` (every row), `bench.md` (the table) in the output folder.

use anyhow::{Context, Result};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use crate::output::write_atomic;
use crate::scene::{Plane, Scene};

/// The seed's published results (seed 001 section 6): case stem after `seed001_`,
/// initiation load (MPa) and kink angle (degrees, magnitude) where the text gives one.
pub const SEED001_TABLE: [(&str, f64, Option<f64>); 11] = [
    ("central_crack", 14.6, None),
    ("inclined_crack", 15.9, Some(56.0)),
    ("edge_crack", 8.5, None),
    ("two_parallel_cracks", 13.7, None),
    ("colinear_edge_cracks", 8.5, None),
    ("two_inclined_parallel", 16.3, None),
    ("two_inclined_mirror", 16.9, None),
    ("three_parallel_cracks", 14.7, None),
    ("three_cracks_middle_inclined", 14.1, None),
    ("three_inclined_cracks", 16.2, None),
    ("three_cracks_middle_horizontal", 13.5, None),
];

/// One configuration of the bench.
#[derive(Debug, Serialize)]
pub struct Seed001Row {
    /// Case stem (`seed001_<name>`).
    pub case: String,
    /// PD grid nodes across the plate.
    pub nx: usize,
    /// Seed 001's initiation load (MPa).
    pub seed_mpa: f64,
    /// Seed 001's kink angle (degrees), where stated.
    pub seed_kink_deg: Option<f64>,
    /// PD initiation load (MPa); `None` if the crack did not run within the ramp.
    pub pd_mpa: Option<f64>,
    /// PD kink per tip (degrees, counter-clockwise from the tip direction).
    pub pd_kink_deg: Vec<Option<f64>>,
    /// LEFM initiation load (MPa) from the BEM K of the same plate.
    pub lefm_mpa: Option<f64>,
    /// LEFM kink of the tip that governs (degrees, counter-clockwise).
    pub lefm_kink_deg: Option<f64>,
    /// PD wall time (s).
    pub pd_wall_s: f64,
    /// Why a column is missing (first line of the error).
    pub error: Option<String>,
}

/// The bench report.
#[derive(Debug, Serialize)]
pub struct Seed001Report {
    /// Benchmark name ("seed001").
    pub bench: &'static str,
    /// Rayon threads.
    pub threads: usize,
    /// One row per configuration.
    pub rows: Vec<Seed001Row>,
}

/// Runs the bench into `out`; `case` restricts it to one configuration (stem with or
/// without the `seed001_` prefix).
pub fn run(out: &Path, quick: bool, case: Option<&str>) -> Result<Seed001Report> {
    let only = case.map(|c| c.trim_start_matches("seed001_").to_string());
    if let Some(o) = &only {
        if !SEED001_TABLE.iter().any(|(n, _, _)| n == o) {
            anyhow::bail!(
                "--case {o}: not a seed 001 configuration (one of: {})",
                SEED001_TABLE.map(|r| r.0).join(", ")
            );
        }
    }
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let mut rows = Vec::new();
    for (name, seed, kink) in SEED001_TABLE {
        if only.as_deref().is_some_and(|o| o != name) {
            continue;
        }
        let mut scene = Scene::load(crate::cases::case_path(&format!("seed001_{name}"))?)?;
        if quick {
            if let Some(pd) = scene.pd.as_mut() {
                pd.nx = Some(40);
            }
        }
        eprintln!("bench seed001: {name}");
        let row = row(name, seed, kink, &scene);
        eprintln!(
            "  PD {} MPa ({:.0} s), LEFM {} MPa, seed {seed} MPa",
            opt(row.pd_mpa),
            row.pd_wall_s,
            opt(row.lefm_mpa)
        );
        rows.push(row);
    }
    let report = Seed001Report {
        bench: "seed001",
        threads: rayon::current_num_threads(),
        rows,
    };
    let text = table(&report);
    crate::console::out(&text);
    write_atomic(&out.join("bench.md"), text.as_bytes())?;
    write_atomic(
        &out.join("bench.json"),
        serde_json::to_string_pretty(&report)?.as_bytes(),
    )?;
    eprintln!("bench seed001: wrote {}", out.join("bench.json").display());
    Ok(report)
}

/// Solves one configuration by PD and by the BEM.
fn row(name: &str, seed: f64, seed_kink: Option<f64>, scene: &Scene) -> Seed001Row {
    let nx = scene.pd.as_ref().and_then(|p| p.nx).unwrap_or(0);
    let mut errors = Vec::new();
    let t0 = Instant::now();
    let (pd_mpa, pd_kink_deg) = match crate::run_pd::solve(scene) {
        Ok((s, _)) => {
            let load = s.extra["initiation_load"].as_f64().map(|v| v / 1e6);
            let kinks = s.extra["kink_deg_per_tip"]
                .as_array()
                .map(|a| a.iter().map(|v| v.as_f64()).collect())
                .unwrap_or_default();
            (load, kinks)
        }
        Err(e) => {
            errors.push(format!("PD: {e}"));
            (None, Vec::new())
        }
    };
    let pd_wall_s = t0.elapsed().as_secs_f64();
    let (lefm_mpa, lefm_kink_deg) = match lefm(scene) {
        Ok(v) => v,
        Err(e) => {
            errors.push(format!("LEFM: {e}"));
            (None, None)
        }
    };
    Seed001Row {
        case: format!("seed001_{name}"),
        nx,
        seed_mpa: seed,
        seed_kink_deg: seed_kink,
        pd_mpa,
        pd_kink_deg,
        lefm_mpa,
        lefm_kink_deg,
        pd_wall_s,
        error: (!errors.is_empty()).then(|| errors.join("; ")),
    }
}

/// LEFM initiation load (MPa) and the governing tip's kink (degrees) of the scene's
/// plate (module docs).
pub fn lefm(scene: &Scene) -> Result<(Option<f64>, Option<f64>)> {
    let mut bem = scene.clone();
    bem.pd = None;
    let g_c = scene
        .material
        .fracture
        .as_ref()
        .and_then(|f| f.g_c)
        .context("material.fracture.g_c is needed for K_Ic")?;
    let e = scene.material.e;
    let nu = scene.material.nu;
    let k_ic = match scene.material.plane {
        Plane::Stress => (e * g_c).sqrt(),
        Plane::Strain => (e * g_c / (1.0 - nu * nu)).sqrt(),
    };
    let factor = crate::setup::final_factor(scene);
    let sigma1 = crate::pd_loads::traction_scale(scene).context("the scene has no traction")?;
    let (summary, _) = crate::run_bem::solve(&bem)?;
    let governing = summary
        .tips
        .iter()
        .map(|t| {
            let theta = pdbem_coupling::growth::criterion::kink_angle(t.k1, t.k2);
            let k_eq = pdbem_coupling::growth::criterion::equivalent_k(t.k1, t.k2, theta);
            (k_eq, theta.to_degrees())
        })
        .filter(|(k, _)| k.is_finite() && *k > 0.0)
        .max_by(|a, b| a.0.total_cmp(&b.0));
    Ok(match governing {
        // `+ 0.0` turns a mode-I tip's -0 into 0.
        Some((k_eq, kink)) => (Some(factor * sigma1 * k_ic / k_eq / 1e6), Some(kink + 0.0)),
        None => (None, None),
    })
}

fn opt(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.2}"))
}

fn pct(v: Option<f64>, reference: f64) -> String {
    v.map_or(String::new(), |v| {
        format!(" ({:+.0} %)", 100.0 * (v / reference - 1.0))
    })
}

/// The markdown table of the report.
pub fn table(r: &Seed001Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| configuration | grid | seed 001 (MPa) | PD (MPa, vs seed) | LEFM (MPa) | PD vs LEFM | PD kinks (deg) | LEFM kink (deg) | seed kink (deg) | PD wall (s) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for row in &r.rows {
        let kinks: Vec<String> = row
            .pd_kink_deg
            .iter()
            .map(|k| k.map_or("-".into(), |k| format!("{k:.0}")))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} x {} | {} | {}{} | {} | {} | {} | {} | {} | {:.0} |",
            row.case.trim_start_matches("seed001_"),
            row.nx,
            row.nx,
            row.seed_mpa,
            opt(row.pd_mpa),
            pct(row.pd_mpa, row.seed_mpa),
            opt(row.lefm_mpa),
            match (row.pd_mpa, row.lefm_mpa) {
                (Some(p), Some(l)) => format!("{:+.0} %", 100.0 * (p / l - 1.0)),
                _ => "-".into(),
            },
            kinks.join(", "),
            row.lefm_kink_deg.map_or("-".into(), |k| format!("{k:.1}")),
            row.seed_kink_deg.map_or("-".into(), |k| format!("{k:.0}")),
            row.pd_wall_s,
        );
        if let Some(e) = &row.error {
            let _ = writeln!(s, "|  | error: {e} | | | | | | | | |");
        }
    }
    s
}
