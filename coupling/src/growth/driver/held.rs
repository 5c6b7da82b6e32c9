//! A crack held by bonds that cannot break: the bonds nearer a tip than its window entry
//! that are past their breaking stretch but protected (the no-fail band along a window's
//! interface sides, seed 002 section 2.3.3; the coarse cells of a refined window,
//! [`crate::growth::fine_zone`]). There the crack is held by that protection, not by its
//! toughness, because the tracker did not see its tip pass the trigger margin.
//! - Every trace of the tips follows a crack held by the no-fail band, or by the coarse
//!   cells at the end of a refined window's fine cells, below the tracking threshold
//!   ([`Growth::follow_held`]), so that its window moves on.
//! - After every converged load step the bonds still held are recorded, at a crack or
//!   away from every crack (where a second crack would start); each run of such steps is
//!   noted ([`held_notes`]), and a run whose held tip the tracker cannot see at all ends
//!   after two such steps in a row ([`held_end`]).

use pdbem_bem::V2;
use pdbem_pd::breaking::{held_bonds, HeldBonds};
use pdbem_pd::crack_path::{trace_crack_finest, CrackPath, PathParams};

use super::Growth;
use crate::error::CouplingError;
use crate::growth::fine_zone::finest_spacing;
use crate::growth::records::{HeldCrack, Scenario, StepResult};
use crate::growth::tips::{margins, near_interface_side, track, TipState};
use crate::setup::WindowModel;

/// Fraction of the damage threshold down to which a held crack is followed
/// ([`Growth::follow_held`]) and below which damage beyond the tracked tip is noted
/// (`Growth::damage_beyond_tips`): 0.304 for seed 002's 0.38, under the 0.365 of a fresh
/// crack between node rows at m = 3.
pub(super) const HELD_THRESHOLD_FACTOR: f64 = 0.8;

impl<S: Scenario> Growth<'_, S> {
    /// The bonds of a converged step that are past their breaking stretch but cannot break
    /// ([`pdbem_pd::breaking::held_bonds`]: the no-fail band along the interface sides or
    /// the coarse cells of a refined window). Near the crack ([`crack_reach`] of its
    /// traced nodes) the crack is held there by that protection, not by its toughness,
    /// and the window did not move on (its tip did not pass the trigger margin or leave
    /// the fine cells, as the tracker sees it, [`Growth::follow_held`] included). The
    /// equilibrium is then not the cracked body's. Away from the crack they are where a
    /// second crack would start (`off_crack`). The account of the window with the most
    /// stretched one, a held crack first.
    /// Only bonds nearer an active tip than that tip's entry into its window count: a
    /// window whose tips ended (at a hole, say) stays where it is by design, and bonds
    /// of the band where the crack crosses into the window bridge its faces behind the
    /// tip rather than hold it (measured on `growth_shear_edge` at load 0.12: 8 pairs up
    /// to 29 s0 at the crack's entry into its window, bonds to the virtual nodes beyond
    /// the side, where the moved window's pre-crack, cut along the traced path, misses
    /// the wiggles of the crack).
    pub(super) fn held_by_protection(&self) -> Option<HeldCrack> {
        let (w, (h, at_crack)) = (0..self.problem.windows.len())
            .filter_map(|w| Some((w, self.held_near(w)?)))
            .max_by(|a, b| (a.1 .1.cmp(&b.1 .1)).then(a.1 .0.worst.total_cmp(&b.1 .0.worst)))?;
        let wm = &self.problem.windows[w];
        let band = margins(&wm.window, self.params.trigger_ratio).0;
        let at = V2::new(h.at[0], h.at[1]);
        let by = if band_bond(wm, self.params.trigger_ratio, h.ends) || finest_spacing(wm).is_none()
        {
            format!(
                "the window's no-fail band ({band:.4} m along its interface sides, \
                 1 - growth.trigger_ratio of its side)"
            )
        } else {
            "the coarse cells of the refined window (bonds between coarse nodes do not \
             break)"
                .to_string()
        };
        let bonds = format!(
            "window {w}: {} bond pair(s) past the critical stretch (up to {:.2} s0, at \
             ({:.4}, {:.4})) cannot break",
            h.pairs, h.worst, h.at[0], h.at[1]
        );
        let tips = || (self.tips.iter()).filter(|t| t.active() && t.window == w);
        if !at_crack {
            let pos = wm.model.positions();
            let off = (tips().flat_map(|t| t.path.nodes.iter()))
                .map(|&i| (pos[i][0] - at.x).hypot(pos[i][1] - at.y))
                .fold(f64::INFINITY, f64::min);
            let account = format!(
                "{bonds}, {off:.4} m from the tracked crack: {by} holds them. No tracked \
                 crack runs there; a body free to crack would start a second crack there, \
                 which PD-BEM does not follow (check with --growth-mode full-pd)"
            );
            return Some(HeldCrack {
                account,
                traced: true,
                off_crack: true,
            });
        }
        let thr = self.params.path.threshold;
        let account = format!(
            "{bonds}, and the window did not move on: the crack is held by {by}, not by its \
             toughness, because the tracker (growth.damage_threshold {thr}, and {:.3} where \
             bonds that cannot break hold a crack) did not see its tip pass the trigger \
             margin or reach the end of the fine cells. Raise growth.trigger_ratio (seed 002: 0.9) or \
             lower growth.damage_threshold (a fresh crack between node rows has damage \
             about 0.365 at m = 3)",
            thr * HELD_THRESHOLD_FACTOR
        );
        let traced = tips().any(|t| !t.path.is_empty());
        Some(HeldCrack {
            account,
            traced,
            off_crack: false,
        })
    }

    /// Follows the crack of active tip `t` past where the tracker lost it, when the crack
    /// is held: the path is traced again down to [`HELD_THRESHOLD_FACTOR`] of the damage
    /// threshold ([`Growth::wide_path`]), and taken when it reaches more than a dx farther
    /// and bonds that cannot break, nearer the tip than its entry and within
    /// [`crack_reach`] of its nodes, are past their breaking stretch ([`held_bonds`]): the
    /// crack runs on to them.
    ///
    /// On the regular lattice with m = 3 a node beside a fresh crack between two node rows
    /// has damage about 0.365, under seed 002's 0.38, and a crack between node columns
    /// that has not opened evenly splits it (0.29-0.44 on `growth_shear_edge`): the traced
    /// tip then stops short of the trigger margin while the crack reaches the no-fail band
    /// (the shear plate at load 0.12: tip traced at (8.65, 3.05), held bonds at (8.75,
    /// 2.65)). Away from a hold the tracker keeps its threshold, so a run whose crack is
    /// never held is unchanged bit for bit.
    ///
    /// In a refined window ([`finest_spacing`]) the same happens at the end of the fine
    /// cells, whose coarse neighbours cannot break (`growth_shear_edge_refined` after load
    /// 0.16: nodes of 0.37 between the tip traced at (8.475, 2.475) and the last fine row
    /// at y = 2.325, of 0.52, before the coarse row at 2.25 held at 1.4 s0). There:
    /// - only the finest cells are traced at the lower threshold: the damage that spreads
    ///   along the size jump where the crack meets the coarse cells (0.33-0.38 on that
    ///   plate, to 0.25 m aside) would take the tip sideways;
    /// - a tip that already triggers the move is not followed: at the end of the fine
    ///   cells the lower threshold can only add that sideways damage (the 2 m tension
    ///   plate with a 0.3 m zone: a followed tip at (10.105, 5.013) beside a traced one
    ///   that triggered at (10.068, 5.121), whose moved window's pre-crack then led the
    ///   crack along x = 10.1 m instead of within 0.006 m of the line).
    pub(super) fn follow_held(&mut self, t: usize) -> Result<(), CouplingError> {
        let tip = &self.tips[t];
        if !tip.active() || tip.path.is_empty() {
            return Ok(());
        }
        let wm = &self.problem.windows[tip.window];
        let refined = finest_spacing(wm).is_some();
        if refined && self.triggers(t) {
            return Ok(());
        }
        let wide = self.wide_path(t)?;
        if wide.length <= tip.path.length + wm.window.spec.dx {
            return Ok(());
        }
        let pos = wm.model.positions();
        let reach = crack_reach(wm);
        let (at, entry) = (tip.position(), tip.entry);
        let ratio = self.params.trigger_ratio;
        let held_at_crack = |x: [f64; 2], ends: [[f64; 2]; 2]| {
            let v = V2::new(x[0], x[1]);
            (v - at).norm() < (v - entry).norm()
                && (refined || band_bond(wm, ratio, ends))
                && near_nodes(pos, &wide.nodes, x, reach)
        };
        if held_bonds(&wm.model, held_at_crack).is_some() {
            self.tips[t].path = wide;
        }
        Ok(())
    }

    /// The path of tip `t` traced down to [`HELD_THRESHOLD_FACTOR`] of the damage
    /// threshold: the crack with the damage a fresh crack between node rows leaves; in a
    /// refined window in its finest cells only ([`trace_crack_finest`]).
    fn wide_path(&self, t: usize) -> Result<CrackPath, CouplingError> {
        let tip = &self.tips[t];
        let wm = &self.problem.windows[tip.window];
        let low = self.params.path.threshold * HELD_THRESHOLD_FACTOR;
        if finest_spacing(wm).is_some() {
            let entry = [tip.entry.x, tip.entry.y];
            return trace_crack_finest(&wm.model, entry, &self.params.path, low)
                .map_err(|e| CouplingError::pd(tip.window, e));
        }
        let params = PathParams {
            threshold: low,
            ..self.params.path
        };
        track(wm, tip.window, tip.entry, &params)
    }

    /// The bonds of window `w` past their breaking stretch that cannot break and lie
    /// nearer an active tip of the window than that tip's entry
    /// ([`Growth::held_by_protection`]), and whether they hold the crack: the held bonds
    /// within [`crack_reach`] of the nodes of a traced crack, traced down to
    /// [`HELD_THRESHOLD_FACTOR`] of the threshold (or ahead of a tip the tracker does not
    /// see), if there are any, else the others (away from the crack:
    /// `growth_shear_edge` at loads 0.22-0.24, bonds of the band at (9.8, 0.35) m beside
    /// the end of the bottom clamp, 1.6 m from the crack, where full PD starts a second
    /// crack).
    fn held_near(&self, w: usize) -> Option<(HeldBonds, bool)> {
        // Each active tip of the window with the nodes of its crack (None: untraced).
        let tips: Vec<(&TipState, Option<Vec<usize>>)> = (0..self.tips.len())
            .filter(|&t| self.tips[t].active() && self.tips[t].window == w)
            .map(|t| {
                let tip = &self.tips[t];
                let nodes = (!tip.path.is_empty()).then(|| {
                    (self.wide_path(t).ok())
                        .filter(|p| p.nodes.len() > tip.path.nodes.len())
                        .map_or_else(|| tip.path.nodes.clone(), |p| p.nodes)
                });
                (tip, nodes)
            })
            .collect();
        if tips.is_empty() {
            return None;
        }
        let wm = &self.problem.windows[w];
        let (pos, reach) = (wm.model.positions(), crack_reach(wm));
        let ahead = |t: &TipState, x: [f64; 2]| {
            let x = V2::new(x[0], x[1]);
            (x - t.position()).norm() < (x - t.entry).norm()
        };
        let at_crack = |x: [f64; 2]| {
            (tips.iter()).any(|(t, nodes)| {
                ahead(t, x) && nodes.as_ref().is_none_or(|n| near_nodes(pos, n, x, reach))
            })
        };
        if let Some(h) = held_bonds(&wm.model, |x, _| at_crack(x)) {
            return Some((h, true));
        }
        held_bonds(&wm.model, |x, _| tips.iter().any(|(t, _)| ahead(t, x))).map(|h| (h, false))
    }
}

/// Whether the bond between `ends` is one of the no-fail band of window `wm` (trigger ratio
/// `ratio`): an end within the band or beyond an interface side ([`protect_band`]'s rule).
///
/// [`protect_band`]: crate::growth::tips::protect_band
fn band_bond(wm: &WindowModel, ratio: f64, ends: [[f64; 2]; 2]) -> bool {
    let band = margins(&wm.window, ratio).0;
    (ends.into_iter()).any(|e| near_interface_side(&wm.window, V2::new(e[0], e[1]), band))
}

/// How far from a crack node held bonds still hold that crack: a horizon and a dx of the
/// window (its coarse ones in a refined window), the reach of the bonds of the crack's
/// last nodes into the band beyond it.
fn crack_reach(wm: &WindowModel) -> f64 {
    wm.window.delta() + wm.window.spec.dx
}

/// Whether `x` lies within `reach` of one of the nodes `nodes` (positions `pos`).
fn near_nodes(pos: &[[f64; 2]], nodes: &[usize], x: [f64; 2], reach: f64) -> bool {
    (nodes.iter()).any(|&i| (pos[i][0] - x[0]).hypot(pos[i][1] - x[1]) <= reach)
}

/// The notes of the runs of steps after which the crack was held by bonds that cannot
/// break ([`StepResult::held`]): its growth over those loads was held back (the shear
/// plate of `growth_shear_edge` after step 2, load 0.12, before its crack was followed
/// past the tracker's threshold in step 3); and of the runs with such bonds away from
/// the cracks (`off_crack`).
pub(super) fn held_notes(steps: &[StepResult]) -> Vec<String> {
    let mut notes = Vec::new();
    let mut k = 0;
    while k < steps.len() {
        let Some(first) = &steps[k].held else {
            k += 1;
            continue;
        };
        let end = (k..steps.len())
            .take_while(|&j| {
                (steps[j].held.as_ref()).is_some_and(|h| h.off_crack == first.off_crack)
            })
            .last()
            .unwrap_or(k);
        let span = format!(
            "steps {}-{} (loads {}-{}): {}",
            steps[k].step, steps[end].step, steps[k].load, steps[end].load, first.account
        );
        if first.off_crack {
            notes.push(span);
        } else {
            let after = if end + 1 == steps.len() {
                "to the end of the run".to_string()
            } else if steps[end + 1].held.is_some() {
                format!(
                    "not held after step {}, where the held bonds lie away from it",
                    end + 1
                )
            } else {
                format!("it grew on in step {}", end + 1)
            };
            notes.push(format!(
                "{span}. The crack's growth over these loads was held back by that \
                 protection ({after})"
            ));
        }
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
    let before_held = (before.held.as_ref()).is_some_and(|h| !h.off_crack);
    if held.traced || held.off_crack || !before_held || last.relocations > 0 {
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
                off_crack: false,
            }),
            ..step_result(k, 1.0 + k as f64)
        }
    }

    /// Step `k` with held bonds away from the crack.
    fn off(k: usize) -> StepResult {
        StepResult {
            held: Some(HeldCrack {
                account: format!("off {k}: away from the crack"),
                traced: true,
                off_crack: true,
            }),
            ..step_result(k, 1.0 + k as f64)
        }
    }

    #[test]
    fn held_bonds_away_from_the_crack_get_their_own_note_and_never_end_the_run() {
        // The shear plate: the crack held after step 2, bonds beside the clamp's end held
        // after steps 4-5 (away from the crack).
        let steps = [
            step(0, None, 0),
            step(1, None, 0),
            step(2, Some(true), 0),
            step(3, None, 3),
            off(4),
            off(5),
        ];
        let notes = held_notes(&steps);
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(notes[0].starts_with("steps 2-2 (loads 3-3): held 2"));
        assert!(notes[0].contains("it grew on in step 3"), "{notes:?}");
        assert_eq!(
            notes[1],
            "steps 4-5 (loads 5-6): off 4: away from the crack"
        );
        assert!((1..=steps.len()).all(|n| held_end(&steps[..n]).is_none()));
        // Held at the crack, then away from it: two runs, the first says the crack was
        // not held after it.
        let notes = held_notes(&[step(0, Some(true), 0), off(1)]);
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(notes[0].contains("not held after step 1"), "{notes:?}");
        // Untraced and held, but away from the crack in the step before: no end.
        assert_eq!(held_end(&[off(0), step(1, Some(false), 0)]), None);
        assert_eq!(held_end(&[step(0, Some(false), 0), off(1)]), None);
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
