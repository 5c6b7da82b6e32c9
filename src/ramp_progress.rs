//! The progress bar of a quasi-static PD ramp (stand-alone PD: the damage and limit
//! ramps, the crack-initiation ramps of the grid, seed 004's cells and its refined
//! particles): the load factor of every converged step, the halvings of a failed one, and,
//! once a step has iterated for [`CRAWL_AFTER`] at one load, how far its equilibrium
//! search has got (ADR's iterations against their budget and its convergence measure
//! against the tolerance, [`RampEvent::Iterating`]), so that a softened body whose ADR
//! crawls says so while it crawls instead of standing still for minutes.

use std::time::{Duration, Instant};

use pdbem_pd::error::factor_text;
use pdbem_pd::solvers::limit::RampEvent;
use pdbem_pd::solvers::Iterating;

use crate::runner::context::RunContext;

/// Steps of the progress bar of a damage ramp: its load in thousandths of the last.
const PROGRESS_LEN: u64 = 1000;

/// How long a step iterates at one load before its progress is shown.
pub const CRAWL_AFTER: Duration = Duration::from_secs(3);

/// The least time between two messages of a step's progress (a log gets one line each).
pub const CRAWL_EVERY: Duration = Duration::from_secs(5);

/// A damage ramp's progress bar (hidden with `--quiet`): on a terminal a bar over the load
/// with the message; in lines (a log file) the message alone, one line per change.
pub struct RampProgress {
    bar: indicatif::ProgressBar,
    /// The ramp's last load factor.
    last: f64,
    /// When the step now iterating started (the last converged step or halving).
    step_start: Instant,
    /// When its progress was last shown.
    shown: Option<Instant>,
}

impl RampProgress {
    /// The bar of a ramp driven to the load factor `last`.
    pub fn new(ctx: &RunContext, last: f64) -> Self {
        let bar = ctx.styled_progress(PROGRESS_LEN, "{elapsed_precise} [{bar:30}] {msg}", "{msg}");
        RampProgress {
            bar,
            last,
            step_start: Instant::now(),
            shown: None,
        }
    }

    /// Shows `message` (a refinement round's, say).
    pub fn message(&self, message: String) {
        self.bar.set_message(message);
    }

    /// Shows the ramp's event `e`.
    pub fn show(&mut self, e: &RampEvent) {
        let now = Instant::now();
        match e {
            RampEvent::Converged { load } => self.converged(*load, ""),
            RampEvent::Halving {
                failed_load,
                level,
                max,
            } => {
                self.bar.set_message(format!(
                    "no equilibrium at load factor {}: step halved ({level} of at most {max})",
                    factor_text(*failed_load)
                ));
                self.restart(now);
            }
            RampEvent::Iterating(it) => {
                let since_shown = self.shown.map(|t| now.duration_since(t));
                let on_load = now.duration_since(self.step_start);
                if let Some(text) = crawl_message(it, self.last, on_load, since_shown) {
                    self.bar.set_message(text);
                    self.shown = Some(now);
                }
            }
        }
    }

    /// Shows the load factor `load` converged, with `detail` (what the step did) after it.
    pub fn converged(&mut self, load: f64, detail: &str) {
        let at = (load / self.last * PROGRESS_LEN as f64).clamp(0.0, PROGRESS_LEN as f64);
        self.bar.set_position(at as u64);
        let sep = if detail.is_empty() { "" } else { ": " };
        self.bar.set_message(format!(
            "load factor {} of {} converged{sep}{detail}",
            factor_text(load),
            factor_text(self.last)
        ));
        self.restart(Instant::now());
    }

    /// Clears the bar at the ramp's end.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }

    fn restart(&mut self, now: Instant) {
        self.step_start = now;
        self.shown = None;
    }
}

/// The message of a step still iterating after `on_load` at its load, its progress last
/// shown `since_shown` ago: none before [`CRAWL_AFTER`] or within [`CRAWL_EVERY`] of the
/// last one.
pub fn crawl_message(
    it: &Iterating,
    last: f64,
    on_load: Duration,
    since_shown: Option<Duration>,
) -> Option<String> {
    if on_load < CRAWL_AFTER || since_shown.is_some_and(|d| d < CRAWL_EVERY) {
        return None;
    }
    let (round, rounds) = it.round;
    let rounds_text = if rounds > 1 {
        format!(", bond-breaking round {round} of at most {rounds}")
    } else {
        String::new()
    };
    let broken_text = it.broken.map_or(String::new(), |b| {
        format!(", {b} bonds broken at this load")
    });
    Some(format!(
        "load factor {} of {}: {} still iterating after {:.0} s, {} iterations \
         (at most {} a round{rounds_text}){broken_text}, convergence measure {:.2e} against {:.0e}",
        factor_text(it.load),
        factor_text(last),
        it.solver,
        on_load.as_secs_f64(),
        it.iterations,
        it.max_iterations,
        it.measure,
        it.tolerance
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn adr_at(iterations: usize) -> Iterating {
        Iterating {
            solver: "adr",
            load: 0.52,
            iterations,
            round: (2, 100),
            max_iterations: 100_000,
            measure: 3.1e-3,
            tolerance: 1e-9,
            broken: Some(1234),
        }
    }

    #[test]
    fn a_step_that_crawls_is_shown_after_a_while_and_not_too_often() {
        let s = Duration::from_secs;
        // A quick step says nothing.
        assert_eq!(crawl_message(&adr_at(1000), 1.0, s(1), None), None);
        // A slow one says where it stands.
        let text = crawl_message(&adr_at(34_000), 1.0, s(41), None).unwrap();
        assert_eq!(
            text,
            "load factor 0.52 of 1: adr still iterating after 41 s, 34000 iterations \
             (at most 100000 a round, bond-breaking round 2 of at most 100), \
             1234 bonds broken at this load, convergence measure 3.10e-3 against 1e-9"
        );
        // Not again within CRAWL_EVERY of the last message, again after it.
        assert_eq!(crawl_message(&adr_at(35_000), 1.0, s(43), Some(s(2))), None);
        assert!(crawl_message(&adr_at(40_000), 1.0, s(47), Some(s(6))).is_some());
        // One round: no round count.
        let one = Iterating {
            round: (1, 1),
            broken: None,
            ..adr_at(5000)
        };
        let text = crawl_message(&one, 2.0, s(4), None).unwrap();
        assert!(
            text.ends_with("(at most 100000 a round), convergence measure 3.10e-3 against 1e-9"),
            "{text}"
        );
    }
}
