//! The loads' nominal strain: the largest prescribed traction (boundary components, normal
//! and shear tractions, the remote stress of an infinite plate) over E, and the largest
//! spread of a prescribed displacement component between the conditions that hold it over
//! the body's size, each times the load factor.
//!
//! - From [`MAX_NOMINAL_STRAIN`] on, the loads are outside the small-strain elasticity that
//!   the BEM solves and the PD constants are calibrated for (and their products overflow:
//!   a traction of 1e300 Pa ran into a non-finite BEM solution).
//! - With PD, below [`MIN_PD_NOMINAL_STRAIN`]: a bond's stretch is a difference of two
//!   lengths, exact to about 2.2e-16 of the bond, so its relative error is about
//!   2.2e-16 / strain, and PD solves stall on that round-off. Measured: the state-based
//!   SENT window (`coupled_sent_a5_state_based`, E = 1e4 Pa) converges at a nominal
//!   strain of 5e-12 and fails at 2e-12 (ADR does not converge; at 5e-13 its measure
//!   stalls at 1.3e-5 against 1e-9); the implicit bar (`pd_bar_tension`) converges at
//!   3e-11 and fails at 1.5e-11 (measure 1.8e-7). The bound keeps a factor 6.7 from the
//!   worst failure (1 Pa on steel, 5e-12, is refused). Where the solves converge the
//!   results do not move with the load's scale: the window's K / sigma agrees to 3e-6
//!   from strain 5e-12 to 5e-10. The elastic solution scales with the loads, so the way
//!   out is to scale them up. The BEM alone is linear in the loads down to the smallest
//!   normal numbers and takes any load below the upper bound.

use super::Checker;
use crate::scene::shapes::SceneGeometry;
use crate::scene::{Component, Scene};

/// Largest nominal strain a scene may load its body with.
pub const MAX_NOMINAL_STRAIN: f64 = 1.0;
/// Smallest nominal strain of a scene with PD (module docs).
pub const MIN_PD_NOMINAL_STRAIN: f64 = 1e-10;

/// One load's nominal strain at factor 1 and the field that sets it.
struct Nominal {
    strain: f64,
    path: String,
    value: f64,
}

/// Checks the nominal strain against [`MAX_NOMINAL_STRAIN`] and, with PD, against
/// [`MIN_PD_NOMINAL_STRAIN`] at the smallest non-zero load factor.
pub fn check(c: &mut Checker, scene: &Scene) {
    let e = scene.material.e;
    if !(e.is_finite() && e > 0.0) {
        return;
    }
    let Some(n) = largest(scene, e) else { return };
    let factors: Vec<f64> = scene
        .load
        .factors()
        .into_iter()
        .map(f64::abs)
        .filter(|f| f.is_finite() && *f > 0.0)
        .collect();
    let (Some(lo), Some(hi)) = (
        factors.iter().copied().reduce(f64::min),
        factors.iter().copied().reduce(f64::max),
    ) else {
        return;
    };
    let (most, least) = (n.strain * hi, n.strain * lo);
    if most.is_nan() || most >= MAX_NOMINAL_STRAIN {
        c.fail(
            n.path.as_str(),
            n.value,
            format!(
                "the loads strain the body by about {most:.3e} (|load| / E, or a displacement's spread over the body's size, at load factor {hi}): from {MAX_NOMINAL_STRAIN} on they are outside the small-strain elasticity the BEM and PD solve (check the units, Pa and m, and material.E)"
            ),
        );
    } else if scene.pd.is_some() && least < MIN_PD_NOMINAL_STRAIN {
        c.fail(
            n.path.as_str(),
            n.value,
            format!(
                "the loads strain the body by about {least:.3e} (|load| / E, or a displacement's spread over the body's size, at load factor {lo}): PD needs at least {MIN_PD_NOMINAL_STRAIN:e}, since a bond's stretch is exact only to about 2.2e-16 of its length and its solves stall on that round-off below; scale the loads up (the elastic solution scales with them)"
            ),
        );
    }
}

/// The largest nominal strain of the scene's loads at load factor 1 and the field that
/// sets it (module docs); `None` when nothing is loaded.
pub fn nominal_strain(scene: &Scene) -> Option<(f64, String)> {
    let e = scene.material.e;
    if !(e.is_finite() && e > 0.0) {
        return None;
    }
    largest(scene, e).map(|n| (n.strain, n.path))
}

/// The load with the largest nominal strain at factor 1 (the first of equals); `None`
/// when nothing is loaded (an impact alone, or every value zero).
fn largest(scene: &Scene, e: f64) -> Option<Nominal> {
    let mut all: Vec<Nominal> = Vec::new();
    if let Some(s) = scene.body.outline.remote_stress() {
        for (name, v) in ["sxx", "syy", "sxy"].into_iter().zip(s) {
            all.push(Nominal {
                strain: v.abs() / e,
                path: format!("body.outline.{name}"),
                value: v,
            });
        }
    }
    for (i, bc) in scene.boundary.iter().enumerate() {
        let comps = [("x", bc.x), ("y", bc.y)];
        for (name, comp) in comps {
            if let Component::Traction(v) = comp {
                all.push(Nominal {
                    strain: v.abs() / e,
                    path: format!("boundary.{i}.{name}"),
                    value: v,
                });
            }
        }
        for (name, v) in [("normal", bc.normal), ("shear", bc.shear)] {
            if let Some(v) = v {
                all.push(Nominal {
                    strain: v.abs() / e,
                    path: format!("boundary.{i}.{name}"),
                    value: v,
                });
            }
        }
    }
    all.extend(displacement_spreads(scene));
    all.into_iter()
        .filter(|n| n.strain.is_finite() && n.strain > 0.0)
        .reduce(|a, b| if b.strain > a.strain { b } else { a })
}

/// Per component, the largest difference between two prescribed displacements over the
/// body's size (one displaced condition alone moves the body rigidly: no strain).
fn displacement_spreads(scene: &Scene) -> Vec<Nominal> {
    let (lo, hi) = SceneGeometry::of(scene).bounds();
    let size = (hi - lo).norm();
    if !(size.is_finite() && size > 0.0) {
        return Vec::new();
    }
    let mut out = Vec::new();
    for axis in 0..2 {
        let held: Vec<(usize, f64)> = scene
            .boundary
            .iter()
            .enumerate()
            .filter_map(|(i, bc)| match [bc.x, bc.y][axis] {
                Component::Displacement(v) => Some((i, v)),
                _ => None,
            })
            .collect();
        let (Some(min), Some(max)) = (
            held.iter().map(|h| h.1).reduce(f64::min),
            held.iter().map(|h| h.1).reduce(f64::max),
        ) else {
            continue;
        };
        let far = held
            .iter()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .expect("held is not empty");
        out.push(Nominal {
            strain: (max - min) / size,
            path: format!("boundary.{}.{}", far.0, ["x", "y"][axis]),
            value: far.1,
        });
    }
    out
}

/// Largest distance of a PD body's coordinates from the origin, in its smallest spacing.
/// Positions are rounded to 2.2e-16 of their magnitude, and the lattice's geometric ties
/// (a cell centre on a zone's edge, a bond through an element's end point) are decided
/// within bands of 1e-9 of a spacing where that rounding is smaller
/// (`pdbem_geometry::tie_band`). Measured with a body moved away from the origin: every
/// coupled case gives its results to 3e-5 at 2e8 spacings (the rotated window at 1e6 m,
/// dx 5 mm); at 1e9 spacings the shear beam's window no longer met the outline ("the
/// outer boundary crosses the window") and at 2e9 the rotated window took 34 coupling
/// iterations instead of 14: the bound keeps a factor 5 from the first failure. Before
/// the tie bands, the SENT window at 1e8 spacings (1e7 m, dx 0.1 m) gave K 2.3 % high and
/// the refined SENT window at 1.96e8 (4.9e6 m, finest cells 0.025 m) split the cells of
/// 556 nodes instead of 700, both with exit 0 (`tests/verification_invariance.rs`).
pub const MAX_SPACINGS_FROM_ORIGIN: f64 = 2e8;

/// [`MAX_SPACINGS_FROM_ORIGIN`] for scenes with `growth` (any mode: `--growth-mode` may
/// switch it at run time). Measured on `growth_tension_edge` (dx 0.1 m) moved away from
/// the origin: at 1e3 and 1e4 m (up to 1e5 spacings) the run ends as at the origin (the
/// tip reaches the outline at (9.9389, 0.0567) m, failure at 3.35). At 1e5 and 1e6 m its
/// first step agrees with the origin's to 1e-13 and its 14 relocations are the same, but
/// the unstable last step ends with the last window's coupling stalled at y = 0.95 m (the
/// same failure load). A load perturbed by 3e-12 at the origin ends as the origin does,
/// so the coordinates' round-off enters, not only the step's sensitivity; where it enters
/// is not found. The bound is the largest distance measured to end alike.
pub const MAX_GROWTH_SPACINGS_FROM_ORIGIN: f64 = 1e5;

/// A PD body (stand-alone or windows) must lie within [`MAX_SPACINGS_FROM_ORIGIN`] of
/// its smallest spacing from the origin ([`MAX_GROWTH_SPACINGS_FROM_ORIGIN`] in growth).
pub fn check_origin(c: &mut Checker, scene: &Scene) {
    let Some(pd) = &scene.pd else { return };
    let Some(h) = smallest_spacing(scene, pd) else {
        return;
    };
    let (lo, hi) = SceneGeometry::of(scene).bounds();
    let far = [lo.x, lo.y, hi.x, hi.y]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let limit = if scene.growth.is_some() {
        MAX_GROWTH_SPACINGS_FROM_ORIGIN
    } else {
        MAX_SPACINGS_FROM_ORIGIN
    };
    if far.is_finite() && far / h > limit {
        c.fail(
            "body.outline",
            format!("reaching {far:.4e} m from the origin"),
            format!(
                "a PD body must lie within {limit:e} of its smallest spacing ({h:.4e} m) from the origin: positions are rounded to 2.2e-16 of their size, {:.2e} m here, and the lattice's ties are decided within 1e-9 of a spacing; move the body to the origin (subtract ({:.6e}, {:.6e}) from every coordinate)",
                far * f64::EPSILON,
                0.5 * (lo.x + hi.x),
                0.5 * (lo.y + hi.y)
            ),
        );
    }
}

/// Largest distance of a body's coordinates from the origin, in its smallest feature (the
/// shortest outline or hole edge, hole radius or crack). The geometry decides
/// "on the outline", "inside" and "a tip" within 1e-9 of the coordinates' magnitude
/// (`pdbem_geometry::scale_of`), so far from the origin that band reaches the features:
/// `sent_bem_a5` moved by 1e9 m (1e9 / 5 m = 2e8) ran as at the origin; at 2e9 m `check`
/// estimated 1e6 elements ("raise bem.element_size"), at 5e9 m the run lost its crack tip
/// (no K, exit 0) and at 1e11 m `check` said the crack crosses the outline. The bound
/// keeps a factor 40 from the first failure (the band then stays within 1e-2 of the
/// smallest feature).
pub const MAX_FEATURES_FROM_ORIGIN: f64 = 1e7;

/// Every body (BEM or PD) away from the origin (its centre farther than half its
/// farthest coordinate) must lie within [`MAX_FEATURES_FROM_ORIGIN`] of its smallest
/// feature from the origin.
pub fn check_feature_origin(c: &mut Checker, scene: &Scene) {
    let geo = SceneGeometry::of(scene);
    let Some((feature, what)) = smallest_feature(&geo) else {
        return;
    };
    let (lo, hi) = geo.bounds();
    let far = [lo.x, lo.y, hi.x, hi.y]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let centre = (lo + hi) * 0.5;
    // A body about the origin keeps its coordinates as small as its size allows; a
    // feature small against the body is the mesh's business, not this rule's.
    let away = centre.x.abs().max(centre.y.abs()) > 0.5 * far;
    if far.is_finite() && away && far > MAX_FEATURES_FROM_ORIGIN * feature {
        let path = if geo.outline.is_some() {
            "body.outline"
        } else {
            "cracks"
        };
        let fix = format!(
            "move the body to the origin (subtract ({:.6e}, {:.6e}) from every coordinate)",
            centre.x, centre.y
        );
        c.fail(
            path,
            format!("reaching {far:.4e} m from the origin"),
            format!(
                "a body must lie within {MAX_FEATURES_FROM_ORIGIN:e} of its smallest feature ({feature:.4e} m, {what}) from the origin: the geometry's tolerances are 1e-9 of the coordinates' size, {:.2e} m here; {fix}",
                far * 1e-9,
            ),
        );
    }
}

/// The shortest outline or hole edge, hole radius or crack, with what it is.
fn smallest_feature(geo: &SceneGeometry) -> Option<(f64, &'static str)> {
    use crate::geometry::HoleShape;
    // The shortest edge of a closed polygon.
    let edges = |pts: &[crate::geometry::P2]| {
        let n = pts.len();
        (0..n)
            .map(|i| (pts[(i + 1) % n] - pts[i]).norm())
            .fold(f64::INFINITY, f64::min)
    };
    let mut out = (f64::INFINITY, "");
    let mut take = |v: f64, what: &'static str| {
        if v > 0.0 && v < out.0 {
            out = (v, what);
        }
    };
    if let Some(o) = &geo.outline {
        take(edges(&o.points), "an outline edge");
    }
    for (_, h) in &geo.holes {
        match h {
            HoleShape::Circle { radius, .. } => take(*radius, "a hole's radius"),
            HoleShape::Polygon(p) => take(edges(p), "a hole's edge"),
        }
    }
    for cr in &geo.cracks {
        take(
            crate::geometry::polyline_length(&cr.points),
            "a crack's length",
        );
    }
    out.0.is_finite().then_some(out)
}

/// The smallest PD spacing a scene asks for: the stand-alone grid's or the windows',
/// divided by its refinement levels; `None` when a value is not usable (other rules
/// report it).
fn smallest_spacing(scene: &Scene, pd: &crate::scene::PdSettings) -> Option<f64> {
    let h = match &scene.coupling {
        Some(co) if co.n > 0 => {
            let levels = co.refine.as_ref().map_or(0, |r| r.levels.min(8));
            co.side / co.n as f64 / f64::from(1u32 << levels)
        }
        Some(_) => return None,
        None => {
            let base = match (pd.dx, pd.nx) {
                (Some(dx), _) => dx,
                (None, Some(nx)) if nx > 0 => {
                    let (lo, hi) = SceneGeometry::of(scene).bounds();
                    (hi.x - lo.x) / nx as f64
                }
                _ => return None,
            };
            let levels = pd.refinement.as_ref().map_or(0, |r| r.max_level.min(8));
            base / f64::from(1u32 << levels)
        }
    };
    (h.is_finite() && h > 0.0).then_some(h)
}
