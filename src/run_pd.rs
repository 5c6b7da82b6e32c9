//! Stand-alone PD solve of a scene (issue 3): grid the body, cut pre-cracks,
//! load, solve, and return a [`RunSummary`] (`mode: "pd"`). STUB: the PD
//! helper replaces the body of [`run`].

use crate::runner::{RunContext, RunSummary};
use crate::scene::Scene;

/// Solves `scene` with peridynamics over the whole body.
pub fn run(scene: &Scene, ctx: &RunContext) -> anyhow::Result<RunSummary> {
    let _ = ctx;
    anyhow::bail!("{}: the PD solver is not wired yet", scene.name)
}
