//! Refusal of crack meshes too coarse for the crack-opening fit: every K a static BEM or
//! PD-BEM run reports from the fit ([`pdbem_bem::post::sif::cod_sif`]) needs at least
//! [`MIN_FIT_STATIONS`] crack-face stations within the fit length `bem.cod_fit_fraction`
//! L behind its tip. With fewer the fit has fewer terms than the opening's shape, its
//! error (up to +26 %) keeps its size as h halves, and the two-level estimate
//! ([`crate::refine`]) reads a few per cent: a K outside its own error bar with exit code 0
//! (the constant's docs give the measurements). The default sizes hold about 24 stations
//! (tip elements L/80); a scene meets this rule's limit by fixing a crack's size
//! (`bem.group_sizes.<crack>`, `bem.tip_refinement`) or by a small `bem.cod_fit_fraction`.
//!
//! [`check`] runs in `pdbem check` and before every static BEM and PD-BEM run, on the
//! static mesh at the scene's own sizes (the primary level, and the coarse level of a
//! Richardson pair); a run with `bem.tolerance` refines until the rule holds
//! ([`crate::refine`]), so it is checked on the level it reports. [`require`] checks any
//! solved mesh (the coupled body's, the reported levels').

use anyhow::{bail, Result};
use pdbem_bem::mesh::Mesh;
use pdbem_bem::post::sif::{fit_station_count, MIN_FIT_STATIONS};

use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// The tips of `mesh` whose fit holds fewer than [`MIN_FIT_STATIONS`] stations, one
/// phrase each ("crack.end (2 stations within 3.000e-1 m)"), grouped by what to change
/// (what sets the crack's elements, and the size that would do): (tips, advice).
pub fn unresolved(scene: &Scene, mesh: &Mesh) -> Vec<(Vec<String>, String)> {
    let fraction = scene.bem.cod_fit_fraction;
    let mut groups: Vec<(Vec<String>, String)> = Vec::new();
    for (ci, at_end, _, _) in mesh.tips() {
        let (fit, n) = fit_station_count(mesh, ci, at_end, fraction);
        if n >= MIN_FIT_STATIONS {
            continue;
        }
        let name = &mesh.cracks[ci].name;
        let end = if at_end { "end" } else { "start" };
        let plural = if n == 1 { "" } else { "s" };
        let tip = format!("{name}.{end} ({n} station{plural} within {fit:.3e} m)");
        let todo = advice(scene, name, fit);
        match groups.iter_mut().find(|(_, a)| *a == todo) {
            Some((tips, _)) => tips.push(tip),
            None => groups.push((vec![tip], todo)),
        }
    }
    groups
}

/// What to change so that the fit of a tip of crack `name` holds enough stations.
fn advice(scene: &Scene, name: &str, fit: f64) -> String {
    let h = fit / MIN_FIT_STATIONS as f64;
    if let Some(size) = scene.bem.group_sizes.get(name) {
        format!(
            "make bem.group_sizes.{name} (now {size}) at most {h:.3e} m, or drop it (the \
             default sizes grade the crack's tips)"
        )
    } else if let Some(t) = &scene.bem.tip_refinement {
        format!(
            "make bem.tip_refinement.element_size (now {}) at most {h:.3e} m",
            t.element_size
        )
    } else {
        format!(
            "raise bem.cod_fit_fraction, or refine the crack's elements to at most {h:.3e} m \
             (bem.group_sizes.{name})"
        )
    }
}

/// Refuses `mesh` (`what`: which mesh, for the message) when [`unresolved`] finds a tip.
pub fn require(scene: &Scene, mesh: &Mesh, what: &str) -> Result<()> {
    let tips = unresolved(scene, mesh);
    if tips.is_empty() {
        return Ok(());
    }
    bail!(
        "{}: {what}: the crack-opening fit of a tip needs at least {MIN_FIT_STATIONS} \
         crack-face stations within its fit length (bem.cod_fit_fraction = {} of the tip's \
         length scale) to give a K (with fewer, its error does not shrink with the elements \
         and no error estimate sees it); {}",
        scene.file_label().display(),
        scene.bem.cod_fit_fraction,
        tips.iter()
            .map(|(t, todo)| {
                let tip = if t.len() == 1 { "tip" } else { "tips" };
                format!("{tip} {}: {todo}", t.join(", "))
            })
            .collect::<Vec<_>>()
            .join("; ")
    )
}

/// The check of `pdbem check` and of every run (module docs): static BEM and PD-BEM
/// scenes without `bem.tolerance`, on the static mesh at the scene's sizes. A body the
/// mesher refuses passes here (the mesher's own error comes first).
pub fn check(scene: &Scene) -> Result<()> {
    let static_body = scene.growth.is_none() && (scene.coupling.is_some() || scene.pd.is_none());
    if !static_body || scene.bem.tolerance.is_some() || scene.cracks.is_empty() {
        return Ok(());
    }
    let geo = SceneGeometry::of(scene);
    let Ok(mesh) = super::bem::mesh_builder(scene, &geo, 1.0).and_then(|b| Ok(b.build()?)) else {
        return Ok(());
    };
    let what = if scene.bem.richardson {
        "the BEM mesh at the scene's sizes (the coarse level of bem.richardson)"
    } else {
        "the BEM mesh at the scene's sizes"
    };
    require(scene, &mesh, what)
}
