//! `pdbem check` reports what `pdbem run` builds: for every scene in `cases/`, the
//! footprint of the one setup layer ([`pdbem::setup::footprint`]) equals the mesh and PD
//! model the run itself solves on (BEM and coupled scenes are solved here; PD and growth
//! scenes are compared with the models their engines start from).

use std::path::PathBuf;

use pdbem::runner::{mode_of, Mode};
use pdbem::scene::{GrowthMode, Scene};
use pdbem::setup::footprint;

mod common_scene;

fn cases() -> Vec<PathBuf> {
    common_scene::case_files()
}

#[test]
fn check_reports_what_run_builds_for_every_case() {
    let mut checked = 0;
    for f in cases() {
        let scene = Scene::load(&f).expect("valid case");
        let fp = footprint::of(&scene).unwrap_or_else(|e| panic!("{}: {e:#}", f.display()));
        let name = f.display();
        match mode_of(&scene) {
            Mode::Bem => {
                let (summary, level) = pdbem::run_bem::solve(&scene).expect("solves");
                let b = fp.bem.expect("a BEM footprint");
                assert_eq!(Some(b.elements), summary.elements, "{name}: elements");
                assert_eq!(b.unknowns, level.info.unknowns, "{name}: unknowns");
                assert_eq!(b.matrix_bytes, level.info.memory_bytes, "{name}: bytes");
            }
            Mode::Coupled => {
                let (summary, out) = pdbem::run_coupled::solve(&scene).expect("solves");
                let b = fp.bem.expect("a BEM footprint");
                assert_eq!(Some(b.elements), summary.elements, "{name}: elements");
                let real: usize = out
                    .setup
                    .problem
                    .windows
                    .iter()
                    .map(|w| w.model.n_real())
                    .sum();
                assert_eq!(fp.pd_real, real, "{name}: PD nodes");
                assert_eq!(summary.extra["pd_nodes"], serde_json::json!(real), "{name}");
            }
            Mode::Pd => {
                let problem = pdbem::setup::pd::problem_from_scene(&scene).expect("PD problem");
                // Refinement on cells starts from its set-up's split grid.
                let cells = scene.pd.as_ref().and_then(|pd| {
                    pd.refinement
                        .as_ref()
                        .filter(|r| r.on_cells(&pd.failure, &pd.solver))
                });
                let model = match cells {
                    Some(r) => {
                        let crit = pdbem::run_pd::cell_criteria(r);
                        pdbem_pd::adapt::ramp::set_up(&problem, &crit)
                            .expect("set-up")
                            .0
                    }
                    None => pdbem_pd::PdModel::new(&problem).expect("PD model"),
                };
                assert_eq!(fp.pd_real, model.n_real(), "{name}: PD nodes");
                assert_eq!(fp.pd_bonds, model.n_bonds(), "{name}: PD bonds");
                assert!(fp.bem.is_none(), "{name}: no BEM body");
            }
            Mode::Growth => {
                let mode = scene.growth.as_ref().map(|g| g.mode).unwrap_or_default();
                match mode {
                    GrowthMode::PdBem => {
                        let input = pdbem::setup::growth::input(&scene).expect("input");
                        let g = input.growth().expect("growth");
                        let b = fp.bem.expect("a BEM footprint");
                        assert_eq!(b.elements, g.problem().mesh.len(), "{name}: elements");
                        assert_eq!(b.unknowns, g.bem_unknowns(), "{name}: unknowns");
                    }
                    GrowthMode::FullPd => {
                        let (model, _, _) = pdbem::growth::full_pd::model_of(&scene).unwrap();
                        assert_eq!(fp.pd_bonds, model.n_bonds(), "{name}: PD bonds");
                    }
                    GrowthMode::BemOnly => assert!(fp.bem.is_some(), "{name}"),
                }
            }
        }
        checked += 1;
    }
    assert!(checked >= 30, "every case checked ({checked})");
}

/// The same scene in its three growth modes: BEM-only starts from the static mesh, full
/// PD from the grid at the windows' spacing.
#[test]
fn growth_modes_count_their_own_models() {
    let f = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/growth_hole_edge.ron");
    let scene = Scene::load(&f).unwrap();
    let pdbem = footprint::of(&scene).unwrap();
    let bem_only =
        footprint::of(&pdbem::cli::with_growth_mode(&scene, GrowthMode::BemOnly).unwrap()).unwrap();
    let full =
        footprint::of(&pdbem::cli::with_growth_mode(&scene, GrowthMode::FullPd).unwrap()).unwrap();
    let static_mesh = pdbem::setup::bem::build(&scene, 1.0, 1.0)
        .unwrap()
        .mesh
        .len();
    assert_eq!(bem_only.bem.unwrap().elements, static_mesh);
    assert!(full.bem.is_none() && full.pd_real > 10 * pdbem.pd_real);
    let co = scene.coupling.as_ref().unwrap();
    assert_eq!(co.dx(), co.side / co.n as f64);
}
