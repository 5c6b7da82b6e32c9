//! `pdbem bench pd`: the refined crack-initiation ramp ([`super::ramp`]) with plain
//! Jacobi-preconditioned conjugate gradients against the Cholesky-preconditioned solves
//! of [`super::direct`], on the seed 004 Table 2 plate with G_c = 1000 J/m^2 and nested
//! tip circles (level 1 within 8 mm, level 2 within 4 mm:
//! `cases/seed004_edge_crack_initiation_nested.ron` at the base spacing `dx`), load step
//! 1 MPa. Both runs must find the same first-break and initiation loads.

use serde::Serialize;

use super::direct::Solver;
use super::{ramp_with, Refinement};
use crate::edge_crack::{crack, problem, HEIGHT, SIDE};
use crate::measure::crack_tips;
use crate::problem::{Failure, Selection};
use crate::traction::TractionLoad;

/// One timed ramp.
#[derive(Clone, Debug, Default, Serialize)]
pub struct RampRun {
    /// `plain CG` or `Cholesky-preconditioned CG`.
    pub solver: String,
    /// Particles at the end.
    pub particles: usize,
    /// Conjugate-gradient iterations, all solves.
    pub iterations: usize,
    /// Wall time of the solves (s).
    pub solve_s: f64,
    /// Wall time of the whole ramp (s).
    pub wall_s: f64,
    /// Load factors (x 10 MPa) of the first break and of the initiation.
    pub first_break: Option<f64>,
    /// Initiation load factor.
    pub initiation: Option<f64>,
    /// A solver error, if any.
    pub error: Option<String>,
}

/// The two ramps and their ratio.
#[derive(Clone, Debug, Serialize)]
pub struct RefinedRampBench {
    /// Base spacing (m).
    pub dx: f64,
    /// Plain CG.
    pub plain: RampRun,
    /// Cholesky-preconditioned CG.
    pub preconditioned: RampRun,
    /// Plain wall time over preconditioned wall time.
    pub speedup: f64,
    /// Both found the same first-break and initiation loads.
    pub same_loads: bool,
}

/// Time both ramps at base spacing `dx`.
pub fn refined_ramp(dx: f64) -> RefinedRampBench {
    let a_over_l = 0.3;
    let mut p = problem(dx, a_over_l, HEIGHT, TractionLoad::TransferFunction);
    p.failure = Failure::FractureEnergy { g_c: 1000.0 };
    let tips = crack_tips(&crack(a_over_l * SIDE, HEIGHT), true);
    let centre = [a_over_l * SIDE, 0.5 * HEIGHT];
    let r = Refinement {
        strain_factor: Some(0.5),
        regions: vec![
            Selection::Circle {
                centre,
                radius: 8e-3,
            },
            Selection::Circle {
                centre,
                radius: 4e-3,
            },
        ],
        region_levels: vec![1, 2],
        max_level: 2,
        ..Default::default()
    };
    let delta = 3.015 * dx;
    let rp = crate::edge_crack::initiation_ramp(0.1, delta);
    let run = |name: &str, solver: Solver| {
        let t = std::time::Instant::now();
        let out = ramp_with(&p, &r, &tips, &rp, solver);
        let wall_s = t.elapsed().as_secs_f64();
        match out {
            Ok(o) => RampRun {
                solver: name.into(),
                particles: o.body.len(),
                iterations: o.record.iterations,
                solve_s: o.record.solve_s,
                wall_s,
                first_break: o.record.first_break_load,
                initiation: o.record.initiation_load,
                error: None,
            },
            Err(e) => RampRun {
                solver: name.into(),
                wall_s,
                error: Some(e.to_string()),
                ..Default::default()
            },
        }
    };
    let mut plain_solver = Solver::default();
    plain_solver.budget = Some(1);
    let plain = run("plain CG", plain_solver);
    let preconditioned = run("Cholesky-preconditioned CG", Solver::default());
    let same = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => (a - b).abs() < 1e-9,
        _ => false,
    };
    RefinedRampBench {
        dx,
        speedup: plain.wall_s / preconditioned.wall_s,
        same_loads: same(plain.first_break, preconditioned.first_break)
            && same(plain.initiation, preconditioned.initiation),
        plain,
        preconditioned,
    }
}

/// The benchmark as a short table.
pub fn table(b: &RefinedRampBench) -> String {
    let mut s = format!(
        "refined crack-initiation ramp (Table 2 plate with G_c, base dx {} mm, nested tip circles):\n",
        b.dx * 1e3
    );
    let load = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{:.1} MPa", 10.0 * v));
    for r in [&b.plain, &b.preconditioned] {
        s.push_str(&format!(
            "  {:<28} {:>6} particles {:>7} iterations  solves {:>7.2} s  wall {:>7.2} s  first break {}  initiation {}{}\n",
            r.solver,
            r.particles,
            r.iterations,
            r.solve_s,
            r.wall_s,
            load(r.first_break),
            load(r.initiation),
            r.error.as_ref().map(|e| format!("  error: {e}")).unwrap_or_default()
        ));
    }
    s.push_str(&format!(
        "  speed-up {:.2}x, same loads: {}\n",
        b.speedup, b.same_loads
    ));
    s
}
