use pdbem::scene::Scene;
use pdbem_pd::solvers::switching;
#[test]
fn dbg() {
    let scene = Scene::load("cases/coupled_sent_a5.ron").unwrap();
    let mut setup = pdbem::run_coupled::prepare(&scene).unwrap();
    let w = &mut setup.problem.windows[0];
    println!(
        "real {} virt {} coupled {} cracks {:?}",
        w.model.n_real(),
        w.model.virtual_nodes().len(),
        w.interface.coupled.len(),
        w.problem.cracks
    );
    println!("elements {:?}", w.interface.elements.len());
    let x: Vec<f64> = w
        .interface
        .positions
        .iter()
        .flat_map(|p| [1e-4 * p.x, 0.0])
        .collect();
    let r = pdbem_coupling::iteration::solve_window(
        w,
        &x,
        &pdbem_coupling::PdSolve::Implicit(pdbem_pd::solvers::implicit::ImplicitParams::default()),
    );
    println!("{r:?}");
    if let pdbem_coupling::PdSolve::Switching(p) = pdbem_coupling::PdSolve::default() {
        let info = switching::solve(&mut w.model, &p);
        println!("{:?}", info.map(|i| i.switch_points));
    }
}
