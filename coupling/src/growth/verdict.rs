//! The end-of-step verdict shared by the BEM-only and full-PD engines.

use serde_json::json;

use super::events::EngineObserver;
use super::front::Front;
use super::history::GrowthHistory;

/// The verdict at step `step` (load `load`): with `failed` (a crack cut the body; `why`
/// says how) the history records the failure and the observer gets a `failure` event;
/// otherwise, when no tip is active any more, a note. Returns whether the run stops.
pub fn stop_after_step(
    history: &mut GrowthHistory,
    observer: &mut dyn EngineObserver,
    front: &Front,
    failed: bool,
    step: usize,
    load: f64,
    why: &str,
) -> bool {
    if failed {
        history.failure = true;
        history.failure_load = Some(load);
        observer.event("failure", json!({"step": step, "load": load}));
        history
            .notes
            .push(format!("failure at load {load} (step {step}): {why}"));
        return true;
    }
    if front.active().is_empty() {
        history
            .notes
            .push(format!("every tip stopped by step {step} (load {load})"));
        let holes = front.holes_reached();
        if !holes.is_empty() {
            history.notes.push(format!(
                "every tip ended and the body holds: cracks ended at hole(s) {} and joined \
                 them (no structural failure; the final geometry has the cracks running into \
                 the holes)",
                holes.join(", ")
            ));
        }
        return true;
    }
    false
}
