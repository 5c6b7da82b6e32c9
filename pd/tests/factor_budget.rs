//! Sparse factors within the memory budget (`pdbem_pd::tangent::set_factor_budget`; its
//! own test binary: the budget is process-wide). Over the budget a factorisation is
//! refused before it allocates (`PdError::TooLarge`), and the frozen-history solver of
//! the breaking passes and the PD windows reaches the same equilibrium by ADR.

use pdbem_pd::cases::bar_tension;
use pdbem_pd::solvers::frozen::{FrozenSolver, Solved};
use pdbem_pd::solvers::implicit::ImplicitParams;
use pdbem_pd::solvers::SolveInfo;
use pdbem_pd::{PdError, PdModel};

#[test]
fn over_the_budget_newton_gives_way_to_adr_with_the_same_equilibrium() {
    let case = bar_tension(0.02 / 4.0);
    let solve = |budget: u64| {
        pdbem_pd::tangent::set_factor_budget(budget);
        let mut m = PdModel::new(&case.problem).unwrap();
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
        (how, m.displacements().to_vec())
    };
    let (small, u_small) = solve(1 << 10);
    let (big, u_big) = solve(8 << 30);
    eprintln!("1 KiB: {small:?}; 8 GiB: {big:?}");
    assert!(matches!(small, Solved::Adr(_)), "{small:?}");
    assert!(matches!(big, Solved::Newton(_)), "{big:?}");
    let top = u_big.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
    let gap = u_small
        .iter()
        .zip(&u_big)
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .fold(0.0, f64::max);
    assert!(gap < 1e-5 * top, "{gap} of {top}");
    // Newton itself refuses with the sizes, before allocating.
    pdbem_pd::tangent::set_factor_budget(1 << 10);
    let mut m = PdModel::new(&case.problem).unwrap();
    let e = pdbem_pd::solvers::implicit::solve(&mut m, &ImplicitParams::default()).unwrap_err();
    assert!(matches!(e, PdError::TooLarge { .. }), "{e}");
    assert!(
        e.to_string().contains("over the budget of 1.000 KiB"),
        "{e}"
    );
}
