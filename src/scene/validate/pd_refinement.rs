//! Validation of `pd.refinement` (seed 004's criteria on particles, `pdbem_pd::refine`, or
//! on the grid's cells, `pdbem_pd::adapt`).

use super::limits::refinement_tolerance;
use super::Checker;
use crate::geometry::{bounding_box, P2};
use crate::scene::shapes::outline_loop;
use crate::scene::{Failure, PdSolver, RefineCircle, Scene};

/// `pd.refinement`: stand-alone; on the grid's cells the rules of
/// [`check_cell_refinement`], on particles the state-based model; the law the solver can
/// run ([`check_refinement_law`]) and its numbers in range.
pub(super) fn check(
    c: &mut Checker,
    scene: &Scene,
    pd: &crate::scene::PdSettings,
    r: &crate::scene::PdRefinement,
) {
    if scene.coupling.is_some() || scene.growth.is_some() {
        c.fail_at(
            "pd.refinement",
            "refinement runs in stand-alone PD only (not in PD-BEM windows or growth): drop `coupling`/`growth` or the field",
        );
    }
    if r.split_before_breaking == Some(true)
        && !(r.on_cells(&pd.failure, &pd.solver) && scene.runs_pd_initiation_ramp())
    {
        c.fail_at(
            "pd.refinement.split_before_breaking",
            "read by the crack-initiation ramp on the grid's cells only (`on: Cells` with a breaking `pd.failure`, pre-cracks and a load ramp): drop the field",
        );
    }
    if r.on_cells(&pd.failure, &pd.solver) {
        check_cell_refinement(c, pd, r);
    } else if pd.model != crate::scene::PdModelKind::StateBased {
        c.fail_at(
            "pd.refinement",
            "refinement on seed 004's particles needs `model: StateBased` (dual-horizon state-based particles); the grid's cells (`on: Cells`, the default for the tanh law) take either model",
        );
    }
    check_refinement_law(c, scene, pd, r);
    if let Some(phi) = r.critical_damage {
        if c.finite("pd.refinement.critical_damage", phi) && !(phi > 0.0 && phi < 1.0) {
            c.fail(
                "pd.refinement.critical_damage",
                phi,
                "phi_c must lie in (0, 1)",
            );
        }
    }
    if let Some(d) = r.near_cracks {
        c.positive(
            "pd.refinement.near_cracks",
            d,
            "distance from the pre-cracks",
        );
    }
    let bbox = outline_loop(&scene.body.outline).map(|o| bounding_box(&o.points));
    for (i, circle) in r.circles.iter().enumerate() {
        let placed = c.finite(
            &format!("pd.refinement.circles.{i}.centre"),
            circle.centre.0,
        ) & c.finite(
            &format!("pd.refinement.circles.{i}.centre"),
            circle.centre.1,
        ) & c.positive(
            &format!("pd.refinement.circles.{i}.radius"),
            circle.radius,
            "radius",
        );
        if let (true, Some((lo, hi))) = (placed, bbox) {
            check_circle_meets_body(c, i, circle, (lo, hi));
        }
        if let Some(l) = circle.level {
            if !(1..=r.max_level).contains(&l) {
                c.fail(
                    format!("pd.refinement.circles.{i}.level"),
                    l,
                    format!("must be 1 to max_level = {}", r.max_level),
                );
            }
        }
    }
    if !(1..=4).contains(&r.max_level) {
        c.fail("pd.refinement.max_level", r.max_level, "must be 1 to 4");
    }
    refinement_tolerance(c, "pd.refinement.tolerance", r.tolerance);
}

/// A circle must reach into the body's bounding box: one that misses it refines nothing,
/// which is a mistyped centre (millimetres for metres, say), not a choice.
fn check_circle_meets_body(c: &mut Checker, i: usize, circle: &RefineCircle, (lo, hi): (P2, P2)) {
    let (x, y) = circle.centre;
    // The body's own checks name a non-finite outline.
    if ![lo.x, lo.y, hi.x, hi.y].iter().all(|v| v.is_finite()) {
        return;
    }
    // The box's point nearest the centre (max / min: no panic on an inverted box).
    let near = (x.max(lo.x).min(hi.x), y.max(lo.y).min(hi.y));
    if (near.0 - x).hypot(near.1 - y) > circle.radius {
        c.fail(
            format!("pd.refinement.circles.{i}.centre"),
            format!("{:?}", circle.centre),
            format!(
                "the circle of radius {} m lies outside the body (x {} to {} m, y {} to {} m): it refines nothing (coordinates are in metres)",
                circle.radius, lo.x, hi.x, lo.y, hi.y
            ),
        );
    }
}

/// The solver and failure law a refined body can run: the elastic solve (`failure:
/// Elastic`, no strain criterion), the quasi-static crack-initiation ramp (a critical
/// stretch, pre-cracks and a load ramp, as stand-alone PD's ramp: [`crate::run_refined`])
/// or adaptive explicit dynamics (`solver: Explicit`, bonds breaking at a critical
/// stretch, children with halved horizons, `check_every` at least 1). The strain
/// criterion (`strain_factor` alpha in (0, 1)) needs a breaking law.
fn check_refinement_law(
    c: &mut Checker,
    scene: &Scene,
    pd: &crate::scene::PdSettings,
    r: &crate::scene::PdRefinement,
) {
    let explicit = matches!(pd.solver, PdSolver::Explicit(_));
    if !explicit {
        match pd.failure {
            Failure::Elastic => {}
            // The grid's cells split under the scene's solver (check_cell_refinement).
            Failure::Degradation { .. } if r.on_cells(&pd.failure, &pd.solver) => {}
            Failure::Degradation { .. } => c.fail_at(
                "pd.refinement.on",
                "seed 004's particles have no tanh degradation: the tanh law refines the grid's cells (`on: Cells` or the default `Auto`)",
            ),
            // The cells run the scene's solver: a ramp to the last load without cracks.
            Failure::CriticalStretch(_) | Failure::FromGc if r.on_cells(&pd.failure, &pd.solver) => {}
            Failure::CriticalStretch(_) | Failure::FromGc => {
                if scene.cracks.is_empty() || scene.load.factors().len() < 2 {
                    c.fail_at(
                        "pd.refinement",
                        "a refined body with a breaking law runs the crack-initiation ramp: it needs pre-cracks (`cracks`) and a load ramp (`load: (initial, step, end)` with more than one step); use `failure: Elastic` for one elastic solve",
                    );
                }
            }
        }
        check_strain_factor(c, pd, r);
        return;
    }
    if matches!(pd.failure, Failure::Degradation { .. }) {
        c.fail_at(
            "pd.failure",
            "adaptive dynamics breaks bonds at a critical stretch (the refined body has no tanh degradation): use CriticalStretch or FromGc",
        );
    }
    if r.keep_horizon {
        c.fail_at(
            "pd.refinement.keep_horizon",
            "adaptive dynamics needs children with halved horizons (the stable time step is bounded through the spacing at a fixed horizon factor): drop the field",
        );
    }
    c.at_least(
        "pd.refinement.check_every",
        r.check_every,
        1,
        "time steps between refinement checks",
    );
    check_strain_factor(c, pd, r);
}

/// `pd.refinement` on the grid's cells (`on: Cells`, or the tanh law under a quasi-static
/// solver, `pdbem_pd::adapt`): a quasi-static solver (the mixed grid has no explicit
/// dynamics), grid tractions as a body-force layer (no transfer functions on mixed
/// grids), a cell splits once or twice (`max_level` 1 or 2, the mixed grid's levels),
/// children halve their horizon with their spacing.
fn check_cell_refinement(
    c: &mut Checker,
    pd: &crate::scene::PdSettings,
    r: &crate::scene::PdRefinement,
) {
    if matches!(pd.solver, PdSolver::Explicit(_)) {
        c.fail_at(
            "pd.refinement.on",
            "refined cells are solved by a quasi-static solver (Adr, Implicit, Switching); explicit dynamics refines seed 004's particles: `on: Particles` or `Auto`",
        );
    }
    if pd.traction == crate::scene::PdTraction::TransferFunction {
        c.fail_at(
            "pd.traction",
            "refined cells (a mixed grid) take tractions as a body-force layer: drop `traction: TransferFunction` or refine seed 004's particles (`pd.refinement.on: Particles`)",
        );
    }
    if r.max_level > 2 {
        c.fail(
            "pd.refinement.max_level",
            r.max_level,
            "refined cells (the tanh law under a quasi-static solver) split at most twice: 1 or 2",
        );
    }
    if r.keep_horizon {
        c.fail_at(
            "pd.refinement.keep_horizon",
            "refined cells take horizons of their own spacing (the dual-horizon grid of pdbem_pd::mixed): drop the field",
        );
    }
}

/// Eq. 16's `strain_factor`: alpha in (0, 1), with a breaking failure law.
fn check_strain_factor(
    c: &mut Checker,
    pd: &crate::scene::PdSettings,
    r: &crate::scene::PdRefinement,
) {
    if let Some(a) = r.strain_factor {
        if c.finite("pd.refinement.strain_factor", a) && !(a > 0.0 && a < 1.0) {
            c.fail(
                "pd.refinement.strain_factor",
                a,
                "alpha of seed 004 Eq. 16 must lie in (0, 1) (the seed's 0.5)",
            );
        }
        if pd.failure == Failure::Elastic {
            c.fail_at(
                "pd.refinement.strain_factor",
                "Eq. 16 compares the strain with the critical stretch: it needs a breaking `pd.failure` (CriticalStretch, FromGc or Degradation)",
            );
        }
    }
}
