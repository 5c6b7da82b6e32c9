//! Translation invariance: a body moved away from the origin gives the same results.
//! Positions are rounded to 2.2e-16 of their magnitude (1.9e-9 m at 1e7 m), and two
//! geometric ties of a PD window were decided in bands of 1e-9 of a spacing: a lattice
//! bond through an interface element's end point (the traction map's crossing share) and
//! a cell centre on the edge of a refined zone. At 1e7 m, 1e8 window spacings, the SENT
//! window gave K_I 2.3 % high, and at 4.9e6 m the refined window (finest cells 0.025 m)
//! split the cells of 556 nodes instead of 700, both with exit 0. `pdbem_geometry::tie_band` widens the bands to the coordinates'
//! round-off; `pdbem check` refuses PD bodies farther than 2e8 of their smallest spacing
//! from the origin (`src/scene/validate/strain.rs`).

use pdbem::scene::Scene;

/// The case file `name` with every point and rectangle corner moved by (off, off).
fn moved(name: &str, off: f64) -> Scene {
    let path = format!("{}/cases/{name}.ron", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(&path).expect("case file");
    let shifted = src
        .replace("x0: 0, y0: 0", &format!("x0: {off:?}, y0: {off:?}"))
        .replace(
            "start: (10, 10)",
            &format!("start: ({:?}, {:?})", 10.0 + off, 10.0 + off),
        );
    assert!(off == 0.0 || shifted != src, "{name}: nothing moved");
    Scene::from_ron_str(&shifted, &path).expect("valid scene")
}

/// (K_I, CMOD, PD nodes) of a coupled solve.
fn solved(scene: &Scene) -> (f64, f64, usize) {
    let (s, _) = pdbem::run_coupled::solve(scene).expect("solves");
    let cmod = s.cracks[0].cmod.expect("an edge crack has a CMOD");
    let nodes = s.extra["pd_nodes"].as_u64().expect("PD nodes") as usize;
    (s.tips[0].k1, cmod, nodes)
}

#[test]
fn a_coupled_window_gives_its_results_anywhere() {
    // 1e8 and 1.96e8 spacings of the windows' finest cells (0.1 m and 0.025 m).
    for (name, off) in [("coupled_sent_a5", 1e7), ("coupled_sent_a5_refined", 4.9e6)] {
        let (k, cmod, nodes) = solved(&moved(name, 0.0));
        let (k_far, cmod_far, nodes_far) = solved(&moved(name, off));
        println!(
            "{name}: K_I {k} -> {k_far}, CMOD {cmod} -> {cmod_far}, nodes {nodes} -> {nodes_far}"
        );
        assert_eq!(
            nodes, nodes_far,
            "{name}: the refined zone split other cells"
        );
        assert!(
            (k_far / k - 1.0).abs() < 1e-5,
            "{name}: K_I {k} at the origin, {k_far} at {off} m"
        );
        assert!(
            (cmod_far / cmod - 1.0).abs() < 1e-5,
            "{name}: CMOD {cmod} at the origin, {cmod_far} at {off} m"
        );
    }
}

#[test]
fn a_pd_body_far_from_the_origin_is_refused() {
    // The SENT window's spacing is 0.1 m: 2e8 spacings are 2e7 m.
    let path = format!("{}/cases/coupled_sent_a5.ron", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(&path).unwrap();
    let far = src
        .replace("x0: 0, y0: 0", "x0: 3e7, y0: 0")
        .replace("start: (10, 10)", "start: (30000010, 10)");
    let err = Scene::from_ron_str(&far, "cases/x.ron").expect_err("refused");
    let msg = err.to_string();
    assert!(
        msg.contains("cases/x.ron: body.outline = reaching 3.0000e7 m from the origin"),
        "{msg}"
    );
    assert!(msg.contains("subtract (3.000001e7, 5.000000e0)"), "{msg}");
    // The BEM alone has no lattice: the same body without its window is accepted.
    let bem = far
        .replace("    pd: (failure: Elastic),\n", "")
        .split("    coupling: (")
        .next()
        .unwrap()
        .to_string()
        + "    reference: SentTada(width: 10, sigma: 0.5),\n)\n";
    Scene::from_ron_str(&bem, "cases/x.ron").expect("BEM alone is not bounded");
}
