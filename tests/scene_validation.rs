//! Scene validation: one test per rule; every message names the file, the
//! dotted field path and the reason.

use pdbem::scene::{Scene, SceneError};

const FILE: &str = "cases/x.ron";
const MAT: &str = "(E: 1e4, nu: 0.3, plane: Stress)";
const BODY: &str = "(outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20))";
const CRACKS: &str = r#"[(name: "c", start: (0, 10), angle_deg: 0, length: 3)]"#;
const BOUNDARY: &str = r#"[(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))]"#;

fn make(mat: &str, body: &str, cracks: &str, boundary: &str, extra: &str) -> String {
    format!(
        "(name: \"t\", material: {mat}, body: {body}, cracks: {cracks}, boundary: {boundary}, {extra})"
    )
}

fn base_with(extra: &str) -> String {
    make(MAT, BODY, CRACKS, BOUNDARY, extra)
}

fn load(src: &str) -> Result<Scene, SceneError> {
    Scene::from_ron_str(src, FILE)
}

/// The error text, which must name the file and contain `path` and `reason`.
fn assert_invalid(src: &str, path: &str, reason: &str) -> String {
    let text = match load(src) {
        Ok(_) => panic!("scene should be invalid ({path}):\n{src}"),
        Err(e) => e.to_string(),
    };
    assert!(
        text.contains(&format!("{FILE}: {path}")),
        "no '{FILE}: {path}' in:\n{text}"
    );
    assert!(text.contains(reason), "no '{reason}' in:\n{text}");
    text
}

#[test]
fn base_scene_is_valid() {
    let s = load(&base_with("")).expect("valid");
    assert!(s.notes.is_empty());
}

#[test]
fn youngs_modulus_must_be_positive() {
    let src = make("(E: 0, nu: 0.3, plane: Stress)", BODY, CRACKS, BOUNDARY, "");
    assert_invalid(&src, "material.E = 0", "Young's modulus must be > 0");
}

#[test]
fn poisson_ratio_range_message_is_exact() {
    let src = make(
        "(E: 1e4, nu: 0.6, plane: Stress)",
        BODY,
        CRACKS,
        BOUNDARY,
        "",
    );
    let text = assert_invalid(&src, "material.nu", "Poisson ratio");
    assert!(text.contains("cases/x.ron: material.nu = 0.6: Poisson ratio must lie in (-1, 0.5)"));
    let src = make(
        "(E: 1e4, nu: -1, plane: Stress)",
        BODY,
        CRACKS,
        BOUNDARY,
        "",
    );
    assert_invalid(&src, "material.nu = -1", "(-1, 0.5)");
}

#[test]
fn thickness_must_be_positive() {
    let src = make(
        "(E: 1e4, nu: 0.3, plane: Strain, thickness: -1)",
        BODY,
        CRACKS,
        BOUNDARY,
        "",
    );
    assert_invalid(&src, "material.thickness = -1", "thickness must be > 0");
}

#[test]
fn negative_fracture_energy() {
    let src = make(
        "(E: 1e4, nu: 0.3, plane: Stress, fracture: (g_c: -5))",
        BODY,
        CRACKS,
        BOUNDARY,
        "",
    );
    assert_invalid(&src, "material.fracture.g_c = -5", "must not be negative");
}

#[test]
fn polygon_needs_three_points() {
    let body = "(outline: Polygon(points: [(0, 0), (1, 0)]))";
    assert_invalid(
        &make(MAT, body, "[]", BOUNDARY, ""),
        "body.outline.points",
        "at least 3 points",
    );
}

#[test]
fn outline_must_not_self_intersect() {
    let body = "(outline: Polygon(points: [(0, 0), (10, 10), (10, 0), (0, 10)]))";
    assert_invalid(
        &make(MAT, body, "[]", "[(on: \"edge0\", x: Traction(1))]", ""),
        "body.outline.points",
        "self-intersecting",
    );
}

#[test]
fn outline_must_have_area() {
    let body = "(outline: Polygon(points: [(0, 0), (1, 0), (2, 0)]))";
    let text = match load(&make(
        MAT,
        body,
        "[]",
        "[(on: \"edge0\", x: Traction(1))]",
        "",
    )) {
        Ok(_) => panic!("collinear outline accepted"),
        Err(e) => e.to_string(),
    };
    assert!(text.contains("cases/x.ron: body.outline.points"), "{text}");
    assert!(
        text.contains("self-intersecting") || text.contains("zero area"),
        "{text}"
    );
}

#[test]
fn repeated_point_is_a_zero_length_edge() {
    let body = "(outline: Polygon(points: [(0, 0), (10, 0), (10, 0), (0, 10)]))";
    assert_invalid(
        &make(MAT, body, "[]", "[(on: \"edge0\", x: Traction(1))]", ""),
        "body.outline.points.2",
        "non-zero length",
    );
}

#[test]
fn edges_outline_must_close() {
    let body = r#"(outline: Edges(edges: [
        (name: "a", points: [(0, 0), (10, 0), (10, 10)]),
        (name: "b", points: [(10, 10), (0, 9)]),
    ]))"#;
    assert_invalid(
        &make(MAT, body, "[]", "[(on: \"a\", x: Traction(1))]", ""),
        "body.outline.edges.1",
        "outline not closed",
    );
}

#[test]
fn closed_edges_outline_is_valid() {
    let body = r#"(outline: Edges(edges: [
        (name: "a", points: [(0, 0), (10, 0), (10, 10)]),
        (name: "b", points: [(10, 10), (0, 10), (0, 0)]),
    ]))"#;
    load(&make(MAT, body, "[]", "[(on: \"a\", x: Traction(1))]", "")).expect("valid");
}

#[test]
fn hole_outside_the_body() {
    let body = "(outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20), holes: [Circle(center: (30, 5), radius: 1)])";
    assert_invalid(
        &make(MAT, body, "[]", BOUNDARY, ""),
        "body.holes.0",
        "outside the body",
    );
}

#[test]
fn hole_overlapping_the_outline() {
    let body = "(outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20), holes: [Circle(center: (9.5, 5), radius: 1)])";
    assert_invalid(
        &make(MAT, body, "[]", BOUNDARY, ""),
        "body.holes.0",
        "overlaps the outline",
    );
}

#[test]
fn holes_overlapping_each_other() {
    let body = "(outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20), holes: [
        Circle(center: (5, 5), radius: 1), Polygon(points: [(5.5, 5), (7, 5), (7, 6)])])";
    assert_invalid(
        &make(MAT, body, "[]", BOUNDARY, ""),
        "body.holes.1",
        "overlaps body.holes.0",
    );
}

#[test]
fn hole_radius_must_be_positive() {
    let body = "(outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20), holes: [Circle(center: (5, 5), radius: 0)])";
    assert_invalid(
        &make(MAT, body, "[]", BOUNDARY, ""),
        "body.holes.0.radius = 0",
        "hole radius must be > 0",
    );
}

#[test]
fn crack_outside_the_body() {
    let cracks = r#"[(name: "c", start: (12, 10), angle_deg: 0, length: 3)]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.0",
        "crack outside the body",
    );
}

#[test]
fn crack_leaving_the_body() {
    let cracks = r#"[(name: "c", center: (9, 10), angle_deg: 0, length: 4)]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.0",
        "outside",
    );
}

#[test]
fn crack_may_only_touch_the_outline_at_its_mouth() {
    let cracks = r#"[(name: "c", start: (0, 10), angle_deg: 0, length: 10)]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.0",
        "touches the outline",
    );
}

#[test]
fn crack_crossing_a_hole() {
    let body = "(outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20), holes: [Circle(center: (2, 10), radius: 0.5)])";
    assert_invalid(
        &make(MAT, body, CRACKS, BOUNDARY, ""),
        "cracks.0",
        "crossing a hole",
    );
}

#[test]
fn crack_of_zero_length() {
    let cracks = r#"[(name: "c", start: (0, 10), angle_deg: 0, length: 0)]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.0.length = 0",
        "crack of zero length",
    );
    let cracks = r#"[(name: "c", points: [(1, 1), (1, 1)])]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.0.points.1",
        "zero length",
    );
}

#[test]
fn crack_needs_exactly_one_form() {
    let cracks = r#"[(name: "c", start: (0, 10), center: (1, 1), angle_deg: 0, length: 1)]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.0",
        "only one of",
    );
    let cracks = r#"[(name: "c", start: (0, 10), length: 1)]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.0",
        "needs `angle_deg`",
    );
}

#[test]
fn crossing_cracks() {
    let cracks = r#"[(name: "a", center: (5, 10), angle_deg: 0, length: 2),
                     (name: "b", center: (5, 10), angle_deg: 90, length: 2)]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.1",
        "crosses cracks.0",
    );
}

#[test]
fn face_gap_must_be_small_and_positive() {
    let cracks = r#"[(name: "c", start: (0, 10), angle_deg: 0, length: 3, faces: Gap(1))]"#;
    assert_invalid(
        &make(MAT, BODY, cracks, BOUNDARY, ""),
        "cracks.0.faces = 1",
        "below 0.25 of the crack length",
    );
    let cracks = r#"[(name: "c", start: (0, 10), angle_deg: 0, length: 3, faces: Gap(1e-4))]"#;
    load(&make(MAT, BODY, cracks, BOUNDARY, "")).expect("valid gap");
}

#[test]
fn element_size_must_be_positive() {
    assert_invalid(
        &base_with("bem: (element_size: 0)"),
        "bem.element_size = 0",
        "element size must be > 0",
    );
    assert_invalid(
        &base_with("bem: (element_size: -0.1)"),
        "bem.element_size = -0.1",
        "must be > 0",
    );
}

#[test]
fn element_size_giving_zero_elements() {
    assert_invalid(
        &base_with("bem: (element_size: 100)"),
        "bem.element_size = 100",
        "zero elements",
    );
    assert_invalid(
        &base_with(r#"bem: (group_sizes: {"c": 50})"#),
        "bem.group_sizes.c = 50",
        "zero elements on crack 'c'",
    );
    assert_invalid(
        &base_with("bem: (elements_per_circle: 0)"),
        "bem.elements_per_circle = 0",
        "zero elements",
    );
}

#[test]
fn unknown_edge_group_in_boundary() {
    let boundary = r#"[(on: "toop", y: Traction(1))]"#;
    let text = assert_invalid(
        &make(MAT, BODY, CRACKS, boundary, ""),
        "boundary.0.on = \"toop\"",
        "unknown edge group",
    );
    assert!(
        text.contains("known groups: bottom, right, top, left"),
        "{text}"
    );
}

#[test]
fn crack_faces_and_holes_are_edge_groups() {
    let body = "(outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20), holes: [Circle(center: (5, 3), radius: 1, name: \"pin\")])";
    let boundary = r#"[(on: "c.upper", normal: -1), (on: "pin", normal: -2), (on: "left", x: Displacement(0), y: Displacement(0))]"#;
    load(&make(MAT, body, CRACKS, boundary, "")).expect("valid");
}

#[test]
fn normal_traction_only_with_free_components() {
    let boundary = r#"[(on: "top", x: Traction(1), normal: 2)]"#;
    assert_invalid(
        &make(MAT, BODY, CRACKS, boundary, ""),
        "boundary.0.normal",
        "leave x and y Free",
    );
}

#[test]
fn same_group_twice() {
    let boundary = r#"[(on: "top", y: Traction(1)), (on: "top", x: Traction(1))]"#;
    assert_invalid(
        &make(MAT, BODY, CRACKS, boundary, ""),
        "boundary.1.on",
        "already has a condition",
    );
}

#[test]
fn nothing_to_solve() {
    assert_invalid(
        &make(MAT, BODY, CRACKS, "[]", ""),
        "boundary",
        "nothing to solve",
    );
    let zero = r#"[(on: "top", y: Traction(0)), (on: "bottom", y: Displacement(0))]"#;
    assert_invalid(
        &make(MAT, BODY, CRACKS, zero, ""),
        "boundary",
        "nothing to solve",
    );
    assert_invalid(
        &base_with("load: (initial: 0)"),
        "load",
        "every load factor is zero",
    );
}

#[test]
fn pure_traction_and_remote_stress_are_fine() {
    load(&base_with("")).expect("pure traction body");
    let body = "(outline: Infinite(syy: 1))";
    let cracks = r#"[(name: "c", center: (0, 0), angle_deg: 30, length: 2)]"#;
    load(&make(MAT, body, cracks, "[]", "")).expect("infinite plate");
}

#[test]
fn infinite_plate_without_stress_has_nothing_to_solve() {
    let body = "(outline: Infinite())";
    let cracks = r#"[(name: "c", center: (0, 0), angle_deg: 30, length: 2)]"#;
    assert_invalid(
        &make(MAT, body, cracks, "[]", ""),
        "boundary",
        "no remote stress",
    );
}

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
    assert_invalid(
        &base_with("pd: (dx: 0.1, solver: Adr(tolerance: -1))"),
        "pd.solver.tolerance = -1",
        "must be > 0",
    );
    load(&base_with("pd: (dx: 0.1, solver: Implicit(max_iter: 20))")).expect("valid");
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
fn reference_must_fit_the_geometry() {
    assert_invalid(
        &base_with("reference: Kirsch(sigma: 1)"),
        "reference",
        "circular hole",
    );
    assert_invalid(
        &base_with("reference: SentTada(width: 2, sigma: 1)"),
        "reference.width = 2",
        "below the strip width",
    );
    load(&base_with("reference: SentTada(width: 10, sigma: 1)")).expect("valid reference");
}

#[test]
fn unknown_field_names_file_line_and_field() {
    let src = "(name: \"t\",\n material: (E: 1e4, nu: 0.3, plane: Stress, poisson: 0.2),\n body: (outline: Infinite(syy: 1)))";
    let text = load(src).err().map(|e| e.to_string()).unwrap_or_default();
    assert!(text.starts_with("cases/x.ron:2:"), "{text}");
    assert!(text.contains("poisson"), "{text}");
}

#[test]
fn syntax_error_names_line_and_column() {
    let src = "(name: \"t\",\n material: (E: 1e4 nu: 0.3, plane: Stress),\n)";
    match load(src) {
        Err(SceneError::Syntax { line, column, .. }) => {
            assert_eq!(line, 2);
            assert!(column > 1);
        }
        other => panic!("expected a syntax error, got {other:?}"),
    }
}

#[test]
fn missing_required_field_is_named() {
    let src = "(name: \"t\", body: (outline: Infinite(syy: 1)))";
    let text = load(src).err().map(|e| e.to_string()).unwrap_or_default();
    assert!(text.contains("material"), "{text}");
}

#[test]
fn scene_name_must_be_a_folder_name() {
    let src = base_with("").replacen("name: \"t\"", "name: \"a/b\"", 1);
    assert_invalid(&src, "name = \"a/b\"", "run folder");
}

#[test]
fn clockwise_outline_is_reversed_with_its_edge_names() {
    let body = r#"(outline: Polygon(points: [(0, 0), (0, 10), (10, 10), (10, 0)], edge_names: ["left", "top", "right", "bottom"]))"#;
    let s = load(&make(
        MAT,
        body,
        "[]",
        r#"[(on: "top", y: Traction(1))]"#,
        "",
    ))
    .expect("valid");
    assert_eq!(s.notes.len(), 1, "{:?}", s.notes);
    let geo = pdbem::scene::shapes::SceneGeometry::of(&s);
    let o = geo.outline.expect("finite");
    assert!(pdbem::geometry::is_ccw(&o.points));
    // The edge named "top" still runs along y = 10.
    let n = o.points.len();
    let k = o.groups.iter().position(|g| g == "top").expect("top edge");
    assert_eq!(o.points[k].y, 10.0);
    assert_eq!(o.points[(k + 1) % n].y, 10.0);
}

#[test]
fn counter_clockwise_outline_gives_no_note() {
    let body = "(outline: Polygon(points: [(0, 0), (10, 0), (10, 10), (0, 10)]))";
    let s = load(&make(
        MAT,
        body,
        "[]",
        r#"[(on: "edge2", y: Traction(1))]"#,
        "",
    ))
    .expect("valid");
    assert!(s.notes.is_empty());
}

#[test]
fn all_issues_are_reported_together() {
    let src = make(
        "(E: -1, nu: 0.7, plane: Stress)",
        BODY,
        CRACKS,
        BOUNDARY,
        "",
    );
    let e = load(&src).expect_err("invalid");
    assert_eq!(e.issues().len(), 2, "{e}");
}

#[test]
fn scene_file_that_does_not_exist() {
    let e = Scene::load("cases/does_not_exist.ron").expect_err("missing file");
    assert!(e
        .to_string()
        .contains("cases/does_not_exist.ron: cannot read scene"));
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
    let displaced = r#"[(on: "top", y: Displacement(0.1)), (on: "bottom", y: Traction(-1))]"#;
    assert_invalid(
        &make(
            MAT,
            BODY,
            CRACKS,
            displaced,
            "pd: (dx: 0.5, model: StateBased, refinement: ())",
        ),
        "pd.refinement",
        "traction-loaded",
    );
    // Adaptive dynamics holds the fictitious layer of a displacement condition.
    let dynamic = "pd: (dx: 0.5, model: StateBased, failure: FromGc, refinement: (), solver: Explicit(end_time: 1e-3)), material: (E: 1e4, nu: 0.3, plane: Stress, density: 1000, fracture: (g_c: 1))";
    let src = make(MAT, BODY, CRACKS, displaced, dynamic);
    load(&src.replace(&format!("material: {MAT}, "), "")).expect("valid");
}
