//! Rules of `bem`, `reference` and `outputs`.

use super::{fmt_pt, Checker};
use crate::geometry::{p2, polyline_length};
use crate::scene::bem::MIN_TOLERANCE;
use crate::scene::shapes::SceneGeometry;
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
        check_element_counts(c, scene);
        let geo = SceneGeometry::of(scene);
        for (i, p) in b.interior_points.iter().enumerate() {
            if !geo.contains(&p2(*p)) {
                c.fail(
                    format!("bem.interior_points.{i}"),
                    fmt_pt(&p2(*p)),
                    "interior point lies outside the body",
                );
            }
        }
    }
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
                    if let Some(why) = not_a_tada_crack(&geo, &cr.points) {
                        c.fail_at(
                            "reference",
                            format!("SentTada is Tada's straight edge crack normal to its edge under tension across it, and cracks.0 {why}: its k1_err, k2_err and cmod_err would be against another geometry; remove `reference` (K and CMOD keep their own error estimates)"),
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
            c.finite("reference.beta_deg", *beta_deg);
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

/// Why the edge crack `pts` (mouth first) is not Tada's: bent (a point off its chord by
/// more than 1e-6 of its length) or leaving the outline edge at its mouth at more than
/// [`TADA_ANGLE_DEG`] from the edge's normal (the coupled SENT plate with its crack at
/// -45 degrees reported k1_err = -50.7 % and cmod_err = -41 % against the table).
fn not_a_tada_crack(geo: &SceneGeometry, pts: &[crate::geometry::P2]) -> Option<String> {
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
    let o = geo.outline.as_ref()?;
    let n = o.points.len();
    // The edges through the mouth (two at a corner): the crack may leave either normally.
    let turns: Vec<f64> = (0..n)
        .filter_map(|i| {
            let (p, q) = (o.points[i], o.points[(i + 1) % n]);
            let d = crate::geometry::point_segment_distance(first, &p, &q);
            let t = q - p;
            (d <= 1e-9 * len.max(t.norm())).then(|| {
                let cos = (t.x * dir.x + t.y * dir.y).abs() / t.norm();
                cos.clamp(0.0, 1.0).asin().to_degrees()
            })
        })
        .collect();
    let least = turns.iter().copied().fold(f64::INFINITY, f64::min);
    (least.is_finite() && least > TADA_ANGLE_DEG).then(|| {
        format!(
            "leaves its edge at {:.2} degrees from the edge's normal",
            least
        )
    })
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
        for (i, g) in o.boundary_stress.iter().enumerate() {
            if !groups.contains(g) {
                c.fail(
                    format!("outputs.boundary_stress.{i}"),
                    format!("{g:?}"),
                    format!("unknown edge group; known groups: {}", groups.join(", ")),
                );
            }
        }
    }
}
