//! Rules of `growth`: the trigger band, the toughness a growth mode needs, the mode
//! against the sections present.

use super::Checker;
use crate::plot::ticks::human;
use crate::scene::{GrowthMode, Placement, Scene};

/// Most increments a BEM-only tip may take to cross the body (its bounding box's
/// diagonal over `growth.da`): each is a BEM solve of the whole body (0.2 s on a 50 x 100
/// mm plate of 1000 elements), so 1e4 is about half an hour per crossing; at da = 1e-7 m
/// that plate's run did not end in 5 minutes and had 1.1e6 increments to go.
pub const MAX_INCREMENTS_ACROSS: f64 = 1e4;

/// Checks the growth section.
pub fn check(c: &mut Checker, scene: &Scene) {
    if let Some(g) = &scene.growth {
        check_growth(c, scene, g);
    }
}

fn check_growth(c: &mut Checker, scene: &Scene, g: &crate::scene::Growth) {
    let t = g.trigger_ratio;
    if c.finite("growth.trigger_ratio", t) && !(t > 0.0 && t < 1.0) {
        c.fail(
            "growth.trigger_ratio",
            t,
            "trigger ratio must lie in (0, 1)",
        );
    } else if g.mode == GrowthMode::PdBem {
        check_trigger_band(c, t);
    }
    c.at_least(
        "growth.elements_per_extension",
        g.elements_per_extension,
        1,
        "elements per extension",
    );
    let d = g.damage_threshold;
    if c.finite("growth.damage_threshold", d) && !(d > 0.0 && d < 1.0) {
        c.fail(
            "growth.damage_threshold",
            d,
            "damage threshold must lie in (0, 1)",
        );
    }
    if let Some(da) = g.da {
        if c.positive("growth.da", da, "crack increment da") && g.mode == GrowthMode::BemOnly {
            check_increments_across(c, scene, da);
        }
    }
    check_positive_factors(c, scene);
    if let Some(sp) = g.sif_spacing {
        if c.finite("growth.sif_spacing", sp) && sp < 0.0 {
            c.fail(
                "growth.sif_spacing",
                sp,
                "spacing of the K record must be >= 0 (0: no record in the PD modes)",
            );
        }
    }
    if let Some(&k) = g.snapshot_steps.iter().find(|&&k| k >= scene.load.count) {
        c.fail(
            "growth.snapshot_steps",
            k,
            format!(
                "load steps are 0-based: the last is {} (load.count = {})",
                scene.load.count.saturating_sub(1),
                scene.load.count
            ),
        );
    }
    match g.mode {
        GrowthMode::PdBem if scene.coupling.is_none() => {
            c.fail_at("growth.mode", "PdBem growth needs a `coupling` section")
        }
        GrowthMode::FullPd if scene.coupling.is_none() => c.fail_at(
            "growth.mode",
            "FullPd growth needs a `coupling` section: its grid spacing is the window's, dx = coupling.side / coupling.n",
        ),
        GrowthMode::FullPd if scene.pd.is_none() => {
            c.fail_at("growth.mode", "FullPd growth needs a `pd` section")
        }
        GrowthMode::BemOnly => check_toughness(c, scene),
        _ => {}
    }
    if g.mode == GrowthMode::FullPd && scene.body.outline.remote_stress().is_some() {
        c.fail_at(
            "growth.mode",
            "FullPd growth needs a finite body: an Infinite outline has no region to fill",
        );
    }
    if g.mode == GrowthMode::PdBem {
        if let Some(co) = &scene.coupling {
            check_ligaments(c, scene, co);
            if t > 0.5 && t < 1.0 {
                check_room_to_move(c, scene, co, t);
            }
        }
        if let Some(pd) = &scene.pd {
            if matches!(pd.failure, crate::scene::Failure::Degradation { .. }) {
                c.fail_at(
                    "pd.failure",
                    pdbem_coupling::growth::params::TANH_LAW_REFUSED,
                );
            }
        }
    }
    if scene.cracks.is_empty() {
        c.fail_at("growth", "growth needs at least one crack");
    }
    if let Some(m) = g.move_distance {
        if c.positive("growth.move_distance", m, "move distance") {
            if let Some(co) = &scene.coupling {
                if m > co.side {
                    c.fail("growth.move_distance", m, format!("move distance larger than the window: must be at most coupling.side = {} m", co.side));
                }
            }
        }
    }
}

/// The no-fail band of a window is (1 - trigger_ratio) times its side wide on every
/// interface side (`pdbem_coupling::growth::tips::margins`); a ratio of 0.5 or less makes
/// the band cover the whole window, and the growth driver refuses it. Scene check and
/// driver share the bound.
fn check_trigger_band(c: &mut Checker, ratio: f64) {
    if ratio <= 0.5 {
        c.fail(
            "growth.trigger_ratio",
            ratio,
            "PD-BEM growth needs a trigger ratio above 0.5: the no-fail band, (1 - trigger_ratio) of the window side on each interface side, would cover the whole window (seed 002: 0.9)",
        );
    }
}

/// A window moves on when its tip comes within the trigger distance of an interface side:
/// the no-fail band, a horizon and a dx (`pdbem_coupling::growth::tips::margins`). The
/// moved window is centred on the tip to the nearest dx, so the tip lies at least half a
/// side less half a dx from each side; a trigger distance beyond that leaves the window
/// no place to move to, and the run would end at the first move
/// (`pdbem_coupling::growth::relocate::moved_spec`).
fn check_room_to_move(c: &mut Checker, scene: &Scene, co: &crate::scene::Coupling, ratio: f64) {
    let m = scene
        .pd
        .as_ref()
        .map_or(crate::scene::pd::default_horizon_factor(), |p| {
            p.horizon_factor
        });
    let (side, dx) = (co.side, co.dx());
    if !(side.is_finite() && dx.is_finite() && side > 0.0 && dx > 0.0) {
        return;
    }
    let trigger = (1.0 - ratio) * side + m * dx + dx;
    let room = 0.5 * side - 0.5 * dx;
    if trigger > room + 1e-9 * dx {
        let lowest = 1.0 - (room - m * dx - dx) / side;
        // (1 - r) side + (m + 1.5) side / n <= side / 2.
        let nodes = ((m + 1.5) / (ratio - 0.5) - 1e-9).ceil();
        let len = |v: f64| human(v, 4);
        // A ratio must stay below 1: where even 1 leaves no room, only more nodes do.
        let remedy = if lowest < 1.0 {
            format!(
                "Use a trigger ratio of at least {}, or at least {nodes} nodes per side (coupling.n)",
                (lowest.max(0.5) * 1e4).ceil() / 1e4
            )
        } else {
            let least = ((m + 1.5) / (0.99 - 0.5) - 1e-9).ceil();
            format!(
                "No trigger ratio below 1 leaves room at {} nodes per side: use at least {least} nodes per side (coupling.n) at a ratio of 0.99, or {nodes} at this one",
                co.n
            )
        };
        c.fail(
            "growth.trigger_ratio",
            ratio,
            format!(
                "a window moves on when its tip comes within {} m of an interface side (the no-fail band (1 - trigger_ratio) x {side} m, a horizon {} m and a dx {} m), but a window centred on the tip leaves it only {} m (half a side less half a dx) from its sides: no window could move on. {remedy}",
                len(trigger),
                len(m * dx),
                len(dx),
                len(room),
            ),
        );
    }
}

/// BEM-only growth compares K_eq with K_c: the material needs `fracture.g_c` > 0 or
/// `fracture.k_c`, or the scene a PD critical stretch and windows to derive it from.
fn check_toughness(c: &mut Checker, scene: &Scene) {
    let f = scene.material.fracture.as_ref();
    let k_c = f.and_then(|f| f.k_c);
    let g_c = f.and_then(|f| f.g_c);
    match (k_c, g_c) {
        (Some(_), _) => {}
        (None, Some(g)) if g <= 0.0 => c.fail(
            "material.fracture.g_c",
            g,
            "BemOnly growth needs G_c > 0 (K_c = sqrt(E' G_c) would be 0)",
        ),
        (None, Some(_)) => {}
        // K_c from the PD failure law (`setup::growth::toughness`).
        (None, None) if derivable(scene) => {}
        (None, None) => c.fail_at(
            "material.fracture",
            "BemOnly growth needs the toughness: give g_c (J/m^2) or k_c (Pa m^0.5), or \
             pd.failure: CriticalStretch with a coupling section to derive it from",
        ),
    }
}

/// K_c can be derived from the PD critical stretch at the window horizon.
fn derivable(scene: &Scene) -> bool {
    scene.coupling.is_some()
        && scene
            .pd
            .as_ref()
            .is_some_and(|pd| matches!(pd.failure, crate::scene::Failure::CriticalStretch(_)))
}

/// PD-BEM windows sit on the tips: each window side must be below the ligament ahead of
/// its tip (the distance from the tip to the outline or a hole along the crack direction).
fn check_ligaments(c: &mut Checker, scene: &Scene, co: &crate::scene::Coupling) {
    use crate::geometry::{ray_circle, ray_polygon};
    use crate::scene::shapes::{HoleShape, SceneGeometry};
    if co.placement != Placement::AtTips || co.side.is_nan() || co.side <= 0.0 {
        return;
    }
    let geo = SceneGeometry::of(scene);
    let Some(outline) = &geo.outline else { return };
    for cr in &geo.cracks {
        for (name, tip, d) in cr.tip_directions() {
            let ahead = geo
                .holes
                .iter()
                .filter_map(|(_, h)| match h {
                    HoleShape::Circle { center, radius } => ray_circle(&tip, &d, center, *radius),
                    HoleShape::Polygon(p) => ray_polygon(&tip, &d, p),
                })
                .chain(ray_polygon(&tip, &d, &outline.points))
                .fold(f64::INFINITY, f64::min);
            if co.side >= ahead {
                c.fail(
                    "coupling.side",
                    co.side,
                    format!(
                        "window larger than the remaining ligament: tip {name} is {ahead:.6} m from the boundary ahead; use a side below that"
                    ),
                );
            }
        }
    }
}

/// BEM-only growth: a tip must cross the body within [`MAX_INCREMENTS_ACROSS`] increments.
fn check_increments_across(c: &mut Checker, scene: &Scene, da: f64) {
    use crate::scene::shapes::SceneGeometry;
    let geo = SceneGeometry::of(scene);
    let Some(o) = &geo.outline else { return };
    let (lo, hi) = crate::geometry::bounding_box(&o.points);
    let diag = (hi - lo).norm();
    let n = diag / da;
    if n > MAX_INCREMENTS_ACROSS {
        c.fail(
            "growth.da",
            da,
            format!(
                "a tip would take up to {n:.2e} increments to cross the body (its {diag:.4e} m \
                 diagonal / da), each a BEM solve of the whole body: use da of at least \
                 {:.4e} m ({MAX_INCREMENTS_ACROSS:.0e} increments across)",
                diag / MAX_INCREMENTS_ACROSS
            ),
        );
    }
}

/// Growth runs take every load factor positive: the growth criteria and the K record
/// (`sif_path.csv`) scale the solution of the loads as written by the factor, and a
/// negative factor reverses every load. Before, negative ramps ran in BEM-only and full PD
/// with K_I < 0 of closing faces in the K record and no note (a compression BEM-only
/// refused only when the loads as written were compressive), while PD-BEM refused them at
/// setup; a ramp through zero reverses the load mid-run, and no growth mode models the
/// crack faces closing (no contact). Loading the other way is a matter of the boundary
/// values' signs.
fn check_positive_factors(c: &mut Checker, scene: &Scene) {
    let factors = scene.load.factors();
    if let Some(k) = factors.iter().position(|f| f.is_nan() || *f <= 0.0) {
        c.fail_at(
            "load",
            format!(
                "growth needs positive load factors: factor {} at step {k} is not (a negative \
                 factor reverses every load, and no growth mode models the crack faces closing); \
                 to load the other way, flip the signs of the boundary values (or the remote \
                 stress) and keep the factors positive",
                factors[k]
            ),
        );
    }
}
