//! A crack held by bonds that cannot break: after every converged load step, the bonds
//! nearer a tip than its window entry that are past their breaking stretch but protected
//! (the no-fail band along a window's interface sides, seed 002 section 2.3.3; the coarse
//! cells of a refined window, [`crate::growth::fine_zone`]). There the crack is held by
//! that protection, not by its toughness, because the tracker did not see its tip pass
//! the trigger margin. Each run of such steps is noted ([`held_notes`]); a run whose held
//! tip the tracker cannot see at all ends after two such steps in a row ([`held_end`]).

use pdbem_bem::V2;
use pdbem_pd::breaking::{held_bonds, HeldBonds};

use super::Growth;
use crate::growth::fine_zone::finest_spacing;
use crate::growth::records::{HeldCrack, Scenario, StepResult};
use crate::growth::tips::{margins, near_interface_side, TipState};

impl<S: Scenario> Growth<'_, S> {
    /// The bonds of a converged step that are past their breaking stretch but cannot break
    /// ([`pdbem_pd::breaking::held_bonds`]: the no-fail band along the interface sides or
    /// the coarse cells of a refined window): the crack is held there by that protection,
    /// not by its toughness, and the window did not move on (its tip did not pass the
    /// trigger margin or leave the fine cells, as the tracker sees it). The equilibrium is
    /// then not the cracked body's; the account of the window with the most stretched one.
    /// Only bonds nearer an active tip than that tip's entry into its window count: a
    /// window whose tips ended (at a hole, say) stays where it is by design, and bonds
    /// of the band where the crack crosses into the window bridge its faces behind the
    /// tip rather than hold it (measured on `growth_shear_edge` at load 0.12: 8 pairs up
    /// to 29 s0 at the crack's entry into its window, bonds to the virtual nodes beyond
    /// the side, where the moved window's pre-crack, cut along the traced path, misses
    /// the wiggles of the crack).
    pub(super) fn held_by_protection(&self) -> Option<HeldCrack> {
        let (w, h) = (0..self.problem.windows.len())
            .filter_map(|w| Some((w, self.held_near(w)?)))
            .max_by(|a, b| a.1.worst.total_cmp(&b.1.worst))?;
        let wm = &self.problem.windows[w];
        let band = margins(&wm.window, self.params.trigger_ratio).0;
        let at = V2::new(h.at[0], h.at[1]);
        // A band bond has an end within the band: its midpoint lies up to half a horizon
        // beyond it.
        let in_band = near_interface_side(&wm.window, at, band + 0.5 * wm.window.delta());
        let by = if in_band || finest_spacing(wm).is_none() {
            format!(
                "the window's no-fail band ({band:.4} m along its interface sides, \
                 1 - growth.trigger_ratio of its side)"
            )
        } else {
            "the coarse cells of the refined window (bonds between coarse nodes do not \
             break)"
                .to_string()
        };
        let account = format!(
            "window {w}: {} bond pair(s) past the critical stretch (up to {:.2} s0, at \
             ({:.4}, {:.4})) cannot break, and the window did not move on: the crack is held \
             by {by}, not by its toughness, because the tracker (growth.damage_threshold \
             {}) did not see its tip pass the trigger margin or reach the end of the fine \
             cells. Raise growth.trigger_ratio \
             (seed 002: 0.9) or lower growth.damage_threshold (a fresh crack between node \
             rows has damage about 0.365 at m = 3)",
            h.pairs, h.worst, h.at[0], h.at[1], self.params.path.threshold
        );
        let traced = (self.tips.iter()).any(|t| t.active() && t.window == w && !t.path.is_empty());
        Some(HeldCrack { account, traced })
    }

    /// The bonds of window `w` past their breaking stretch that cannot break and lie
    /// nearer an active tip of the window than that tip's entry
    /// ([`Growth::held_by_protection`]).
    fn held_near(&self, w: usize) -> Option<HeldBonds> {
        let tips: Vec<&TipState> = (self.tips.iter())
            .filter(|tip| tip.active() && tip.window == w)
            .collect();
        if tips.is_empty() {
            return None;
        }
        let near_tip = |x: [f64; 2]| {
            let x = V2::new(x[0], x[1]);
            (tips.iter()).any(|t| (x - t.position()).norm() < (x - t.entry).norm())
        };
        held_bonds(&self.problem.windows[w].model, near_tip)
    }
}

/// The notes of the runs of steps after which the crack was held by bonds that cannot
/// break ([`StepResult::held`]): its growth over those loads was held back (the shear
/// plate of `growth_shear_edge` after steps 2-7, loads 0.12-0.22, until its traced tip
/// passed the margin in step 8).
pub(super) fn held_notes(steps: &[StepResult]) -> Vec<String> {
    let mut notes = Vec::new();
    let mut k = 0;
    while k < steps.len() {
        let Some(first) = &steps[k].held else {
            k += 1;
            continue;
        };
        let end = (k..steps.len())
            .take_while(|&j| steps[j].held.is_some())
            .last()
            .unwrap_or(k);
        let after = if end + 1 < steps.len() {
            format!("it grew on in step {}", end + 1)
        } else {
            "to the end of the run".to_string()
        };
        notes.push(format!(
            "steps {}-{} (loads {}-{}): {}. The crack's growth over these loads was held \
             back by that protection ({after})",
            steps[k].step, steps[end].step, steps[k].load, steps[end].load, first.account
        ));
        k = end + 1;
    }
    notes
}

/// The end of a run whose crack is held by bonds that cannot break after two steps in a
/// row, the second without a window move, while the tracker sees no growth of the tip
/// (so no move can free it): every later load would be carried by those bonds (the
/// refined tension plate with `growth.damage_threshold: 0.95` ran to load 5.25 with
/// "grew 0 m" and exit 0).
pub(super) fn held_end(steps: &[StepResult]) -> Option<String> {
    let [.., before, last] = steps else {
        return None;
    };
    let held = last.held.as_ref()?;
    if held.traced || before.held.is_none() || last.relocations > 0 {
        return None;
    }
    Some(format!(
        "run ended at load {} (step {}): the crack was held at the end of steps {} and {} \
         and the tracker sees no growth of its tip, so no window move can free it: {}",
        last.load, last.step, before.step, last.step, held.account
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::fixtures::step_result;

    /// Step `k` after which the crack is held (`held`: traced or not) with `relocations`
    /// moves in it.
    fn step(k: usize, held: Option<bool>, relocations: usize) -> StepResult {
        StepResult {
            relocations,
            held: held.map(|traced| HeldCrack {
                account: format!("held {k}: cannot break"),
                traced,
            }),
            ..step_result(k, 1.0 + k as f64)
        }
    }

    #[test]
    fn a_held_crack_is_noted_per_run_of_steps_and_ends_the_run_only_when_no_move_can_free_it() {
        // Held after steps 1-2 with a traced tip, freed by a move in step 3 (the shear
        // plate): one note naming the steps, no end.
        let freed = [
            step(0, None, 0),
            step(1, Some(true), 0),
            step(2, Some(true), 0),
            step(3, None, 2),
        ];
        let notes = held_notes(&freed);
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(
            notes[0].starts_with("steps 1-2 (loads 2-3): held 1"),
            "{notes:?}"
        );
        assert!(notes[0].contains("it grew on in step 3"), "{notes:?}");
        assert!((1..=freed.len()).all(|n| held_end(&freed[..n]).is_none()));
        // Two separate runs, the last to the end.
        let twice = [
            step(0, Some(true), 0),
            step(1, None, 1),
            step(2, Some(true), 0),
        ];
        let notes = held_notes(&twice);
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(notes[1].starts_with("steps 2-2") && notes[1].contains("to the end"));
        // Untraced and held after two steps in a row without a move: the end.
        let stuck = [step(0, Some(false), 0), step(1, Some(false), 0)];
        assert_eq!(held_end(&stuck[..1]), None, "one step may still be freed");
        let end = held_end(&stuck).expect("ends");
        assert!(
            end.contains("steps 0 and 1") && end.contains("held 1"),
            "{end}"
        );
        // A move in the second step, or a traced tip: no end.
        assert_eq!(
            held_end(&[step(0, Some(false), 0), step(1, Some(false), 1)]),
            None
        );
        assert_eq!(
            held_end(&[step(0, Some(false), 0), step(1, Some(true), 0)]),
            None
        );
        // Not held: nothing.
        let free = [step(0, None, 0), step(1, None, 0)];
        assert!(held_notes(&free).is_empty() && held_end(&free).is_none());
    }
}
