//! The seed cases as [`PdProblem`] constructors, shared by the CLI, the tests
//! and the benchmarks. Each returns a [`PdCase`]: the problem plus its
//! loading schedule (target load factor and the seed's step counts).

use serde::Serialize;

use crate::problem::{
    BoundaryCondition, Failure, Hole, Layer, PdProblem, Plane, Region, Selection,
};

/// A problem with its loading schedule.
#[derive(Clone, Debug, Serialize)]
pub struct PdCase {
    /// Short name (`pd_cantilever`, ...).
    pub name: String,
    /// The problem.
    pub problem: PdProblem,
    /// Load factor at the end of the loading (1 unless stated).
    pub target_load: f64,
    /// Implicit steps `N_i` of the seed (switching solver).
    pub implicit_steps: usize,
    /// Explicit increments `N_e` of the seed (switching solver; counted
    /// over the whole load there, see [`crate::solvers::switching`]).
    pub explicit_steps: usize,
    /// Steps of pure ADR with one iteration each (the seed's loading rate).
    pub adr_rate_steps: usize,
}

fn fixed_side(min: [f64; 2], max: [f64; 2], ux: Option<f64>, uy: Option<f64>) -> BoundaryCondition {
    BoundaryCondition::Displacement {
        on: Selection::Box { min, max },
        ux,
        uy,
        layer: Layer::Fictitious,
    }
}

/// Bar in tension (seed 000 section 3.1 in a thin 2-D strip): length 0.2 m,
/// width 0.02 m, thickness 0.02 m, E = 200 GPa (seed 000), left end fixed by
/// a fictitious layer, a total force of 2000 N pulling the last node column
/// (`u(x) = F x/(A E) = 2.5e-5 x/0.2` m at the end). `dx` must divide 0.02.
/// The surface correction is on: without it the discrete horizon sum of a
/// regular grid with m = 3.015 carries only 86 % of the continuum bond
/// energy (a quadrature error that does not vanish as dx -> 0 at fixed m),
/// and the bar is about 21 % too soft.
pub fn bar_tension(dx: f64) -> PdCase {
    let (l, w) = (0.2, 0.02);
    PdCase {
        name: "pd_bar_tension".into(),
        problem: PdProblem {
            region: Region::rectangle([0.0, 0.0], [l, w]),
            dx,
            thickness: w,
            youngs_modulus: 200e9,
            surface_correction: true,
            boundary: vec![
                fixed_side([-1.0, -1.0], [0.0, 1.0], Some(0.0), Some(0.0)),
                BoundaryCondition::Force {
                    on: Selection::Box {
                        min: [l - dx, -1.0],
                        max: [l, 1.0],
                    },
                    force: [BAR_FORCE, 0.0],
                },
            ],
            ..Default::default()
        },
        target_load: 1.0,
        implicit_steps: 1,
        explicit_steps: 1,
        adr_rate_steps: 1,
    }
}

/// Total force of [`bar_tension`] (N).
pub const BAR_FORCE: f64 = 2000.0;

/// Cantilever of seed 000 section 3.2: 0.5 m x 0.05 m, `nx x ny` grid
/// (seed: 100 x 10, dx = 0.005 m), thickness dx (the seed's cell is dx^3),
/// E = 200 GPa, left end clamped by a fictitious layer of depth delta, 125 N
/// downward on the last node column (body force 1e8 N/m^3 at 100 x 10).
pub fn cantilever(nx: usize, ny: usize, surface_correction: bool) -> PdCase {
    let (l, w) = (0.5, 0.05);
    let dx = l / nx as f64;
    assert!(
        (w / ny as f64 - dx).abs() < 1e-12 * dx,
        "cantilever needs square cells"
    );
    PdCase {
        name: "pd_cantilever".into(),
        problem: PdProblem {
            region: Region::rectangle([0.0, 0.0], [l, w]),
            dx,
            thickness: dx,
            youngs_modulus: 200e9,
            surface_correction,
            boundary: vec![
                fixed_side([-1.0, -1.0], [0.0, 1.0], Some(0.0), Some(0.0)),
                BoundaryCondition::Force {
                    on: Selection::Box {
                        min: [l - dx, -1.0],
                        max: [l, 1.0],
                    },
                    force: [0.0, -CANTILEVER_LOAD],
                },
            ],
            ..Default::default()
        },
        target_load: 1.0,
        implicit_steps: 1,
        explicit_steps: 1,
        adr_rate_steps: 1,
    }
}

/// Tip load of [`cantilever`] (N), seed 000 section 3.2.
pub const CANTILEVER_LOAD: f64 = 125.0;

/// Square plate with a central hole, seed 000 section 5.2: side 0.05 m,
/// `n x n` grid (seed 50), hole radius 0.005 m, E = 192 GPa, degradation
/// `s_m = 0.015, s_c = 0.02, beta = 3`, top and bottom fictitious layers
/// moved outward by 0.275 mm each, both components prescribed (clamped
/// grips, which also removes the rigid modes). Seed schedule: `N_i = 3`,
/// `N_e = 180`; pure ADR at 2.75e-7 m per iteration (1000 steps).
///
/// Loading per end, not total: seed 000 section 5.2 says "The upper and
/// lower ends of the plate are subjected to the outward vertical
/// displacement loadings with a magnitude of 0.275 mm", and its schedule
/// reads "the loading rate for deformation computation is
/// 2.75e-4/3 m/iteration" and "for the explicit-ADR scheme, the loading
/// rate is set to be 2.75e-7 m/iteration": the rate applies to each
/// loaded end and sums to 2.75e-4 m = 0.275 mm over the schedule, so each
/// end moves 0.275 mm (section 3.3, by contrast, states "a total magnitude
/// of 1.6 mm"). With 0.1375 mm per end no bond would break at all.
pub fn plate_hole(n: usize) -> PdCase {
    let l = 0.05;
    let dx = l / n as f64;
    let d = 0.275e-3;
    PdCase {
        name: "pd_plate_hole".into(),
        problem: PdProblem {
            region: Region {
                outline: Region::rectangle([0.0, 0.0], [l, l]).outline,
                holes: vec![Hole::Circle {
                    centre: [0.5 * l, 0.5 * l],
                    radius: 0.005,
                }],
            },
            dx,
            thickness: dx,
            youngs_modulus: 192e9,
            failure: Failure::Degradation {
                s_m: 0.015,
                s_c: 0.02,
                beta: 3.0,
            },
            boundary: vec![
                fixed_side([-1.0, -1.0], [1.0, 0.0], Some(0.0), Some(-d)),
                fixed_side([-1.0, l], [1.0, 1.0], Some(0.0), Some(d)),
            ],
            ..Default::default()
        },
        target_load: 1.0,
        implicit_steps: 3,
        explicit_steps: 180,
        adr_rate_steps: 1000,
    }
}

/// Three-point bend, seed 000 section 5.3: 0.24 m x 0.06 m, `nx x ny` grid
/// (seed 200 x 50), E = 200 GPa, degradation `s_m = 0.016, s_c = 0.02,
/// beta = 3`, central bottom notch of length 0.3 w (a pre-crack), supports
/// at +-0.105 m from the centre and the load point at the top centre, each a
/// fictitious area of depth delta and span 4 dx; supports fix `uy`, the load
/// point moves `uy = -4 mm` with `ux = 0` (removes the rigid x motion).
/// Seed schedule: `N_i = 5`, `N_e = 1000`; pure ADR at 1e-7 m per iteration.
pub fn three_point_bend(nx: usize, ny: usize) -> PdCase {
    let (l, w) = (0.24, 0.06);
    let dx = l / nx as f64;
    assert!(
        (w / ny as f64 - dx).abs() < 1e-9 * dx,
        "three-point bend needs square cells"
    );
    let c = 0.5 * l;
    let span = 2.0 * dx;
    PdCase {
        name: "pd_three_point_bend".into(),
        problem: PdProblem {
            region: Region::rectangle([0.0, 0.0], [l, w]),
            dx,
            thickness: dx,
            youngs_modulus: 200e9,
            failure: Failure::Degradation {
                s_m: 0.016,
                s_c: 0.02,
                beta: 3.0,
            },
            cracks: vec![vec![[c, -0.5 * dx], [c, 0.3 * w]]],
            boundary: vec![
                fixed_side(
                    [c - 0.105 - span, -1.0],
                    [c - 0.105 + span, 0.0],
                    None,
                    Some(0.0),
                ),
                fixed_side(
                    [c + 0.105 - span, -1.0],
                    [c + 0.105 + span, 0.0],
                    None,
                    Some(0.0),
                ),
                fixed_side([c - span, w], [c + span, 1.0], Some(0.0), Some(-4e-3)),
            ],
            ..Default::default()
        },
        target_load: 1.0,
        implicit_steps: 5,
        explicit_steps: 1000,
        adr_rate_steps: 40_000,
    }
}

/// Pre-crack of the seed 001 section 6.1 plates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum CrackKind {
    /// Horizontal central crack, 10 mm (seed: initiation at 14.6 MPa).
    Central,
    /// Central crack at 45 degrees, 10 mm (seed: 15.9 MPa, kink 56 degrees).
    Inclined,
    /// Horizontal edge crack from the left side (seed: 8.5 MPa). Seed 001
    /// section 6.1 says only "The plate preset an edge crack is shown in
    /// Fig. 10. Under the tension of 8.5 MPa, the crack propagates in a
    /// straight line"; no length is given, so 10 mm is assumed (the length
    /// of the central and inclined cracks of the same section; LEFM gives
    /// 7.5 MPa for it, and 8.5 MPa would correspond to about 8.2 mm).
    Edge,
}

/// Base traction of the seed 001 cases: load factor 1 = 1 MPa.
pub const SEED001_UNIT_TRACTION: f64 = 1e6;

/// Seed 001 section 6.1: 50 mm square centred at the origin, `n x n` grid
/// (seed 200), E = 30 GPa, G_c = 110 J/m^2 (s0 = 0.0026 at n = 200), plane
/// stress, uniaxial vertical tension as body force in the top and bottom
/// node rows (seed 000 section 2.3 instead of seed 001's transfer
/// functions), three pinned DOFs at the top and bottom centre nodes against
/// rigid motion (the load is self-equilibrated, so they carry no reaction).
/// Load factor = applied stress in MPa; `n` even.
pub fn seed001_crack(kind: CrackKind, n: usize) -> PdCase {
    let h = 0.025;
    let dx = 2.0 * h / n as f64;
    let a = 0.005;
    let crack = match kind {
        CrackKind::Central => vec![[-a, 0.0], [a, 0.0]],
        CrackKind::Inclined => {
            let r = a * std::f64::consts::FRAC_1_SQRT_2;
            vec![[-r, -r], [r, r]]
        }
        CrackKind::Edge => vec![[-h, 0.0], [-h + 2.0 * a, 0.0]],
    };
    let pin = |y: f64, ux: Option<f64>, uy: Option<f64>| BoundaryCondition::Displacement {
        on: Selection::Circle {
            centre: [0.5 * dx, y],
            radius: 0.1 * dx,
        },
        ux,
        uy,
        layer: Layer::Real,
    };
    let t = SEED001_UNIT_TRACTION;
    PdCase {
        name: match kind {
            CrackKind::Central => "pd_central_crack",
            CrackKind::Inclined => "pd_inclined_crack",
            CrackKind::Edge => "pd_edge_crack",
        }
        .into(),
        problem: PdProblem {
            region: Region::rectangle([-h, -h], [h, h]),
            dx,
            thickness: 1e-3,
            youngs_modulus: 30e9,
            plane: Plane::Stress,
            failure: Failure::FractureEnergy { g_c: 110.0 },
            cracks: vec![crack],
            boundary: vec![
                BoundaryCondition::Traction {
                    edge: vec![[-h, h], [h, h]],
                    traction: [0.0, t],
                    depth: None,
                },
                BoundaryCondition::Traction {
                    edge: vec![[-h, -h], [h, -h]],
                    traction: [0.0, -t],
                    depth: None,
                },
                pin(-h + 0.5 * dx, Some(0.0), Some(0.0)),
                pin(h - 0.5 * dx, Some(0.0), None),
            ],
            ..Default::default()
        },
        target_load: 20.0,
        implicit_steps: 1,
        explicit_steps: 1,
        adr_rate_steps: 1,
    }
}

/// Seed 004 section 4.2's dynamic crack-branching plate: 100 mm x 40 mm, thickness
/// 1 mm, a 50 mm pre-crack from the middle of the left edge along the mid-line, Table 4
/// material (E = 32 GPa, nu = 0.2, rho = 2450 kg/m^3 for [`crate::dynamics`], G_c =
/// 3 J/m^2, state-based PD, plane stress), tractions `sigma` (Pa) pulling the top and
/// bottom edges held from t = 0 (load factor 1). `dx` should divide 40 mm.
pub fn branching_plate(dx: f64, sigma: f64) -> PdCase {
    let (l, w) = (0.1, 0.04);
    let traction = |y: f64, ty: f64| BoundaryCondition::Traction {
        edge: vec![[0.0, y], [l, y]],
        traction: [0.0, ty],
        depth: Some(dx),
    };
    PdCase {
        name: "seed004_branching".into(),
        problem: PdProblem {
            region: Region::rectangle([0.0, 0.0], [l, w]),
            dx,
            thickness: 1e-3,
            youngs_modulus: 32e9,
            plane: Plane::Stress,
            material: crate::problem::PdMaterial::StateBased { poisson_ratio: 0.2 },
            failure: Failure::FractureEnergy { g_c: 3.0 },
            cracks: vec![vec![[-dx, 0.5 * w], [0.05, 0.5 * w]]],
            boundary: vec![traction(w, sigma), traction(0.0, -sigma)],
            ..Default::default()
        },
        target_load: 1.0,
        implicit_steps: 1,
        explicit_steps: 1,
        adr_rate_steps: 1,
    }
}

/// Mass density of seed 004's Table 4 material (kg/m^3), [`branching_plate`].
pub const SEED004_DENSITY: f64 = 2450.0;
