//! When does the branching plate fork, measured at one physical length for every grid?
//! [`pdbem_pd::dynamics::crack::CrackTracker`] splits columns at gaps wider than 2.5 dx
//! and wants the split to persist over a horizon, both in the grid's own spacing, so a
//! finer grid reports its branch when the bands are closer together. This probe runs seed
//! 004's plate (`cases::branching_plate`, case `sigma` in MPa) at spacing `dx` and
//! measures every 0.5 us with the grid's own tracker and with one at the 1 mm grid's
//! lengths (2.5 mm gaps over 3.015 mm). Arguments: dx (default 5e-4), sigma (default 1).
//!
//! `cargo run --release -p pdbem-pd --example branch_time_probe -- 5e-4 1`

use pdbem_pd::cases::{branching_plate, SEED004_DENSITY};
use pdbem_pd::dynamics::crack::CrackTracker;
use pdbem_pd::dynamics::{run, DynamicsObserver, ExplicitParams};
use pdbem_pd::PdModel;

struct Probe {
    own: CrackTracker,
    physical: CrackTracker,
    own_time: Option<f64>,
    physical_time: Option<f64>,
}

impl DynamicsObserver for Probe {
    fn snapshot(&mut self, time: f64, model: &PdModel) {
        if self.own_time.is_none() && self.own.measure(model).branch.is_some() {
            self.own_time = Some(time);
        }
        if self.physical_time.is_none() && self.physical.measure(model).branch.is_some() {
            self.physical_time = Some(time);
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let dx: f64 = args.get(1).map_or(Ok(5e-4), |s| s.parse())?;
    let sigma: f64 = args.get(2).map_or(Ok(1.0), |s| s.parse())?;
    let case = branching_plate(dx, sigma * 1e6);
    let mut model = PdModel::new(&case.problem)?;
    let cracks = &case.problem.cracks;
    let n = model.n_real();
    let pos = model.positions()[..n].to_vec();
    let mut probe = Probe {
        own: CrackTracker::new(&model, cracks, 0.4),
        physical: CrackTracker::for_points(&pos, cracks, 0.4, 1e-3, 3.015e-3),
        own_time: None,
        physical_time: None,
    };
    let end = 50e-6;
    let p = ExplicitParams {
        density: SEED004_DENSITY,
        end_time: end,
        dt: Some(1e-8),
        snapshots: (1..=100).map(|k| k as f64 * 0.5e-6).collect(),
        ..Default::default()
    };
    let info = run(&mut model, &p, cracks, &mut probe)?;
    let us = |t: Option<f64>| t.map(|t| format!("{:.1} us", t * 1e6));
    println!(
        "dx {dx:e}, {sigma} MPa: branch by the run {:?}, own tracker {:?}, at the 1 mm grid's lengths {:?}",
        us(info.branch_time),
        us(probe.own_time),
        us(probe.physical_time)
    );
    Ok(())
}
