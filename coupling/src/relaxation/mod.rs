//! Interface acceleration for the partitioned PD-BEM iteration (seed 002 Algorithm 1).
//!
//! One fixed-point map H takes the interface displacements given to PD, $x_k$, to those
//! the BEM returns, $\tilde x_k = H(x_k)$; the residual is $r_k = \tilde x_k - x_k$.
//! Every scheme implements [`Relaxation`]: given $(x_k, \tilde x_k)$ it proposes
//! $x_{k+1}$. Files: `aitken.rs`, `iqn_ils.rs`, `qr_filter.rs` (the filtered QR of
//! IQN-ILS), `test_maps.rs` (synthetic maps for the unit tests).
//!
//! ## Constant
//! $x_{k+1} = x_k + w\,r_k$ (seed 002 Eq. 25 with a fixed w).
//!
//! ## Aitken ([`Aitken`]), seed 002 Eqs. 25-28
//! The secant-optimal weight
//! $$w_k = \frac{e_{PD}\cdot(e_{PD} - e_{BEM})}{\|e_{PD} - e_{BEM}\|^2},\qquad
//!   e_{PD} = x_k - x_{k-1},\quad e_{BEM} = \tilde x_k - \tilde x_{k-1},$$
//! capped at w_max (the seed's 0 < w <= 1 by default). For a linear scalar map
//! $H(x) = a x + b$ it returns the exact $1/(1-a)$. A secant weight below w_min
//! (zero or negative: the last step mixed modes of the interface operator so that no
//! positive weight reduces the residual along it) keeps the previous weight instead of
//! being clamped to w_min. Clamping stalls: on `coupled_sent_a8` the iteration sat
//! ten iterations at e = 0.011 with w = 0.001, then the next secant from those tiny
//! steps gave w = 0.6 and e jumped to 0.12; with the previous weight kept it converges
//! in 25 iterations instead of 38 (psi = 1e-3) and in 35 instead of not in 50
//! (psi = 1e-4), and every other case is unchanged.
//!
//! ## IQN-ILS ([`IqnIls`]): interface quasi-Newton, inverse least squares
//! Degroote et al. (2009), as in preCICE. With the columns (differences against the
//! newest pair, newest first, at most `max_columns` = 50)
//! $$V = [r_k - r_i]_i,\qquad W = [\tilde x_k - \tilde x_i]_i,$$
//! the least-squares coefficients $c = \arg\min_c \|V c + r_k\|$ (thin QR of V with the
//! QR2 filter, below) give
//! $$x_{k+1} = x_k + \beta\, r_k + \big(W - (1 - \beta)\, V\big)\, c
//!   = \bar x + \beta\, \bar r,\qquad \bar x = x_k + (W - V)\,c,\quad \bar r = r_k + V c.$$
//! $\bar x$ is the combination of past inputs whose predicted residual $\bar r$ is
//! smallest (for an affine map, the GMRES iterate: Walker & Ni 2011) and $\beta$ relaxes
//! the step on the residual the secant model leaves unexplained; $\beta = 1$ is
//! Degroote's $x_{k+1} = \tilde x_k + W c$. The first step (no column yet) is
//! $x_1 = x_0 + w_0 r_0$; the iteration count hardly depends on $w_0$ (a8: 12 for every
//! w0 in 0.02 ... 1). $\beta$ = [`IQN_BETA`] = 0.5: the unexplained residual still
//! holds stiff-mode parts, which a full step multiplies by $|\lambda| \approx 38$
//! (the excursions that follow also reach where the map is least affine: the windows'
//! bonds use their deformed length while the BEM is linear, and at the solution scale
//! the a8 map is 10 % off affine); a much smaller $\beta$ makes each new difference
//! column nearly a combination of the older ones (the new direction enters only as
//! $\beta \bar r$), which the least squares resolve poorly (a8, beta = 0.3 / 0.1: 12
//! to 14 / 16 iterations; 14 / 15 with the bonds linearised).
//! Filter [`IQN_FILTER`] = 1e-2 (QR2 of Haelterman et al. 2016): a column whose part
//! orthogonal to the newer kept columns is below 1e-2 of its norm is dropped (old
//! columns go first, as they are processed last). Measured on
//! `coupled_sent_a8`, psi = 1e-4: 17 iterations before (beta = 1, relative-diagonal
//! filter 1e-10), 15 with the filter alone, 13 with beta alone, 12 with both.
//! A bound from Arnoldi on the operator linearised at zero (30 steps): the smallest
//! residual in $x_0$ + the Krylov space (GMRES) is 1.4e-4 of the solution after 8 steps
//! and 4.9e-5 after 9, which take 9 evaluations to build and a 10th to check: no method
//! whose iterates stay in that space converges in fewer than 10 iterations here. With
//! the bonds linearised (an experiment, not the model) the map is affine to 1e-6 and
//! IQN-ILS takes 13 (beta = 1) and 12 (beta = 0.5) iterations: the nonlinearity costs
//! little, the spectrum sets the count.

mod aitken;
mod iqn_ils;
mod qr_filter;

pub use aitken::Aitken;
pub use iqn_ils::{IqnIls, IQN_BETA, IQN_FILTER};
pub use qr_filter::{filtered_qr, FilteredQr};

/// An interface acceleration scheme.
pub trait Relaxation: Send {
    /// Next interface input from the current input `x` and the map's output `xt = H(x)`.
    fn next(&mut self, x: &[f64], xt: &[f64]) -> Vec<f64>;
    /// Forgets the history (new load step or new geometry).
    fn reset(&mut self);
    /// Weight used in the last step (None for quasi-Newton steps).
    fn last_weight(&self) -> Option<f64>;
    /// Short name for reports.
    fn name(&self) -> &'static str;
}

/// $x + w (\tilde x - x)$.
pub(crate) fn relax(x: &[f64], xt: &[f64], w: f64) -> Vec<f64> {
    x.iter().zip(xt).map(|(a, b)| a + w * (b - a)).collect()
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// $a - b$.
pub(crate) fn sub(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

/// Constant under-relaxation.
#[derive(Debug, Clone)]
pub struct Constant {
    /// Weight w in (0, 1].
    pub w: f64,
}

impl Relaxation for Constant {
    fn next(&mut self, x: &[f64], xt: &[f64]) -> Vec<f64> {
        relax(x, xt, self.w)
    }
    fn reset(&mut self) {}
    fn last_weight(&self) -> Option<f64> {
        Some(self.w)
    }
    fn name(&self) -> &'static str {
        "constant"
    }
}

#[cfg(test)]
pub(crate) mod test_maps;

#[cfg(test)]
mod tests {
    use super::test_maps::{iterations, Rotated};
    use super::*;

    #[test]
    fn all_schemes_converge_where_plain_iteration_diverges() {
        let map = Rotated::four();
        let plain = iterations(&map, Constant { w: 1.0 }, 1e-10, 500);
        let constant = iterations(&map, Constant { w: 0.35 }, 1e-10, 500);
        let aitken = iterations(&map, Aitken::new(0.35), 1e-10, 500);
        let iqn = iterations(&map, IqnIls::new(0.35), 1e-10, 500);
        println!("plain {plain:?} constant {constant:?} aitken {aitken:?} iqn {iqn:?}");
        assert_eq!(plain, None);
        let constant = constant.unwrap();
        assert!(constant < 200);
        assert!(aitken.unwrap() < constant);
        // A linear map of dimension 4 is solved once 4 secant columns exist.
        assert!(iqn.unwrap() <= 7, "iqn {iqn:?}");
    }
}
