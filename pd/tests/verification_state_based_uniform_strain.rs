//! Ordinary state-based PD (seed 004 section 2.1) under uniform uniaxial stress: a free
//! plate pulled by equal and opposite tractions on its ends must take the homogeneous
//! strain of linear elasticity, $\varepsilon_{xx} = \sigma/E'$ and
//! $\varepsilon_{yy} = -\nu'\sigma/E'$ (plane stress $E' = E$, $\nu' = \nu$; plane strain
//! $E' = E/(1-\nu^2)$, $\nu' = \nu/(1-\nu)$), for Poisson ratios the bond-based model
//! cannot represent (0.2, 0.3) and for 1/3. Strains are fitted by least squares over the
//! middle third of the plate (away from the loaded ends): in the bulk rows (more than a
//! horizon from the free edges) and in the outermost rows. Also: the work of the loads
//! equals the strain energy (Clapeyron) on the same plates.

use pdbem_pd::solvers::implicit::{self, ImplicitParams};
use pdbem_pd::{
    BoundaryCondition, Layer, PdMaterial, PdModel, PdProblem, Plane, Region, Selection,
};

const L: f64 = 36.0;
const H: f64 = 18.0;
const SIGMA: f64 = 1e-6;

fn plate(nu: f64, plane: Plane, surface_correction: bool) -> PdProblem {
    let pin = |x: f64, ux: Option<f64>| BoundaryCondition::Displacement {
        on: Selection::Circle {
            centre: [x, 0.5 * H + 0.5],
            radius: 0.1,
        },
        ux,
        uy: Some(0.0),
        layer: Layer::Real,
    };
    PdProblem {
        region: Region::rectangle([0.0, 0.0], [L, H]),
        dx: 1.0,
        youngs_modulus: 1.0,
        plane,
        material: PdMaterial::StateBased { poisson_ratio: nu },
        surface_correction,
        boundary: vec![
            BoundaryCondition::Traction {
                edge: vec![[L, 0.0], [L, H]],
                traction: [SIGMA, 0.0],
                depth: None,
            },
            BoundaryCondition::Traction {
                edge: vec![[0.0, 0.0], [0.0, H]],
                traction: [-SIGMA, 0.0],
                depth: None,
            },
            pin(0.5 * L + 0.5, Some(0.0)),
            pin(0.5 * L + 1.5, None),
        ],
        ..Default::default()
    }
}

/// Least-squares slope of `v` against `x`.
fn slope(pts: &[(f64, f64)]) -> f64 {
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let mv = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxv: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - mv)).sum();
    sxv / sxx
}

/// (eps_xx bulk, eps_yy bulk, eps_xx edge row, eps_yy across the edge layer: from the
/// edge row to the first row with a full family), the solved model.
fn strains(p: &PdProblem) -> ([f64; 4], PdModel) {
    let mut m = PdModel::new(p).unwrap();
    implicit::solve(&mut m, &ImplicitParams::default()).unwrap();
    let (x, u) = (m.positions(), m.displacements());
    let mid = |q: [f64; 2]| q[0] > L / 3.0 && q[0] < 2.0 * L / 3.0;
    let bulk = |q: [f64; 2]| q[1] > 4.0 && q[1] < H - 4.0;
    let real = 0..m.n_real();
    let exx: Vec<(f64, f64)> = real
        .clone()
        .filter(|&i| mid(x[i]) && bulk(x[i]))
        .map(|i| (x[i][0], u[i][0]))
        .collect();
    let eyy: Vec<(f64, f64)> = real
        .clone()
        .filter(|&i| mid(x[i]) && bulk(x[i]))
        .map(|i| (x[i][1], u[i][1]))
        .collect();
    let top = |i: usize| (x[i][1] - (H - 0.5)).abs() < 1e-9;
    // The first row with a full family (more than a horizon from the edge).
    let below = |i: usize| (x[i][1] - (H - 4.5)).abs() < 1e-9;
    let exx_edge: Vec<(f64, f64)> = real
        .clone()
        .filter(|&i| mid(x[i]) && top(i))
        .map(|i| (x[i][0], u[i][0]))
        .collect();
    let mean = |f: &dyn Fn(usize) -> bool| {
        let v: Vec<f64> = real
            .clone()
            .filter(|&i| mid(x[i]) && f(i))
            .map(|i| u[i][1])
            .collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let eyy_edge = (mean(&top) - mean(&below)) / 4.0;
    let e = [slope(&exx), slope(&eyy), slope(&exx_edge), eyy_edge];
    (e, m)
}

/// Relative errors of eps_xx and of the effective Poisson ratio -eps_yy/eps_xx, bulk and
/// edge row.
fn errors(nu: f64, plane: Plane, corr: bool) -> [f64; 4] {
    let (e, _) = strains(&plate(nu, plane, corr));
    let (ep, nup) = match plane {
        Plane::Stress => (1.0, nu),
        Plane::Strain => (1.0 / (1.0 - nu * nu), nu / (1.0 - nu)),
    };
    let exx = SIGMA / ep;
    [
        e[0] / exx - 1.0,
        -e[1] / e[0] / nup - 1.0,
        e[2] / exx - 1.0,
        -e[3] / e[2] / nup - 1.0,
    ]
}

#[test]
fn uniaxial_stress_gives_e_and_nu_in_plane_stress_and_strain() {
    let mut worst = [0.0f64; 4];
    for plane in [Plane::Stress, Plane::Strain] {
        for nu in [0.2, 0.3, 1.0 / 3.0] {
            let e = errors(nu, plane, true);
            eprintln!(
                "{plane:?} nu = {nu:.4}: bulk eps_xx {:+.2e}, nu {:+.2e}; edge row eps_xx {:+.2e}, nu {:+.2e}",
                e[0], e[1], e[2], e[3]
            );
            for k in 0..4 {
                worst[k] = worst[k].max(e[k].abs());
            }
        }
    }
    eprintln!("worst: {worst:?}");
    // Measured worst over the six materials (36 x 18 cells, m = 3.015, surface
    // correction): bulk eps_xx 0.80 %, bulk nu 1.14 %; edge row eps_xx 0.29 %, nu across
    // the edge layer 5.2 %. The bulk error is the lattice's fourth-moment anisotropy
    // (energy density within 0.51 % of the classical one, `state_based` unit tests) plus
    // what the 3-row edge layers leave in an 18-row plate.
    assert!(worst[0] < 0.012 && worst[1] < 0.015, "bulk {worst:?}");
    assert!(worst[2] < 0.005 && worst[3] < 0.07, "edge {worst:?}");
}

#[test]
fn without_surface_correction_the_edge_is_soft() {
    let e = errors(0.3, Plane::Stress, false);
    eprintln!("no correction, nu = 0.3 plane stress: {e:?}");
    // Measured: eps_xx +3.2 % (bulk) and +3.8 % (edge row), nu +10 % across the edge
    // layer: the truncated families at the free edges soften the 18-row plate, which the
    // surface correction removes (the test above).
    assert!(e[0] > 0.02 && e[2] > 0.02, "the plate is not softer: {e:?}");
}

#[test]
fn work_of_the_loads_equals_the_strain_energy() {
    for (nu, plane) in [(0.2, Plane::Strain), (0.3, Plane::Stress)] {
        let (_, mut m) = strains(&plate(nu, plane, true));
        let v = m.grid().volume;
        let body = m.boundary().body.clone();
        let u = m.displacements().to_vec();
        let work: f64 = (0..u.len())
            .map(|i| 0.5 * v * (body[i][0] * u[i][0] + body[i][1] * u[i][1]))
            .sum();
        let energy = m.energy();
        let f = m.internal_forces();
        let pins: f64 = f
            .iter()
            .zip(&m.boundary().fixed)
            .filter(|(_, fx)| fx[0] || fx[1])
            .map(|(g, _)| g[0].hypot(g[1]))
            .sum();
        eprintln!(
            "{plane:?} nu = {nu}: work {work:.6e}, energy {energy:.6e}, ratio - 1 = {:.2e}, pin reactions {pins:.2e}",
            work / energy - 1.0
        );
        // Measured 9.7e-8 and 1.1e-7: the geometric nonlinearity at strain 1e-6 and the
        // Newton tolerance; the pins carry no load (reactions 5e-14 of the unit load).
        assert!(
            (work / energy - 1.0).abs() < 1e-6,
            "work {work} vs energy {energy}"
        );
    }
}
