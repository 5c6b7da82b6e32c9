//! The horizon against the body in stand-alone PD: peridynamics converges to the elastic
//! body as the horizon $\delta$ shrinks against the body's length scales, and a cracked or
//! holed body whose smaller side spans only a few horizons answers with the PD model's
//! own, stiffer-or-softer nonlocal response.
//!
//! Measured on seed 001's 50 mm square with a 10 mm edge crack (E = 30 GPa, 1 MPa on the
//! top and bottom edges, elastic bonds, surface correction, implicit solver): the opening
//! between the loaded edges against the BEM alone (2.033e-6 m), horizon factor 6:
//! $\delta / H$ = 0.06 +3.4 %, 0.12 +6.1 %, 0.24 +10.8 %, 0.46 +19.6 %; horizon factor
//! 3.015: 0.03 -1.1 %, 0.06 -2.2 %, 0.12 -3.7 %, 0.23 +0.6 % (the grid's own error
//! of the opposite sign cancelling). So a stand-alone PD scene with a crack or a hole
//! whose horizon exceeds [`HORIZON_FRACTION`] of the body's smaller side gets a note (and
//! full-PD growth, which runs the whole body at the windows' spacing).
//! Under a uniform strain the surface correction makes any horizon exact (a strip of 1.7
//! horizons, `pd_bar_tension`, gives the bar's solution), so bodies without cracks or
//! holes get none. A refinement (`pd.refinement`, `pd.refine_zones`) is taken at its finest
//! spacing: it is where the cracks are (`pd_notched_bar_adaptive`, 0.30 on its 2 mm grid
//! and 0.15 at its 1 mm level, has the peak force of the uniform 1 mm grid within 0.2 %).

use crate::geometry::bounding_box;
use crate::runner::mode::{mode_of, Mode};
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// Largest horizon, as a fraction of the body's smaller side, of a cracked or holed
/// stand-alone PD body without a note (module docs: about 10 % from the elastic opening
/// at 0.24, 6 % at 0.12).
pub const HORIZON_FRACTION: f64 = 0.2;

/// 2^levels of the finest spacing a refinement or a refinement zone reaches (children of
/// seed 004's particles that keep their parent's horizon do not shrink it).
fn finest_halvings(pd: &crate::scene::PdSettings) -> f64 {
    let refined = pd
        .refinement
        .as_ref()
        .filter(|r| !r.keep_horizon)
        .map_or(0, |r| u32::from(r.max_level));
    let zones = pd.refine_zones.iter().map(|z| z.levels).max().unwrap_or(0);
    2f64.powi(refined.max(zones).min(30) as i32)
}

/// The note of a stand-alone PD scene (or full-PD growth, at the windows' spacing) whose
/// horizon is large against its body.
pub fn note(scene: &Scene) -> Option<String> {
    let full_pd = scene
        .growth
        .as_ref()
        .is_some_and(|g| g.mode == crate::scene::GrowthMode::FullPd);
    let whole_body = mode_of(scene) == Mode::Pd || full_pd;
    if !whole_body || (scene.cracks.is_empty() && scene.body.holes.is_empty()) {
        return None;
    }
    let pd = scene.pd.as_ref()?;
    let geo = SceneGeometry::of(scene);
    let outline = geo.outline.as_ref()?;
    let (lo, hi) = bounding_box(&outline.points);
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    // Full-PD growth runs the whole body at the windows' spacing, uniform.
    let (dx, halvings) = match (full_pd, &scene.coupling, pd.dx, pd.nx) {
        (true, Some(c), _, _) => (c.dx(), 1.0),
        (false, _, Some(dx), _) => (dx, finest_halvings(pd)),
        (false, _, None, Some(nx)) if nx > 0 => (w / nx as f64, finest_halvings(pd)),
        _ => return None,
    };
    let delta = pd.horizon_factor * dx / halvings;
    let side = w.min(h);
    let ratio = delta / side;
    (ratio.is_finite() && ratio > HORIZON_FRACTION).then(|| {
        format!(
            "pd: the horizon {delta:.4e} m (dx {dx:.4e} m times {}, at the finest level) is \
             {ratio:.2} of the body's \
             smaller side {side:.4e} m (a note over {HORIZON_FRACTION}): with cracks or holes \
             the PD body then answers with its own nonlocal stiffness, not the elastic body's \
             (an edge-cracked square's opening +11 % at 0.24, +20 % at 0.46, against +3.4 % at \
             0.06); a finer grid (pd.dx, pd.nx) or a smaller pd.horizon_factor brings it closer",
            pd.horizon_factor
        )
    })
}
