//! Spectrum of the interface operator of Algorithm 1 (seed 002 section 2.3.1).
//!
//! With elastic windows the fixed-point map is affine, $H(x) = J x + b$, and the error of
//! a relaxed iteration $x_{k+1} = x_k + w_k (H(x_k) - x_k)$ evolves as
//! $\varepsilon_{k+1} = (I - w_k (I - J))\,\varepsilon_k$. For the Dirichlet-Neumann
//! split (displacements to PD, forces to BEM) the eigenvalues $\lambda$ of J are real and
//! negative, $-\lambda$ being the ratio of PD to BEM interface stiffness in that mode.
//! A constant weight w contracts mode $\lambda$ by $|1 - w(1-\lambda)|$; the best constant
//! weight over $\mu = 1-\lambda \in [\mu_{min}, \mu_{max}]$ is
//! $w = 2/(\mu_{min}+\mu_{max})$ with factor $(\mu_{max}-\mu_{min})/(\mu_{max}+\mu_{min})$.
//! Aitken (seed 002 Eqs. 25-28) varies one scalar weight; IQN-ILS fits a matrix from the
//! secant history and so treats a few stiff modes separately.
//!
//! [`ritz_values`] estimates the eigenvalues excited by the loading: Arnoldi on J from
//! $H(0)$, J applied by differences $J v = (H(x_0 + s v) - H(x_0))/s$ (exact up to the PD
//! solver tolerance for elastic windows).

use nalgebra::DMatrix;

use crate::error::CouplingError;
use crate::iteration::{interface_map, CoupledProblem, CouplingParams, PreparedBem};

/// Arnoldi with `steps` steps (twice-orthogonalised Gram-Schmidt) on the operator
/// `apply`, from `start`; returns the Ritz values (re, im) sorted by decreasing modulus.
/// Stops early when the Krylov space is invariant.
pub fn arnoldi_ritz<E>(
    mut apply: impl FnMut(&[f64]) -> Result<Vec<f64>, E>,
    start: &[f64],
    steps: usize,
) -> Result<Vec<(f64, f64)>, E> {
    let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
    let s0 = norm(start);
    if s0 == 0.0 || steps == 0 {
        return Ok(Vec::new());
    }
    let mut q: Vec<Vec<f64>> = vec![start.iter().map(|a| a / s0).collect()];
    let mut h = DMatrix::<f64>::zeros(steps + 1, steps);
    let mut m = steps;
    for j in 0..steps {
        let mut w = apply(&q[j])?;
        for _ in 0..2 {
            for (i, qi) in q.iter().enumerate().take(j + 1) {
                let d: f64 = w.iter().zip(qi).map(|(a, b)| a * b).sum();
                h[(i, j)] += d;
                w.iter_mut().zip(qi).for_each(|(a, b)| *a -= d * b);
            }
        }
        let nw = norm(&w);
        h[(j + 1, j)] = nw;
        if nw <= 1e-12 * h.column(j).amax() {
            m = j + 1;
            break;
        }
        q.push(w.iter().map(|a| a / nw).collect());
    }
    let hm = h.view((0, 0), (m, m)).into_owned();
    let mut ev: Vec<(f64, f64)> = hm
        .complex_eigenvalues()
        .iter()
        .map(|c| (c.re, c.im))
        .collect();
    ev.sort_by(|a, b| (b.0.hypot(b.1)).total_cmp(&a.0.hypot(a.1)));
    Ok(ev)
}

/// Ritz values of the interface operator J of `problem` (windows elastic, load scale 1):
/// `steps` Arnoldi steps from H(0), each one map evaluation. Leaves the windows in the
/// state of the last evaluation.
pub fn ritz_values(
    problem: &mut CoupledProblem,
    bem: &PreparedBem,
    params: &CouplingParams,
    steps: usize,
) -> Result<Vec<(f64, f64)>, CouplingError> {
    let n: usize = problem.windows.iter().map(|w| w.interface.len()).sum();
    let x0 = vec![0.0; n];
    let h0 = interface_map(problem, bem, &x0, params)?;
    // Differences taken at 1 % of the response size: well above the PD solver tolerance,
    // small enough for the geometric nonlinearity of the bonds to stay negligible.
    let s = 1e-2 * h0.iter().map(|a| a * a).sum::<f64>().sqrt();
    arnoldi_ritz(
        |v| {
            let xv: Vec<f64> = v.iter().map(|a| a * s).collect();
            let hv = interface_map(problem, bem, &xv, params)?;
            Ok(hv.iter().zip(&h0).map(|(a, b)| (a - b) / s).collect())
        },
        &h0,
        steps,
    )
}

/// Best constant relaxation for real eigenvalues `lambda` (all < 1): the weight and the
/// contraction factor per iteration (see the module docs).
pub fn best_constant_weight(lambda: &[f64]) -> Option<(f64, f64)> {
    let mu = lambda.iter().map(|l| 1.0 - l);
    let lo = mu.clone().fold(f64::INFINITY, f64::min);
    let hi = mu.fold(f64::NEG_INFINITY, f64::max);
    (lo > 0.0 && hi.is_finite()).then(|| (2.0 / (lo + hi), (hi - lo) / (hi + lo)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arnoldi_finds_the_extreme_eigenvalues_of_a_known_operator() {
        // Diagonal in a rotated basis: eigenvalues -40, -20, then 60 values in [-2, 0].
        let n = 62;
        let mut lam = vec![-40.0, -20.0];
        lam.extend((0..60).map(|i| -2.0 * i as f64 / 59.0));
        let c = std::f64::consts::FRAC_1_SQRT_2;
        let apply = |v: &[f64]| -> Result<Vec<f64>, ()> {
            // Q^T diag(lam) Q with Q rotating pairs (2i, 2i+1) by 45 degrees.
            let mut y = vec![0.0; n];
            for i in (0..n).step_by(2) {
                let (a, b) = (c * (v[i] + v[i + 1]), c * (v[i + 1] - v[i]));
                let (a, b) = (lam[i] * a, lam[i + 1] * b);
                y[i] = c * (a - b);
                y[i + 1] = c * (a + b);
            }
            Ok(y)
        };
        let start: Vec<f64> = (0..n).map(|i| 1.0 + (i as f64).sin()).collect();
        let ev = arnoldi_ritz(apply, &start, 30).unwrap();
        assert!(
            (ev[0].0 + 40.0).abs() < 1e-8 && ev[0].1.abs() < 1e-8,
            "{ev:?}"
        );
        assert!((ev[1].0 + 20.0).abs() < 1e-8, "{ev:?}");
        assert!(ev[2].0 >= -2.0 - 1e-8 && ev.iter().all(|e| e.0 <= 1e-8));
        let (w, f) = best_constant_weight(&[-40.0, 0.0]).unwrap();
        assert!((w - 2.0 / 42.0).abs() < 1e-15 && (f - 40.0 / 42.0).abs() < 1e-15);
    }
}
