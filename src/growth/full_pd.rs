//! full_pd growth: placeholder until the coupling growth lands.

use anyhow::Result;

use crate::growth::GrowthHistory;
use crate::runner::RunContext;
use crate::scene::Scene;

/// Runs full_pd growth of `scene`.
pub fn run(scene: &Scene, _ctx: &RunContext) -> Result<GrowthHistory> {
    anyhow::bail!(
        "{}: full_pd growth is not wired yet",
        scene.file_label().display()
    )
}
