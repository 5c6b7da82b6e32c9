//! `pd.model: StateBased` in a stand-alone PD scene (src/run_pd.rs): a free plate under
//! uniaxial tension with nu = 0.3 runs with the default solver (the explicit-implicit
//! switch) and contracts laterally by nu; the same scene with the bond-based model gets
//! a note that it ignores material.nu.

use pdbem::scene::Scene;

fn plate(model: &str) -> String {
    format!(
        r#"(name: "osb", material: (E: 2e11, nu: 0.3, plane: Stress),
           body: (outline: Rectangle(x0: 0, y0: 0, width: 2, height: 1)),
           boundary: [(on: "left", x: Traction(-1e6)), (on: "right", x: Traction(1e6))],
           pd: (model: {model}, failure: Elastic, dx: 0.05, surface_correction: true))"#
    )
}

#[test]
fn state_based_plate_contracts_by_nu() {
    let scene = Scene::from_ron_str(&plate("StateBased"), "osb.ron").unwrap();
    assert!(scene.notes.is_empty(), "{:?}", scene.notes);
    let (_, model) = pdbem::run_pd::solve(&scene).unwrap();
    let (x, u) = (model.positions(), model.displacements());
    // Strains from the displacement differences over the middle of the plate.
    let near = |p: [f64; 2]| {
        (0..model.n_real())
            .min_by(|&a, &b| {
                let d = |k: usize| (x[k][0] - p[0]).hypot(x[k][1] - p[1]);
                d(a).total_cmp(&d(b))
            })
            .unwrap()
    };
    let (l, r, b, t) = (
        near([0.7, 0.5]),
        near([1.3, 0.5]),
        near([1.0, 0.3]),
        near([1.0, 0.7]),
    );
    let exx = (u[r][0] - u[l][0]) / (x[r][0] - x[l][0]);
    let eyy = (u[t][1] - u[b][1]) / (x[t][1] - x[b][1]);
    let (e, nu) = (1e6 / exx, -eyy / exx);
    println!("E {e:.4e}, nu {nu:.4}");
    // Measured: E = 1.988e11 (-0.59 %) and nu = 0.3027 (+0.9 %), 40 x 20 cells, strains
    // from node pairs 0.6 m and 0.4 m apart.
    assert!((e / 2e11 - 1.0).abs() < 0.01, "E {e}");
    assert!((nu / 0.3 - 1.0).abs() < 0.02, "nu {nu}");
}

/// Elastic bonds take one equilibrium at the final load whatever `load.count` (src/run_pd.rs):
/// a ramp of 70 Newton steps on the 200 x 200 seed 001 plate took 230 s and gave the
/// one-step field to 1.6e-11. Implicit and ADR, a 20-step ramp against one step at the
/// same final factor: the same field, and as few iterations.
#[test]
fn an_elastic_ramp_is_one_equilibrium_at_the_final_load() {
    for solver in ["Implicit()", "Adr()"] {
        let src = |load: &str| {
            plate("StateBased").replace(
                "pd: (model: StateBased,",
                &format!("{load} pd: (solver: {solver}, model: StateBased,"),
            )
        };
        let ramp =
            Scene::from_ron_str(&src("load: (initial: 0.1, step: 0.1, count: 20),"), "r.ron")
                .unwrap();
        let once = Scene::from_ron_str(&src("load: (initial: 2.0),"), "o.ron").unwrap();
        let (sr, mr) = pdbem::run_pd::solve(&ramp).unwrap();
        let (so, mo) = pdbem::run_pd::solve(&once).unwrap();
        let umax = mo
            .displacements()
            .iter()
            .map(|u| u[0].hypot(u[1]))
            .fold(0.0, f64::max);
        let gap = mr
            .displacements()
            .iter()
            .zip(mo.displacements())
            .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
            .fold(0.0, f64::max);
        let it = |s: &pdbem::runner::RunSummary| s.extra["iterations"].as_u64().unwrap();
        println!(
            "{solver}: gap {gap:e} of {umax:e}, iterations {} and {}",
            it(&sr),
            it(&so)
        );
        assert!(gap <= 1e-9 * umax, "{solver}: {gap} of {umax}");
        assert_eq!(it(&sr), it(&so), "{solver}");
    }
}

#[test]
fn the_bond_based_model_notes_that_it_ignores_nu() {
    let scene = Scene::from_ron_str(&plate("Pmb"), "pmb.ron").unwrap();
    assert!(
        scene
            .notes
            .iter()
            .any(|n| n.contains("material.nu = 0.3") && n.contains("pd.model: StateBased")),
        "{:?}",
        scene.notes
    );
}

#[test]
fn an_unknown_model_is_refused_naming_the_field() {
    let err = Scene::from_ron_str(&plate("Lps"), "lps.ron")
        .unwrap_err()
        .to_string();
    println!("{err}");
    assert!(err.contains("Lps") && err.contains("StateBased"), "{err}");
}
