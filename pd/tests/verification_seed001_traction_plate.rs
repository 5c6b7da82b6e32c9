//! Seed 001 section 5: the 50 mm square plate (E = 192 GPa, nu = 1/3, plane
//! stress) under 200 MPa at both ends, loaded through seed 001's traction
//! transfer functions (`TractionLoad::TransferFunction`), against elasticity
//! (seed 001 Eq. 26), against the body-force layer, under dx refinement at
//! m = 3.015, and with every solver. Grids dx = 1.25, 1 and 0.5 mm here (the
//! seed goes to 0.125 mm: `cargo run --release -p pdbem-pd --example
//! traction_convergence`).
//!
//! Bulk factor: the discrete horizon sum of pd::bonds at m = 3.015 (partial
//! volumes, no correction) is 1 / 1.1616 of the continuum stiffness
//! (measured in coupling::pd_window's `bulk_factor_measures_the_discrete_horizon_sum`),
//! so PD strains are 1.1616 times the elastic ones at any dx: that factor is
//! divided out before comparing with elasticity.

use pdbem_pd::solvers::{adr, implicit, switching};
use pdbem_pd::traction::study::{plate, study_row, MONITOR};
use pdbem_pd::{PdModel, TractionLoad};

const BULK: f64 = 1.1616;

#[test]
fn transfer_function_plate_is_uniform_and_elastic_up_to_the_bulk_factor() {
    let tf = study_row(1e-3, 3.015, TractionLoad::TransferFunction).unwrap();
    let bf = study_row(1e-3, 3.015, TractionLoad::BodyForceLayer).unwrap();
    eprintln!("{tf:?}\n{bf:?}");
    // Equilibrium: the mean force flux across the mid-plane is the traction
    // (measured 1 + 1.3e-10; the Newton residual tolerance is 1e-10).
    assert!(
        (tf.mid_flux_mean - 1.0).abs() < 1e-6,
        "{}",
        tf.mid_flux_mean
    );
    // Uniform interior stress: the mid-plane columns 2 delta inside the free
    // sides within 2.5 % of p (measured 1.7 %; body-force layer 2.3 %).
    assert!(
        tf.mid_flux_dev_interior < 0.025,
        "{}",
        tf.mid_flux_dev_interior
    );
    // Interior strain E eps_yy / p over the bulk factor: measured 1.0058.
    assert!(
        (tf.interior_strain_ratio / BULK - 1.0).abs() < 0.01,
        "{}",
        tf.interior_strain_ratio
    );
    // Monitoring point (-12.25, -12.25) mm over elasticity and the bulk factor:
    // measured u_x 0.987, u_y 1.010.
    for c in 0..2 {
        let r = tf.u_over_elastic[c] / BULK;
        assert!((r - 1.0).abs() < 0.02, "component {c}: {r}");
    }
    // The loaded edge: elastic theory keeps it straight and stretched as the
    // interior. Transfer functions: extra stretch 0.65 %, unevenness 3.5 %;
    // body-force layer: 5.5 % and 10.6 %. The transfer functions are closer.
    assert!(tf.edge_excess.abs() < 0.02, "{}", tf.edge_excess);
    assert!(tf.edge_unevenness < 0.05, "{}", tf.edge_unevenness);
    assert!(tf.edge_excess.abs() < 0.5 * bf.edge_excess.abs());
    assert!(tf.edge_unevenness < 0.5 * bf.edge_unevenness);
}

/// delta-convergence at m = 3.015 (seed 001 Fig. 2): the monitoring-point
/// displacement approaches its fine-grid value as dx falls.
#[test]
fn monitoring_displacement_converges_under_refinement() {
    let rows: Vec<_> = [1.25e-3, 1e-3, 0.5e-3]
        .iter()
        .map(|&dx| study_row(dx, 3.015, TractionLoad::TransferFunction).unwrap())
        .collect();
    let fine = rows[2].u_monitor;
    let gap = |u: [f64; 2]| ((u[0] - fine[0]).hypot(u[1] - fine[1])) / fine[0].hypot(fine[1]);
    let (g0, g1) = (gap(rows[0].u_monitor), gap(rows[1].u_monitor));
    eprintln!("gaps to dx = 0.5 mm: {g0:.4} (1.25 mm), {g1:.4} (1 mm)");
    // Measured 0.0071 and 0.0043: smaller on the finer grid, under 1 %.
    assert!(g1 < g0, "{g1} >= {g0}");
    assert!(g1 < 0.01, "{g1}");
}

/// The transfer-function term is a dead load in every solver's residual:
/// ADR, implicit Newton and the switch reach the same equilibrium.
#[test]
fn every_solver_reaches_the_same_equilibrium() {
    let p = plate(1.25e-3, 3.015, TractionLoad::TransferFunction);
    let mut newton = PdModel::new(&p).unwrap();
    implicit::solve(&mut newton, &implicit::ImplicitParams::default()).unwrap();
    let mut dr = PdModel::new(&p).unwrap();
    let info = adr::solve(
        &mut dr,
        &adr::AdrParams {
            convergence: pdbem_pd::Convergence::Displacement { e0: 1e-11 },
            ..Default::default()
        },
    )
    .unwrap();
    let mut sw = PdModel::new(&p).unwrap();
    switching::solve(&mut sw, &switching::SwitchingParams::default()).unwrap();
    let (g_adr, g_sw) = (
        newton.relative_displacement_gap(&dr),
        newton.relative_displacement_gap(&sw),
    );
    eprintln!(
        "ADR gap {g_adr:.2e} ({} iterations), switching gap {g_sw:.2e}",
        info.iterations
    );
    // Measured 1.0e-9 (1955 ADR iterations) and 2.6e-10.
    assert!(g_adr < 1e-6, "ADR {g_adr}");
    assert!(g_sw < 1e-6, "switching {g_sw}");
    // And the monitoring point moves: the load reached the body.
    let u = pdbem_pd::traction::study::displacement_at(&dr, MONITOR);
    assert!(u[1] < -1e-5, "{u:?}");
}

/// A general outline: the same plate rotated by 30 degrees (grid along its
/// sides, tractions normal to the rotated edges) is the rotated solution of
/// the axis-aligned one; k and the normalisation come from the area and the
/// loaded length, which the rotation keeps.
#[test]
fn rotated_plate_gives_the_rotated_solution() {
    use pdbem_pd::problem::{BoundaryCondition, Region, Selection};
    let (dx, a) = (1.25e-3, 30f64.to_radians());
    let rot = |p: [f64; 2]| {
        let (s, c) = a.sin_cos();
        [c * p[0] - s * p[1], s * p[0] + c * p[1]]
    };
    let base = plate(dx, 3.015, TractionLoad::TransferFunction);
    let mut turned = base.clone();
    turned.region = Region::rotated_rectangle([0.0, 0.0], 0.05, 0.05, a);
    turned.grid_angle = a;
    for bc in &mut turned.boundary {
        match bc {
            BoundaryCondition::Traction { edge, traction, .. } => {
                *edge = edge.iter().map(|&p| rot(p)).collect();
                *traction = rot(*traction);
            }
            BoundaryCondition::Displacement { on, .. } => {
                if let Selection::Circle { centre, .. } = on {
                    *centre = rot(*centre);
                }
            }
            BoundaryCondition::Force { .. } => unreachable!(),
        }
    }
    let mut m0 = PdModel::new(&base).unwrap();
    implicit::solve(&mut m0, &implicit::ImplicitParams::default()).unwrap();
    let mut m1 = PdModel::new(&turned).unwrap();
    implicit::solve(&mut m1, &implicit::ImplicitParams::default()).unwrap();
    let (b0, b1) = (m0.boundary(), m1.boundary());
    let f0: f64 = b0.body.iter().map(|b| b[1].abs()).sum();
    let f1: f64 = b1.body.iter().map(|b| b[0].hypot(b[1])).sum();
    assert!((f1 / f0 - 1.0).abs() < 1e-9, "{f0} {f1}");
    // Interior strain along the load: u . n_load between two interior nodes.
    let strain = |m: &PdModel, dir: [f64; 2]| {
        let (x, u) = (m.positions(), m.displacements());
        let (mut lo, mut hi) = ((f64::INFINITY, 0.0), (f64::NEG_INFINITY, 0.0));
        for i in 0..m.n_real() {
            let s = x[i][0] * dir[0] + x[i][1] * dir[1];
            let t = -x[i][0] * dir[1] + x[i][1] * dir[0];
            if t.abs() < 0.6 * dx && s.abs() < 0.01 {
                let v = u[i][0] * dir[0] + u[i][1] * dir[1];
                if s < lo.0 {
                    lo = (s, v);
                }
                if s > hi.0 {
                    hi = (s, v);
                }
            }
        }
        (hi.1 - lo.1) / (hi.0 - lo.0)
    };
    let (e0, e1) = (strain(&m0, [0.0, 1.0]), strain(&m1, rot([0.0, 1.0])));
    eprintln!("interior strain: axis-aligned {e0:.6e}, rotated {e1:.6e}");
    // Measured 4.2e-4 apart: the top pin holds the global x component, which in the
    // rotated plate is not across the load, so it carries a small reaction there
    // (rigid modes alone cannot explain a strain change). Bound 1e-3; the
    // two-node strain itself is 1.004 times the elastic p / E times the bulk factor.
    assert!((e1 / e0 - 1.0).abs() < 1e-3, "{e0} {e1}");
}
