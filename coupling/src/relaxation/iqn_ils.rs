//! Interface quasi-Newton with an inverse Jacobian from least squares (IQN-ILS,
//! Degroote et al. 2009), with the QR2 filter and a relaxed quasi-Newton step; see the
//! module docs of [`crate::relaxation`].

use super::qr_filter::filtered_qr;
use super::{relax, sub, Relaxation, SecantColumns};

/// Default [`IqnIls::beta`]. Measured at psi = 1e-4 (1e-5 for the plates and beams),
/// iterations with beta = 1 / 0.7 / 0.5 / 0.4 (filter 1e-2): `coupled_sent_a8` 15 / 13
/// / 12 / 14, `_a2` 12 / 12 / 12 / 11, `_a5` 11 / 11 / 11 / 9; at 0.5 the three
/// `coupled_plate_window_*` take 10 / 11 / 10 and the two `coupled_beam_*` 6 / 7 (11 / 12
/// / 11 and 7 / 8 with beta = 1 and no filter).
pub const IQN_BETA: f64 = 0.5;

/// Default [`IqnIls::filter`] (preCICE's usual QR2 limit). Measured on `coupled_sent_a8`
/// with beta = 0.5: 1e-10 (no filtering) 13, 1e-3 13, 3e-3 12, 1e-2 12 for every w0 in
/// 0.02 ... 1, 3e-2 14, 1e-1 16.
pub const IQN_FILTER: f64 = 1e-2;

/// Interface quasi-Newton, inverse least squares (IQN-ILS).
#[derive(Debug, Clone)]
pub struct IqnIls {
    /// Constant weight of the first step.
    pub w0: f64,
    /// Weight beta of the part of the residual the secant model leaves unexplained.
    pub beta: f64,
    /// Most difference columns kept.
    pub max_columns: usize,
    /// QR2 filter: a column whose part orthogonal to the newer kept ones is below this
    /// fraction of its norm is dropped.
    pub filter: f64,
    /// Most columns kept from earlier maps ([`Relaxation::end_map`]); 0 keeps none.
    pub max_reused: usize,
    residuals: Vec<Vec<f64>>,
    outputs: Vec<Vec<f64>>,
    /// Difference columns (V, W) of earlier maps, newest first.
    reused: SecantColumns,
    last_w: Option<f64>,
}

/// Default [`IqnIls::max_reused`]: as many as the model keeps of its own.
pub const IQN_MAX_REUSED: usize = 50;

impl IqnIls {
    /// IQN-ILS with first weight `w0`.
    pub fn new(w0: f64) -> Self {
        Self {
            w0,
            beta: IQN_BETA,
            max_columns: 50,
            filter: IQN_FILTER,
            max_reused: IQN_MAX_REUSED,
            residuals: Vec::new(),
            outputs: Vec::new(),
            reused: SecantColumns::default(),
            last_w: None,
        }
    }

    /// Stores the pair (x, H(x)) as secant data without taking a step.
    pub(crate) fn record(&mut self, x: &[f64], xt: &[f64]) {
        self.residuals.push(sub(xt, x));
        self.outputs.push(xt.to_vec());
        let keep = self.max_columns + 1;
        if self.residuals.len() > keep {
            let drop = self.residuals.len() - keep;
            self.residuals.drain(..drop);
            self.outputs.drain(..drop);
        }
    }

    /// Pairs stored.
    pub(crate) fn pairs(&self) -> usize {
        self.residuals.len()
    }

    /// The step from the stored pairs, the newest being (x, H(x)), and the reused
    /// columns: None when no column survives the filter.
    fn quasi_newton(&self, x: &[f64]) -> Option<Vec<f64>> {
        let k = self.residuals.len();
        let (r, xt) = (&self.residuals[k - 1], &self.outputs[k - 1]);
        // Columns: differences against the newest pair, newest first, then the reused
        // columns (newest first), so the filter drops the oldest information first.
        let (mut v, mut w): (Vec<Vec<f64>>, Vec<Vec<f64>>) = (0..k - 1)
            .rev()
            .map(|i| (sub(r, &self.residuals[i]), sub(xt, &self.outputs[i])))
            .unzip();
        v.extend(self.reused.v.iter().cloned());
        w.extend(self.reused.w.iter().cloned());
        let qr = filtered_qr(v.iter().map(Vec::as_slice).take(x.len()), self.filter);
        if qr.is_empty() {
            return None;
        }
        let minus_r: Vec<f64> = r.iter().map(|a| -a).collect();
        let c = qr.solve(&minus_r);
        if c.iter().any(|a| !a.is_finite()) {
            return None;
        }
        // x + beta r + sum_j c_j (W_j - (1 - beta) V_j).
        let mut out = relax(x, xt, self.beta);
        for (cj, &col) in c.iter().zip(&qr.kept) {
            for (o, (wj, vj)) in out.iter_mut().zip(w[col].iter().zip(&v[col])) {
                *o += cj * (wj - (1.0 - self.beta) * vj);
            }
        }
        Some(out)
    }

    /// Columns of the current map's pairs (differences of consecutive pairs, newest
    /// first) followed by the reused ones, at most `max_reused`.
    fn all_columns(&self) -> SecantColumns {
        let k = self.residuals.len();
        let mut out = SecantColumns::default();
        for i in (1..k).rev() {
            out.v.push(sub(&self.residuals[i], &self.residuals[i - 1]));
            out.w.push(sub(&self.outputs[i], &self.outputs[i - 1]));
        }
        out.v.extend(self.reused.v.iter().cloned());
        out.w.extend(self.reused.w.iter().cloned());
        out.v.truncate(self.max_reused);
        out.w.truncate(self.max_reused);
        out
    }
}

impl Relaxation for IqnIls {
    fn next(&mut self, x: &[f64], xt: &[f64]) -> Vec<f64> {
        self.record(x, xt);
        let step = if self.pairs() < 2 && self.reused.is_empty() {
            None
        } else {
            self.quasi_newton(x)
        };
        match step {
            Some(out) => {
                self.last_w = None;
                out
            }
            None => {
                self.last_w = Some(self.w0);
                relax(x, xt, self.w0)
            }
        }
    }
    fn reset(&mut self) {
        self.residuals.clear();
        self.outputs.clear();
        self.reused = SecantColumns::default();
        self.last_w = None;
    }
    fn end_map(&mut self, last: Option<(&[f64], &[f64])>) {
        if let Some((x, xt)) = last {
            self.record(x, xt);
        }
        self.reused = self.all_columns();
        self.residuals.clear();
        self.outputs.clear();
    }
    fn take_secants(&mut self) -> SecantColumns {
        let out = self.all_columns();
        self.reset();
        out
    }
    fn seed(&mut self, columns: SecantColumns) {
        self.reused = columns;
        self.reused.v.truncate(self.max_reused);
        self.reused.w.truncate(self.max_reused);
    }
    fn last_weight(&self) -> Option<f64> {
        self.last_w
    }
    fn name(&self) -> &'static str {
        "iqn-ils"
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_maps::Rotated;
    use super::super::{norm, sub};
    use super::*;

    /// Iterations of `relax` on `h` from `x` until |H(x) - x| < 1e-10 |H(x)|, and the end point.
    fn solve(h: &dyn Fn(&[f64]) -> Vec<f64>, relax: &mut IqnIls, x: &[f64]) -> (usize, Vec<f64>) {
        let mut x = x.to_vec();
        for k in 1..=200 {
            let xt = h(&x);
            if norm(&sub(&xt, &x)) < 1e-10 * norm(&xt) {
                return (k, x);
            }
            x = relax.next(&x, &xt);
        }
        (usize::MAX, x)
    }

    #[test]
    fn reused_columns_solve_a_shifted_map_in_a_few_iterations() {
        // The measured coupled_sent_a8 spectrum (two stiff modes over a bulk of 8): the
        // second map has the same Jacobian and another load (what a bond break or a new
        // load step does away from the tip, exactly).
        let map = Rotated::stiff(8);
        let h1 = |x: &[f64]| map.apply(x);
        let h2 = |x: &[f64]| {
            let y = map.apply(x);
            y.iter()
                .enumerate()
                .map(|(i, v)| v + 0.3 * (i as f64).cos())
                .collect()
        };
        let mut warm = IqnIls::new(0.5);
        let (k1, x1) = solve(&h1, &mut warm, &vec![0.0; map.len()]);
        warm.end_map(None);
        let (k_warm, x_warm) = solve(&h2, &mut warm, &x1);
        let mut cold = IqnIls::new(0.5);
        let (k_cold, x_cold) = solve(&h2, &mut cold, &x1);
        println!("first {k1}, cold {k_cold}, warm {k_warm}");
        // Measured (evaluations, the last one the check): 12 for the first map, 12 cold
        // and 2 warm for the second.
        assert!(k1 < 20 && k_cold < 20, "{k1} {k_cold}");
        assert!(
            k_warm <= 4 && k_warm + 5 <= k_cold,
            "warm {k_warm}, cold {k_cold}"
        );
        assert!(norm(&sub(&x_warm, &x_cold)) < 1e-8 * norm(&x_cold));
        // Taking the columns out leaves the scheme empty; seeding gives them back.
        let cols = warm.take_secants();
        assert!(!cols.is_empty() && cols.len() <= IQN_MAX_REUSED);
        assert_eq!(cols.clone().for_unknowns(map.len() + 1).len(), 0);
        let mut seeded = IqnIls::new(0.5);
        seeded.seed(cols.for_unknowns(map.len()));
        let (k_seeded, _) = solve(&h1, &mut seeded, &x_warm);
        assert!(k_seeded <= 4, "seeded {k_seeded}");
    }
}
