//! Bar in tension against u(x) = F x/(A E) (seed 000 section 3.1, as a thin
//! 2-D strip): the relative L2 error of u_x must fall with dx at a rate near
//! 1 (fixed m = 3.015).

use pdbem_pd::cases::{bar_tension, BAR_FORCE};
use pdbem_pd::solvers::implicit;
use pdbem_pd::PdModel;

fn l2_error(dx: f64) -> f64 {
    let case = bar_tension(dx);
    let mut m = PdModel::new(&case.problem).unwrap();
    implicit::solve(&mut m, &implicit::ImplicitParams::default()).unwrap();
    let (a, e) = (0.02 * 0.02, 200e9);
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..m.n_real() {
        let x = m.positions()[i][0];
        let ua = BAR_FORCE * x / (a * e);
        num += (m.displacements()[i][0] - ua).powi(2);
        den += ua * ua;
    }
    (num / den).sqrt()
}

#[test]
fn error_falls_at_rate_about_one() {
    let dxs = [0.02 / 4.0, 0.02 / 8.0, 0.02 / 16.0, 0.02 / 32.0];
    let errs: Vec<f64> = dxs.iter().map(|&dx| l2_error(dx)).collect();
    let rates: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    eprintln!("errors {errs:?}, rates {rates:?}");
    // Measured: errors 5.7e-2, 3.0e-2, 1.5e-2, 7.6e-3 (dx = W/4 .. W/32);
    // rates 0.937, 0.997, 0.974.
    let last = *rates.last().unwrap();
    assert!(last > 0.8 && last < 1.3, "observed rate {last}");
    assert!(errs.windows(2).all(|w| w[1] < w[0]));
}
