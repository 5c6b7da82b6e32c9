//! Displacement conditions on outline patches in PD scenes (src/run_pd.rs): the
//! fictitious layer of a patch lies outside the body whichever way the scene writes the
//! patch. Seed 002's shear plate (cases/growth_shear_edge.ron) writes its top patches
//! left to right, clockwise; with the layer built on the wrong side the full-PD model
//! lost its loading once 45 bonds had broken (its displacement fell to 1e-13 m).

use pdbem::scene::Scene;
use pdbem_pd::solvers::implicit::{ImplicitParams, Newton};
use pdbem_pd::solvers::{Convergence, SolveInfo};
use pdbem_pd::PdModel;

/// The elastic equilibrium of the PD model of scene `src` at load factor 1.
fn solved(src: &str, file: &str) -> PdModel {
    let scene = Scene::from_ron_str(src, file).unwrap_or_else(|e| panic!("{e}"));
    let problem = pdbem::setup::pd::problem_from_scene(&scene).unwrap();
    let mut model = PdModel::new(&problem).unwrap();
    let mut newton = Newton::new(&model).unwrap();
    let mut info = SolveInfo::default();
    let ip = ImplicitParams {
        residual_tol: 1e-10,
        convergence: Convergence::Residual { tol: 1e-10 },
        ..Default::default()
    };
    newton.predict_to(&mut model, 1.0, &mut info).unwrap();
    newton.equilibrate(&mut model, &ip, &mut info).unwrap();
    model
}

/// A 1 m x 0.5 m plate, left edge clamped, the right edge pulled by 1 mm through a patch
/// written from `from` to `to`; returns (x, y, ux, uy) of the real nodes.
fn pulled_plate(from: (f64, f64), to: (f64, f64)) -> Vec<[f64; 4]> {
    let src = format!(
        r#"(name: "p", material: (E: 1e4, nu: 0.3333333333333333, plane: Stress),
           body: (outline: Rectangle(x0: 0, y0: 0, width: 1, height: 0.5),
                  patches: [(name: "pull", from: ({}, {}), to: ({}, {}))]),
           boundary: [(on: "left", x: Displacement(0), y: Displacement(0)),
                      (on: "pull", x: Displacement(1e-3))],
           pd: (failure: Elastic, dx: 0.05))"#,
        from.0, from.1, to.0, to.1
    );
    let model = solved(&src, "patch.ron");
    let (x, u) = (model.positions(), model.displacements());
    (0..model.n_real())
        .map(|i| [x[i][0], x[i][1], u[i][0], u[i][1]])
        .collect()
}

#[test]
fn a_patch_pulls_from_outside_whichever_way_it_is_written() {
    // The whole right edge as a patch, written upwards (counter-clockwise) and downwards.
    let ccw = pulled_plate((1.0, 0.0), (1.0, 0.5));
    let cw = pulled_plate((1.0, 0.5), (1.0, 0.0));
    let worst = ccw
        .iter()
        .zip(&cw)
        .map(|(a, b)| (a[2] - b[2]).abs().max((a[3] - b[3]).abs()))
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-12,
        "orientation changes the field by {worst:e} m"
    );
    // The pull reaches the body: the last node column (x = 0.975 m, half a spacing in from
    // the edge) moves by nearly the 1 mm the layer outside it is given; measured 0.940 mm
    // (written the wrong way round before the fix: no pull at all).
    let right: Vec<f64> = ccw.iter().filter(|n| n[0] > 0.95).map(|n| n[2]).collect();
    let mean = right.iter().sum::<f64>() / right.len() as f64;
    assert!(mean > 0.9e-3 && mean < 1e-3, "right-edge ux {mean:e}");
}

/// Vertical displacement of the real node nearest `p` in a 1 m square plate with an edge
/// crack from the top middle down to mid-height; the top-left half held, the top-right
/// half pushed down by 1 mm.
fn sheared_mouth(p: [f64; 2]) -> f64 {
    let src = r#"(name: "m", material: (E: 1e4, nu: 0.3333333333333333, plane: Stress),
       body: (outline: Rectangle(x0: 0, y0: 0, width: 1, height: 1),
              patches: [(name: "held", from: (0, 1), to: (0.5, 1)),
                        (name: "moved", from: (0.5, 1), to: (1, 1))]),
       cracks: [(name: "c", start: (0.5, 1), angle_deg: -90, length: 0.5)],
       boundary: [(on: "held", x: Displacement(0), y: Displacement(0)),
                  (on: "moved", y: Displacement(-1e-3)),
                  (on: "bottom", x: Displacement(0), y: Displacement(0))],
       pd: (failure: Elastic, dx: 0.05))"#;
    let model = solved(src, "mouth.ron");
    let x = model.positions();
    let i = (0..model.n_real())
        .min_by(|&a, &b| {
            let d = |k: usize| (x[k][0] - p[0]).hypot(x[k][1] - p[1]);
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    model.displacements()[i][1]
}

#[test]
fn an_edge_crack_separates_the_boundary_layers_at_its_mouth() {
    // The real nodes on either side of the mouth (x = 0.475 and 0.525, y = 0.975): the
    // held side stays put, the moved side goes down with its layer. Measured: -0.0003 mm
    // and -0.905 mm. Before: -0.88 mm on the held side (the two patches' layers shared a
    // square of nodes at the mouth, the moved condition winning); with only that fixed,
    // -0.16 mm (the crack stopped at the outline, the moved layer bonded across it).
    let held = sheared_mouth([0.475, 0.975]);
    let moved = sheared_mouth([0.525, 0.975]);
    eprintln!("mouth: held side {held:e} m, moved side {moved:e} m");
    assert!(
        held.abs() < 0.05e-3,
        "held side of the mouth moved {held:e} m"
    );
    assert!(moved < -0.8e-3, "moved side {moved:e} m");
}

/// An edge's condition stops at the patches on it, in PD as in the BEM mesh: a traction
/// on `top` with a 0.2 m patch `pin` on it loads 0.8 m of the 1 m edge. Before, the PD
/// set-up gave `top`'s condition to the whole edge (1 m: the patch's piece carried both
/// conditions; `pd_bar_tension`'s pin was held in x too, by `left`).
#[test]
fn an_edge_condition_stops_at_its_patches() {
    let src = r#"(name: "p", material: (E: 1e4, nu: 0.3333333333333333, plane: Stress),
           body: (outline: Rectangle(x0: 0, y0: 0, width: 1, height: 0.5),
                  patches: [(name: "pin", from: (0.4, 0.5), to: (0.6, 0.5))]),
           boundary: [(on: "bottom", x: Displacement(0), y: Displacement(0)),
                      (on: "top", y: Traction(2)),
                      (on: "pin", x: Displacement(0))],
           pd: (failure: Elastic, dx: 0.05))"#;
    let scene = Scene::from_ron_str(src, "edge.ron").unwrap_or_else(|e| panic!("{e}"));
    let f = pdbem::setup::pd::applied_resultant(&scene, "top");
    assert!((f[1] - 2.0 * 0.8).abs() < 1e-12, "{f:?}");
}
