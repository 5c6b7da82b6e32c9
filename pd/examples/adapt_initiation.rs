//! Quasi-static crack initiation on a grid whose cells split by seed 004's criteria
//! (`pdbem_pd::adapt::initiation`: Newton on the mixed grid, bonds breaking at their own
//! horizon's critical stretch): the seed 004 Table 2 plate (`pdbem_pd::edge_crack`,
//! a/L = 0.3, tractions as a body-force layer) with seed 004 Eq. 11's critical stretch
//! from G_c = 1000 J/m^2, the tension ramped until the crack runs two coarse horizons.
//! Arguments: mode, load step (default 0.1, i.e. 1 MPa), coarse spacing (default 2 mm),
//! radius (default 6 mm), model (`sb` state-based, default, or `pmb`). Modes: `coarse`
//! and `fine` (half the spacing): uniform grids, no refinement; `criteria`: Eq. 15 with
//! phi_c = 0.4 and Eq. 16 with alpha = 0.5 at every equilibrium, and the cells holding
//! an end of an overstretched bond split before the bonds break (`before_breaking`);
//! `circle`: the same and
//! the cells within `radius` of the pre-crack tip split before the ramp; `nested`: the
//! circle at level 2 inside a level-1 circle of twice the radius. Numbers in
//! docs/seed004.md.
//!
//! `cargo run --release -p pdbem-pd --example adapt_initiation -- circle`

use std::time::Instant;

use pdbem_pd::adapt::initiation::ramp_to_initiation;
use pdbem_pd::adapt::CellCriteria;
use pdbem_pd::edge_crack::{crack, initiation_ramp, problem, HEIGHT, SIDE, SIGMA};
use pdbem_pd::measure::{crack_tips, kink_angle};
use pdbem_pd::{Failure, PdMaterial, TractionLoad};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let mode = args.get(1).map_or("circle", |s| s.as_str());
    let step: f64 = args.get(2).map_or(Ok(0.1), |s| s.parse())?;
    let coarse: f64 = args.get(3).map_or(Ok(2e-3), |s| s.parse())?;
    let radius: f64 = args.get(4).map_or(Ok(6e-3), |s| s.parse())?;
    let pmb = args.get(5).is_some_and(|s| s == "pmb");
    let dx = if mode == "fine" { 0.5 * coarse } else { coarse };
    let a_over_l = 0.3;
    let mut p = problem(dx, a_over_l, HEIGHT, TractionLoad::BodyForceLayer);
    p.failure = Failure::FractureEnergy { g_c: 1000.0 };
    if pmb {
        p.material = PdMaterial::Pmb;
    }
    let tip = [a_over_l * SIDE, 0.5 * HEIGHT];
    let (criteria, circles) = match mode {
        "coarse" | "fine" => (false, vec![]),
        "criteria" => (true, vec![]),
        "circle" => (true, vec![(tip, radius, 1)]),
        "nested" => (true, vec![(tip, 2.0 * radius, 1), (tip, radius, 2)]),
        other => return Err(format!("unknown mode {other}").into()),
    };
    let crit = CellCriteria {
        critical_damage: criteria.then_some(0.4),
        strain_factor: criteria.then_some(0.5),
        max_level: circles.iter().map(|c| c.2).max().unwrap_or(1),
        near_cracks: None,
        circles,
        before_breaking: criteria,
    };
    let delta = p.horizon();
    let tips = crack_tips(&crack(a_over_l * SIDE, HEIGHT), true);
    let params = initiation_ramp(step, delta);
    let t0 = Instant::now();
    let out = ramp_to_initiation(&p, &crit, &tips, &params, &mut |_| {})?;
    let wall = t0.elapsed().as_secs_f64();
    let mpa = |f: Option<f64>| f.map(|f| f * SIGMA / 1e6);
    let kink = kink_angle(&out.model, tips[0], delta, 4.0 * delta);
    let g = out.model.grid();
    let fine = (0..out.model.n_real())
        .filter(|&k| g.node_dx(k) < g.dx)
        .count();
    println!(
        "{mode} dx {dx:e} ({}): first break {:?} MPa, initiation {:?} MPa, unstable {}, kink {:?} deg, {} real nodes ({fine} refined), {} rounds, {wall:.2} s",
        if pmb { "PMB" } else { "state-based" },
        mpa(out.init.first_break_load),
        mpa(out.init.initiation_load),
        out.init.unstable,
        kink,
        out.model.n_real(),
        out.rounds.len(),
    );
    Ok(())
}
