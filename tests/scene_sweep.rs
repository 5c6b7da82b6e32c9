//! Dotted-path overrides used by `pdbem sweep`.

use pdbem::scene::path::{parse_value, with_overrides};
use pdbem::scene::{Outline, Scene, SceneError};
use serde_json::json;

const SRC: &str = r#"(
    name: "s",
    material: (E: 1e4, nu: 0.3, plane: Stress),
    body: (outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20)),
    cracks: [(name: "c", start: (0, 10), angle_deg: 0, length: 3, faces: Gap(1e-4))],
    boundary: [(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))],
    bem: (element_size: 0.5),
    pd: (dx: 0.1, solver: Adr(tolerance: 1e-8)),
)"#;

fn scene() -> Scene {
    Scene::from_ron_str(SRC, "sweep.ron").expect("valid")
}

fn set(path: &str, value: serde_json::Value) -> Result<Scene, SceneError> {
    with_overrides(&scene(), &[(path.to_string(), value)])
}

#[test]
fn sets_crack_length_and_element_size() {
    let s = with_overrides(
        &scene(),
        &[
            ("cracks.0.length".into(), json!(5)),
            ("bem.element_size".into(), json!(0.25)),
        ],
    )
    .expect("valid");
    assert_eq!(s.cracks[0].length, Some(5.0));
    assert_eq!(s.bem.element_size, Some(0.25));
    assert_eq!(s.source, scene().source);
}

#[test]
fn enum_variants_are_transparent() {
    let s = set("body.outline.width", json!(12)).expect("valid");
    assert!(matches!(s.body.outline, Outline::Rectangle { width, .. } if width == 12.0));
    let s = set("pd.solver.tolerance", json!(1e-6)).expect("valid");
    assert!(matches!(s.pd.and_then(|p| match p.solver {
        pdbem::scene::PdSolver::Adr(a) => Some(a.tolerance),
        _ => None,
    }), Some(t) if t == 1e-6));
    let s = set("body.outline.Rectangle.height", json!(30)).expect("explicit variant");
    assert!(matches!(s.body.outline, Outline::Rectangle { height, .. } if height == 30.0));
}

#[test]
fn number_on_newtype_variant_sets_its_content() {
    let s = set("cracks.0.faces", json!(1e-5)).expect("valid");
    assert_eq!(s.cracks[0].faces, pdbem::scene::Faces::Gap(1e-5));
}

#[test]
fn unit_variant_by_name() {
    let s = set("material.plane", parse_value("Strain")).expect("valid");
    assert_eq!(s.material.plane, pdbem::scene::Plane::Strain);
}

#[test]
fn tuple_values() {
    let s = set("cracks.0.start", parse_value("(0, 5)")).expect("valid");
    assert_eq!(s.cracks[0].start, Some((0.0, 5.0)));
}

fn path_error(path: &str, value: serde_json::Value) -> String {
    match set(path, value) {
        Err(e @ SceneError::Path { .. }) => e.to_string(),
        other => panic!("expected a path error for {path}, got {other:?}"),
    }
}

#[test]
fn unknown_field_lists_the_available_ones() {
    let text = path_error("cracks.0.lenght", json!(1));
    assert!(text.contains("--vary cracks.0.lenght"), "{text}");
    assert!(text.contains("no field 'lenght' in cracks.0"), "{text}");
    assert!(text.contains("length"), "{text}");
}

#[test]
fn index_out_of_range() {
    let text = path_error("cracks.3.length", json!(1));
    assert!(
        text.contains("index 3 out of range: cracks has 1 entries"),
        "{text}"
    );
}

#[test]
fn list_needs_an_index() {
    let text = path_error("cracks.first.length", json!(1));
    assert!(text.contains("expected an index"), "{text}");
}

#[test]
fn unset_option_cannot_be_entered() {
    let text = path_error("bem.tip_refinement.radius", json!(1));
    assert!(text.contains("bem.tip_refinement is not set"), "{text}");
}

#[test]
fn number_field_rejects_text() {
    let text = path_error("bem.element_size", json!("fine"));
    assert!(text.contains("is a number"), "{text}");
}

#[test]
fn wrong_type_after_deserialising_is_a_path_error() {
    let text = path_error("material.plane", json!("Plastic"));
    assert!(text.contains("does not fit the scene"), "{text}");
    assert!(text.contains("Plastic"), "{text}");
}

#[test]
fn invalid_value_is_revalidated() {
    match set("cracks.0.length", json!(20)) {
        Err(e @ SceneError::Invalid { .. }) => {
            assert!(e.to_string().contains("sweep.ron: cracks.0"))
        }
        other => panic!("expected a validation error, got {other:?}"),
    }
    match set("bem.element_size", json!(-1)) {
        Err(e @ SceneError::Invalid { .. }) => {
            assert!(e.to_string().contains("bem.element_size = -1"))
        }
        other => panic!("expected a validation error, got {other:?}"),
    }
}

#[test]
fn vary_grid_covers_every_combination() {
    let a = pdbem::sweep::parse_vary("cracks.0.length=1,2,3").expect("parses");
    let b = pdbem::sweep::parse_vary("bem.element_size=0.5,0.25").expect("parses");
    let g = pdbem::sweep::grid(&[a, b]);
    assert_eq!(g.len(), 6);
}

#[test]
fn switching_a_struct_variant_by_name_uses_its_defaults() {
    let s = set("pd.solver", parse_value("Implicit")).expect("valid");
    assert!(matches!(
        s.pd.map(|p| p.solver),
        Some(pdbem::scene::PdSolver::Implicit(_))
    ));
}
