//! Crack growth runs of a scene (issue 5; seed 002 Algorithm 2, sections 2.3.2-2.3.3):
//! the three engines live in `pdbem_coupling::growth` and all return the same
//! [`GrowthHistory`]; this module runs them on a scene and reports what they produce.
//! - [`pd_bem`]: moving PD windows over the tips iterated against the BEM body
//!   (`pdbem_coupling::growth::Growth`), with its observer (progress bar, run log,
//!   window snapshots);
//! - [`bem_only`]: SIF at the tip, kink by maximum circumferential stress, fixed
//!   increment `da`, critical load from K_c = sqrt(E' G_c) (Liu, Li & Xie 2017, seed 002
//!   ref. \[34\]; `pdbem_coupling::growth::bem_only`);
//! - [`full_pd`]: the whole body in PD at the window resolution
//!   (`pdbem_coupling::growth::full_pd`).
//!
//! Checkpoints and `--resume`: [`checkpoint`](mod@checkpoint).
//!
//! Thin ligaments the paths form along other boundaries: [`ligaments`].
//!
//! Reporting: [`log`] (`growth_log.jsonl`, progress bar), [`output`] (files and
//! plots of a run, [`output::finish`]), [`sif_record`] (K along the path, `sif_path.csv`), [`overlay`] (`pdbem plot-paths`), [`bench`](mod@bench)
//! (`pdbem bench growth`); path comparison is `pdbem_coupling::growth::compare`.
//!
//! Loads: step k applies the factor `load.initial + k load.step` to every boundary value
//! of the scene (`Load::factors`); `load` in the records is that factor, which is the
//! physical load (Pa or m) when the scene writes unit boundary values.

pub mod bem_only;
pub mod bench;
pub mod checkpoint;
pub mod full_pd;
pub mod ligaments;
pub mod log;
pub mod output;
pub mod overlay;
pub mod pd_bem;
pub mod sif_record;
pub mod vtk;

/// File name of the growth log ([`log`]), which checkpoints carry ([`checkpoint`]).
pub const LOG_FILE: &str = "growth_log.jsonl";

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
