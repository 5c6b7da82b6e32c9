//! Rules of `bem`, `reference` and `outputs`.

use super::{fmt_pt, Checker};
use crate::geometry::{p2, polyline_length, P2};
use crate::scene::bem::MIN_TOLERANCE;
use crate::scene::shapes::{CrackLine, SceneGeometry};
use crate::scene::{elements_on, Hole, Reference, Scene};

/// Checks the BEM settings, the reference and the outputs.
pub fn check(c: &mut Checker, scene: &Scene, body_ok: bool) {
    check_bem(c, scene, body_ok);
    if body_ok {
        check_reference(c, scene);
    }
    check_outputs(c, scene, body_ok);
}

fn check_bem(c: &mut Checker, scene: &Scene, body_ok: bool) {
    let b = &scene.bem;
    if let Some(h) = b.element_size {
        if !c.positive("bem.element_size", h, "element size") {
            return;
        }
    }
    let groups = scene.edge_groups();
    for (g, h) in &b.group_sizes {
        let path = format!("bem.group_sizes.{g}");
        if !groups.contains(g) {
            c.fail(
                path.clone(),
                format!("{g:?}"),
                format!("unknown edge group; known groups: {}", groups.join(", ")),
            );
        }
        c.positive(&path, *h, "element size");
    }
    if let Some(t) = &b.tip_refinement {
        c.positive(
            "bem.tip_refinement.element_size",
            t.element_size,
            "tip element size",
        );
        c.positive(
            "bem.tip_refinement.radius",
            t.radius,
            "tip refinement radius",
        );
    }
    if let Some(n) = b.elements_per_circle {
        c.at_least(
            "bem.elements_per_circle",
            n,
            3,
            "elements per circle (zero elements otherwise)",
        );
    }
    if let Some(t) = b.tolerance {
        if c.finite("bem.tolerance", t) && !(MIN_TOLERANCE..=0.5).contains(&t) {
            c.fail(
                "bem.tolerance",
                t,
                "a relative tolerance on K and CMOD must lie in [4e-4, 0.5]: below it no \
                 error estimate can certify it (twice the estimate's floor 2e-4, which \
                 covers biases of constant elements that refinement does not remove)",
            );
        }
        if scene.pd.is_some() || scene.coupling.is_some() || scene.growth.is_some() {
            c.fail(
                "bem.tolerance",
                t,
                "applies to static BEM runs only (no pd, coupling or growth section): \
                 coupled K carry an error estimate but are not refined to a tolerance, \
                 and growth K carry no estimate yet",
            );
        }
    }
    let f = b.cod_fit_fraction;
    if c.finite("bem.cod_fit_fraction", f) && !(f > 0.0 && f <= 1.0) {
        c.fail(
            "bem.cod_fit_fraction",
            f,
            "fit range fraction must lie in (0, 1]",
        );
    }
    let r = b.j_contour.radius_fraction;
    if c.finite("bem.j_contour.radius_fraction", r) && !(r > 0.0 && r < 1.0) {
        c.fail(
            "bem.j_contour.radius_fraction",
            r,
            "contour radius fraction must lie in (0, 1)",
        );
    }
    c.at_least(
        "bem.j_contour.points",
        b.j_contour.points,
        8,
        "contour points",
    );
    if body_ok && c.issues.is_empty() {
        // Stand-alone PD meshes no BEM: its cracks are checked on the grid.
        let standalone_pd =
            scene.pd.is_some() && scene.coupling.is_none() && scene.growth.is_none();
        if !standalone_pd {
            check_element_counts(c, scene);
        }
        check_interior_points(c, scene);
    }
}

/// Interior points closer to the boundary than this fraction of the body's bounding-box
/// diagonal are refused. On a 10 m plate (diagonal 14.1 m) under uniform tension, a point
/// 1e-9 m from an edge (7e-11 of the diagonal) lost the field (sigma_yy 4e-11 instead of
/// 1, sigma_xy -0.25 instead of 0, exit 0); from 1e-8 m (7e-10) on it was exact. The
/// evaluation's reach scales with the element length, at most the diagonal, so the limit
/// keeps a margin of 14 over the last exact point.
pub const INTERIOR_CLEARANCE: f64 = 1e-8;

/// `bem.interior_points` lie inside the body, off its outline, holes and cracks by
/// [`INTERIOR_CLEARANCE`].
fn check_interior_points(c: &mut Checker, scene: &Scene) {
    let geo = SceneGeometry::of(scene);
    let (lo, hi) = geo.bounds();
    let clearance = INTERIOR_CLEARANCE * (hi - lo).norm();
    for (i, p) in scene.bem.interior_points.iter().enumerate() {
        let q = p2(*p);
        let path = format!("bem.interior_points.{i}");
        if !geo.contains(&q) {
            c.fail(path, fmt_pt(&q), "interior point lies outside the body");
        } else if let Some((d, what)) = nearest_boundary(&geo, &q).filter(|(d, _)| *d <= clearance)
        {
            c.fail(
                path,
                fmt_pt(&q),
                format!(
                    "interior point lies {d:.3e} m from {what}, within {clearance:.3e} m ({INTERIOR_CLEARANCE:.0e} of the body's size), where the interior evaluation is not accurate: move it away (values on the outline and holes are in outputs.boundary_stress)"
                ),
            );
        }
    }
}

/// The distance from `p` to the nearest outline edge, hole or crack, and which.
fn nearest_boundary(geo: &SceneGeometry, p: &P2) -> Option<(f64, String)> {
    let outline = geo.outline.as_ref().map(|o| {
        (
            crate::geometry::polygon_distance(p, &o.points),
            "the outline".to_string(),
        )
    });
    let holes = geo
        .holes
        .iter()
        .map(|(n, h)| (h.boundary_distance(p), format!("hole '{n}'")));
    let cracks = geo.cracks.iter().map(|c| {
        (
            crate::geometry::polyline_distance_hypot(p, &c.points),
            format!("crack '{}'", c.name),
        )
    });
    outline
        .into_iter()
        .chain(holes)
        .chain(cracks)
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

/// Every edge group and crack gets at least one element.
fn check_element_counts(c: &mut Checker, scene: &Scene) {
    let geo = SceneGeometry::of(scene);
    let h = scene.bem.base_size(&geo);
    let size_of = |g: &str| scene.bem.group_sizes.get(g).copied().unwrap_or(h);
    let path_of = |g: &str| {
        if scene.bem.group_sizes.contains_key(g) {
            format!("bem.group_sizes.{g}")
        } else {
            "bem.element_size".to_string()
        }
    };
    if let Some(o) = &geo.outline {
        let n = o.points.len();
        for k in 0..n {
            let len = (o.points[(k + 1) % n] - o.points[k]).norm();
            let g = &o.groups[k];
            if elements_on(len, size_of(g)) == 0 {
                c.fail(
                    path_of(g),
                    size_of(g),
                    format!("gives zero elements on edge '{g}' (length {len} m): use at most twice the edge length"),
                );
                return;
            }
        }
    }
    for cr in &geo.cracks {
        let len = polyline_length(&cr.points);
        if elements_on(len, size_of(&cr.name)) == 0 {
            c.fail(
                path_of(&cr.name),
                size_of(&cr.name),
                format!("gives zero elements on crack '{}' (length {len} m): use at most twice the crack length", cr.name),
            );
            return;
        }
    }
    for (i, hole) in scene.body.holes.iter().enumerate() {
        if let Hole::Polygon { points, .. } = hole {
            let pts: Vec<_> = points.iter().map(|p| p2(*p)).collect();
            let name = hole.name(i);
            let mut closed = pts.clone();
            closed.push(pts[0]);
            let min_edge = closed
                .windows(2)
                .map(|w| (w[1] - w[0]).norm())
                .fold(f64::INFINITY, f64::min);
            if elements_on(min_edge, size_of(&name)) == 0 {
                c.fail(
                    path_of(&name),
                    size_of(&name),
                    format!(
                        "gives zero elements on an edge of hole '{name}' (length {min_edge} m)"
                    ),
                );
                return;
            }
        }
    }
}

fn check_reference(c: &mut Checker, scene: &Scene) {
    let Some(r) = &scene.reference else { return };
    let geo = SceneGeometry::of(scene);
    match r {
        Reference::SentTada { width, sigma } => {
            c.positive("reference.width", *width, "strip width");
            c.finite("reference.sigma", *sigma);
            match geo.cracks.first() {
                Some(cr) if cr.mouth => {
                    let a = polyline_length(&cr.points);
                    if *width > 0.0 && a >= *width {
                        c.fail(
                            "reference.width",
                            width,
                            format!("crack length {a} m must be below the strip width"),
                        );
                    }
                    if let Some(why) = not_a_tada_crack(&geo, cr) {
                        c.fail_at(
                            "reference",
                            format!("SentTada is Tada's straight edge crack normal to its edge under tension across it, and cracks.0 {why}: its k1_err, k2_err and cmod_err would be against another geometry; remove `reference` (K and CMOD keep their own error estimates)"),
                        );
                    } else if let Some((field, why)) = not_tadas_strip(scene, &geo, cr, *width) {
                        c.fail_at(
                            field,
                            format!("SentTada is Tada's strip of width W along its one crack, with no hole, and {why}: its k1_err, k2_err and cmod_err would be against another geometry"),
                        );
                    }
                }
                _ => c.fail_at(
                    "reference",
                    "SentTada needs an edge crack (first point on the outline) as cracks.0",
                ),
            }
        }
        Reference::InclinedCrackInfinite { sigma, beta_deg } => {
            c.finite("reference.sigma", *sigma);
            if let Some(b) = beta_deg {
                c.finite("reference.beta_deg", *b);
            }
            if geo.cracks.first().is_none_or(|cr| cr.mouth) {
                c.fail_at(
                    "reference",
                    "InclinedCrackInfinite needs an interior crack as cracks.0",
                );
            }
        }
        Reference::Kirsch { sigma } => {
            c.finite("reference.sigma", *sigma);
            if !matches!(scene.body.holes.first(), Some(Hole::Circle { .. })) {
                c.fail_at("reference", "Kirsch needs a circular hole as body.holes.0");
            }
        }
    }
}

/// Largest turn (degrees) of an edge crack from its edge's normal that Tada's table of
/// the straight edge crack still describes (the crack at -89 degrees instead of -90: K_I
/// changes by about 1e-4).
const TADA_ANGLE_DEG: f64 = 1.0;

/// Why the edge crack `cr` is not Tada's: bent (a point off its chord by more than 1e-6
/// of its length) or leaving the outline edge at its mouth at more than
/// [`TADA_ANGLE_DEG`] from the edge's normal (the coupled SENT plate with its crack at
/// -45 degrees reported k1_err = -50.7 % and cmod_err = -41 % against the table).
fn not_a_tada_crack(geo: &SceneGeometry, cr: &CrackLine) -> Option<String> {
    let pts = &cr.points;
    let (first, last) = (pts.first()?, pts.last()?);
    let chord = last - first;
    let len = chord.norm();
    if len == 0.0 {
        return None;
    }
    let dir = chord / len;
    let off = pts
        .iter()
        .map(|p| ((p - first).x * dir.y - (p - first).y * dir.x).abs())
        .fold(0.0, f64::max);
    if off > 1e-6 * len {
        return Some(format!("bends ({off:.3e} m off its chord)"));
    }
    let least = geo
        .mouth_axis(cr)?
        .dot(&dir)
        .clamp(-1.0, 1.0)
        .acos()
        .to_degrees();
    (least > TADA_ANGLE_DEG).then(|| {
        format!(
            "leaves its edge at {:.2} degrees from the edge's normal",
            least
        )
    })
}

/// Why the body of the Tada crack `cr` is not Tada's strip of width `width`: `(field,
/// reason)` for a hole, a second crack, an outline that is no rectangle with sides along
/// and across the normal of the crack's edge ([`SceneGeometry::mouth_axis`]), a strip
/// shorter than W on either side of the crack (REFERENCES.md: end effects fade for a
/// half-height H >= W; at H = W / 4 `sent_bem_a5`'s plate read k1_err_fem = +68 % and
/// cmod_err = +266 %, exit 0), or a width that is not the outline's extent along that
/// normal from the mouth (`width: 20`, the plate's length: k1_err = +88.8 %, cmod_err =
/// +145 %, exit 0).
fn not_tadas_strip(
    scene: &Scene,
    geo: &SceneGeometry,
    cr: &CrackLine,
    width: f64,
) -> Option<(&'static str, String)> {
    if !scene.body.holes.is_empty() {
        return Some(("body.holes", "this body has a hole".into()));
    }
    if scene.cracks.len() > 1 {
        return Some((
            "cracks",
            format!("this body has {} cracks", scene.cracks.len()),
        ));
    }
    let o = geo.outline.as_ref()?;
    let first = cr.points.first()?;
    let d = geo.mouth_axis(cr)?;
    let e = crate::geometry::P2::new(-d.y, d.x);
    let along = |p: &crate::geometry::P2| (p - first).dot(&d);
    let across = |p: &crate::geometry::P2| (p - first).dot(&e);
    let span = |f: &dyn Fn(&crate::geometry::P2) -> f64| {
        o.points
            .iter()
            .map(f)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            })
    };
    let ((back, w), (lo, hi)) = (span(&along), span(&across));
    // About the mouth: at 1e9 m from the origin the area of the corners loses its digits.
    let about_mouth: Vec<_> = o.points.iter().map(|p| p - first).collect();
    let area = crate::geometry::signed_area(&about_mouth).abs();
    if (area - (w - back) * (hi - lo)).abs() > 1e-6 * area {
        return Some((
            "body.outline",
            "the outline is no rectangle with sides along and across the normal of the crack's edge".into(),
        ));
    }
    // Half-height: the nearer end of the strip from the crack's line.
    let half = (-lo).min(hi);
    if half < (1.0 - 1e-9) * w {
        return Some((
            "body.outline",
            format!("the outline reaches {half} m from the line of cracks.0 towards its nearer end, under the strip's width {w} m (Tada's strip is long: against a strip 4 W high, K_I and the CMOD are 0.03 % and 0.13 % higher at a half-height of W, 6 % and 24 % at W / 2; a = W / 2)"),
        ));
    }
    ((w - width).abs() > 1e-6 * w).then(|| {
        (
            "reference.width",
            format!("the outline spans {w} m from the mouth of cracks.0 along its edge's normal, not {width} m"),
        )
    })
}

/// The groups `outputs.boundary_stress` takes: every hole and, on a finite body,
/// `outline` (the closed loops around which the BEM writes the tangential stress).
fn loop_groups(scene: &Scene) -> Vec<String> {
    let mut out: Vec<String> = (scene.body.holes.iter().enumerate())
        .map(|(i, h)| h.name(i))
        .collect();
    if !matches!(scene.body.outline, crate::scene::Outline::Infinite { .. }) {
        out.push("outline".into());
    }
    out
}

fn check_outputs(c: &mut Checker, scene: &Scene, body_ok: bool) {
    let o = &scene.outputs;
    if o.plots && o.formats.is_empty() {
        c.fail_at(
            "outputs.formats",
            "plots are on but no format is chosen: add Png and/or Svg",
        );
    }
    for (i, g) in o.grids.iter().enumerate() {
        let path = format!("outputs.grids.{i}");
        c.at_least(&format!("{path}.nx"), g.nx, 1, "grid points along x");
        c.at_least(&format!("{path}.ny"), g.ny, 1, "grid points along y");
        if !(g.to.0 >= g.from.0 && g.to.1 >= g.from.1) {
            c.fail_at(
                path,
                "`to` must be the upper-right corner (to >= from in x and y)",
            );
        }
    }
    for (i, l) in o.lines.iter().enumerate() {
        let path = format!("outputs.lines.{i}");
        c.at_least(&format!("{path}.n"), l.n, 2, "points on a line");
        if l.from == l.to {
            c.fail_at(path, "line has zero length");
        }
    }
    if body_ok {
        let groups = scene.edge_groups();
        let loops = loop_groups(scene);
        for (i, g) in o.boundary_stress.iter().enumerate() {
            let path = format!("outputs.boundary_stress.{i}");
            if !groups.contains(g) {
                c.fail(
                    path,
                    format!("{g:?}"),
                    format!("unknown edge group; known groups: {}", groups.join(", ")),
                );
            } else if !loops.contains(g) {
                // An edge's name wrote the whole outline's stress under its name; a crack's
                // was skipped without a word.
                c.fail(
                    path,
                    format!("{g:?}"),
                    format!("the boundary stress is written around a closed loop: name a hole or `outline` ({})", loops.join(", ")),
                );
            } else if scene.growth.is_some() || scene.coupling.is_some() || scene.pd.is_some() {
                c.fail(
                    path,
                    format!("{g:?}"),
                    "the boundary stress is written by static BEM runs (no `pd`, `coupling` or `growth` section): remove it",
                );
            }
        }
    }
}
