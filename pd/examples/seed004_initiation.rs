//! Quasi-static crack initiation on refined particles (`pdbem_pd::refine::ramp`): the
//! seed 004 Table 2 plate (`pdbem_pd::edge_crack`, a/L = 0.3) with seed 004 Eq. 11's
//! critical stretch from G_c = 1000 J/m^2, the tension ramped until the crack runs two
//! coarse horizons. Arguments: mode, load step (default 0.1, i.e. 1 MPa), coarse spacing
//! (default 1 mm), radius (default 4 mm). Modes: `coarse` (no refinement), `adaptive`
//! (Eq. 15 with phi_c = 0.4 and Eq. 16 with alpha = 0.5 at every equilibrium), `region`
//! (adaptive, and the particles within `radius` of the pre-crack tip split before the
//! ramp: the static criterion), `region2` (the same circle refined twice, to a quarter of
//! the spacing: one size jump of 4 at its edge), `nested` (the circle at level 2 inside a
//! level-1 circle of radius `outer`, argument 5, default three radii: every jump a factor
//! 2), `fine` (half the spacing, no refinement). LEFM: sigma_c = sqrt(E G_c) / (K_I / sigma), K_I /
//! sigma = 0.36063 m^0.5 from the BEM (`cases/seed004_table2_bem.ron`). Numbers in
//! docs/seed004.md.
//!
//! `cargo run --release -p pdbem-pd --example seed004_initiation -- adaptive`

use pdbem_pd::edge_crack::{crack, initiation_ramp, problem, HEIGHT, SIDE, SIGMA, YOUNGS};
use pdbem_pd::measure::crack_tips;
use pdbem_pd::refine::{ramp, Refinement};
use pdbem_pd::{Failure, Selection, TractionLoad};

const G_C: f64 = 1000.0;
const K_OVER_SIGMA: f64 = 0.36063;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let mode = args.get(1).map_or("adaptive", |s| s.as_str());
    let step: f64 = args.get(2).map_or(Ok(0.1), |s| s.parse())?;
    let coarse: f64 = args.get(3).map_or(Ok(1e-3), |s| s.parse())?;
    let radius: f64 = args.get(4).map_or(Ok(4e-3), |s| s.parse())?;
    let outer: f64 = args.get(5).map_or(Ok(3.0 * radius), |s| s.parse())?;
    let dx = if mode == "fine" { 0.5 * coarse } else { coarse };
    let a_over_l = 0.3;
    let mut p = problem(dx, a_over_l, HEIGHT, TractionLoad::TransferFunction);
    p.failure = Failure::FractureEnergy { g_c: G_C };
    let settings = match mode {
        "adaptive" => Refinement {
            strain_factor: Some(0.5),
            ..Default::default()
        },
        "region" => Refinement {
            strain_factor: Some(0.5),
            regions: vec![Selection::Circle {
                centre: [a_over_l * SIDE, 0.5 * HEIGHT],
                radius,
            }],
            ..Default::default()
        },
        "region2" => Refinement {
            strain_factor: Some(0.5),
            regions: vec![Selection::Circle {
                centre: [a_over_l * SIDE, 0.5 * HEIGHT],
                radius,
            }],
            max_level: 2,
            ..Default::default()
        },
        "nested" => Refinement {
            strain_factor: Some(0.5),
            regions: vec![
                Selection::Circle {
                    centre: [a_over_l * SIDE, 0.5 * HEIGHT],
                    radius: outer,
                },
                Selection::Circle {
                    centre: [a_over_l * SIDE, 0.5 * HEIGHT],
                    radius,
                },
            ],
            region_levels: vec![1, 2],
            max_level: 2,
            ..Default::default()
        },
        _ => Refinement {
            critical_damage: None,
            ..Default::default()
        },
    };
    let line = crack(a_over_l * SIDE, HEIGHT);
    let tips = crack_tips(&line, true);
    let delta = 3.015 * coarse;
    let rp = initiation_ramp(step, delta);
    let t = std::time::Instant::now();
    let out = ramp(&p, &settings, &tips, &rp)?;
    let r = &out.record;
    let lefm = (YOUNGS * G_C).sqrt() / K_OVER_SIGMA;
    let b = &out.body;
    let kink = b.kink_angle(tips[0], delta, 4.0 * delta);
    println!("mode {mode}, dx {dx}, step {step}");
    println!(
        "first break {:?} MPa, initiation {:?} MPa (LEFM {:.2} MPa), unstable {}, extension {:.4} m, kink {:?}",
        r.first_break_load.map(|f| f * SIGMA / 1e6),
        r.initiation_load.map(|f| f * SIGMA / 1e6),
        lefm / 1e6,
        r.unstable,
        r.extension,
        kink
    );
    println!(
        "particles {} (set-up split {}, ramp split {}), steps {}, CG iterations {}, split {:.2} s, solve {:.2} s, wall {:.2} s",
        b.len(),
        r.setup_split,
        r.steps.iter().map(|s| s.split).sum::<usize>(),
        r.steps.len(),
        r.iterations,
        r.split_s,
        r.solve_s,
        t.elapsed().as_secs_f64()
    );
    Ok(())
}
