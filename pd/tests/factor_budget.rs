//! Sparse tangents within the memory budget (`pdbem_pd::tangent::set_factor_budget`; its
//! own test binary: the budget is process-wide). Over the budget the tangent's pattern,
//! and then its factor, are refused before they are allocated (`PdError::TooLarge`), and
//! the frozen-history solver of the breaking passes and the PD windows reaches the same
//! equilibrium by ADR.

use pdbem_pd::solvers::frozen::{FrozenSolver, Solved};
use pdbem_pd::solvers::implicit::{ImplicitParams, Newton};
use pdbem_pd::solvers::SolveInfo;
use pdbem_pd::{BoundaryCondition, Layer, PdError, PdModel, PdProblem, Region, Selection};

type Field = Vec<[f64; 2]>;

/// A 40 x 40 plate held on its left side's fictitious layer and pulled on its right
/// column: square, so its factor fills in (a thin bar's stays below its pattern).
fn plate() -> PdModel {
    let n = 40.0;
    PdModel::new(&PdProblem {
        region: Region::rectangle([0.0, 0.0], [n, n]),
        dx: 1.0,
        youngs_modulus: 1.0,
        boundary: vec![
            BoundaryCondition::Displacement {
                on: Selection::Box {
                    min: [-n, -n],
                    max: [0.0, 2.0 * n],
                },
                ux: Some(0.0),
                uy: Some(0.0),
                layer: Layer::Fictitious,
            },
            BoundaryCondition::Force {
                on: Selection::Box {
                    min: [n - 1.0, -1.0],
                    max: [n, n + 1.0],
                },
                force: [1e-3, 2e-4],
            },
        ],
        ..Default::default()
    })
    .unwrap()
}

/// The bar solved by the frozen-history solver under `budget` bytes: whether it had
/// Newton, which solver succeeded, the field.
fn frozen_under(budget: u64) -> (bool, Solved, Field) {
    pdbem_pd::tangent::set_factor_budget(budget);
    let mut m = plate();
    m.set_load_factor(1.0);
    let start = m.displacements().to_vec();
    let mut s = FrozenSolver::new(&m).unwrap();
    let how = s
        .equilibrate(
            &mut m,
            &ImplicitParams::default(),
            &start,
            &mut SolveInfo::default(),
        )
        .unwrap();
    (s.has_newton(), how, m.displacements().to_vec())
}

/// What `Newton::new` and its solve say under `budget` bytes (`Ok` when both
/// run).
fn refusal_under(budget: u64) -> Result<(), PdError> {
    pdbem_pd::tangent::set_factor_budget(budget);
    let mut m = plate();
    let mut newton = Newton::new(&m)?;
    m.set_load_factor(1.0);
    newton.equilibrate(
        &mut m,
        &ImplicitParams::default(),
        &mut SolveInfo::default(),
    )?;
    eprintln!(
        "pattern {} entries, factor {:?}",
        newton.tangent.nnz(),
        newton.tangent.factor_nnz()
    );
    Ok(())
}

fn gap(a: &Field, b: &Field) -> f64 {
    let top = b.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
    a.iter()
        .zip(b)
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0, f64::max)
        / top
}

#[test]
fn over_the_budget_newton_gives_way_to_adr_with_the_same_equilibrium() {
    let (with_newton, big, u_big) = frozen_under(8 << 30);
    assert!(with_newton && matches!(big, Solved::Newton(_)), "{big:?}");

    // 1 KiB: the pattern itself is refused, with its size; the solver is ADR alone.
    let e = refusal_under(1 << 10).unwrap_err();
    let PdError::TooLarge { bytes: pattern, .. } = e else {
        panic!("{e}")
    };
    assert!(e.to_string().contains("tangent pattern"), "{e}");
    assert!(
        e.to_string().contains("over the budget of 1.000 KiB"),
        "{e}"
    );
    let (with_newton, small, u_small) = frozen_under(1 << 10);
    assert!(!with_newton && matches!(small, Solved::Adr(_)), "{small:?}");
    assert!(gap(&u_small, &u_big) < 1e-5, "{}", gap(&u_small, &u_big));

    // Exactly the pattern's bytes: the pattern is built, its factor refused when Newton
    // is set up (before any solve).
    let e = refusal_under(pattern as u64).unwrap_err();
    assert!(
        matches!(e, PdError::TooLarge { .. }) && e.to_string().contains("Cholesky factor"),
        "{e}"
    );
    let (with_newton, mid, u_mid) = frozen_under(pattern as u64);
    assert!(!with_newton && matches!(mid, Solved::Adr(_)), "{mid:?}");
    assert!(gap(&u_mid, &u_big) < 1e-5, "{}", gap(&u_mid, &u_big));
    eprintln!("pattern bound {pattern} bytes: {small:?} / {mid:?} / {big:?}");
}
