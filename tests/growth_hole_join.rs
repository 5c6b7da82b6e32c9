//! A crack that runs into a hole joins it (issue 18 item 5), BEM-only: an edge crack of
//! 6 mm rising from (40, 0) mm straight at a hole of radius 5 mm centred at (40, 22) mm in
//! an 80 mm x 40 mm plate (the stand-in geometry of `growth_hole_edge` with the crack under
//! the hole), K_c = 1e7 Pa m^0.5 so that it runs at the first load. The tip is taken onto
//! the meshed hole polygon, the joined geometry is solved once more for the final outputs,
//! and the run ends complete with `end_state: tips_ended_at_holes_body_holds` (not a
//! failure). Measured: 11.2 s wall at a load average of 12 (3.5 s CPU).

use std::path::PathBuf;

use pdbem::growth::bem_only;
use pdbem::runner::RunContext;
use pdbem::scene::Scene;

const SCENE: &str = r#"(
    name: "hole_join",
    description: "edge crack straight into a hole",
    material: (E: 72e9, nu: 0.3333333333333333, plane: Stress, fracture: (k_c: 1.0e7)),
    body: (
        outline: Rectangle(x0: 0, y0: 0, width: 0.08, height: 0.04),
        holes: [Circle(center: (0.04, 0.022), radius: 0.005, name: "hole")],
    ),
    cracks: [
        (name: "crack", start: (0.04, 0), angle_deg: 90, length: 0.006),
    ],
    boundary: [
        (on: "left", x: Displacement(0), y: Displacement(0)),
        (on: "right", x: Traction(1e6)),
    ],
    load: (initial: 115, step: 1, count: 2),
    bem: (element_size: 0.001, elements_per_circle: 32),
    growth: (mode: BemOnly, da: 0.001),
)"#;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdbem-hole-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn bem_only_crack_into_a_hole_joins_it_and_the_body_holds() {
    let scene = Scene::from_ron_str(SCENE, "inline.ron").unwrap_or_else(|e| panic!("{e}"));
    let dir = scratch("bem-only");
    let ctx = RunContext::new(&dir, true).expect("run folder");
    let h = bem_only::run(&scene, &ctx).unwrap_or_else(|e| panic!("{e:#}"));
    ctx.writer.abort();
    assert_eq!(
        h.paths[0].ended.as_deref(),
        Some("hole:hole"),
        "{:?}",
        h.notes
    );
    assert!(!h.failure && h.failure_reason.is_none(), "{:?}", h.notes);
    assert_eq!(h.end_state(), "tips_ended_at_holes_body_holds");
    // The crack ends on the 32-gon of the mesh: between its edges' distance from the
    // centre, r cos(pi/32), and r (the polygon's vertices lie on the circle).
    let p = h.paths[0].points.last().expect("path");
    let d = (p.x - 0.04).hypot(p.y - 0.022);
    let inner = 0.005 * (std::f64::consts::PI / 32.0).cos();
    assert!(
        d >= inner - 1e-9 && d <= 0.005 + 1e-9,
        "end {d:.6e} m from the centre"
    );
    // The joined geometry was solved for the final outputs: besides the snapshot at
    // initiation, one of the last step (without that solve the run keeps none).
    let last = h.steps.len() - 1;
    let at_last = h
        .snapshots
        .iter()
        .filter(|s| s.label == "displacement" && s.step == last && !s.values.is_empty())
        .count();
    let initiation = usize::from(last == 0);
    assert_eq!(
        at_last,
        1 + initiation,
        "no final snapshot of the joined body"
    );
    assert!(
        h.notes.iter().any(|n| n.contains("the body holds")),
        "{:?}",
        h.notes
    );
}
