//! The size budget (issue 17): the cheap estimate of [`pdbem::setup::estimate`] is close
//! to the exact footprint for every case, and scenes that would need more memory than
//! the budget fail before anything is built, naming the setting that drives the size.

use std::path::PathBuf;

use pdbem::scene::Scene;
use pdbem::setup::{estimate, footprint};

const GIB: u64 = 1 << 30;

fn load(src: &str) -> Scene {
    Scene::from_ron_str(src, "cases/x.ron").unwrap_or_else(|e| panic!("valid scene: {e}"))
}

/// A strip `w` x `h` with an edge crack of length `a` from the middle of its top edge.
fn strip(w: f64, h: f64, a: f64, extra: &str) -> String {
    format!(
        r#"(name: "s", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: {w}, height: {h})),
        cracks: [(name: "c", start: ({}, {h}), angle_deg: -90, length: {a})],
        boundary: [(on: "left", x: Traction(-1)), (on: "right", x: Traction(1))], {extra})"#,
        0.5 * w
    )
}

#[test]
fn the_estimate_is_close_to_the_exact_footprint_of_every_case() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("cases/")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "ron"))
        .collect();
    files.sort();
    for f in files {
        let scene = Scene::load(&f).expect("valid case");
        let e = estimate::check(&scene).unwrap_or_else(|e| panic!("{}: {e:#}", f.display()));
        let fp = footprint::of(&scene).expect("footprint");
        let name = f.display();
        if let Some(b) = fp.bem {
            // Coupled meshes leave out the outline inside the windows: the estimate counts it.
            let ratio = e.bem_elements / b.elements as f64;
            assert!(
                (0.7..=2.0).contains(&ratio),
                "{name}: {} estimated BEM elements, {} built",
                e.bem_elements,
                b.elements
            );
        }
        // PD: the estimate puts fictitious layers all round, the models only where a
        // condition needs them.
        if fp.pd_nodes > 0 {
            let ratio = e.pd_nodes / fp.pd_nodes as f64;
            assert!(
                (0.5..=3.0).contains(&ratio),
                "{name}: {} estimated PD nodes, {} built",
                e.pd_nodes,
                fp.pd_nodes
            );
            let ratio = e.pd_bonds / fp.pd_bonds as f64;
            assert!(
                (0.5..=5.0).contains(&ratio),
                "{name}: {} estimated PD bonds, {} built",
                e.pd_bonds,
                fp.pd_bonds
            );
        }
    }
}

#[test]
fn a_long_strip_with_default_sizes_fits_and_names_the_default_size_over_a_small_budget() {
    // Local-feature sizes: the 1000:1 strip needs about 3000 elements, not 2e5 (1.2 TiB
    // before them); the estimate is the exact count.
    let scene = load(&strip(1000.0, 1.0, 0.5, ""));
    let e = estimate::of(&scene).unwrap();
    assert!(e.bem_elements < 4000.0, "{} elements", e.bem_elements);
    e.within(&scene, 12 * GIB).expect("fits");
    let msg = format!("{:#}", e.within(&scene, 64 << 20).expect_err("over 64 MiB"));
    assert!(msg.contains("cases/x.ron"), "{msg}");
    assert!(msg.contains("default element size"), "{msg}");
    assert!(msg.contains("give a larger bem.element_size"), "{msg}");
    assert!(msg.contains("> budget 64.000 MiB"), "{msg}");
}

#[test]
fn a_tiny_element_size_is_over_budget_naming_bem_element_size() {
    let scene = load(&strip(20.0, 10.0, 5.0, "bem: (element_size: 0.0005)"));
    let msg = format!(
        "{:#}",
        estimate::of(&scene)
            .unwrap()
            .within(&scene, 12 * GIB)
            .unwrap_err()
    );
    assert!(
        msg.contains("bem.element_size = 0.0005 gives about"),
        "{msg}"
    );
    assert!(msg.contains("raise bem.element_size"), "{msg}");
}

#[test]
fn a_deep_crack_fits_and_names_the_crack_over_a_small_budget() {
    // a/W = 0.999: the tip is 0.01 m from the bottom edge; its tip zone (L/80 within L)
    // grades out, so the mesh stays small (16 882 elements before local sizes).
    let scene = load(&strip(20.0, 10.0, 9.99, "bem: (element_size: 0.1)"));
    let e = estimate::of(&scene).unwrap();
    assert!(e.bem_elements < 2500.0, "{} elements", e.bem_elements);
    let msg = format!("{:#}", e.within(&scene, 1 << 20).unwrap_err());
    assert!(msg.contains("cracks.0 ('c')"), "{msg}");
    assert!(msg.contains("bem.group_sizes.c"), "{msg}");
}

#[test]
fn a_tiny_crack_group_size_is_over_budget_naming_it() {
    let scene = load(&strip(
        20.0,
        10.0,
        9.99,
        r#"bem: (element_size: 0.1, group_sizes: {"c": 1e-6})"#,
    ));
    let msg = format!(
        "{:#}",
        estimate::of(&scene)
            .unwrap()
            .within(&scene, 12 * GIB)
            .unwrap_err()
    );
    assert!(msg.contains("bem.group_sizes.c = 0.000001"), "{msg}");
}

#[test]
fn a_tiny_tip_element_is_over_budget_naming_the_tip_refinement() {
    let scene = load(&strip(
        20.0,
        10.0,
        5.0,
        "bem: (element_size: 0.1, tip_refinement: (element_size: 1e-7, radius: 1))",
    ));
    let msg = format!(
        "{:#}",
        estimate::of(&scene)
            .unwrap()
            .within(&scene, GIB)
            .unwrap_err()
    );
    assert!(
        msg.contains("bem.tip_refinement (element_size = 0.0000001)"),
        "{msg}"
    );
    assert!(
        msg.contains("raise bem.tip_refinement.element_size"),
        "{msg}"
    );
}

#[test]
fn a_fine_pd_grid_is_over_budget_naming_pd_nx() {
    let scene = load(&strip(20.0, 10.0, 5.0, "pd: (nx: 100000)"));
    let msg = format!(
        "{:#}",
        estimate::of(&scene)
            .unwrap()
            .within(&scene, 12 * GIB)
            .unwrap_err()
    );
    assert!(msg.contains("pd.nx = 100000 gives about"), "{msg}");
    assert!(msg.contains("lower pd.nx"), "{msg}");
}

#[test]
fn fine_windows_are_over_budget_naming_coupling_n() {
    let scene = load(&strip(
        20.0,
        10.0,
        5.0,
        "pd: (), coupling: (side: 2, n: 5000)",
    ));
    let msg = format!(
        "{:#}",
        estimate::of(&scene)
            .unwrap()
            .within(&scene, GIB)
            .unwrap_err()
    );
    assert!(msg.contains("coupling.n = 5000"), "{msg}");
}

#[test]
fn byte_counts_with_suffixes() {
    assert_eq!(estimate::parse_bytes("4G"), Ok(4 * GIB));
    assert_eq!(estimate::parse_bytes("512M"), Ok(512 << 20));
    assert_eq!(estimate::parse_bytes("1.5GiB"), Ok(3 * GIB / 2));
    assert_eq!(estimate::parse_bytes("1073741824"), Ok(GIB));
    for bad in ["", "G", "-1G", "1e400", "four"] {
        assert!(estimate::parse_bytes(bad).is_err(), "{bad}");
    }
}

#[test]
fn state_based_bonds_are_estimated_at_their_own_size() {
    // The state-based model holds more per bond than PMB (constants, reverse index and the
    // force pass's half forces and lengths): the estimate counts its bonds at
    // STATE_BASED_BOND_BYTES, and both per-bond sizes cover what the models hold
    // (`pdbem bench pd` measures it the same way).
    let pmb = estimate::of(&load(&strip(20.0, 10.0, 5.0, "pd: (nx: 200)"))).unwrap();
    let osb = estimate::of(&load(&strip(
        20.0,
        10.0,
        5.0,
        "pd: (nx: 200, model: StateBased)",
    )))
    .unwrap();
    assert_eq!(pmb.pd_bonds, osb.pd_bonds);
    let extra = osb.pd_bytes() - pmb.pd_bytes();
    let expected = osb.pd_bonds * (estimate::STATE_BASED_BOND_BYTES - estimate::BOND_BYTES);
    assert!(
        (extra - expected).abs() <= 1e-9 * expected,
        "{extra} vs {expected}"
    );
    use pdbem_pd::problem::PdMaterial;
    for (material, bytes) in [
        (PdMaterial::Pmb, estimate::BOND_BYTES),
        (
            PdMaterial::StateBased { poisson_ratio: 0.3 },
            estimate::STATE_BASED_BOND_BYTES,
        ),
    ] {
        let held = pdbem_pd::bench::kernel_of(19, 0.0, material).bytes_per_bond;
        assert!(
            held <= bytes,
            "{material:?}: {held} bytes per bond, estimated {bytes}"
        );
    }
}
