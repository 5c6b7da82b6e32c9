//! Unit tests of the transfer-function traction (seed 001 Eqs. 16, 17, 23).

use super::*;
use crate::problem::{Layer, Region, Selection};
use crate::PdModel;

/// Seed 001's plate (50 mm square, both 50 mm ends loaded): S = 0.1 m.
#[test]
fn decay_k_of_the_seed_plate() {
    let (lw, s) = (0.05 * 0.05, 0.1);
    // delta = 3.015 dx: LW / (8 S delta) = 4.15 at dx = 0.25 mm, 1.04 at 1 mm,
    // 8.29 at 0.125 mm, 0.41 at 2.5 mm (floor 0, held at 1).
    assert_eq!(decay_k(lw, s, 3.015 * 0.25e-3), 4.0);
    assert_eq!(decay_k(lw, s, 3.015 * 1e-3), 1.0);
    assert_eq!(decay_k(lw, s, 3.015 * 0.125e-3), 8.0);
    assert_eq!(decay_k(lw, s, 3.015 * 2.5e-3), 1.0);
}

#[test]
fn q_decays_linearly_inside_the_horizon() {
    let d = 2.0;
    assert_eq!(q(0.0, 4.0, d), 1.0);
    assert!((q(d, 4.0, d) - 0.75).abs() < 1e-15);
    assert!((q(0.5 * d, 1.0, d) - 0.5).abs() < 1e-15);
    assert_eq!(q(d * 1.0001, 4.0, d), 0.0);
}

#[test]
fn boundary_points_cover_the_edge() {
    let pts = boundary_points(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.35]], 0.1);
    assert_eq!(pts.len(), 10 + 4);
    let total: f64 = pts.iter().map(|p| p.1).sum();
    assert!((total - 1.35).abs() < 1e-12);
    assert!((pts[0].0[0] - 0.05).abs() < 1e-12);
    assert!((pts[13].0[1] - 0.35 * 7.0 / 8.0).abs() < 1e-12);
}

fn pinned(mut p: PdProblem) -> PdProblem {
    p.boundary.push(BoundaryCondition::Displacement {
        on: Selection::All,
        ux: Some(0.0),
        uy: Some(0.0),
        layer: Layer::Real,
    });
    p
}

/// Equilibrium invariant (seed 001 Eq. 2 with chi = 1): the body forces of
/// a traction sum to the traction times the edge length and thickness, on a
/// rectangle and on a slanted edge of a general polygon with a hole.
#[test]
fn applied_force_equals_traction_times_edge_length() {
    let edges: [(Vec<P2>, Region); 2] = [
        (
            vec![[0.0, 1.0], [2.0, 1.0]],
            Region::rectangle([0.0, 0.0], [2.0, 1.0]),
        ),
        (
            vec![[2.0, 0.0], [1.3, 1.5]],
            Region {
                outline: vec![[0.0, 0.0], [2.0, 0.0], [1.3, 1.5], [0.0, 1.2]],
                holes: vec![Hole::Circle {
                    centre: [0.8, 0.6],
                    radius: 0.2,
                }],
            },
        ),
    ];
    for (edge, region) in edges {
        let t = [3.0e6, -7.0e6];
        let p = pinned(PdProblem {
            region,
            dx: 0.05,
            thickness: 0.01,
            youngs_modulus: 1e9,
            boundary: vec![BoundaryCondition::Traction {
                edge: edge.clone(),
                traction: t,
                depth: None,
            }],
            traction: TractionLoad::TransferFunction,
            ..Default::default()
        });
        let m = PdModel::new(&p).unwrap();
        let v = m.grid().volume;
        let mut f = [0.0; 2];
        for b in &m.boundary().body {
            f[0] += b[0] * v;
            f[1] += b[1] * v;
        }
        let len = crate::geometry::polyline_length(&edge);
        for c in 0..2 {
            let want = t[c] * len * 0.01;
            assert!(
                (f[c] / want - 1.0).abs() < 1e-12,
                "component {c}: {} vs {want}",
                f[c]
            );
        }
        // Every loaded node lies within the horizon of the edge.
        let delta = m.grid().delta;
        for (i, b) in m.boundary().body.iter().enumerate() {
            if b[0] != 0.0 || b[1] != 0.0 {
                assert!(
                    crate::geometry::dist_point_polyline(m.positions()[i], &edge)
                        <= delta * 1.000001
                );
            }
        }
    }
}

/// The transfer function spreads each boundary point's force over the
/// horizon: on a straight edge away from corners, the node rows within
/// delta all carry load, and the body force falls off with depth (q
/// decreasing in r), unlike the one-row body-force layer.
#[test]
fn load_spreads_over_the_horizon_and_decays_with_depth() {
    let p = pinned(PdProblem {
        region: Region::rectangle([0.0, 0.0], [4.0, 4.0]),
        dx: 0.1,
        youngs_modulus: 1e9,
        boundary: vec![BoundaryCondition::Traction {
            edge: vec![[0.0, 4.0], [4.0, 4.0]],
            traction: [0.0, 1.0],
            depth: None,
        }],
        traction: TractionLoad::TransferFunction,
        ..Default::default()
    });
    let m = PdModel::new(&p).unwrap();
    let (x, b) = (m.positions(), &m.boundary().body);
    // Column x = 2.05 (middle): body force by row depth.
    let mut rows: Vec<(f64, f64)> = (0..m.n_real())
        .filter(|&i| (x[i][0] - 2.05).abs() < 1e-9 && b[i][1] != 0.0)
        .map(|i| (4.0 - x[i][1], b[i][1]))
        .collect();
    rows.sort_by(|a, c| a.0.total_cmp(&c.0));
    // delta = 0.3015: rows at depth 0.05, 0.15, 0.25.
    assert_eq!(rows.len(), 3, "{rows:?}");
    assert!(rows[0].1 > rows[1].1 && rows[1].1 > rows[2].1, "{rows:?}");
}

#[test]
fn a_depth_with_transfer_functions_is_an_error() {
    let p = pinned(PdProblem {
        region: Region::rectangle([0.0, 0.0], [1.0, 1.0]),
        dx: 0.1,
        youngs_modulus: 1e9,
        boundary: vec![BoundaryCondition::Traction {
            edge: vec![[0.0, 1.0], [1.0, 1.0]],
            traction: [0.0, 1.0],
            depth: Some(0.1),
        }],
        traction: TractionLoad::TransferFunction,
        ..Default::default()
    });
    let e = PdModel::new(&p).unwrap_err().to_string();
    assert!(e.contains("boundary[0].depth"), "{e}");
}

#[test]
fn an_edge_away_from_the_body_is_an_error() {
    let p = pinned(PdProblem {
        region: Region::rectangle([0.0, 0.0], [1.0, 1.0]),
        dx: 0.1,
        youngs_modulus: 1e9,
        boundary: vec![BoundaryCondition::Traction {
            edge: vec![[0.0, 3.0], [1.0, 3.0]],
            traction: [0.0, 1.0],
            depth: None,
        }],
        traction: TractionLoad::TransferFunction,
        ..Default::default()
    });
    let e = PdModel::new(&p).unwrap_err().to_string();
    assert!(e.contains("boundary[0].edge"), "{e}");
}
