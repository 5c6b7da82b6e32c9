//! Crack growth (issue 5; seed 002 Algorithm 2, sections 2.3.2-2.3.3).
//!
//! Three modes produce the same [`GrowthHistory`] so that outputs, plots and the
//! `plot-paths` overlay treat them alike:
//! - PD-BEM: moving PD windows over the tips iterated against the BEM body
//!   (`pdbem_coupling::growth`);
//! - BEM-only: SIF at the tip, kink by maximum circumferential stress, fixed increment
//!   `da`, critical load from K_c = sqrt(E' G_c) (Liu, Li & Xie 2017, seed 002 ref. \[34\]);
//! - full PD: the whole body in PD at the window resolution.
//!
//! Shared pieces: [`log`] (`growth_log.jsonl`, progress bar), [`output`] (files and
//! plots of a run, [`output::finish`]), [`overlay`] (`pdbem plot-paths`), [`bench`](mod@bench)
//! (`pdbem bench growth`); path comparison is `pdbem_coupling::growth::compare`.
//!
//! Loads: step k applies the factor `load.initial + k load.step` to every boundary value
//! of the scene (`Load::factors`); `load` in the records is that factor, which is the
//! physical load (Pa or m) when the scene writes unit boundary values.

pub mod bem_only;
pub mod bench;
pub mod full_pd;
pub mod log;
pub mod output;
pub mod overlay;
pub mod pd_bem;

pub use pdbem_coupling::growth::history::{
    FieldSnapshot, GrowthHistory, Overstrain, PathPoint, Relocation, StepRecord, TipPath,
    WindowOutline,
};

/// `growth.snapshot_steps` of `scene` (none without a growth section).
pub fn snapshot_steps(scene: &crate::scene::Scene) -> &[usize] {
    scene
        .growth
        .as_ref()
        .map_or(&[][..], |g| &g.snapshot_steps[..])
}
