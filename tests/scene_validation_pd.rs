//! Scene validation of the `pd`, `coupling` and `growth` sections: one test per rule;
//! every message names the file, the dotted field path and the reason (the other
//! sections: `scene_validation.rs`).

mod scene_validation_common;

use scene_validation_common::*;

#[test]
fn pd_horizon_smaller_than_dx() {
    // Below 2 the PD calibration no longer holds (scene_validation_limits: the range).
    assert_invalid(
        &base_with("pd: (dx: 0.1, horizon_factor: 0.8)"),
        "pd.horizon_factor = 0.8",
        "must lie in [2, 6]",
    );
}

#[test]
fn pd_dx_must_be_positive() {
    assert_invalid(
        &base_with("pd: (dx: 0)"),
        "pd.dx = 0",
        "grid spacing dx must be > 0",
    );
    assert_invalid(&base_with("pd: ()"), "pd", "give the grid spacing");
}

#[test]
fn pd_grid_must_fit_a_horizon_across_the_body() {
    // The 10 x 20 body: nx = 2 gives dx = 5 and a horizon of 15.1 > 10.
    assert_invalid(
        &base_with("pd: (nx: 2)"),
        "pd.nx = 2",
        "must fit across the body's 1.0000e1 m",
    );
    assert_invalid(
        &base_with("pd: (dx: 4)"),
        "pd.dx = 4",
        "in a thinner body every family is cut by both faces",
    );
    // dx = 3.3 gives a horizon of 9.95: it fits.
    load(&base_with("pd: (dx: 3.3)")).expect("valid");
}

#[test]
fn pd_degradation_needs_s_m_below_s_c() {
    let extra = "pd: (dx: 0.1, failure: Degradation(s_m: 0.02, s_c: 0.015, beta: 3))";
    assert_invalid(
        &base_with(extra),
        "pd.failure.s_m = 0.02",
        "s_m must be below s_c",
    );
}

#[test]
fn pd_from_gc_needs_gc() {
    assert_invalid(
        &base_with("pd: (dx: 0.1, failure: FromGc)"),
        "pd.failure",
        "needs material.fracture.g_c",
    );
}

#[test]
fn pd_solver_params_are_checked() {
    // A relative tolerance lies in [1e-14, 1): below, the measure is round-off (an ADR
    // run at 1e-300 ran 100 000 iterations to fail at 2.2e-16); from 1 on, the first
    // iterate passes. The value shows in exponent form, not as 300 zeros.
    for (solver, value) in [
        ("Adr(tolerance: -1)", "-1"),
        ("Adr(tolerance: 1e-300)", "1e-300"),
        ("Implicit(tolerance: 1e-15)", "1e-15"),
        ("Switching(tolerance: 1)", "1"),
    ] {
        assert_invalid(
            &base_with(&format!("pd: (dx: 0.1, solver: {solver})")),
            &format!("pd.solver.tolerance = {value}:"),
            "a relative tolerance must lie in [1e-14, 1)",
        );
    }
    load(&base_with("pd: (dx: 0.1, solver: Implicit(max_iter: 20))")).expect("valid");
    load(&base_with("pd: (dx: 0.1, solver: Adr(tolerance: 1e-14))")).expect("valid");
    // A cap of 1 always failed at run time ("did not converge in 1 iterations: measure
    // inf"): convergence is measured from the second iteration. Implicit converges on an
    // elastic plate with 2; the switching solver's caps may be 1.
    for (field, solver) in [
        (
            "pd.solver.max_iter = 1",
            "pd: (dx: 0.1, solver: Adr(max_iter: 1))",
        ),
        (
            "pd.solver.max_iter = 1",
            "pd: (dx: 0.1, solver: Implicit(max_iter: 1))",
        ),
        (
            "coupling.max_iter = 1",
            "pd: (), coupling: (side: 2, n: 20, max_iter: 1)",
        ),
    ] {
        assert_invalid(
            &base_with(solver),
            field,
            "iteration cap (convergence is measured from the second iteration) must be at least 2",
        );
    }
    load(&base_with("pd: (dx: 0.1, solver: Implicit(max_iter: 2))")).expect("valid");
    load(&base_with(
        "pd: (dx: 0.1, solver: Switching(max_newton: 1, max_adr: 1))",
    ))
    .expect("valid");
}

#[test]
fn coupling_window_larger_than_the_body() {
    let extra = "pd: (), coupling: (side: 12, n: 20)";
    assert_invalid(
        &base_with(extra),
        "coupling.side = 12",
        "larger than the body",
    );
}

#[test]
fn coupling_window_outside_the_body() {
    let extra = "pd: (), coupling: (side: 2, n: 20, placement: Centered(center: (9.5, 5)))";
    assert_invalid(&base_with(extra), "coupling.placement", "outside the body");
}

#[test]
fn coupling_region_width_must_be_the_side() {
    // dx = side / n for every placement: a Region narrower than `side` would silently
    // take another spacing.
    let extra =
        "pd: (), coupling: (side: 2, n: 20, placement: Region(x0: 1, y0: 1, width: 3, height: 2))";
    assert_invalid(&base_with(extra), "coupling.side = 2", "region width 3");
}

#[test]
fn iqn_ils_reuse_is_not_a_field() {
    // Parsed and then dropped until now: secant pairs are not carried between load steps.
    let extra = "pd: (), coupling: (side: 2, n: 20, relaxation: IqnIls(w0: 0.1, reuse: 2))";
    let text = base_with(extra);
    let err = pdbem::scene::Scene::from_ron_str(&text, "t.ron")
        .unwrap_err()
        .to_string();
    assert!(err.contains("reuse"), "{err}");
}

#[test]
fn adr_dt_is_not_a_field() {
    // ADR's fictitious density comes from the Gershgorin bound at dt = 1 (seed 002
    // Eqs. 9-15): a time step would only rescale it, so the field was parsed and dropped.
    let text = base_with("pd: (solver: Adr(dt: 0.5))");
    let err = pdbem::scene::Scene::from_ron_str(&text, "t.ron")
        .unwrap_err()
        .to_string();
    assert!(err.contains("dt"), "{err}");
}

#[test]
fn coupling_relaxation_range() {
    let extra = "pd: (), coupling: (side: 2, n: 20, relaxation: Constant(1.5))";
    assert_invalid(&base_with(extra), "coupling.relaxation = 1.5", "(0, 1]");
}

#[test]
fn growth_move_distance_larger_than_the_window() {
    let extra = "pd: (), coupling: (side: 2, n: 20), growth: (move_distance: 3)";
    assert_invalid(
        &base_with(extra),
        "growth.move_distance = 3",
        "larger than the window",
    );
}

#[test]
fn growth_trigger_ratio_range() {
    let extra = "pd: (), coupling: (side: 2, n: 20), growth: (trigger_ratio: 1.2)";
    assert_invalid(
        &base_with(extra),
        "growth.trigger_ratio = 1.2",
        "must lie in (0, 1)",
    );
    let extra = "pd: (), coupling: (side: 2, n: 20), growth: (trigger_ratio: 0)";
    assert_invalid(
        &base_with(extra),
        "growth.trigger_ratio = 0",
        "must lie in (0, 1)",
    );
}

#[test]
fn growth_pd_bem_needs_coupling() {
    assert_invalid(
        &base_with("growth: ()"),
        "growth.mode",
        "needs a `coupling` section",
    );
}

#[test]
fn state_based_pd_refuses_a_negative_poisson_ratio() {
    // Below 0 the discrete state-based energy is not positive definite; the BEM and PMB
    // take any nu in (-1, 0.5).
    let scene = |nu: &str, model: &str| {
        make(
            &format!("(E: 1e4, nu: {nu}, plane: Stress)"),
            BODY,
            CRACKS,
            BOUNDARY,
            &format!("pd: (dx: 0.5, model: {model})"),
        )
    };
    assert_invalid(
        &scene("-0.1", "StateBased"),
        "material.nu = -0.1",
        "takes a Poisson ratio from 0 on",
    );
    load(&scene("0", "StateBased")).expect("nu = 0");
    load(&scene("-0.1", "Pmb")).expect("PMB notes nu, does not refuse it");
}

#[test]
fn pd_refinement_rules() {
    let ok = "pd: (dx: 0.5, model: StateBased, refinement: (near_cracks: 1, circles: [(centre: (3, 10), radius: 1)]))";
    load(&base_with(ok)).expect("valid refinement");
    assert_invalid(
        &base_with("pd: (dx: 0.5, refinement: ())"),
        "pd.refinement",
        "model: StateBased",
    );
    assert_invalid(
        &base_with(
            "pd: (dx: 0.5, model: StateBased, failure: CriticalStretch(0.01), refinement: ())",
        ),
        "pd.refinement",
        "failure: Elastic",
    );
    // With pre-cracks and a load ramp a breaking law runs the refined initiation ramp.
    let ramp = "load: (initial: 1, step: 0.1, count: 10), pd: (dx: 0.5, model: StateBased, failure: CriticalStretch(0.01), refinement: (strain_factor: 0.5))";
    load(&base_with(ramp)).expect("valid refined ramp");
    // The tanh law splits the grid's cells under the quasi-static solvers, either model;
    // explicit dynamics still refuses it.
    for model in ["StateBased", "Pmb"] {
        load(&base_with(&format!("load: (initial: 1, step: 0.1, count: 10), pd: (dx: 0.5, model: {model}, failure: Degradation(s_m: 0.01, s_c: 0.02, beta: 3), refinement: ())")))
            .expect("valid refined cells");
    }
    assert_invalid(
        &base_with("load: (initial: 1, step: 0.1, count: 10), pd: (dx: 0.5, model: StateBased, failure: Degradation(s_m: 0.01, s_c: 0.02, beta: 3), refinement: (max_level: 3))"),
        "pd.refinement.max_level",
        "at most twice",
    );
    assert_invalid(
        &base_with("pd: (dx: 0.5, model: StateBased, refinement: (strain_factor: 0.5))"),
        "pd.refinement.strain_factor",
        "breaking",
    );
    assert_invalid(
        &base_with("pd: (dx: 0.5, model: StateBased, refinement: (critical_damage: 1.2))"),
        "pd.refinement.critical_damage",
        "(0, 1)",
    );
    assert_invalid(
        &base_with("pd: (dx: 0.5, model: StateBased, refinement: (max_level: 0))"),
        "pd.refinement.max_level",
        "1 to 4",
    );
    assert_invalid(
        &base_with("pd: (dx: 0.5, model: StateBased, refinement: (circles: [(centre: (3, 10), radius: 0)]))"),
        "pd.refinement.circles.0.radius",
        "radius must be > 0",
    );
    // The refined conjugate gradients stall at 4e-14 of the load on 1 mm particles: their
    // floor is 1e-12, above the solvers' 1e-14.
    assert_invalid(
        &base_with("pd: (dx: 0.5, model: StateBased, refinement: (tolerance: 1e-13))"),
        "pd.refinement.tolerance = 0.0000000000001",
        "a relative tolerance must lie in [1e-12, 1)",
    );
    load(&base_with(
        "pd: (dx: 0.5, model: StateBased, refinement: (tolerance: 1e-12))",
    ))
    .expect("the floor");
    assert_invalid(
        &base_with("pd: (dx: 0.5, model: StateBased, refinement: (max_level: 2, circles: [(centre: (3, 10), radius: 2, level: 1), (centre: (3, 10), radius: 1, level: 3)]))"),
        "pd.refinement.circles.1.level",
        "max_level = 2",
    );
    load(&base_with("pd: (dx: 0.5, model: StateBased, refinement: (max_level: 2, circles: [(centre: (3, 10), radius: 2, level: 1), (centre: (3, 10), radius: 1)]))"))
        .expect("nested circles");
    // A circle beside the 10 x 20 body (its centre in millimetres, say) refines nothing;
    // one that reaches into it from outside does.
    assert_invalid(
        &base_with("pd: (dx: 0.5, model: StateBased, refinement: (circles: [(centre: (3000, 10000), radius: 1)]))"),
        "pd.refinement.circles.0.centre = (3000.0, 10000.0)",
        "lies outside the body (x 0 to 10 m, y 0 to 20 m): it refines nothing",
    );
    load(&base_with("pd: (dx: 0.5, model: StateBased, refinement: (circles: [(centre: (-0.5, 10), radius: 1)]))"))
        .expect("a circle reaching into the body");
    let displaced = r#"[(on: "top", y: Displacement(0.1)), (on: "bottom", y: Traction(-1))]"#;
    // The quasi-static solves and adaptive dynamics hold the fictitious layer of a
    // displacement condition.
    load(&make(
        MAT,
        BODY,
        CRACKS,
        displaced,
        "pd: (dx: 0.5, model: StateBased, refinement: ())",
    ))
    .expect("displacement-loaded refinement");
    let dynamic = "pd: (dx: 0.5, model: StateBased, failure: FromGc, refinement: (), solver: Explicit(end_time: 1e-3)), material: (E: 1e4, nu: 0.3, plane: Stress, density: 1000, fracture: (g_c: 1))";
    let src = make(MAT, BODY, CRACKS, displaced, dynamic);
    load(&src.replace(&format!("material: {MAT}, "), "")).expect("valid");
}

#[test]
fn pd_refine_zones_rules() {
    let z = "refine_zones: [(centre: (3, 10), half_size: 1.5)]";
    load(&base_with(&format!("pd: (dx: 0.5, {z})"))).expect("a zone at the tip");
    load(&base_with(&format!(
        "pd: (dx: 0.5, model: StateBased, failure: Degradation(s_m: 0.01, s_c: 0.02, beta: 3), {z})"
    )))
    .expect("the tanh law on a zone");
    assert_invalid(
        &base_with(&format!("pd: (dx: 0.5, {z}), coupling: (side: 4, n: 20)")),
        "pd.refine_zones",
        "coupling.refine",
    );
    assert_invalid(
        &base_with(&format!(
            "pd: (dx: 0.5, model: StateBased, refinement: (), {z})"
        )),
        "pd.refine_zones",
        "not both",
    );
    assert_invalid(
        &base_with(&format!("pd: (dx: 0.5, traction: TransferFunction, {z})")),
        "pd.traction",
        "uniform grid",
    );
    let dynamic = format!("pd: (dx: 0.5, solver: Explicit(end_time: 1e-3), {z}), material: (E: 1e4, nu: 0.3, plane: Stress, density: 1000)");
    let src = base_with(&dynamic).replace(&format!("material: {MAT}, "), "");
    assert_invalid(&src, "pd.refine_zones", "explicit dynamics");
    assert_invalid(
        &base_with("pd: (dx: 0.5, refine_zones: [(centre: (3, 10), half_size: 0)])"),
        "pd.refine_zones.0.half_size",
        "must be > 0",
    );
    assert_invalid(
        &base_with("pd: (dx: 0.5, refine_zones: [(centre: (3, 10), half_size: 1, levels: 3)])"),
        "pd.refine_zones.0.levels",
        "1 (4 children",
    );
    let many = vec!["(centre: (3, 10), half_size: 1)"; 101].join(", ");
    assert_invalid(
        &base_with(&format!("pd: (dx: 0.5, refine_zones: [{many}])")),
        "pd.refine_zones",
        "at most 100",
    );
}

/// The crack-initiation ramp (a breaking law, pre-cracks, a load ramp) solves by Newton
/// on the grid, uniform or refined cells: ADR, the switch or Newton's own settings get a
/// note that `pd.solver` is not read; the default solver and `Implicit()` do not. Seed
/// 004's particles and a single load step (no ramp) are not that ramp.
#[test]
fn pd_initiation_ramp_notes_a_solver_it_does_not_read() {
    let ramp = "load: (initial: 1, step: 0.1, count: 10), ";
    let notes = |pd: &str, load_part: &str| {
        load(&base_with(&format!("{load_part}pd: ({pd})")))
            .expect("valid")
            .notes
            .into_iter()
            .filter(|n| n.contains("crack-initiation ramp"))
            .count()
    };
    let brittle = "dx: 0.5, failure: CriticalStretch(0.01)";
    assert_eq!(notes(&format!("{brittle}, solver: Adr()"), ramp), 1);
    assert_eq!(
        notes(
            &format!("{brittle}, solver: Implicit(tolerance: 1e-12)"),
            ramp
        ),
        1
    );
    assert_eq!(
        notes(
            &format!("{brittle}, solver: Switching(tolerance: 1e-8)"),
            ramp
        ),
        1
    );
    assert_eq!(notes(&format!("{brittle}, solver: Implicit()"), ramp), 0);
    assert_eq!(notes(brittle, ramp), 0);
    assert_eq!(notes(&format!("{brittle}, solver: Adr()"), ""), 0);
    assert_eq!(notes("dx: 0.5, solver: Adr()", ramp), 0);
    let cells = format!("{brittle}, model: StateBased, solver: Adr(), refinement: (on: Cells)");
    assert_eq!(notes(&cells, ramp), 1);
    let particles = format!("{brittle}, model: StateBased, solver: Adr(), refinement: ()");
    assert_eq!(notes(&particles, ramp), 0);
}

/// PD pre-cracks are traction-free: a condition on the faces of a crack that PD models
/// (a window over its tip, stand-alone PD, full-PD growth) is refused, naming the crack
/// (`src/scene/validate/face_loads.rs`; before, a coupled face pressure was dropped
/// inside the window and K_I came out 6.3 % low). The BEM alone, BEM-only growth and a
/// window away from the crack keep the condition.
#[test]
fn crack_face_conditions_are_refused_where_pd_models_the_crack() {
    let pressure =
        r#"[(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1)), (on: "c", normal: -1)]"#;
    let upper = r#"[(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1.1)), (on: "c.upper", y: Traction(1))]"#;
    let with = |boundary: &str, extra: &str| make(MAT, BODY, CRACKS, boundary, extra);
    let tips = "pd: (), coupling: (side: 2, n: 20)";
    let text = assert_invalid(
        &with(pressure, tips),
        "boundary.2.on = \"c\"",
        "faces of crack 'c', and a PD window covers its tips",
    );
    assert!(text.contains("traction-free"), "{text}");
    assert_invalid(
        &with(upper, tips),
        "boundary.2.on = \"c.upper\"",
        "a PD window covers its tips",
    );
    assert_invalid(
        &with(pressure, "pd: (dx: 0.1)"),
        "boundary.2.on = \"c\"",
        "stand-alone PD models every crack",
    );
    let full_pd = "material: (E: 1e4, nu: 0.3, plane: Stress, fracture: (g_c: 1)), pd: (), \
                   coupling: (side: 2, n: 20), load: (initial: 1, step: 1, count: 2), \
                   growth: (mode: FullPd)";
    let full =
        make(MAT, BODY, CRACKS, pressure, full_pd).replacen(&format!("material: {MAT}, "), "", 1);
    assert_invalid(
        &full,
        "boundary.2.on = \"c\"",
        "full-PD growth models every crack",
    );
    load(&full.replace("FullPd", "BemOnly")).expect("BEM-only growth");
    // A window away from the crack, the BEM alone, BEM-only growth: valid.
    let away = "pd: (), coupling: (side: 2, n: 20, placement: Centered(center: (5, 4)))";
    load(&with(pressure, away)).expect("a window away from the crack");
    load(&with(pressure, "")).expect("the BEM alone");
    let over = "pd: (), coupling: (side: 2, n: 20, placement: Centered(center: (2, 10)))";
    assert_invalid(
        &with(pressure, over),
        "boundary.2.on = \"c\"",
        "the PD window (coupling.placement) covers part of it",
    );
}
