//! Seed 001 section 5: the 50 mm square plate (E = 192 GPa, plane stress,
//! nu = 1/3) under 200 MPa uniaxial tension at both ends, and the measures
//! of its convergence study: the displacement at the monitoring point
//! against elasticity (seed 001 Eq. 26, $u_x = -\nu p x / E$,
//! $u_y = p y / E$), the force-flux stress across horizontal cuts, and the
//! displacement of the loaded edge against elasticity.
//!
//! Monitoring point: seed 001 gives "(0.1225, -0.1225)" for Fig. 2 and
//! "(-0.01225, -0.01225)" for Fig. 3; in metres the first lies outside the
//! 50 mm plate centred at the origin, so [`MONITOR`] is the second.
//!
//! Rigid motion: the plate is held by two pins (as the seed 001 crack
//! cases); displacements are compared after subtracting the mean
//! displacement of the four nodes around the centre (zero in the exact
//! solution by symmetry).

use crate::geometry::P2;
use crate::model::PdModel;
use crate::problem::{BoundaryCondition, Layer, PdProblem, Plane, Region, Selection};
use crate::traction::TractionLoad;

/// Half side of the plate (m).
pub const HALF: f64 = 0.025;
/// Applied traction at load factor 1 (Pa), seed 001 section 5.
pub const PRESSURE: f64 = 200e6;
/// Young's modulus (Pa), seed 001 section 5.
pub const YOUNGS: f64 = 192e9;
/// Poisson's ratio of 2-D bond-based PD in plane stress.
pub const NU: f64 = 1.0 / 3.0;
/// Monitoring point (m), seed 001 Fig. 3.
pub const MONITOR: P2 = [-0.01225, -0.01225];

/// The plate at spacing `dx` (`0.05 / dx` an even integer) and horizon
/// factor `m`, loaded by `mode`.
pub fn plate(dx: f64, m: f64, mode: TractionLoad) -> PdProblem {
    let h = HALF;
    let pin = |y: f64, ux: Option<f64>, uy: Option<f64>| BoundaryCondition::Displacement {
        on: Selection::Circle {
            centre: [0.5 * dx, y],
            radius: 0.1 * dx,
        },
        ux,
        uy,
        layer: Layer::Real,
    };
    let depth = match mode {
        TractionLoad::BodyForceLayer => Some(dx),
        TractionLoad::TransferFunction => None,
    };
    PdProblem {
        region: Region::rectangle([-h, -h], [h, h]),
        dx,
        horizon_factor: m,
        thickness: 1e-3,
        youngs_modulus: YOUNGS,
        plane: Plane::Stress,
        boundary: vec![
            BoundaryCondition::Traction {
                edge: vec![[-h, h], [h, h]],
                traction: [0.0, PRESSURE],
                depth,
            },
            BoundaryCondition::Traction {
                edge: vec![[-h, -h], [h, -h]],
                traction: [0.0, -PRESSURE],
                depth,
            },
            pin(-h + 0.5 * dx, Some(0.0), Some(0.0)),
            pin(h - 0.5 * dx, Some(0.0), None),
        ],
        traction: mode,
        ..Default::default()
    }
}

/// Elastic displacement of the plate (seed 001 Eq. 26).
pub fn elastic(x: P2) -> P2 {
    let e = PRESSURE / YOUNGS;
    [-NU * e * x[0], e * x[1]]
}

/// Mean displacement of the real nodes within `1.5 dx` (each axis) of the
/// origin: the rigid translation to remove.
fn centre_shift(m: &PdModel) -> P2 {
    let (x, u, dx) = (m.positions(), m.displacements(), m.grid().dx);
    let (mut s, mut n) = ([0.0; 2], 0.0);
    for i in 0..m.n_real() {
        if x[i][0].abs() < dx && x[i][1].abs() < dx {
            s[0] += u[i][0];
            s[1] += u[i][1];
            n += 1.0;
        }
    }
    [s[0] / n, s[1] / n]
}

/// Displacement at `p` (bilinear interpolation over the four surrounding
/// real nodes of the regular grid), rigid translation removed.
pub fn displacement_at(m: &PdModel, p: P2) -> P2 {
    let g = m.grid();
    let (x, u, dx) = (m.positions(), m.displacements(), g.dx);
    let c = centre_shift(m);
    let (mut s, mut w_sum) = ([0.0; 2], 0.0);
    for i in 0..m.n_real() {
        let (rx, ry) = ((x[i][0] - p[0]).abs() / dx, (x[i][1] - p[1]).abs() / dx);
        if rx < 1.0 && ry < 1.0 {
            let w = (1.0 - rx) * (1.0 - ry);
            s[0] += w * (u[i][0] - c[0]);
            s[1] += w * (u[i][1] - c[1]);
            w_sum += w;
        }
    }
    [s[0] / w_sum, s[1] / w_sum]
}

/// Force-flux stress sigma_yy (Pa) across the horizontal line `y = y_cut`
/// (between node rows), per column of width dx: the y force of every intact
/// bond from a node below the line to one above it, attributed to the
/// column where the bond segment crosses the line, over `dx` times the
/// thickness. Returns (column centre x, stress), left to right. PMB bonds
/// without degradation.
pub fn flux_stress(m: &PdModel, y_cut: f64, thickness: f64) -> Vec<(f64, f64)> {
    let g = m.grid();
    let (x, u, b, intact) = (m.positions(), m.displacements(), m.bonds(), m.bond_intact());
    let dx = g.dx;
    let (lo, hi) = (-HALF, HALF);
    let ncol = ((hi - lo) / dx).round() as usize;
    let mut col = vec![0.0; ncol];
    for i in 0..m.n_real() {
        if x[i][1] >= y_cut {
            continue;
        }
        for k in b.row(i) {
            let j = b.nbr[k] as usize;
            if intact[k] == 0 || j >= m.n_real() || x[j][1] <= y_cut {
                continue;
            }
            let y = [
                b.xi[k][0] + u[j][0] - u[i][0],
                b.xi[k][1] + u[j][1] - u[i][1],
            ];
            let l = y[0].hypot(y[1]);
            let s = l * b.inv_len[k] - 1.0;
            // Force on i from j (N): density k s / l y times V_i.
            let fy = b.k[k] * s / l * y[1] * g.volume;
            let t = (y_cut - x[i][1]) / (x[j][1] - x[i][1]);
            let xc = x[i][0] + t * (x[j][0] - x[i][0]);
            // A crossing on a column boundary (lattice bonds often cross there) counts
            // half to each side, so the attribution is mirror symmetric.
            let r = (xc - lo) / dx;
            let near = r.round();
            if (r - near).abs() < 1e-6 {
                let c = near as usize;
                if c > 0 {
                    col[c - 1] += 0.5 * fy;
                }
                if c < ncol {
                    col[c] += 0.5 * fy;
                }
            } else {
                col[(r.floor().max(0.0) as usize).min(ncol - 1)] += fy;
            }
        }
    }
    col.iter()
        .enumerate()
        .map(|(c, f)| (lo + (c as f64 + 0.5) * dx, f / (dx * thickness)))
        .collect()
}

/// Largest relative deviation of the column stresses from `p` over the
/// columns whose centre lies at least `margin` inside the side edges.
pub fn flux_deviation(cols: &[(f64, f64)], p: f64, margin: f64) -> f64 {
    cols.iter()
        .filter(|(x, _)| x.abs() <= HALF - margin)
        .map(|(_, s)| (s / p - 1.0).abs())
        .fold(0.0, f64::max)
}

/// Interior strain eps_yy: least-squares slope of u_y against y over the
/// real nodes with |x|, |y| < h/2.
pub fn interior_strain(m: &PdModel) -> f64 {
    let (x, u) = (m.positions(), m.displacements());
    let (mut n, mut sy, mut su, mut syy, mut syu) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in 0..m.n_real() {
        if x[i][0].abs() < 0.5 * HALF && x[i][1].abs() < 0.5 * HALF {
            let (y, v) = (x[i][1], u[i][1]);
            n += 1.0;
            sy += y;
            su += v;
            syy += y * y;
            syu += y * v;
        }
    }
    (n * syu - sy * su) / (n * syy - sy * sy)
}

/// The y displacement of the top node row (rigid translation removed)
/// against the interior strain carried up to the edge: (mean of
/// $u_y / (\varepsilon_{int} y) - 1$, (max - min of $u_y$) /
/// ($\varepsilon_{int} h$)). Elasticity gives (0, 0): the first measures the
/// extra stretch of the loaded boundary layer, the second how uneven the
/// loaded edge is.
pub fn edge_measures(m: &PdModel) -> (f64, f64) {
    let (x, u, dx) = (m.positions(), m.displacements(), m.grid().dx);
    let c = centre_shift(m);
    let e = interior_strain(m);
    let (mut s, mut n, mut lo, mut hi) = (0.0, 0.0, f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..m.n_real() {
        if x[i][1] > HALF - dx {
            let v = u[i][1] - c[1];
            s += v / (e * x[i][1]) - 1.0;
            n += 1.0;
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    (s / n, (hi - lo) / (e * HALF))
}

/// One plate solve of the convergence study.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StudyRow {
    /// Grid spacing (m).
    pub dx: f64,
    /// Traction loading.
    pub mode: TractionLoad,
    /// Decay integer k of seed 001 Eq. 17 at this spacing.
    pub k: f64,
    /// Displacement at [`MONITOR`] (m), rigid translation removed.
    pub u_monitor: P2,
    /// The same over the elastic value, per component.
    pub u_over_elastic: P2,
    /// Interior strain eps_yy times E / p (elasticity: 1).
    pub interior_strain_ratio: f64,
    /// Mean force-flux stress across y = 0 over p (equilibrium: 1).
    pub mid_flux_mean: f64,
    /// Largest |sigma_yy / p - 1| of the mid-cut columns at least 2 delta
    /// inside the side edges.
    pub mid_flux_dev_interior: f64,
    /// The same over every column (the side columns carry the PD surface
    /// effect).
    pub mid_flux_dev_all: f64,
    /// Largest |sigma_yy / p - 1| across the cut `ceil(m) dx` below the top
    /// edge (the first cut below all of the transfer-function load), columns
    /// at least 2 delta inside.
    pub edge_flux_dev_interior: f64,
    /// [`edge_measures`]: extra stretch of the loaded boundary layer.
    pub edge_excess: f64,
    /// [`edge_measures`]: unevenness of the loaded edge.
    pub edge_unevenness: f64,
    /// Newton iterations.
    pub iterations: usize,
    /// CPU-bound wall time of the solve (s).
    pub time_s: f64,
}

/// Solve the plate at `dx` with `mode` (one implicit Newton solve, the
/// problem is linear up to geometric terms) and measure it.
pub fn study_row(dx: f64, m: f64, mode: TractionLoad) -> Result<StudyRow, crate::PdError> {
    let p = plate(dx, m, mode);
    let t0 = std::time::Instant::now();
    let mut model = PdModel::new(&p)?;
    let info = crate::solvers::implicit::solve(
        &mut model,
        &crate::solvers::implicit::ImplicitParams::default(),
    )?;
    let u = displacement_at(&model, MONITOR);
    let e = elastic(MONITOR);
    let delta = p.horizon();
    let mid = flux_stress(&model, 0.0, p.thickness);
    let mean = mid.iter().map(|c| c.1).sum::<f64>() / mid.len() as f64;
    let edge = flux_stress(&model, HALF - m.ceil() * dx, p.thickness);
    let (excess, uneven) = edge_measures(&model);
    Ok(StudyRow {
        dx,
        mode,
        k: crate::traction::decay_k(4.0 * HALF * HALF, 4.0 * HALF, delta),
        u_monitor: u,
        u_over_elastic: [u[0] / e[0], u[1] / e[1]],
        interior_strain_ratio: interior_strain(&model) * YOUNGS / PRESSURE,
        mid_flux_mean: mean / PRESSURE,
        mid_flux_dev_interior: flux_deviation(&mid, PRESSURE, 2.0 * delta),
        mid_flux_dev_all: flux_deviation(&mid, PRESSURE, 0.0),
        edge_flux_dev_interior: flux_deviation(&edge, PRESSURE, 2.0 * delta),
        edge_excess: excess,
        edge_unevenness: uneven,
        iterations: info.iterations,
        time_s: t0.elapsed().as_secs_f64(),
    })
}
