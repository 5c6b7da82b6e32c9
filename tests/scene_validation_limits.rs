//! Scene validation at the extremes (issue 17): the bounds of counts and sampling
//! coordinates, safe output names, the coupling node count, psi and the horizon factor.
//! One test per rule; every message names the file, the dotted field path and the reason.
//! (A file of its own: `scene_validation.rs` is at its size limit.)

mod scene_validation_common;

use scene_validation_common::{assert_invalid, load};

/// A 10 x 20 plate with an edge crack from (0, 10), tip at (3, 10), pulled at top and
/// bottom; `extra` adds sections, `crack` replaces the crack name.
fn scene_named(crack: &str, extra: &str) -> String {
    format!(
        r#"(name: "t", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20)),
        cracks: [(name: {crack:?}, start: (0, 10), angle_deg: 0, length: 3)],
        boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))], {extra})"#
    )
}

fn scene(extra: &str) -> String {
    scene_named("c", extra)
}

#[test]
fn the_base_scene_and_a_coupled_one_are_valid() {
    load(&scene("")).expect("valid");
    load(&scene("pd: (), coupling: (side: 2, n: 20)")).expect("valid");
}

#[test]
fn load_count_is_bounded_and_huge_counts_do_not_panic() {
    assert_invalid(
        &scene("load: (count: 18446744073709551615)"),
        "load.count = 18446744073709551615",
        "load steps (each is a solve) must be at most 100000",
    );
    assert_invalid(
        &scene("load: (count: 4294967296)"),
        "load.count",
        "at most 100000",
    );
}

#[test]
fn elements_per_circle_is_bounded() {
    assert_invalid(
        &scene("bem: (elements_per_circle: 18446744073709551615)"),
        "bem.elements_per_circle",
        "elements per circle must be at most 100000",
    );
}

#[test]
fn j_contour_points_are_bounded() {
    assert_invalid(
        &scene("bem: (j_contour: (points: 1000000000))"),
        "bem.j_contour.points",
        "contour points must be at most 100000",
    );
}

#[test]
fn pd_nx_is_bounded() {
    assert_invalid(
        &scene("pd: (nx: 100000000)"),
        "pd.nx = 100000000",
        "PD nodes across the body must be at most 100000",
    );
}

#[test]
fn pd_solver_caps_are_bounded() {
    assert_invalid(
        &scene("pd: (nx: 20, solver: Adr(max_iter: 18446744073709551615))"),
        "pd.solver.max_iter",
        "iteration cap must be at most 100000000",
    );
    assert_invalid(
        &scene("pd: (nx: 20, solver: Switching(explicit_steps: 1000000000))"),
        "pd.solver.explicit_steps",
        "loading steps must be at most 1000000",
    );
}

#[test]
fn coupling_n_and_max_iter_are_bounded() {
    assert_invalid(
        &scene("pd: (), coupling: (side: 2, n: 18446744073709551614)"),
        "coupling.n",
        "PD nodes per window side must be at most 5000",
    );
    assert_invalid(
        &scene("pd: (), coupling: (side: 2, n: 20, max_iter: 1000000000)"),
        "coupling.max_iter",
        "coupling iterations must be at most 100000",
    );
}

#[test]
fn coupling_n_gives_two_horizons() {
    assert_invalid(
        &scene("pd: (), coupling: (side: 2, n: 6)"),
        "coupling.n = 6",
        "must be at least 7: a window must be at least 2 horizons wide",
    );
    // With m = 4 the window needs 8 nodes.
    assert_invalid(
        &scene("pd: (horizon_factor: 4), coupling: (side: 2, n: 6, placement: Centered(center: (5, 5)))"),
        "coupling.n = 6",
        "at least 8",
    );
    load(&scene("pd: (), coupling: (side: 2, n: 8)")).expect("n = 8 is valid");
}

#[test]
fn region_windows_are_two_horizons_high() {
    // dx = 2 / 20 = 0.1: a region 0.5 high has 5 node rows, fewer than 7.
    assert_invalid(
        &scene("pd: (), coupling: (side: 2, n: 20, placement: Region(x0: 4, y0: 1, width: 2, height: 0.5))"),
        "coupling.placement.height = 0.5",
        "it must be at least 7 (2 horizons",
    );
}

#[test]
fn full_pd_growth_builds_no_window_and_takes_any_node_count() {
    // Full PD takes dx = side / n from `coupling` and builds no window.
    let src = scene("pd: (failure: FromGc), coupling: (side: 2, n: 5), growth: (mode: FullPd)")
        .replace("plane: Stress)", "plane: Stress, fracture: (g_c: 1))");
    load(&src).unwrap_or_else(|e| panic!("{e}"));
    // The same section for PD-BEM growth builds windows of 5 nodes: refused.
    assert_invalid(
        &src.replace("FullPd", "PdBem"),
        "coupling.n = 5",
        "at least 7",
    );
}

#[test]
fn odd_coupling_n_at_tips_is_refused() {
    assert_invalid(
        &scene("pd: (), coupling: (side: 2, n: 21)"),
        "coupling.n = 21",
        "AtTips windows need an even number of nodes per side",
    );
    // Elsewhere an odd n is fine.
    load(&scene(
        "pd: (), coupling: (side: 2, n: 21, placement: Centered(center: (5, 5)))",
    ))
    .expect("odd n in a centred window");
}

#[test]
fn tip_window_outside_the_body() {
    // Tip at (3, 10): a side of 7 reaches x = -0.5.
    assert_invalid(
        &scene("pd: (), coupling: (side: 7, n: 20)"),
        "coupling.side = 7",
        "the window on tip c.end reaches outside the body",
    );
}

#[test]
fn tip_windows_need_a_crack() {
    let src = r#"(name: "t", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20)),
        boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
        pd: (), coupling: (side: 2, n: 20))"#;
    assert_invalid(src, "coupling.placement", "the scene has no crack");
}

#[test]
fn psi_is_a_small_relative_tolerance() {
    for psi in ["1.0", "1e300", "0"] {
        assert_invalid(
            &scene(&format!("pd: (), coupling: (side: 2, n: 20, psi: {psi})")),
            "coupling.psi",
            "it must lie in (0, 0.1]",
        );
    }
    load(&scene("pd: (), coupling: (side: 2, n: 20, psi: 0.1)")).expect("psi = 0.1");
    // Below what the iteration can settle to: round-off near 1e-12 in a static solve
    // (coupled_sent_a5 ended unconverged at 9.7e-12 with psi = 1e-12).
    assert_invalid(
        &scene("pd: (), coupling: (side: 2, n: 20, psi: 1e-12)"),
        "coupling.psi",
        "below 1e-10 cannot mean convergence",
    );
    load(&scene("pd: (), coupling: (side: 2, n: 20, psi: 1e-10)")).expect("psi = 1e-10");
}

#[test]
fn horizon_factor_range() {
    for m in ["1", "1.5", "6.5"] {
        assert_invalid(
            &scene(&format!("pd: (nx: 20, horizon_factor: {m})")),
            &format!("pd.horizon_factor = {m}"),
            "must lie in [2, 6]",
        );
    }
    load(&scene("pd: (nx: 20, horizon_factor: 2)")).expect("m = 2");
}

#[test]
fn crack_names_are_safe_file_names() {
    for bad in ["a/b", "x y", "\u{e9}t\u{e9}"] {
        assert_invalid(
            &scene_named(bad, ""),
            "cracks.0.name",
            "it names the output file path_<tip>.csv",
        );
    }
    load(&scene_named("crack_1-a", "")).expect("safe name");
}

#[test]
fn grid_points_are_bounded() {
    assert_invalid(
        &scene(
            "outputs: (grids: [(name: \"g\", from: (1, 1), to: (9, 19), nx: 10, ny: 100000000)])",
        ),
        "outputs.grids.0.ny = 100000000",
        "nx * ny must be at most 1000000",
    );
}

#[test]
fn grid_and_line_coordinates_are_bounded() {
    assert_invalid(
        &scene("outputs: (grids: [(name: \"g\", from: (-1e308, 1), to: (9, 19), nx: 10, ny: 10)])"),
        "outputs.grids.0.from",
        "at most 1e12 m in magnitude",
    );
    assert_invalid(
        &scene("outputs: (lines: [(name: \"l\", from: (1, 1), to: (1e300, 19), n: 10)])"),
        "outputs.lines.0.to",
        "at most 1e12 m in magnitude",
    );
}

#[test]
fn grid_and_line_names_and_counts() {
    assert_invalid(
        &scene("outputs: (grids: [(name: \"../g\", from: (1, 1), to: (9, 19), nx: 10, ny: 10)])"),
        "outputs.grids.0.name",
        "grid_<name>.csv",
    );
    assert_invalid(
        &scene(
            "outputs: (lines: [(name: \"l\", from: (1, 1), to: (2, 19), n: 18446744073709551615)])",
        ),
        "outputs.lines.0.n",
        "points on a line must be at most 1000000",
    );
}

#[test]
fn bem_tolerance_is_a_relative_tolerance_of_static_runs() {
    load(&scene("bem: (tolerance: 1e-3)")).expect("valid");
    assert_invalid(
        &scene("bem: (tolerance: 1.0)"),
        "bem.tolerance",
        "[4e-4, 0.5]",
    );
    assert_invalid(
        &scene("bem: (tolerance: 0.0)"),
        "bem.tolerance",
        "[4e-4, 0.5]",
    );
    assert_invalid(
        &scene("bem: (tolerance: 1e-3), pd: (), coupling: (side: 2, n: 20)"),
        "bem.tolerance",
        "static BEM runs only",
    );
}

/// The 10 x 20 plate of [`scene_named`] with E and the boundary replaced.
fn loaded(e: &str, boundary: &str, extra: &str) -> String {
    format!(
        r#"(name: "t", material: (E: {e}, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20)),
        cracks: [(name: "c", start: (0, 10), angle_deg: 0, length: 3)],
        boundary: {boundary}, {extra})"#
    )
}

#[test]
fn loads_must_strain_the_body_less_than_one() {
    // 1e300 Pa ran into a non-finite BEM solution at run time; so did E = 1e-300.
    let pull =
        |t: &str| format!(r#"[(on: "top", y: Traction({t})), (on: "bottom", y: Traction(-1))]"#);
    assert_invalid(
        &loaded("1e4", &pull("1e300"), ""),
        "boundary.0.y = 1e300",
        "strain the body by about 1.000e296",
    );
    assert_invalid(
        &loaded("1e-300", &pull("1"), ""),
        "boundary.0.y = 1",
        "outside the small-strain elasticity",
    );
    // The load factor counts: 1e3 / 1e4 is 0.1, at factor 20 it is 2.
    load(&loaded("1e4", &pull("1e3"), "")).expect("valid");
    assert_invalid(
        &loaded("1e4", &pull("1e3"), "load: (initial: 20)"),
        "boundary.0.y = 1000",
        "about 2.000e0 (|load| / E, or a displacement's spread over the body's size, at load factor 20)",
    );
    // Displacements: their spread over the body's size (the diagonal, 22.36 m); one
    // displaced edge alone moves the body rigidly.
    let pulled = |d: &str| {
        format!(r#"[(on: "top", y: Displacement({d})), (on: "bottom", y: Displacement(0))]"#)
    };
    assert_invalid(
        &loaded("1e4", &pulled("30"), ""),
        "boundary.0.y = 30",
        "about 1.342e0",
    );
    load(&loaded("1e4", &pulled("20"), "")).expect("valid");
    let moved = r#"[(on: "top", y: Displacement(30)), (on: "bottom", y: Traction(-1))]"#;
    load(&loaded("1e4", moved, "")).expect("a rigid shift is no strain");
    // A remote stress.
    let infinite = r#"(name: "t", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Infinite(syy: 2e4)),
        cracks: [(name: "c", center: (0, 0), angle_deg: 0, length: 1)], boundary: [])"#;
    assert_invalid(infinite, "body.outline.syy = 20000", "about 2.000e0");
}

#[test]
fn pd_needs_loads_above_its_round_off() {
    let pull =
        |t: &str| format!(r#"[(on: "top", y: Traction({t})), (on: "bottom", y: Traction(-{t}))]"#);
    let pd = "pd: (dx: 0.5)";
    // 1e-7 Pa on E = 1e4 is a strain of 1e-11: the PD solves stall on round-off.
    assert_invalid(
        &loaded("1e4", &pull("1e-7"), pd),
        "boundary.0.y",
        "PD needs at least 1e-10",
    );
    load(&loaded("1e4", &pull("2e-6"), pd)).expect("2e-10 is resolved");
    // The BEM alone takes it; the smallest load factor counts.
    load(&loaded("1e4", &pull("1e-7"), "")).expect("BEM is linear in the loads");
    assert_invalid(
        &loaded("1e4", &pull("2e-6"), &format!("{pd}, load: (initial: 0.1, step: 0.1, count: 10)")),
        "boundary.0.y",
        "about 2.000e-11 (|load| / E, or a displacement's spread over the body's size, at load factor 0.1)",
    );
}
