//! 1-norm condition estimate of the factored, scaled system (Hager 1984 / Higham 1988
//! estimator: a few solves with A and A^T, no inverse formed).

use super::BemSystem;

/// cond_1(A) ~ ||A||_1 * est(||A^{-1}||_1).
pub(super) fn estimate_cond1(sys: &BemSystem, norm1: f64) -> f64 {
    let n = sys.n;
    let mut x = vec![1.0 / n as f64; n];
    let mut est = 0.0;
    for _ in 0..5 {
        let mut y = x.clone();
        sys.substitute(&mut y, false);
        let new_est: f64 = y.iter().map(|v| v.abs()).sum();
        let mut z: Vec<f64> = y
            .iter()
            .map(|v| if *v >= 0.0 { 1.0 } else { -1.0 })
            .collect();
        sys.substitute(&mut z, true);
        let (jmax, zmax) =
            z.iter().enumerate().fold(
                (0, 0.0),
                |(bj, bv), (j, v)| if v.abs() > bv { (j, v.abs()) } else { (bj, bv) },
            );
        let ztx: f64 = z.iter().zip(&x).map(|(a, b)| a * b).sum();
        if new_est <= est || zmax <= ztx {
            est = est.max(new_est);
            break;
        }
        est = new_est;
        x.iter_mut().for_each(|v| *v = 0.0);
        x[jmax] = 1.0;
    }
    norm1 * est
}
