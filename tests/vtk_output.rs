//! `outputs.vtk: true` writes ParaView files in every mode, and they read back (with the
//! vtkio crate that wrote them) with the right sizes and values.

use std::path::{Path, PathBuf};

use pdbem::runner::run_scene;
use pdbem::scene::path::{parse_value, with_overrides};
use pdbem::scene::Scene;
use vtkio::model::{Attribute, DataSet, UnstructuredGridPiece, Vtk};

fn temp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pdbem-vtk-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn case(name: &str, overrides: &[(&str, &str)]) -> Scene {
    let s = Scene::load(format!("{}/cases/{name}.ron", env!("CARGO_MANIFEST_DIR"))).expect("case");
    let ov: Vec<(String, serde_json::Value)> = overrides
        .iter()
        .map(|(p, v)| (p.to_string(), parse_value(v)))
        .collect();
    with_overrides(&s, &ov).expect("overrides")
}

/// The one piece of a `.vtu`.
fn piece(file: &Path) -> UnstructuredGridPiece {
    let vtk = Vtk::import(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("{}: not an unstructured grid", file.display())
    };
    pieces[0].load_piece_data(None).expect("inline piece")
}

fn array(attrs: &[Attribute], name: &str) -> Vec<f64> {
    attrs
        .iter()
        .find_map(|a| match a {
            Attribute::DataArray(d) if d.name == name => d.data.clone().cast_into::<f64>(),
            _ => None,
        })
        .unwrap_or_else(|| panic!("no array {name}"))
}

#[test]
fn bem_boundary_and_grid() {
    let dir = temp("bem");
    let s = case(
        "first_scene",
        &[
            ("outputs.vtk", "true"),
            ("outputs.plots", "false"),
            (
                "outputs.grids",
                r#"[{"name": "g", "from": [0.1, 0.05], "to": [0.3, 0.2], "nx": 5, "ny": 4}]"#,
            ),
        ],
    );
    let summary = run_scene(&s, &dir, true).expect("runs");
    let b = piece(&dir.join("boundary.vtu"));
    assert_eq!(b.cells.types.len(), summary.elements.expect("elements"));
    assert_eq!(
        array(&b.data.cell, "traction").len(),
        3 * b.cells.types.len()
    );
    let g = piece(&dir.join("grid_g.vtu"));
    assert_eq!(g.num_points(), 20);
    let vm = array(&g.data.point, "von_mises");
    assert!(vm.iter().all(|v| *v > 0.0 && v.is_finite()), "{vm:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pd_nodes_with_displacement_and_damage() {
    let dir = temp("pd");
    let s = case(
        "pd_cantilever",
        &[("outputs.vtk", "true"), ("outputs.plots", "false")],
    );
    let summary = run_scene(&s, &dir, true).expect("runs");
    let nodes = summary.extra["nodes"].as_u64().expect("nodes") as usize;
    let p = piece(&dir.join("nodes.vtu"));
    assert_eq!(p.num_points(), nodes);
    assert_eq!(array(&p.data.point, "damage").len(), nodes);
    let u = array(&p.data.point, "displacement");
    assert!(u.iter().any(|v| *v != 0.0));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn coupled_window_nodes_and_bem_body() {
    let dir = temp("coupled");
    let s = case(
        "coupled_sent_a5",
        &[("outputs.vtk", "true"), ("outputs.plots", "false")],
    );
    let summary = run_scene(&s, &dir, true).expect("runs");
    let p = piece(&dir.join("pd_nodes.vtu"));
    assert_eq!(
        p.num_points() as u64,
        summary.extra["pd_nodes"].as_u64().expect("pd_nodes")
    );
    // The BEM body: one cell per element; under the SENT tension the crack's faces open
    // (displacements of both signs across the crack) and the loaded edges carry traction.
    let b = piece(&dir.join("boundary.vtu"));
    assert_eq!(b.cells.types.len(), summary.elements.expect("elements"));
    let t = array(&b.data.cell, "traction");
    assert_eq!(t.len(), 3 * b.cells.types.len());
    assert!(t.iter().all(|v| v.is_finite()) && t.iter().any(|v| v.abs() > 0.4));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn growth_snapshots_paths_and_collection() {
    use pdbem::growth::{FieldSnapshot, GrowthHistory, PathPoint, TipPath};
    let dir = temp("growth");
    let ctx = pdbem::runner::RunContext::new(&dir, true).expect("context");
    let point = |x: f64, y: f64, step| PathPoint {
        x,
        y,
        step,
        load: 1.0,
    };
    let h = GrowthHistory {
        paths: vec![TipPath {
            name: "c.end".into(),
            points: vec![point(0.0, 0.0, 0), point(0.1, 0.0, 1), point(0.2, 0.05, 2)],
            ended: None,
        }],
        snapshots: vec![
            FieldSnapshot {
                step: 0,
                label: "damage_window0_step0".into(),
                points: vec![[0.0, 0.0], [0.1, 0.0]],
                values: vec![0.0, 0.4],
                tips: Vec::new(),
                groups: Vec::new(),
            },
            FieldSnapshot {
                step: 2,
                label: "displacement".into(),
                points: vec![[0.0, 0.0]],
                values: vec![1e-3],
                tips: Vec::new(),
                groups: Vec::new(),
            },
        ],
        ..Default::default()
    };
    pdbem::growth::vtk::write(&ctx, &h).expect("writes");
    ctx.writer.commit().expect("commit");
    let pvd = std::fs::read_to_string(dir.join("growth.pvd")).expect("pvd");
    assert!(pvd.contains("snapshot_damage_window0_step0.vtu"), "{pvd}");
    assert!(pvd.contains("snapshot_displacement_step002.vtu"), "{pvd}");
    let s = piece(&dir.join("snapshot_damage_window0_step0.vtu"));
    assert_eq!(array(&s.data.point, "damage"), [0.0, 0.4]);
    let paths = piece(&dir.join("paths.vtu"));
    assert_eq!(array(&paths.data.cell, "step"), [1.0, 2.0]);
    let _ = std::fs::remove_dir_all(&dir);
}
