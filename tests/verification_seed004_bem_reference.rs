//! Seed 004 Table 2 against the elastic solution of the same plate. Irwin's formula (seed
//! 004 Eq. 32) is Tada's long strip: the 2L-high plate of `pdbem_pd::edge_crack` opens
//! 1.76 % more at the mouth at a/L = 0.3 (BEM, `cases/seed004_table2_bem.ron`), so Table 2's
//! errors mix the discretisation with the formula's finite-height error. Here the PD
//! openings (state-based, surface-corrected, transfer-function tractions) are compared
//! with the BEM's displacements at the very points the PD reads them (the nodes nearest
//! the mouth, half a spacing from the edge and the crack line), so what is left is the PD
//! model's own error, and it must fall as the spacing does (first order: the nonlocal
//! error of PD is O(delta)).

mod common_scene;

use common_scene::case;
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::V2;
use pdbem_pd::edge_crack::{mouth_opening, problem, HEIGHT};
use pdbem_pd::solvers::implicit::{solve, ImplicitParams};
use pdbem_pd::{PdModel, TractionLoad};

const A_OVER_L: f64 = 0.3;

/// The BEM opening between the points `(dx/2, L ± dx/2)` of the case's plate (2640
/// elements: CMOD error estimate 0.13 %, the interior openings within 0.1 % of a solve
/// to the tolerance 1e-3), a tenth of the PD errors measured here.
fn bem_openings(dxs: &[f64]) -> Vec<f64> {
    let scene = case("seed004_table2_bem", &[]);
    let (summary, level) = pdbem::run_bem::solve(&scene).unwrap();
    let crack = &summary.cracks[0];
    let cmod = crack.cmod.expect("edge crack CMOD");
    let estimate = crack.cmod_err_est.expect("CMOD error estimate");
    assert!(estimate < 2e-3 * cmod, "{crack:?}");
    let ev = FieldEvaluator::new(
        &level.setup.mesh,
        &level.setup.material,
        &level.solution,
        level.setup.background,
    );
    let mid = HEIGHT / 2.0;
    dxs.iter()
        .map(|&dx| {
            let up = ev.displacement(V2::new(dx / 2.0, mid + dx / 2.0));
            let down = ev.displacement(V2::new(dx / 2.0, mid - dx / 2.0));
            up[1] - down[1]
        })
        .collect()
}

fn pd_opening(dx: f64) -> f64 {
    let mut m = PdModel::new(&problem(
        dx,
        A_OVER_L,
        HEIGHT,
        TractionLoad::TransferFunction,
    ))
    .expect("model");
    solve(&mut m, &ImplicitParams::default()).expect("solve");
    mouth_opening(&m.positions()[..m.n_real()], m.displacements(), HEIGHT).expect("mouth")
}

/// Measured: BEM 6.9146 um (dx = 1 mm points) and 6.9839 um (0.5 mm); PD 7.0109 um
/// (+1.39 %) and 7.0274 um (+0.62 %): the error ratio 0.45, first order (against the
/// tolerance-1e-3 BEM of docs/seed004.md: +1.47 %, +0.70 %, 0.48). Bounds: both
/// errors positive (PD's softer skin at the crack faces and the free edge) and below
/// 2 % and 1 %, and the ratio within [0.35, 0.65] of a first-order method's 0.5.
#[test]
fn pd_opening_converges_to_the_elastic_solution_at_first_order() {
    let dxs = [1e-3, 5e-4];
    let bem = bem_openings(&dxs);
    let errors: Vec<f64> = dxs
        .iter()
        .zip(&bem)
        .map(|(&dx, &b)| {
            let pd = pd_opening(dx);
            let e = pd / b - 1.0;
            println!(
                "dx = {dx}: BEM {:.4} um, PD {:.4} um, {:+.2} %",
                b * 1e6,
                pd * 1e6,
                100.0 * e
            );
            e
        })
        .collect();
    assert!(errors[0] > 0.0 && errors[0] < 0.02, "{errors:?}");
    assert!(errors[1] > 0.0 && errors[1] < 0.01, "{errors:?}");
    let ratio = errors[1] / errors[0];
    println!("error ratio {ratio:.3}");
    assert!((0.35..=0.65).contains(&ratio), "{ratio}");
}

/// Dual-horizon particles (`pdbem_pd::refine`) refined within 4 mm of the crack read the
/// opening at the children's points (dx/2 = 0.25 mm): measured +1.02 % against the BEM
/// there, between the coarse grid's +1.39 % and the fine grid's +0.62 %. Asserted:
/// between half the coarse grid's error and the coarse grid's error.
#[test]
fn region_refinement_lies_between_the_coarse_and_fine_grids() {
    use pdbem_pd::edge_crack::{crack, SIDE};
    use pdbem_pd::refine::{run, Refinement};
    use pdbem_pd::Selection;
    let bem = bem_openings(&[1e-3, 5e-4]);
    let coarse = pd_opening(1e-3) / bem[0] - 1.0;
    let p = problem(1e-3, A_OVER_L, HEIGHT, TractionLoad::TransferFunction);
    let settings = Refinement {
        critical_damage: None,
        regions: vec![Selection::NearPolyline {
            points: crack(A_OVER_L * SIDE, HEIGHT),
            distance: Some(4e-3),
        }],
        ..Default::default()
    };
    let out = run(&p, &settings, 1.0).expect("refined solve");
    let b = &out.body;
    let cod = mouth_opening(b.positions(), &b.u, HEIGHT).expect("mouth particles");
    let refined = cod / bem[1] - 1.0;
    println!(
        "coarse {:+.2} %, refined {:+.2} % ({} particles)",
        100.0 * coarse,
        100.0 * refined,
        b.len()
    );
    assert!(
        refined > 0.5 * coarse && refined < coarse,
        "{refined} {coarse}"
    );
}
