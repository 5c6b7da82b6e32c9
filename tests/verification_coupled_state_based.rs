//! PD-BEM coupling for any Poisson ratio (seed 002 section 3.2.1 plate, seed 004 model):
//! the SENT plate a/W = 0.5 with nu = 0.3 and a state-based PD window on the tip must
//! give the CMOD of the BEM-only solve of the same plate (same element size) within 1 %,
//! in plane stress and in plane strain.

use pdbem::scene::{Plane, Scene};

/// (coupled CMOD, BEM-only CMOD, coupling iterations) of the plate in `plane`.
fn cmods(plane: Plane) -> (f64, f64, usize) {
    let mut coupled = Scene::load("cases/coupled_sent_a5_state_based.ron").unwrap();
    coupled.material.plane = plane;
    cmods_of(coupled)
}

/// (coupled CMOD, BEM-only CMOD, coupling iterations) of the `coupled` plate.
fn cmods_of(coupled: Scene) -> (f64, f64, usize) {
    let (s, out) = pdbem::run_coupled::solve(&coupled).unwrap();
    (
        s.cracks[0].cmod.unwrap(),
        bem_cmod(&coupled),
        out.info.iterations,
    )
}

/// The CMOD of the BEM-only solve of the `coupled` plate's material (same element size).
fn bem_cmod(coupled: &Scene) -> f64 {
    let mut bem = Scene::load("cases/sent_bem_a5.ron").unwrap();
    bem.material.nu = coupled.material.nu;
    bem.material.plane = coupled.material.plane;
    let (sb, _) = pdbem::run_bem::solve(&bem).unwrap();
    sb.cracks[0].cmod.unwrap()
}

#[test]
fn sent_a5_nu_0_3_cmod_within_one_percent_of_bem_alone() {
    for plane in [Plane::Stress, Plane::Strain] {
        let (c, b, it) = cmods(plane);
        let err = c / b - 1.0;
        println!("{plane:?}: coupled CMOD {c:.6e}, BEM alone {b:.6e}, difference {err:+.4} ({it} iterations)");
        // Measured: +0.48 % (plane stress, 10 IQN-ILS iterations) and +0.59 % (plane
        // strain, 11); PMB at nu = 1/3 on coupled_sent_a5: +0.54 %. Without the surface
        // correction of the window (the truncated families of its outer virtual nodes):
        // +0.95 % in plane stress, +0.97 % at nu = 1/3.
        assert!(err.abs() < 0.01, "{plane:?}: {err}");
    }
}

/// The plate in plane strain at Poisson ratio `nu`.
fn plane_strain_plate(nu: f64) -> Scene {
    let mut s = Scene::load("cases/coupled_sent_a5_state_based.ron").unwrap();
    s.material.plane = Plane::Strain;
    s.material.nu = nu;
    s
}

#[test]
fn a_nearly_incompressible_body_is_noted_and_named_as_the_cause_of_a_stall() {
    // nu = 0.499 in plane strain (2-D bulk modulus 500 times the shear modulus): the
    // coupling iteration stalls (measured: residual 0.17 after 50 IQN-ILS iterations);
    // `check` notes it and the failed solve names it as the likely cause.
    let stiff = plane_strain_plate(0.499);
    let fp = pdbem::setup::footprint::of(&stiff).unwrap();
    let named = |t: &str, nu: &str, ratio: &str| {
        t.contains(&format!("material.nu = {nu} in plane strain"))
            && t.contains(&format!("is {ratio} times the shear modulus"))
    };
    assert!(
        fp.notes.iter().any(|n| named(n, "0.499", "500")),
        "{:?}",
        fp.notes
    );
    let e = format!("{:#}", pdbem::run_coupled::solve(&stiff).err().unwrap());
    assert!(
        e.contains("likely cause") && named(&e, "0.499", "500"),
        "{e}"
    );
    // nu = 0.49 (ratio 50) converges, noted: the windows stiffen, the CMOD falls
    // below the BEM alone's by more than at nu = 0.3 (measured -1.70 % against +0.59 %),
    // within the run's error estimate.
    let soft = plane_strain_plate(0.49);
    let (s, out) = pdbem::run_coupled::solve(&soft).unwrap();
    let (c, est) = (s.cracks[0].cmod.unwrap(), s.cracks[0].cmod_err_est.unwrap());
    let b = bem_cmod(&soft);
    println!("nu = 0.49, plane strain: coupled CMOD {c:.6e} (estimate {est:.3e}), BEM alone {b:.6e}, {} iterations", out.info.iterations);
    assert!(
        s.notes.iter().any(|n| named(n, "0.49", "50")),
        "{:?}",
        s.notes
    );
    assert!(
        (c - b).abs() <= est && c / b - 1.0 < -0.01 && c / b - 1.0 > -0.025,
        "{c} {b} {est}"
    );
    // nu = 0.45 (ratio 10): no note.
    assert!(pdbem::setup::footprint::of(&plane_strain_plate(0.45))
        .unwrap()
        .notes
        .is_empty());
}
