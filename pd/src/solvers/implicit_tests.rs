//! Newton on a kept factor ([`super::Newton`]) reaches the equilibria of Newton that
//! factorises at every step, with fewer factorisations, for brittle state-based bonds that
//! break, degrading bonds under prescribed displacements, and a factor that no longer
//! fits the body.

use super::*;
use crate::cases::{seed001_crack, CrackKind};
use crate::problem::PdMaterial;
use crate::solvers::limit::tests::pulled_notched_bar;

/// What a ramp did: the model at its end, broken pairs after every step, factorisations,
/// kept-factor solves.
struct Ramped {
    model: PdModel,
    broken: Vec<usize>,
    info: SolveInfo,
}

/// `loads` one step each by [`Newton::load_step`], the kept factor allowed or not.
fn ramp(mut model: PdModel, loads: &[f64], p: &ImplicitParams, reuse: bool) -> Ramped {
    let mut newton = Newton::new(&model).unwrap();
    newton.reuse_factor = reuse;
    let mut info = SolveInfo::default();
    let mut broken = Vec::new();
    for &lam in loads {
        if let Err(e) = newton.load_step(&mut model, lam, p, &mut info) {
            panic!("reuse {reuse}, load {lam}: {e:?}");
        }
        broken.push(model.broken_bonds());
    }
    Ramped {
        model,
        broken,
        info,
    }
}

/// Both ramps, checked against each other: the same broken bonds after every step, the
/// displacements within `tol` of the largest, fewer factorisations with the kept factor.
fn kept_matches_fresh(model: PdModel, loads: &[f64], p: &ImplicitParams, tol: f64) -> Ramped {
    let fresh = ramp(model.clone(), loads, p, false);
    let kept = ramp(model, loads, p, true);
    assert_eq!(fresh.info.kept_factor_solves, 0);
    assert_eq!(kept.broken, fresh.broken, "bonds broken step by step");
    let gap = fresh.model.relative_displacement_gap(&kept.model);
    assert!(gap < tol, "kept factor vs fresh Newton: {gap:.2e}");
    assert!(kept.info.kept_factor_solves > 0);
    assert!(
        kept.info.factorizations < fresh.info.factorizations,
        "factorisations: kept {} against fresh {}",
        kept.info.factorizations,
        fresh.info.factorizations
    );
    kept
}

#[test]
fn kept_factor_steps_reach_newtons_equilibria_while_state_based_bonds_break() {
    // The seed 001 edge-crack plate (30 x 30 nodes, brittle bonds from G_c) made
    // state-based, ramped under tractions past its first breaks.
    let mut p = seed001_crack(CrackKind::Edge, 30).problem;
    p.material = PdMaterial::StateBased { poisson_ratio: 0.3 };
    let model = PdModel::new(&p).unwrap();
    let loads: Vec<f64> = (1..=14).map(|k| 0.5 * k as f64).collect();
    let kept = kept_matches_fresh(model, &loads, &ImplicitParams::default(), 1e-8);
    assert!(
        *kept.broken.last().unwrap() > 0,
        "the ramp breaks bonds: {:?}",
        kept.broken
    );
}

#[test]
fn kept_factor_steps_reach_newtons_equilibria_of_degrading_bonds_pulled_at_one_end() {
    // The notched tanh bar with its end column pulled, through its softening onset:
    // the linear predictor's factor serves the first step of each load.
    let model = PdModel::new(&pulled_notched_bar()).unwrap();
    let loads: Vec<f64> = (1..=15).map(|k| 0.1 * k as f64).collect();
    let params = ImplicitParams {
        max_iters: 25,
        ..Default::default()
    };
    let kept = kept_matches_fresh(model, &loads, &params, 1e-8);
    let degraded = kept.model.s_hist.iter().filter(|&&s| s > 4e-5).count();
    assert!(degraded > 0, "bonds pass the degradation onset");
}

/// The bar of [`crate::cases::bar_tension`] (elastic bonds) at its full load, at rest,
/// Young's modulus scaled by `scale`.
fn bar(scale: f64) -> PdModel {
    let mut p = crate::cases::bar_tension(0.005).problem;
    p.youngs_modulus *= scale;
    let mut m = PdModel::new(&p).unwrap();
    m.set_load_factor(1.0);
    m
}

/// Newton's equilibrium of the bar at rest, the kept factor allowed or not (`reuse`),
/// starting on a kept factor of the bar's tangent with E scaled by `factor_scale` (`None`:
/// no kept factor at the start). Returns the model, the record and the iterations.
fn from_kept_factor(factor_scale: Option<f64>, reuse: bool) -> (PdModel, SolveInfo, usize) {
    let mut m = bar(1.0);
    let mut newton = Newton::new(&m).unwrap();
    newton.reuse_factor = reuse;
    if let Some(scale) = factor_scale {
        bar(scale).assemble_tangent(&mut newton.tangent, TangentKind::Consistent);
        newton.tangent.factorize().unwrap();
        newton.kept = Some((newton.tangent.factor_generation().unwrap(), bond_state(&m)));
        // As a predictor leaves it: the next solve may start on the factor.
        newton.predicted = Some(m.load_factor());
    }
    let p = ImplicitParams {
        convergence: Convergence::Residual { tol: 1e-13 },
        residual_tol: 1e-13,
        ..Default::default()
    };
    let mut info = SolveInfo::default();
    let (iterations, _) = newton.equilibrate(&mut m, &p, &mut info).unwrap();
    (m, info, iterations)
}

#[test]
fn a_kept_factor_that_does_not_fit_is_undone_or_replaced_and_newtons_equilibrium_found() {
    let (reference, _, _) = from_kept_factor(None, false);
    let (_, plain, plain_its) = from_kept_factor(None, true);
    // The factor of a bar 100 times softer: its step overshoots 100 times, the residual
    // grows, the step is undone (not an iteration) and Newton goes on as without it.
    let (m, info, its) = from_kept_factor(Some(0.01), true);
    assert_eq!(info.kept_factor_solves, plain.kept_factor_solves + 1);
    assert_eq!(its, plain_its, "the undone step is not an iteration");
    assert_eq!(info.factorizations, plain.factorizations);
    let gap = reference.relative_displacement_gap(&m);
    assert!(gap < 1e-10, "{gap:.2e}");
    // The factor of a bar 100 times stiffer: its step covers a hundredth of the way, the
    // residual falls by about 1 %, the step is kept (an iteration) but cannot end the
    // iteration, and the next step refactorises.
    let (m, info, its) = from_kept_factor(Some(100.0), true);
    assert_eq!(its, plain_its + 1);
    assert_eq!(info.factorizations, plain.factorizations);
    let first = info.residual_history[0];
    assert!(first > 0.9 && first < 1.0, "{:?}", info.residual_history);
    let gap = reference.relative_displacement_gap(&m);
    assert!(gap < 1e-10, "{gap:.2e}");
}

#[test]
fn a_load_step_does_not_depend_on_what_the_newton_solved_before() {
    // A growth run resumed from a checkpoint builds a new Newton: its next load step must
    // be the uninterrupted run's bit for bit, kept factors or not. The state-based plate
    // under tractions (no predictor) and the notched bar pulled at one end (predictor).
    let mut plate = seed001_crack(CrackKind::Edge, 30).problem;
    plate.material = PdMaterial::StateBased { poisson_ratio: 0.3 };
    let pulled = pulled_notched_bar();
    let steps = |n: usize, d: f64| (1..=n).map(|k| d * k as f64).collect::<Vec<_>>();
    for (p, loads) in [(plate, steps(14, 0.5)), (pulled, steps(13, 0.1))] {
        let params = ImplicitParams {
            max_iters: 25,
            ..Default::default()
        };
        let (last, before) = loads.split_last().unwrap();
        let mut on = PdModel::new(&p).unwrap();
        let mut newton = Newton::new(&on).unwrap();
        let mut info = SolveInfo::default();
        for &lam in before {
            newton.load_step(&mut on, lam, &params, &mut info).unwrap();
        }
        let mut resumed = on.clone();
        newton
            .load_step(&mut on, *last, &params, &mut info)
            .unwrap();
        let mut again = Newton::new(&resumed).unwrap();
        again
            .load_step(&mut resumed, *last, &params, &mut SolveInfo::default())
            .unwrap();
        assert!(info.kept_factor_solves > 0);
        assert!(
            on.displacements() == resumed.displacements(),
            "not bit for bit: {:.2e}",
            on.relative_displacement_gap(&resumed)
        );
        assert!(on.bond_intact() == resumed.bond_intact());
    }
}
