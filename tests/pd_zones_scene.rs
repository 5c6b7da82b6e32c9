//! `pd.refine_zones` from a scene: fixed zones of finer cells on a stand-alone grid
//! (`pdbem_pd::mixed`). `cases/pd_edge_crack_zone.ron` (the seed 004 Table 2 plate with
//! G_c, a 2 mm grid with a 6 mm zone of 1 mm cells at the tip) through `pdbem run`'s
//! runner gives the uniform 1 mm grid's crack-initiation loads, which the uniform 2 mm
//! grid misses; zones that would split a pin's cell or hold no cell are refused when the
//! problem is built (what `pdbem check` does).

use std::path::{Path, PathBuf};

use pdbem::scene::path::{parse_value, with_overrides};
use pdbem::scene::Scene;

fn case() -> Scene {
    let f = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/pd_edge_crack_zone.ron");
    Scene::load(&f).expect("valid case")
}

fn with(scene: &Scene, overrides: &[(&str, &str)]) -> Scene {
    let o: Vec<_> = overrides
        .iter()
        .map(|(p, v)| (p.to_string(), parse_value(v)))
        .collect();
    with_overrides(scene, &o).expect("override")
}

/// First-break and initiation loads (Pa), nodes and refined nodes of a run of `scene`.
fn loads(scene: &Scene, tag: &str) -> (f64, f64, u64, u64) {
    let dir: &Path =
        &std::env::temp_dir().join(format!("pdbem-zones-{tag}-{}", std::process::id()));
    let s = pdbem::runner::run_scene(scene, dir, true).expect("run");
    let x = &s.extra;
    assert!(s.notes.is_empty(), "{tag}: {:?}", s.notes);
    assert!(
        x["kink_deg"].as_f64().is_some_and(|k| k.abs() < 5.0),
        "{tag}: a straight mode-I crack, got {}",
        x["kink_deg"]
    );
    assert!(dir.join("nodes.csv").exists());
    let _ = std::fs::remove_dir_all(dir);
    (
        x["first_break_load"].as_f64().expect("first break"),
        x["initiation_load"].as_f64().expect("initiation"),
        x["nodes"].as_u64().unwrap(),
        x.get("refined_nodes").and_then(|v| v.as_u64()).unwrap_or(0),
    )
}

#[test]
fn a_tip_zone_gives_the_finer_grids_initiation_loads() {
    let zoned = case();
    let coarse = with(&zoned, &[("pd.refine_zones", "[]")]);
    let fine = with(&coarse, &[("pd.dx", "0.001")]);
    let z = loads(&zoned, "zone");
    let c = loads(&coarse, "coarse");
    let f = loads(&fine, "fine");
    eprintln!("zone {z:?}, 2 mm {c:?}, 1 mm {f:?}");
    // Measured (1 MPa steps): zone 41 / 45 MPa with 1376 nodes (168 of them 1 mm
    // children of 42 cells), uniform 1 mm 41 / 45 MPa with 5000, uniform 2 mm 33 / 43 MPa.
    let step = 1e6 * (1.0 + 1e-9);
    assert!(
        (z.0 - f.0).abs() <= step,
        "first break {} against {}",
        z.0,
        f.0
    );
    assert!(
        (z.1 - f.1).abs() <= step,
        "initiation {} against {}",
        z.1,
        f.1
    );
    assert!(
        f.1 - c.1 >= 2e6 * (1.0 - 1e-9),
        "the 2 mm grid {} against {}",
        c.1,
        f.1
    );
    assert_eq!((z.2, z.3), (1376, 168));
    assert!(3 * z.2 < f.2, "{} nodes against {}", z.2, f.2);
    let e = pdbem::setup::estimate::of(&zoned).expect("estimate");
    assert!(
        e.pd_nodes >= z.2 as f64,
        "estimate {} below {}",
        e.pd_nodes,
        z.2
    );
}

#[test]
fn zones_on_a_pin_or_outside_the_grid_are_refused_before_the_run() {
    // The pure-traction plate is pinned at the middle of its bottom row, (25, 1) mm.
    let pin = with(
        &case(),
        &[(
            "pd.refine_zones",
            "[{\"centre\": [0.025, 0.001], \"half_size\": 0.002, \"levels\": 1}]",
        )],
    );
    let e = pdbem::setup::footprint::of(&pin).unwrap_err();
    let text = format!("{e:#}");
    assert!(
        text.contains("pd_edge_crack_zone.ron")
            && text.contains("pd.refine_zones.0")
            && text.contains("pins"),
        "{text}"
    );
    let outside = with(
        &case(),
        &[(
            "pd.refine_zones",
            "[{\"centre\": [0.2, 0.2], \"half_size\": 0.002, \"levels\": 1}]",
        )],
    );
    let text = format!("{:#}", pdbem::setup::footprint::of(&outside).unwrap_err());
    assert!(
        text.contains("pd_edge_crack_zone.ron")
            && text.contains(
                "pd.refine_zones.0: the zone holds no grid cell with a point in the body"
            ),
        "{text}"
    );
}

#[test]
fn a_two_level_zone_against_coarse_cells_gets_a_note() {
    let lone = with(
        &case(),
        &[(
            "pd.refine_zones",
            "[{\"centre\": [0.015, 0.05], \"half_size\": 0.004, \"levels\": 2}]",
        )],
    );
    assert!(
        lone.notes
            .iter()
            .any(|n| n.contains("pd.refine_zones.0") && n.contains("size jump of 4")),
        "{:?}",
        lone.notes
    );
    // Nested as in docs/seed004.md: 1 mm within 8 mm, 0.5 mm within 4 mm (46 MPa, the
    // uniform 0.5 mm grid's initiation load).
    let nested = with(
        &case(),
        &[(
            "pd.refine_zones",
            "[{\"centre\": [0.015, 0.05], \"half_size\": 0.008, \"levels\": 1}, {\"centre\": [0.015, 0.05], \"half_size\": 0.004, \"levels\": 2}]",
        )],
    );
    assert!(nested.notes.is_empty(), "{:?}", nested.notes);
}
