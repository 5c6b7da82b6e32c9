//! Aitken's dynamic relaxation (seed 002 Eqs. 25-28); see the module docs of
//! [`crate::relaxation`].

use super::{dot, relax, Relaxation};

/// Aitken's dynamic relaxation (seed 002 Eqs. 25-28).
#[derive(Debug, Clone)]
pub struct Aitken {
    /// Weight of the first step.
    pub w0: f64,
    /// Smallest secant weight accepted; below it the previous weight is kept.
    pub w_min: f64,
    /// Upper clamp (the seed: 1).
    pub w_max: f64,
    w: f64,
    prev: Option<(Vec<f64>, Vec<f64>)>,
}

impl Aitken {
    /// Aitken with first weight `w0` and the seed's clamp (0, 1].
    pub fn new(w0: f64) -> Self {
        Self {
            w0,
            w_min: 1e-3,
            w_max: 1.0,
            w: w0,
            prev: None,
        }
    }
}

impl Relaxation for Aitken {
    fn next(&mut self, x: &[f64], xt: &[f64]) -> Vec<f64> {
        if let Some((px, pxt)) = &self.prev {
            let e_pd: Vec<f64> = x.iter().zip(px).map(|(a, b)| a - b).collect();
            let diff: Vec<f64> = e_pd
                .iter()
                .zip(xt.iter().zip(pxt))
                .map(|(e, (a, b))| e - (a - b))
                .collect();
            let den = dot(&diff, &diff);
            if den > 0.0 {
                let w = dot(&e_pd, &diff) / den;
                if w.is_finite() && w >= self.w_min {
                    self.w = w.min(self.w_max);
                }
            }
        } else {
            self.w = self.w0;
        }
        self.prev = Some((x.to_vec(), xt.to_vec()));
        relax(x, xt, self.w)
    }
    fn reset(&mut self) {
        self.prev = None;
        self.w = self.w0;
    }
    fn last_weight(&self) -> Option<f64> {
        Some(self.w)
    }
    fn name(&self) -> &'static str {
        "aitken"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aitken_weight_is_exact_for_a_scalar_linear_map() {
        let mut a = Aitken::new(0.5);
        a.w_max = 10.0;
        let h = |x: f64| -3.0 * x + 2.0; // fixed point 0.5, optimal w = 1/(1+3)
        let x0 = 0.0;
        let x1 = a.next(&[x0], &[h(x0)])[0];
        let x2 = a.next(&[x1], &[h(x1)])[0];
        assert!((a.last_weight().unwrap() - 0.25).abs() < 1e-12);
        assert!((x2 - 0.5).abs() < 1e-12);
    }

    #[test]
    fn aitken_keeps_its_weight_when_the_secant_weight_is_not_positive() {
        // Two steps whose residual grew along the step: the secant weight is negative.
        let mut a = Aitken::new(0.4);
        a.next(&[0.0, 0.0], &[1.0, 0.0]);
        let w_before = a.last_weight().unwrap();
        // x moved by 0.4 in the first component; the residual grew from 1 to 2 there.
        a.next(&[0.4, 0.0], &[2.4, 0.0]);
        assert_eq!(a.last_weight(), Some(w_before));
        // A positive secant weight is taken (capped at w_max).
        let mut b = Aitken::new(0.4);
        b.next(&[0.0], &[1.0]);
        b.next(&[0.4], &[0.6]); // H(x) = 1 - x: optimal w = 1/2
        assert!((b.last_weight().unwrap() - 0.5).abs() < 1e-12);
    }
}
