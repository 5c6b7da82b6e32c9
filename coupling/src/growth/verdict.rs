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

/// Why an infinite plate failed: its tips grew `cap` increments at load `load` without
/// arresting. A crack under a constant remote load has a K that rises with its length
/// (Griffith), so once it has grown past the plate's features (the cap allows each tip
/// twice their extent, times the number of tips) it does not arrest: the plate fails at
/// that load. Before, the run
/// ended with "increase growth.da", rolled the path back, and noted that no tip reached
/// K_c although the log held every increment.
pub fn unstable_note(cap: usize, load: f64) -> String {
    format!(
        "unstable growth in the infinite plate: the tips grew for {cap} rounds of increments \
         at load {load} (the run's cap, far past the extent of the cracks and holes) without \
         arresting; a crack under a constant remote load does not arrest once its K rises \
         with its length, so the plate fails at this load (the paths end at the cap)"
    )
}

/// The note of a run in which no tip advanced by a horizon: before its failure at
/// `failure` (a body that came apart elsewhere, e.g. at a clamp) or within the load budget
/// ending at `last`.
pub fn no_initiation_note(failure: Option<f64>, last: f64) -> String {
    match failure {
        Some(f) => format!("no tip advanced by a horizon before the failure at load {f}"),
        None => format!("no tip advanced by a horizon within the load budget (last factor {last})"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_that_failed_before_any_tip_moved_names_the_failure_load() {
        // Full PD on a clamped plate pulled sideways broke at its clamp at load 3.3 with
        // a budget to 5.25: "within the load budget (last factor 5.25)" read as if the
        // loads had reached 5.25.
        let n = no_initiation_note(Some(3.3), 5.25);
        assert!(
            n.contains("before the failure at load 3.3") && !n.contains("5.25"),
            "{n}"
        );
        let n = no_initiation_note(None, 5.25);
        assert!(
            n.contains("within the load budget (last factor 5.25)"),
            "{n}"
        );
    }
}
