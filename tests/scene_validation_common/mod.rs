//! What the scene validation tests share: a base scene (file name, material, body,
//! crack, boundary), its assembly and the check that an error names the file, the dotted
//! field path and the reason.
// Each test file that includes this module uses part of it.
#![allow(dead_code)]

use pdbem::scene::{Scene, SceneError};

pub const FILE: &str = "cases/x.ron";
pub const MAT: &str = "(E: 1e4, nu: 0.3, plane: Stress)";
pub const BODY: &str = "(outline: Rectangle(x0: 0, y0: 0, width: 10, height: 20))";
pub const CRACKS: &str = r#"[(name: "c", start: (0, 10), angle_deg: 0, length: 3)]"#;
pub const BOUNDARY: &str = r#"[(on: "top", y: Traction(1)), (on: "bottom", y: Traction(-1))]"#;

pub fn make(mat: &str, body: &str, cracks: &str, boundary: &str, extra: &str) -> String {
    format!(
        "(name: \"t\", material: {mat}, body: {body}, cracks: {cracks}, boundary: {boundary}, {extra})"
    )
}

pub fn base_with(extra: &str) -> String {
    make(MAT, BODY, CRACKS, BOUNDARY, extra)
}

pub fn load(src: &str) -> Result<Scene, SceneError> {
    Scene::from_ron_str(src, FILE)
}

/// The error text, which must name the file and contain `path` and `reason`.
pub fn assert_invalid(src: &str, path: &str, reason: &str) -> String {
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
