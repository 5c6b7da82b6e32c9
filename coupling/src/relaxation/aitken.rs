//! Aitken's dynamic relaxation (seed 002 Eqs. 25-28) with the safeguards of the module
//! docs of [`crate::relaxation`]: bounds on the weight, a restart from the best iterate
//! when the residual jumps, and IQN-ILS for the rest of the solve when a restart did not
//! help.

use super::iqn_ils::IqnIls;
use super::{dot, norm, relax, sub, Relaxation, RelaxationEvent};

/// Default [`Aitken::w_min`].
pub const AITKEN_W_MIN: f64 = 1e-3;

/// Default [`Aitken::jump_factor`]. Measured (psi = 1e-4 / 1e-5, w0 = 0.3 / 0.4): the
/// healthy cases (`coupled_sent_a2`, `_a5`, the three `coupled_plate_window_*`, the two
/// `coupled_beam_*`) never exceed 3.4 times their best residual; at 2 or 3 they would
/// restart needlessly (plate rotated 14 -> 17 iterations, beam tension 9 -> 12 with one
/// restart), while `coupled_sent_a8` jumps 6.7 to 26 times above its best.
pub const AITKEN_JUMP_FACTOR: f64 = 4.0;

/// Default [`Aitken::max_restarts`].
pub const AITKEN_MAX_RESTARTS: usize = 1;

/// One stored iterate: residual norm, input, output.
type Iterate = (f64, Vec<f64>, Vec<f64>);

/// Aitken's dynamic relaxation (seed 002 Eqs. 25-28), safeguarded.
#[derive(Debug, Clone)]
pub struct Aitken {
    /// Weight of the first step and of every restart.
    pub w0: f64,
    /// Smallest secant weight accepted; below it the previous weight is kept.
    pub w_min: f64,
    /// Upper clamp of the weight (the seed: 1).
    pub w_max: f64,
    /// A residual norm above this factor times the best one so far is a jump.
    pub jump_factor: f64,
    /// Restarts allowed; the next jump hands the solve to IQN-ILS.
    pub max_restarts: usize,
    w: f64,
    prev: Option<(Vec<f64>, Vec<f64>)>,
    best: Option<Iterate>,
    restarts: usize,
    history: IqnIls,
    fallback: bool,
    events: Vec<RelaxationEvent>,
    /// The last step was w0 from the best iterate (the first step, or a restart).
    fresh: bool,
}

impl Aitken {
    /// Aitken with first weight `w0` and the default bounds and safeguards.
    pub fn new(w0: f64) -> Self {
        Self {
            w0,
            w_min: AITKEN_W_MIN,
            w_max: 1.0,
            jump_factor: AITKEN_JUMP_FACTOR,
            max_restarts: AITKEN_MAX_RESTARTS,
            w: w0,
            prev: None,
            best: None,
            restarts: 0,
            history: IqnIls::new(w0),
            fallback: false,
            events: Vec::new(),
            fresh: false,
        }
    }

    /// Whether IQN-ILS has taken over.
    pub fn fell_back(&self) -> bool {
        self.fallback
    }

    /// Restarts so far.
    pub fn restarts(&self) -> usize {
        self.restarts
    }

    /// The secant weight of seed 002 Eqs. 26-28 from the previous pair, or None when it
    /// is not a finite number of at least `w_min`.
    fn secant_weight(&self, x: &[f64], xt: &[f64]) -> Option<f64> {
        let (px, pxt) = self.prev.as_ref()?;
        let e_pd = sub(x, px);
        let diff = sub(&e_pd, &sub(xt, pxt));
        let den = dot(&diff, &diff);
        let w = dot(&e_pd, &diff) / den;
        (den > 0.0 && w.is_finite() && w >= self.w_min).then_some(w)
    }

    /// The residual norm `rn` over the best so far, when it is a jump.
    fn jump(&self, rn: f64) -> Option<f64> {
        let (best, _, _) = self.best.as_ref()?;
        let ratio = rn / best;
        (ratio > self.jump_factor || !rn.is_finite()).then_some(ratio)
    }

    /// A restart: back to the best iterate, a step of w0 from it, no secant history.
    fn restart(&mut self, ratio: f64) -> Vec<f64> {
        self.restarts += 1;
        self.events.push(RelaxationEvent::Restart {
            ratio,
            count: self.restarts,
        });
        self.w = self.w0;
        self.fresh = true;
        let (_, bx, bxt) = self.best.clone().expect("a jump needs a best iterate");
        let out = relax(&bx, &bxt, self.w);
        self.prev = Some((bx, bxt));
        out
    }

    /// IQN-ILS from here on, with every iterate so far as its secant data.
    fn hand_over(&mut self, x: &[f64], xt: &[f64], ratio: f64) -> Vec<f64> {
        self.fallback = true;
        self.events.push(RelaxationEvent::Fallback {
            ratio,
            restarts: self.restarts,
            pairs: self.history.pairs() + 1,
        });
        self.history.next(x, xt)
    }

    /// The plain Aitken step (seed 002 Eq. 25) with the bounded secant weight.
    fn aitken_step(&mut self, x: &[f64], xt: &[f64]) -> Vec<f64> {
        if self.prev.is_none() {
            self.w = self.w0;
            self.fresh = true;
        } else if let Some(w) = self.secant_weight(x, xt) {
            self.w = w.min(self.w_max);
        }
        self.prev = Some((x.to_vec(), xt.to_vec()));
        relax(x, xt, self.w)
    }
}

impl Relaxation for Aitken {
    fn next(&mut self, x: &[f64], xt: &[f64]) -> Vec<f64> {
        if self.fallback {
            return self.history.next(x, xt);
        }
        let rn = norm(&sub(xt, x));
        let fresh = std::mem::replace(&mut self.fresh, false);
        if let Some(ratio) = self.jump(rn) {
            if self.restarts >= self.max_restarts || fresh {
                return self.hand_over(x, xt, ratio);
            }
            self.history.record(x, xt);
            return self.restart(ratio);
        }
        self.history.record(x, xt);
        if self.best.as_ref().is_none_or(|b| rn < b.0) {
            self.best = Some((rn, x.to_vec(), xt.to_vec()));
        }
        self.aitken_step(x, xt)
    }
    fn reset(&mut self) {
        let fresh = Aitken {
            w_min: self.w_min,
            w_max: self.w_max,
            jump_factor: self.jump_factor,
            max_restarts: self.max_restarts,
            ..Aitken::new(self.w0)
        };
        *self = fresh;
    }
    fn last_weight(&self) -> Option<f64> {
        if self.fallback {
            self.history.last_weight()
        } else {
            Some(self.w)
        }
    }
    fn name(&self) -> &'static str {
        "aitken"
    }
    fn take_events(&mut self) -> Vec<RelaxationEvent> {
        std::mem::take(&mut self.events)
    }
}

#[cfg(test)]
mod tests;
