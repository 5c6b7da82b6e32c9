//! Interface quasi-Newton with an inverse Jacobian from least squares (IQN-ILS,
//! Degroote et al. 2009), with the QR2 filter and a relaxed quasi-Newton step; see the
//! module docs of [`crate::relaxation`].

use super::qr_filter::filtered_qr;
use super::{relax, sub, Relaxation};

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
    residuals: Vec<Vec<f64>>,
    outputs: Vec<Vec<f64>>,
    last_w: Option<f64>,
}

impl IqnIls {
    /// IQN-ILS with first weight `w0`.
    pub fn new(w0: f64) -> Self {
        Self {
            w0,
            beta: IQN_BETA,
            max_columns: 50,
            filter: IQN_FILTER,
            residuals: Vec::new(),
            outputs: Vec::new(),
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

    /// The step from the stored pairs, the newest being (x, H(x)): None when no column
    /// survives the filter.
    fn quasi_newton(&self, x: &[f64]) -> Option<Vec<f64>> {
        let k = self.residuals.len();
        let (r, xt) = (&self.residuals[k - 1], &self.outputs[k - 1]);
        // Columns: differences against the newest, newest first.
        let v: Vec<Vec<f64>> = (0..k - 1)
            .rev()
            .map(|i| sub(r, &self.residuals[i]))
            .collect();
        let qr = filtered_qr(v.iter().map(Vec::as_slice).take(x.len()), self.filter);
        if qr.is_empty() {
            return None;
        }
        let minus_r: Vec<f64> = r.iter().map(|a| -a).collect();
        let c = qr.solve(&minus_r);
        if c.iter().any(|a| !a.is_finite()) {
            return None;
        }
        // x + beta r + sum_j c_j (W_j - (1 - beta) V_j), W_j = xt - xt_i, V_j = r - r_i.
        let mut out = relax(x, xt, self.beta);
        for (cj, &col) in c.iter().zip(&qr.kept) {
            let i = k - 2 - col;
            let (ri, xti) = (&self.residuals[i], &self.outputs[i]);
            for (o, (a, (b, (d, e)))) in out
                .iter_mut()
                .zip(xt.iter().zip(xti.iter().zip(r.iter().zip(ri))))
            {
                *o += cj * ((a - b) - (1.0 - self.beta) * (d - e));
            }
        }
        Some(out)
    }
}

impl Relaxation for IqnIls {
    fn next(&mut self, x: &[f64], xt: &[f64]) -> Vec<f64> {
        self.record(x, xt);
        let step = if self.pairs() < 2 {
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
        self.last_w = None;
    }
    fn last_weight(&self) -> Option<f64> {
        self.last_w
    }
    fn name(&self) -> &'static str {
        "iqn-ils"
    }
}
