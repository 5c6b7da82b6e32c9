//! PD-BEM crack growth (seed 002 Algorithm 2): placeholder until the coupling growth lands.

use anyhow::Result;

use crate::growth::GrowthHistory;
use crate::runner::RunContext;
use crate::scene::Scene;

/// Runs PD-BEM growth of `scene`.
pub fn run(scene: &Scene, _ctx: &RunContext) -> Result<GrowthHistory> {
    anyhow::bail!(
        "{}: PD-BEM growth is not wired yet",
        scene.file_label().display()
    )
}
