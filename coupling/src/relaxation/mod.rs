//! Interface acceleration for the partitioned PD-BEM iteration (seed 002 Algorithm 1).
//!
//! One fixed-point map H takes the interface displacements given to PD, $x_k$, to those
//! the BEM returns, $\tilde x_k = H(x_k)$; the residual is $r_k = \tilde x_k - x_k$.
//! Every scheme implements [`Relaxation`]: given $(x_k, \tilde x_k)$ it proposes
//! $x_{k+1}$, and reports what the person running the solve should know as
//! [`RelaxationEvent`]s (Algorithm 1 turns them into
//! [`CouplingInfo::notes`](crate::CouplingInfo::notes), which reach `summary.json`'s
//! `notes` and the growth log). Files: `aitken.rs`, `iqn_ils.rs`, `qr_filter.rs` (the
//! filtered QR of IQN-ILS), `test_maps.rs` (synthetic maps for the unit tests).
//!
//! ## Constant
//! $x_{k+1} = x_k + w\,r_k$ (seed 002 Eq. 25 with a fixed w).
//!
//! ## Aitken ([`Aitken`]), seed 002 Eqs. 25-28, safeguarded
//! The secant-optimal weight
//! $$w_k = \frac{e_{PD}\cdot(e_{PD} - e_{BEM})}{\|e_{PD} - e_{BEM}\|^2},\qquad
//!   e_{PD} = x_k - x_{k-1},\quad e_{BEM} = \tilde x_k - \tilde x_{k-1},$$
//! i.e. $w_k = -w_{k-1}\, r_{k-1}\cdot(r_k - r_{k-1}) / \|r_k - r_{k-1}\|^2$, then
//! $x_{k+1} = x_k + w_k r_k$. For a scalar affine map $H(x) = a x + b$ it is the exact
//! $1/(1-a)$. The safeguards, in order:
//! 1. **Bounds** $[w_{min}, w_{max}] = [10^{-3}, 1]$ (the seed's $0 < w \le 1$; `w_max`
//!    is halved with every back-off of Algorithm 1). A secant weight above $w_{max}$ is
//!    clamped to it; one below $w_{min}$ (zero or negative: the last step mixed modes
//!    of the interface operator so that no positive weight reduces the residual along
//!    it) or not finite keeps the previous weight instead of being clamped to $w_{min}$:
//!    clamping stalled `coupled_sent_a8` ten iterations at e = 0.011 with w = 0.001.
//! 2. **Restart on a jump.** With $b$ the iterate of smallest $\|r\|$ so far, a residual
//!    $\|r_k\| > \rho\,\|r_b\|$, $\rho$ = `jump_factor` = 4 ([`AITKEN_JUMP_FACTOR`]
//!    says why 4), restarts: $x_{k+1} = x_b + w_0 r_b$ and the next secant is taken
//!    against $(x_b, \tilde x_b)$; the jumped iterate's secant information is dropped.
//! 3. **Hand-over to IQN-ILS.** A jump after `max_restarts` = 1 restarts, or right after
//!    a step of $w_0$ from the best iterate (the first step, or a restart: restarting
//!    would repeat it), hands the rest of the solve to [`IqnIls`], whose model starts
//!    from every iterate so far. For an affine map every relaxed iterate lies in
//!    $x_0$ + the Krylov space of the Jacobian, so the seeded model is as rich as
//!    IQN-ILS's own after as many evaluations.
//!
//! Why: on `coupled_sent_a8` the interface operator has two stiff modes (Ritz values
//! -38.4 and -19.5, `tests/verification_coupled_sent.rs`) above a bulk in [-5.4, 0]. A
//! weight good for the bulk (0.2 ... 1) multiplies the stiff modes by up to
//! $|1 - w(1 - \lambda)| \approx 38$, a weight good for them (1/40) barely moves the bulk,
//! and the secant weight alternates between the two: the residual jumped back from 0.36
//! to 1.21 at iteration 9 and Aitken needed 35 iterations from w0 = 0.3 and did not
//! converge in 50 from 0.05, 0.5, 0.7 or 1 (psi = 1e-4). Safeguarded, measured at psi =
//! 1e-4 from w0 = 0.05 / 0.1 / 0.3 / 0.5 / 0.7 / 1: 21 / 18 / 12 / 12 / 12 / 12
//! iterations (from 0.05: restart after iteration 8, hand-over after 12; from 0.1: after
//! 7 and 9; from 0.3 up the first step jumps and IQN-ILS takes over after iteration 2),
//! K_I within 5e-5 of IQN-ILS. The cases where plain Aitken works (`coupled_sent_a2`,
//! `_a5`, the plate windows, the beams) never jump by 4 and are unchanged. With
//! `max_restarts = 0` (hand over at the first jump) a8 takes 17 / 15 / 12 / 12 / 12 /
//! 12; the restart is kept so that a single bad secant weight does not end Aitken.
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
//!
//! ## Reuse of secant columns when the map changes ([`SecantColumns`])
//! When bonds break the map H changes a little (a few bonds near a tip), so pairs
//! evaluated before and after the break do not lie on one map. A difference of two pairs
//! across the break reads the jump of H as the response to a tiny change of x, and the
//! least squares then pull $x_{k+1}$ back towards the old fixed point: measured on
//! `growth_tension_edge` (n = 20) with the pre-break pair in the new model, the residual
//! after a break stayed at 0.17 for five iterations and then alternated between 0.17
//! and 1e-3 for 10 to 30 iterations. [`Relaxation::end_map`] closes the old map: IQN-ILS
//! turns its pairs into difference columns $V_j = r_{i+1} - r_i$,
//! $W_j = \tilde x_{i+1} - \tilde x_i$ (newest first), which approximate the Jacobian
//! of the new map away from
//! the broken bonds, and starts a new set of pairs. The least squares take the new
//! map's columns first and the reused ones after them, so the QR2 filter drops the
//! reused ones first when they are (nearly) dependent on new information; at most
//! [`IQN_MAX_REUSED`] are kept. This is the column reuse of IQN-ILS across time steps
//! (Degroote et al. 2009, preCICE's reused time windows) applied to bond breaks. With
//! no pair of the new map yet, the first step uses the reused columns alone.

mod aitken;
mod iqn_ils;
mod qr_filter;

pub use aitken::{Aitken, AITKEN_JUMP_FACTOR, AITKEN_MAX_RESTARTS, AITKEN_W_MIN};
pub use iqn_ils::{IqnIls, IQN_BETA, IQN_FILTER, IQN_MAX_REUSED};
pub use qr_filter::{filtered_qr, FilteredQr};

/// Something an accelerator did that the person running the solve should know about
/// (reported by [`Relaxation::take_events`], collected by Algorithm 1 into
/// [`CouplingInfo::notes`](crate::CouplingInfo::notes)).
#[derive(Debug, Clone, PartialEq)]
pub enum RelaxationEvent {
    /// Aitken's residual norm jumped to `ratio` times its best (more than its
    /// `jump_factor`): it restarted from the best iterate with its first weight.
    Restart {
        /// |r_k| over the smallest |r| so far.
        ratio: f64,
        /// Restarts so far in this solve.
        count: usize,
    },
    /// Aitken's residual norm jumped to `ratio` times its best with no restart left (or
    /// right after a step of its first weight, which a restart would repeat): IQN-ILS
    /// takes the rest of the solve, its model built from the `pairs` iterates so far.
    Fallback {
        /// |r_k| over the smallest |r| so far.
        ratio: f64,
        /// Restarts before the hand-over.
        restarts: usize,
        /// Iterates handed over as secant data.
        pairs: usize,
    },
}

impl std::fmt::Display for RelaxationEvent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RelaxationEvent::Restart { ratio, count } => write!(
                f,
                "Aitken restart {count}: interface residual at {ratio:.1} times its best; \
                 back to the best iterate with the first weight"
            ),
            RelaxationEvent::Fallback {
                ratio,
                restarts,
                pairs,
            } => write!(
                f,
                "Aitken handed over to IQN-ILS for the rest of the solve: interface residual \
                 at {ratio:.1} times its best after {restarts} restart(s); the {pairs} \
                 iterates so far seed the quasi-Newton model"
            ),
        }
    }
}

/// Secant information carried from one fixed-point map to the next (IQN-ILS column
/// reuse, module docs): difference columns $V_j = r_{i+1} - r_i$ and
/// $W_j = \tilde x_{i+1} - \tilde x_i$ of earlier iterates, newest first.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SecantColumns {
    /// Residual differences.
    pub v: Vec<Vec<f64>>,
    /// Output differences.
    pub w: Vec<Vec<f64>>,
}

impl SecantColumns {
    /// No column.
    pub fn is_empty(&self) -> bool {
        self.v.is_empty()
    }

    /// Columns.
    pub fn len(&self) -> usize {
        self.v.len()
    }

    /// The columns if they all have `n` entries, else none (a different interface).
    pub fn for_unknowns(self, n: usize) -> SecantColumns {
        if self.v.iter().chain(&self.w).all(|c| c.len() == n) {
            self
        } else {
            SecantColumns::default()
        }
    }
}

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
    /// The map changed (bonds broke, a new load step or geometry): the pairs so far no
    /// longer lie on one map. Quasi-Newton schemes keep their differences as reused
    /// columns ([`SecantColumns`]); the others forget (default: [`Relaxation::reset`]).
    /// `last`: a pair (x, H(x)) of the old map not yet passed to [`Relaxation::next`].
    fn end_map(&mut self, _last: Option<(&[f64], &[f64])>) {
        self.reset();
    }
    /// The secant columns of everything seen so far (current pairs and reused columns),
    /// leaving the scheme reset; none by default.
    fn take_secants(&mut self) -> SecantColumns {
        self.reset();
        SecantColumns::default()
    }
    /// Starts from columns of an earlier map; ignored by default.
    fn seed(&mut self, _columns: SecantColumns) {}
    /// Events since the last call (restarts, fallbacks); none by default.
    fn take_events(&mut self) -> Vec<RelaxationEvent> {
        Vec::new()
    }
}

/// $x + w (\tilde x - x)$.
pub(crate) fn relax(x: &[f64], xt: &[f64], w: f64) -> Vec<f64> {
    x.iter().zip(xt).map(|(a, b)| a + w * (b - a)).collect()
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(crate) fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
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
