//! Probe: seed 001 crack initiation on an n x n grid.
use pdbem_pd::cases::{seed001_crack, CrackKind};
use pdbem_pd::measure::{crack_tips, kink_angle, ramp_to_initiation, RampParams};
use pdbem_pd::PdModel;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let kind = match a.get(1).map(|s| s.as_str()) {
        Some("i") => CrackKind::Inclined,
        Some("e") => CrackKind::Edge,
        _ => CrackKind::Central,
    };
    let n: usize = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(80);
    let start: f64 = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(5.0);
    let grow: f64 = a.get(4).and_then(|s| s.parse().ok()).unwrap_or(0.0);
    let case = seed001_crack(kind, n);
    let delta = case.problem.horizon();
    let mut m = PdModel::new(&case.problem).unwrap();
    let tips = crack_tips(&case.problem.cracks[0], kind == CrackKind::Edge);
    let p = RampParams {
        start,
        step: 0.25,
        max_load: 25.0,
        run_length: 2.0 * delta,
        grow_to: grow,
        max_rounds: 400,
    };
    let t = std::time::Instant::now();
    let r = ramp_to_initiation(&mut m, &tips, &p).unwrap();
    println!(
        "{kind:?} n {n}: first {:?} init {:?} ext {:.2e} time {:.1}s fact {} ({:.1}s)",
        r.first_break_load,
        r.initiation_load,
        r.extension,
        t.elapsed().as_secs_f64(),
        r.info.factorizations,
        r.info.time_factorization_s
    );
    for (i, tip) in tips.iter().enumerate() {
        println!(
            "tip {i}: kink {:?}",
            kink_angle(&m, *tip, 1.5 * delta, 4.0 * delta)
        );
    }
}
