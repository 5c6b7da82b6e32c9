//! The data of a growth run: the scene-specific [`Scenario`], the initial [`GrowthSetup`] and the records a run produces
//! ([`StepResult`], [`RelocationRecord`], [`GrowthResult`], ...).

use pdbem_bem::post::Background;
use pdbem_bem::{Bc, Material, Mesh, SolveParams, V2};
use pdbem_pd::solvers::frozen::Tally;

use crate::growth::overstrain::Hotspot;
use crate::growth::tips::TipSpec;
use crate::growth::transfer::TransferInfo;
use crate::pd_window::EdgeCondition;
use crate::setup::Layout;
use crate::window::Window;

/// The scene-specific parts of a growth run, all at load factor 1.
pub trait Scenario: Sync {
    /// Conditions of every element of `mesh` (scene values; interface elements are
    /// overwritten by the coupling).
    fn bem_conditions(&self, mesh: &Mesh) -> Result<Vec<[Bc; 2]>, String>;
    /// Scene conditions on the sides of `window` that lie on the outline.
    fn outer_conditions(&self, window: &Window) -> Vec<EdgeCondition>;
}

/// One Algorithm 1 iteration, as seen by the observer.
#[derive(Debug, Clone)]
pub struct IterationEvent<'a> {
    /// Load step.
    pub step: usize,
    /// Load factor.
    pub load: f64,
    /// Iteration within the current geometry.
    pub iteration: usize,
    /// Relative interface residual.
    pub residual: f64,
    /// Bond pairs broken in this iteration.
    pub bonds_broken: usize,
    /// Tip positions (m), in tip order.
    pub tips: &'a [V2],
}

/// The initial macro model of a growth run.
#[derive(Debug, Clone)]
pub struct GrowthSetup {
    /// Outline, holes, cracks (ending at the tips) and one window per tip.
    pub layout: Layout,
    /// The tips the windows follow.
    pub tips: Vec<TipSpec>,
    /// BEM material.
    pub material: Material,
    /// BEM solver parameters.
    pub bem_params: SolveParams,
    /// Remote field (finite bodies: none).
    pub background: Background,
    /// Thickness (m).
    pub thickness: f64,
}

/// One load step.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepResult {
    /// Step index (0-based).
    pub step: usize,
    /// Load factor.
    pub load: f64,
    /// Algorithm 1 iterations in the step (all geometries).
    pub iterations: usize,
    /// Last interface residual.
    pub residual: f64,
    /// Whether the step converged (false when it ended in structural failure).
    pub converged: bool,
    /// Broken bond pairs in all windows after the step (pre-cracks excluded).
    pub broken_bonds: usize,
    /// Tip positions after the step (m), in tip order.
    pub tips: Vec<V2>,
    /// CMOD of the first crack with a mouth on the outline (m).
    pub cmod: Option<f64>,
    /// Relocations during the step.
    pub relocations: usize,
    /// Wall time (s).
    pub wall_s: f64,
    /// Of which PD solves (s).
    pub pd_s: f64,
    /// The most strained point of the BEM body one horizon inside its boundary, away from
    /// the windows ([`crate::growth::overstrain`]); None when the step did not converge
    /// (failure) or the bonds never break.
    pub overstrain: Option<Hotspot>,
    /// Damage in a window off every crack it tracks after the step (a second crack,
    /// [`crate::growth::driver`]'s stray-damage watch); None when there is none.
    #[serde(default)]
    pub stray: Option<StrayDamage>,
    /// Bonds past their breaking stretch that cannot break near a tip after the step
    /// (the crack held by a window's protection, not by its toughness,
    /// [`crate::growth::driver`]); None when there are none.
    #[serde(default)]
    pub held: Option<HeldCrack>,
    /// The windows' PD equilibria in the step, by solver (PD-BEM; the chord iteration and
    /// its fallbacks, [`pdbem_pd::solvers::frozen`]).
    #[serde(default)]
    pub window_solves: Tally,
}

/// A crack held by bonds that cannot break after a load step, or such bonds away from
/// the cracks ([`StepResult::held`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HeldCrack {
    /// What holds it, where, and what to change.
    pub account: String,
    /// A tip of the window has a traced path, so a window move may still free the crack;
    /// false when the tracker sees no growth at all.
    pub traced: bool,
    /// The bonds lie away from every tracked crack (where a second crack would start),
    /// so they hold no crack the window follows.
    #[serde(default)]
    pub off_crack: bool,
}

/// Damage in a PD window farther than [`STRAY_REACH`] horizons from every crack line the
/// window holds (its pre-cracks and the traced paths of its tips): a crack that PD-BEM
/// does not track.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StrayDamage {
    /// Window index.
    pub window: usize,
    /// The damaged node farthest from the window's crack lines (m).
    pub position: V2,
    /// Its damage.
    pub damage: f64,
    /// Its distance to the nearest crack line of the window (m).
    pub distance: f64,
    /// The window's horizon (m).
    pub horizon: f64,
}

/// Distance (in horizons) from every tracked crack line beyond which window damage above
/// the tracking threshold is a second crack: the tracked tip lags the damage by up to 3
/// dx (about a horizon, [`crate::growth::driver`]'s under-threshold note), and the damage
/// band of a crack reaches about a horizon either side of its line.
pub const STRAY_REACH: f64 = 2.0;

/// One window relocation.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RelocationRecord {
    /// Load step.
    pub step: usize,
    /// Load factor.
    pub load: f64,
    /// Tip.
    pub tip: String,
    /// Window centre before and after (m).
    pub from: V2,
    /// Window centre after (m).
    pub to: V2,
    /// Tip position when the window moved (m).
    pub tip_at: V2,
    /// BEM elements added to each crack face.
    pub elements_added: usize,
    /// Largest distance of the new window's traced pre-crack from the old traced path (m).
    pub precrack_deviation: f64,
    /// Where the new window's state came from.
    pub transfer: TransferInfo,
    /// Corners of the new window, counter-clockwise (m).
    pub corners: [V2; 4],
    /// The window's angle before and after (degrees) when it turned to lie against the
    /// outline ([`crate::growth::relocate::turned_to_outline`]); None when it kept its
    /// orientation.
    #[serde(default)]
    pub turned_deg: Option<[f64; 2]>,
    /// BEM elements of the new mesh.
    pub elements: usize,
    /// This relocation's share of the rebuild wall time (mesh, assembly, factorization,
    /// windows, transfer): the rebuild time over the relocations carried out together
    /// (`rebuild_shared_by`), so that the shares add up to the rebuild time (s).
    pub rebuild_s: f64,
    /// Relocations carried out by one rebuild together with this one (itself included).
    pub rebuild_shared_by: usize,
    /// Wall time of the rebuild's BEM assembly and of its factorization with the
    /// response precomputation (s; whole rebuild, not shared out).
    pub bem_assembly_s: f64,
    /// See [`Self::bem_assembly_s`].
    pub bem_factor_s: f64,
    /// Fraction of the new mesh's element pairs whose blocks were copied from the last
    /// assembly ([`pdbem_bem::PairCache`]) instead of integrated.
    pub bem_pairs_reused: f64,
}

/// A relocation worked out but not yet carried out ([`crate::growth::Growth::plan`]).
#[derive(Debug, Clone)]
pub struct RelocationPlan {
    /// The macro layout after the moves and merges.
    pub layout: Layout,
    /// Window of every tip afterwards.
    pub owner: Vec<usize>,
    /// Per relocated tip: (tip, (old window centre, tip position, BEM elements added)).
    pub moves: Vec<(usize, (V2, V2, usize))>,
    /// Tips past their margin whose window cannot move on because a hole is in the way,
    /// with the hole's name: [`Growth::apply`](crate::growth::Growth::apply) ends them at
    /// the hole ([`crate::growth::TipEnd::Hole`]).
    pub blocked: Vec<(usize, String)>,
    /// Tips past their margin for which no window containing them fits inside the body:
    /// the outline is within the window's reach, the crack reaches it (structural failure,
    /// seed 002 Algorithm 2 step 9).
    pub at_outline: Vec<usize>,
    /// Windows merged.
    pub merges: usize,
    /// The new layout cuts the BEM body apart ([`crate::growth::topology`]): the windows
    /// alone hold a piece of it ([`crate::floating`]).
    pub cuts_body: bool,
}

/// Why the run stopped early.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Failure {
    /// Step.
    pub step: usize,
    /// Load factor.
    pub load: f64,
    /// The tip that cut the body.
    pub tip: String,
}

/// What a growth run produced.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GrowthResult {
    /// Load steps.
    pub steps: Vec<StepResult>,
    /// Relocations in order.
    pub relocations: Vec<RelocationRecord>,
    /// Structural failure (a crack reached the outline), if it happened.
    pub failure: Option<Failure>,
    /// First load factor at which a bond broke.
    pub initiation_load: Option<f64>,
    /// Messages (tips ended, windows merged, ...).
    pub notes: Vec<String>,
    /// Why the run ended before its load budget without structural failure: a load step
    /// that no back-off could solve ([`crate::growth::driver`] module docs), with what
    /// was tried. None for a run that completed.
    #[serde(default)]
    pub failure_reason: Option<String>,
}

/// Outcome of one Algorithm 1 run at a load.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveOutcome {
    /// Converged (residual and no bond breaking).
    pub converged: bool,
    /// Iterations.
    pub iterations: usize,
    /// Last residual.
    pub residual: f64,
    /// Bond pairs broken during the run.
    pub bonds_broken: usize,
    /// PD wall time (s).
    pub pd_s: f64,
    /// The windows' PD equilibria, by solver.
    pub window_solves: Tally,
    /// What the interface accelerator reported ([`crate::CouplingInfo::notes`]).
    pub notes: Vec<String>,
}

/// The note on the windows' PD equilibria of `steps` when a fallback found any or none
/// was found (the chord iteration failed: a window nearly cut; ADR on a trial budget,
/// Newton, then ADR on its full budget, [`pdbem_pd::solvers::frozen::Fallbacks`]).
pub(crate) fn fallback_note(steps: &[StepResult]) -> Option<String> {
    let t: Tally = steps.iter().map(|s| s.window_solves).sum();
    if t.fallbacks() + t.failed == 0 {
        return None;
    }
    let all = t.chord + t.fallbacks() + t.failed;
    let mut note = format!(
        "window PD equilibria: {all}, {} by the chord iteration; where it failed, {} by ADR \
         and {} by Newton ({} ADR trials ran out before Newton)",
        t.chord, t.adr, t.newton, t.adr_trials_run_out
    );
    if t.loose > 0 {
        note += &format!(", {} Newton stalls accepted", t.loose);
    }
    if t.failed > 0 {
        note += &format!(", {} found by no solver", t.failed);
    }
    Some(note)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::fixtures::step_result;

    #[test]
    fn the_fallback_note_sums_the_steps_and_is_left_out_without_fallbacks() {
        let step = |k: usize, t: Tally| StepResult {
            window_solves: t,
            ..step_result(k, 1.0)
        };
        let chord = |n: usize| Tally {
            chord: n,
            ..Tally::default()
        };
        assert_eq!(
            fallback_note(&[step(0, chord(40)), step(1, chord(7))]),
            None
        );
        let hard = Tally {
            chord: 3,
            adr: 2,
            newton: 5,
            adr_trials_run_out: 4,
            ..Tally::default()
        };
        let note = fallback_note(&[step(0, chord(40)), step(1, hard)]).expect("a note");
        assert_eq!(
            note,
            "window PD equilibria: 50, 43 by the chord iteration; where it failed, 2 by ADR \
             and 5 by Newton (4 ADR trials ran out before Newton)"
        );
        let failed = Tally {
            failed: 1,
            ..Tally::default()
        };
        let note = fallback_note(&[step(0, failed)]).expect("a note");
        assert!(note.ends_with(", 1 found by no solver"), "{note}");
    }
}
