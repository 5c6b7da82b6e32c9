//! Synthetic fixed-point maps for the accelerator tests: $H(x) = Q \Lambda Q x + b$ with
//! Q a Householder reflection (symmetric and orthogonal), so the eigenvalues of the
//! Jacobian are the given $\lambda_i$ in a basis that mixes every component.

use super::{norm, sub, Relaxation};

/// An affine map with known Jacobian eigenvalues.
pub(crate) struct Rotated {
    lam: Vec<f64>,
    u: Vec<f64>,
    b: Vec<f64>,
}

impl Rotated {
    /// Eigenvalues `lam`; reflection vector and load fixed by the dimension.
    pub(crate) fn new(lam: Vec<f64>) -> Self {
        let n = lam.len();
        let u: Vec<f64> = (0..n).map(|i| 1.0 + 0.3 * (i as f64 * 1.7).sin()).collect();
        let b: Vec<f64> = (0..n).map(|i| 1.0 + 0.5 * (i as f64 * 0.9).cos()).collect();
        Rotated { lam, u, b }
    }

    /// Eigenvalues -1.6, -0.9, 0.3, 0.7: plain iteration diverges.
    pub(crate) fn four() -> Self {
        Rotated::new(vec![-1.6, -0.9, 0.3, 0.7])
    }

    /// The spectrum measured on `coupled_sent_a8` (tests/verification_coupled_sent.rs):
    /// two stiff modes -38.4 and -19.5 above a bulk of `bulk` values spread over
    /// [-5.4, 0].
    pub(crate) fn stiff(bulk: usize) -> Self {
        let mut lam = vec![-38.4, -19.5];
        lam.extend((0..bulk).map(|i| -5.4 * i as f64 / (bulk - 1).max(1) as f64));
        Rotated::new(lam)
    }

    fn reflect(&self, x: &[f64]) -> Vec<f64> {
        let s = 2.0 * super::dot(&self.u, x) / super::dot(&self.u, &self.u);
        x.iter().zip(&self.u).map(|(a, u)| a - s * u).collect()
    }

    /// H(x).
    pub(crate) fn apply(&self, x: &[f64]) -> Vec<f64> {
        let y = self.reflect(x);
        let y: Vec<f64> = y.iter().zip(&self.lam).map(|(a, l)| a * l).collect();
        let y = self.reflect(&y);
        y.iter().zip(&self.b).map(|(a, b)| a + b).collect()
    }

    /// Dimension.
    pub(crate) fn len(&self) -> usize {
        self.lam.len()
    }
}

/// Iterations of `relax` on `map` from zero until the relative change of x falls below
/// `tol` (None after `max`); asserts that the end point is a fixed point.
pub(crate) fn iterations(
    map: &Rotated,
    mut relax: impl Relaxation,
    tol: f64,
    max: usize,
) -> Option<usize> {
    let mut x = vec![0.0; map.len()];
    for k in 1..=max {
        let xt = map.apply(&x);
        if norm(&sub(&xt, &x)) < tol * norm(&xt) {
            return Some(k);
        }
        x = relax.next(&x, &xt);
        if x.iter().any(|v| !v.is_finite()) {
            return None;
        }
    }
    None
}
