//! Shared by the PD-BEM growth test files: the shipped scenes and a PD-BEM run through the
//! runner.

use pdbem::scene::Scene;

/// The shipped scene `cases/{name}.ron`.
pub fn scene(name: &str) -> Scene {
    Scene::load(format!("cases/{name}.ron")).expect("case file")
}

/// PD-BEM growth of `sc` through the runner (outputs to a scratch folder, discarded),
/// without the K record along the path (`growth.sif_spacing: 0`; one BEM solve per row,
/// up to half the run; it is verified in `verification_growth_sif.rs`).
pub fn run_pd_bem(sc: &Scene, tag: &str) -> pdbem::growth::GrowthHistory {
    let dir = std::env::temp_dir().join(format!("pdbem-{tag}-{}", std::process::id()));
    let ctx = pdbem::runner::RunContext::new(&dir, true).unwrap();
    let mut sc = sc.clone();
    if let Some(g) = sc.growth.as_mut() {
        g.sif_spacing = Some(0.0);
    }
    let h = pdbem::growth::pd_bem::run(&sc, &ctx).unwrap();
    ctx.writer.abort();
    h
}
