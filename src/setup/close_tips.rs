//! Tips close to another boundary: where the two-level error estimate of the static BEM
//! was measured to miss the error of K and CMOD (see [`CLOSE_FEATURE_RATIO`]). Below
//! [`MIN_FEATURE_RATIO`](super::sizing::MIN_FEATURE_RATIO) of the geometry the mesh cannot resolve the tip at all and the
//! scene is refused ([`super::sizing::LocalSizes::of`]); between the two, a note.

use super::sizing::{geometry_extent, tip_features, OWN_LENGTH};
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// Tips nearer another boundary than this fraction of the geometry's largest extent get
/// a note ([`close_tip_notes`]): the two-level estimate was measured to miss the error
/// there. An edge crack in a 10 m x 40 m strip pulled along its length, K_I against the
/// ligament's bending limit 3.975 M / b^1.5: ligament b of 2.5e-6 of the extent +1.0 %
/// (estimate 1.7 %); 1.25e-6 +1.9 % (1.2 %); 7.5e-7 +4.3 % (1.1 %); 2.5e-7 +31 % (4.7 %).
/// Refined to `--tol 0.01`: 7.5e-7 +1.7 % (2.5 %), 2.5e-7 +15.0 % (14.4 %).
pub const CLOSE_FEATURE_RATIO: f64 = 1e-5;

/// Notes on the tips of `scene` whose length scale is set by another boundary closer than
/// [`CLOSE_FEATURE_RATIO`] of the geometry's extent (and not below [`MIN_FEATURE_RATIO`](super::sizing::MIN_FEATURE_RATIO),
/// which [`super::sizing::LocalSizes::of`] refuses).
pub fn close_tip_notes(scene: &Scene) -> Vec<String> {
    let geo = SceneGeometry::of(scene);
    if geo.cracks.is_empty() {
        return Vec::new();
    }
    let loops = super::bem::loops(scene, &geo, 1.0);
    let extent = geometry_extent(&geo);
    tip_features(&geo, &loops)
        .iter()
        .filter(|t| t.nearest != OWN_LENGTH && t.scale < CLOSE_FEATURE_RATIO * extent)
        .map(|t| {
            format!(
                "cracks.{} ('{}'): its {} tip lies {:.3e} m from {}, {:.1e} of the body's size \
                 {:.3e} m (under {CLOSE_FEATURE_RATIO:.0e}): there the two-level error estimate \
                 was measured to miss the error of K and CMOD (a deep edge crack's K_I 31 % high \
                 with an estimate of 4.7 % at 2.5e-7 of the size); a tolerance (--tol, \
                 bem.tolerance) refines it closer (+15 % with an estimate of 14 % there), but take \
                 K as uncertain by more than its estimate, or move the tip away",
                t.crack,
                scene.cracks[t.crack].name,
                if t.at_end { "end" } else { "start" },
                t.scale,
                t.nearest,
                t.scale / extent,
                extent,
            )
        })
        .collect()
}
