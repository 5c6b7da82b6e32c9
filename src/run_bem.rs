//! BEM solve of a scene (issue 2): mesh the scene, solve, post-process SIF,
//! kink and CMOD, and return a [`RunSummary`]. STUB: the BEM lead replaces
//! the body of [`run`].

use crate::runner::{RunContext, RunSummary};
use crate::scene::Scene;

/// Solves `scene` with the BEM alone. Outputs beyond the summary (extra CSVs,
/// field plots) go through `ctx.writer`.
pub fn run(scene: &Scene, ctx: &RunContext) -> anyhow::Result<RunSummary> {
    let _ = ctx;
    anyhow::bail!("{}: the BEM solver is not wired yet", scene.name)
}
