//! Loads on a mixed grid (`pdbem_pd::mixed`): a body-force layer that crosses a
//! refinement zone is spread by node volume (`pdbem_pd::boundary`), so a child carries a
//! quarter of its parent's share per level and the layer is loaded uniformly. Checked on a
//! plate clamped on its left edge by a fictitious layer and pulled by a traction on its
//! right edge, with a zone over part of the loaded layer: the body forces sum to the
//! applied force and scale with the node volume, and the solved field matches the uniform
//! grid's (PMB and state-based, nu = 0.3, surface-corrected) where a count-based spread
//! (every node its coarse share) puts four times the load on the zone's cells.

use pdbem_pd::mixed::RefineZone;
use pdbem_pd::solvers::implicit;
use pdbem_pd::{BoundaryCondition, Layer, PdMaterial, PdModel, PdProblem, Region, Selection};

type P2 = [f64; 2];

/// Plate side (m, dx = 1 m) and the traction on the right edge (Pa, E = 1 Pa).
const SIDE: f64 = 20.0;
const TRACTION: f64 = 1e-3;

fn plate(material: PdMaterial, zones: Vec<RefineZone>) -> PdProblem {
    PdProblem {
        region: Region::rectangle([0.0, 0.0], [SIDE, SIDE]),
        dx: 1.0,
        youngs_modulus: 1.0,
        material,
        boundary: vec![
            BoundaryCondition::Displacement {
                on: Selection::Box {
                    min: [-10.0, -10.0],
                    max: [0.0, SIDE + 10.0],
                },
                ux: Some(0.0),
                uy: Some(0.0),
                layer: Layer::Fictitious,
            },
            BoundaryCondition::Traction {
                edge: vec![[SIDE, 0.0], [SIDE, SIDE]],
                traction: [TRACTION, 0.0],
                depth: None,
            },
        ],
        refine_zones: zones,
        surface_correction: true,
        ..Default::default()
    }
}

/// The zone over the three right-hand columns, rows 7.5 to 12.5 (30 of the 400 cells).
fn zone() -> Vec<RefineZone> {
    vec![RefineZone {
        centre: [18.5, 10.0],
        half_size: 2.5,
        levels: 1,
    }]
}

fn solved(p: &PdProblem) -> PdModel {
    let mut m = PdModel::new(p).unwrap();
    implicit::solve(&mut m, &implicit::ImplicitParams::default()).unwrap();
    m
}

/// The uniform grid's displacement at `x`, from its node nearest to `x`.
fn nearest(m: &PdModel, x: P2) -> P2 {
    let pos = m.positions();
    let k = (0..m.n_real())
        .min_by(|&a, &b| {
            let d = |i: usize| (pos[i][0] - x[0]).powi(2) + (pos[i][1] - x[1]).powi(2);
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    m.displacements()[k]
}

#[test]
fn a_loaded_layer_across_a_zone_is_spread_by_node_volume() {
    let m = PdModel::new(&plate(PdMaterial::Pmb, zone())).unwrap();
    let g = m.grid();
    let body = &m.boundary().body;
    let layer: Vec<usize> = (0..m.n_real()).filter(|&i| body[i][0] != 0.0).collect();
    // The layer is the right-hand strip of depth dx: 16 coarse cells and 4 x 6 children.
    let children = layer.iter().filter(|&&i| g.node_dx(i) < g.dx).count();
    assert_eq!((layer.len() - children, children), (14, 24));
    let total: f64 = layer.iter().map(|&i| body[i][0] * g.volume).sum();
    let applied = TRACTION * SIDE * g.volume / (g.dx * g.dx);
    assert!(
        (total - applied).abs() <= 1e-12 * applied,
        "resultant {total:e} against {applied:e}"
    );
    let coarse = layer.iter().find(|&&i| g.node_dx(i) == g.dx).unwrap();
    for &i in &layer {
        let ratio = body[i][0] / body[*coarse][0];
        let expected = (g.node_dx(i) / g.dx).powi(2);
        assert!(
            (ratio - expected).abs() < 1e-12,
            "node {i} (dx {}): {ratio} of a coarse node's load, expected {expected}",
            g.node_dx(i)
        );
    }
}

#[test]
fn a_zone_under_the_loaded_edge_leaves_the_field_of_the_uniform_grid() {
    for material in [
        PdMaterial::Pmb,
        PdMaterial::StateBased { poisson_ratio: 0.3 },
    ] {
        let uniform = solved(&plate(material, Vec::new()));
        let mixed = solved(&plate(material, zone()));
        let g = mixed.grid();
        // Every child of the loaded column against the uniform grid's node of its cell.
        let scale = nearest(&uniform, [SIDE - 0.5, 0.5 * SIDE])[0];
        let mut worst = 0.0f64;
        for i in 0..mixed.n_real() {
            let x = mixed.positions()[i];
            if g.node_dx(i) < g.dx && x[0] > SIDE - 1.0 {
                let cell = [x[0].floor() + 0.5, x[1].floor() + 0.5];
                let d = mixed.displacements()[i][0] - nearest(&uniform, cell)[0];
                worst = worst.max(d.abs() / scale);
            }
        }
        // The load's mean displacement, volume-weighted on the mixed grid.
        let load = |m: &mut PdModel| m.bc_resultants()[1].displacement[0];
        let (mut u, mut z) = (uniform, mixed);
        let mean = (load(&mut z) - load(&mut u)).abs() / load(&mut u);
        eprintln!(
            "{material:?}: loaded children off by {worst:.3e}, the layer's mean by {mean:.3e}"
        );
        // Measured (surface-corrected): PMB 1.6e-2 and 1.3e-3, state-based 1.3e-2 and
        // 1.4e-3, the size jump's patch error; a count-based spread (each child its
        // coarse share) puts the children 0.33 off (the mean 1.7e-3). Without the surface
        // correction the children's thinner soft edge layer alone gives 5.5e-2.
        assert!(worst < 0.05, "{material:?}: children off by {worst}");
        assert!(mean < 5e-3, "{material:?}: the layer's mean off by {mean}");
    }
}
