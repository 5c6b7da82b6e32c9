//! bem_only growth: placeholder until the coupling growth lands.

use anyhow::Result;

use crate::growth::GrowthHistory;
use crate::runner::RunContext;
use crate::scene::Scene;

/// Runs bem_only growth of `scene`.
pub fn run(scene: &Scene, _ctx: &RunContext) -> Result<GrowthHistory> {
    anyhow::bail!(
        "{}: bem_only growth is not wired yet",
        scene.file_label().display()
    )
}
