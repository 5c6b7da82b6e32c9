//! PD-BEM coupling for any Poisson ratio (seed 002 section 3.2.1 plate, seed 004 model):
//! the SENT plate a/W = 0.5 with nu = 0.3 and a state-based PD window on the tip must
//! give the CMOD of the BEM-only solve of the same plate (same element size) within 1 %,
//! in plane stress and in plane strain.

use pdbem::scene::{Plane, Scene};

/// (coupled CMOD, BEM-only CMOD, coupling iterations) of the plate in `plane`.
fn cmods(plane: Plane) -> (f64, f64, usize) {
    let mut coupled = Scene::load("cases/coupled_sent_a5_state_based.ron").unwrap();
    coupled.material.plane = plane;
    let (s, out) = pdbem::run_coupled::solve(&coupled).unwrap();
    let mut bem = Scene::load("cases/sent_bem_a5.ron").unwrap();
    bem.material.nu = coupled.material.nu;
    bem.material.plane = plane;
    let (sb, _) = pdbem::run_bem::solve(&bem).unwrap();
    (
        s.cracks[0].cmod.unwrap(),
        sb.cracks[0].cmod.unwrap(),
        out.info.iterations,
    )
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
