//! From a scene to a stand-alone PD problem (issue 3): grid spacing, holes, pre-cracks
//! carried through the boundary layer, displacement conditions on fictitious strips and
//! tractions as body forces one node column deep (seed 000 section 2.3) or through seed
//! 001's transfer functions (`pd.traction`), and two pins for
//! pure-traction scenes. Full-PD growth builds its model here too.

use super::{pd_failure, pd_material, pd_plane};
use crate::scene::shapes::{HoleShape, SceneGeometry};
use crate::scene::{Component, PdSettings as ScenePd, PdSolver, PdTraction, Scene};
use anyhow::{bail, Context, Result};
use pdbem_pd::problem::{BoundaryCondition as PdBc, Hole, Layer, Region, Selection};
use pdbem_pd::{PdProblem, TractionLoad};

type P = [f64; 2];

/// The outline edges (or patch pieces) of a group as polylines. An edge's group is the
/// edge without the patches on it, as in the BEM mesh ([`super::bem::split_at_patches`]):
/// `pd_bar_tension` held its `pin` patch in x too, through the `left` edge's condition,
/// where the BEM held it in y only.
fn group_polylines(scene: &Scene, geo: &SceneGeometry, name: &str) -> Vec<Vec<P>> {
    let mut out = Vec::new();
    for p in &scene.body.patches {
        if p.name == name {
            out.push(counter_clockwise(
                geo,
                [p.from.0, p.from.1],
                [p.to.0, p.to.1],
            ));
        }
    }
    if let Some(o) = &geo.outline {
        let (pts, groups) = super::bem::split_at_patches(scene, &o.points, &o.groups);
        let patch = scene.body.patches.iter().any(|p| p.name == name);
        let n = pts.len();
        for i in 0..n {
            if name == "outline" || (groups[i] == name && !patch) {
                let (a, b) = (pts[i], pts[(i + 1) % n]);
                out.push(vec![[a.x, a.y], [b.x, b.y]]);
            }
        }
    }
    for (hn, shape) in &geo.holes {
        if hn == name {
            let pts: Vec<P> = match shape {
                // Clockwise, as polygon holes: the right-hand normal points out of the
                // body (a `normal` traction) and `shear` runs clockwise (docs/scene.md).
                HoleShape::Circle { center, radius } => {
                    crate::geometry::circle_polygon(center, *radius, 128, true)
                        .iter()
                        .map(|p| [p.x, p.y])
                        .collect()
                }
                HoleShape::Polygon(p) => p.iter().map(|q| [q.x, q.y]).collect(),
            };
            let mut closed = pts.clone();
            closed.push(pts[0]);
            out.push(closed);
        }
    }
    out
}

/// The force (N, thickness included) the traction conditions of boundary group `name` put
/// on the body at load factor 1: the traction vector of each condition on the group plus
/// its normal and shear tractions along each segment's outward normal and running
/// direction ([`traction_pieces`], as the PD loads are built), integrated over the
/// group's outline edges, patches and holes.
pub fn applied_resultant(scene: &Scene, name: &str) -> [f64; 2] {
    let geo = SceneGeometry::of(scene);
    let lines = group_polylines(scene, &geo, name);
    let mut f = [0.0; 2];
    for bc in scene.boundary.iter().filter(|b| b.on == name) {
        let trac = |c: Component| match c {
            Component::Traction(v) => v,
            _ => 0.0,
        };
        let t = [trac(bc.x), trac(bc.y)];
        for line in &lines {
            for (piece, t) in traction_pieces(line, t, bc.normal, bc.shear) {
                let l = pdbem_pd::geometry::polyline_length(&piece) * scene.material.thickness;
                f[0] += t[0] * l;
                f[1] += t[1] * l;
            }
        }
    }
    f
}

/// The traction pieces of a condition on `line`, one polyline of its group (an outline
/// edge or a patch, counter-clockwise, or a hole, clockwise: the right-hand normal points
/// out of the body): the global components `t` on the whole line, or, with a `normal` or
/// `shear` traction, one piece per segment with t + t_n n + t_s s, n the segment's outward
/// normal and s its running direction (docs/scene.md, Conventions). Pieces without load
/// are left out. Before, the normal of the first segment was taken for the whole line (a
/// pressurised circular hole pushed the body sideways with the pressure times the
/// perimeter) and `shear` was dropped.
fn traction_pieces(line: &[P], t: P, normal: Option<f64>, shear: Option<f64>) -> Vec<(Vec<P>, P)> {
    if normal.is_none() && shear.is_none() {
        return if t == [0.0, 0.0] {
            Vec::new()
        } else {
            vec![(line.to_vec(), t)]
        };
    }
    let (tn, ts) = (normal.unwrap_or(0.0), shear.unwrap_or(0.0));
    line.windows(2)
        .filter_map(|w| {
            let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
            let l = dx.hypot(dy);
            let piece = [
                t[0] + (tn * dy + ts * dx) / l,
                t[1] + (-tn * dx + ts * dy) / l,
            ];
            (l > 0.0 && piece != [0.0, 0.0]).then(|| (w.to_vec(), piece))
        })
        .collect()
}

/// Pre-crack polyline of a crack: an end on the outline (within `tol`) is carried on
/// outwards by `reach` (just under the horizon, the depth of the layer, which the PD
/// problem accepts as the farthest a crack may reach out) along the crack, so that no bond
/// from a boundary-layer node to a real node crosses the crack line near its mouth. Cut
/// at the outline, the crack left the layer of a displacement condition bonded across
/// the mouth: on the shear plate (`cases/growth_shear_edge.ron`) the moved top half
/// dragged the fixed side of the mouth with it.
fn through_boundary_layer(
    geo: &SceneGeometry,
    pts: &[crate::geometry::P2],
    reach: f64,
    tol: f64,
) -> Vec<P> {
    let mut out: Vec<P> = pts.iter().map(|p| [p.x, p.y]).collect();
    let (Some(o), true) = (&geo.outline, pts.len() >= 2) else {
        return out;
    };
    let on_outline = |p: &crate::geometry::P2| {
        let n = o.points.len();
        (0..n).any(|i| {
            crate::geometry::point_segment_distance(p, &o.points[i], &o.points[(i + 1) % n]) <= tol
        })
    };
    let beyond = |end: &crate::geometry::P2, next: &crate::geometry::P2| -> P {
        let d = (end - next).normalize();
        [end.x + reach * d.x, end.y + reach * d.y]
    };
    let n = pts.len();
    if on_outline(&pts[n - 1]) {
        out.push(beyond(&pts[n - 1], &pts[n - 2]));
    }
    if on_outline(&pts[0]) {
        out.insert(0, beyond(&pts[0], &pts[1]));
    }
    out
}

/// A patch `a -> b` of the outline oriented counter-clockwise, the orientation of the
/// outline edges, so that its right-hand normal points out of the body
/// ([`outward_strip`], traction `normal`). Scenes may write a patch either way: the
/// shear plate of seed 002 section 3.2.3 (`cases/growth_shear_edge.ron`) gives its top
/// patches left to right, clockwise, and before this its fictitious layers were built
/// inside the plate and the full-PD model lost its loading after a few broken bonds.
fn counter_clockwise(geo: &SceneGeometry, a: P, b: P) -> Vec<P> {
    let Some(o) = &geo.outline else {
        return vec![a, b];
    };
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l = dx.hypot(dy);
    if l == 0.0 {
        return vec![a, b];
    }
    // A point just off the middle of the patch along its right-hand normal.
    let eps = 1e-6 * l;
    let probe = crate::geometry::P2::new(
        0.5 * (a[0] + b[0]) + eps * dy / l,
        0.5 * (a[1] + b[1]) - eps * dx / l,
    );
    if crate::geometry::point_in_polygon(&probe, &o.points) {
        vec![b, a]
    } else {
        vec![a, b]
    }
}

/// Fictitious-node selection for a displacement condition on `line`: for an axis-aligned
/// edge the strip of depth `delta` outside it, with the corner square at each end that is
/// a corner of the outline (`corners`), so no fictitious node sits over the neighbouring
/// free surface (that would clamp it too: a cantilever came out 5 % stiff); otherwise
/// every node within `delta` of the polyline. A patch end inside an edge gets no square:
/// two patches meeting there would otherwise share a square of nodes, the later condition
/// winning over the earlier one's side (the held half of the shear plate's top edge was
/// pushed down with the moved half).
fn outward_strip(line: &[P], delta: f64, corners: &[P]) -> Selection {
    if let [a, b] = line {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let l = dx.hypot(dy);
        // Outward normal of a counter-clockwise outline edge: (dy, -dx)/l.
        let n = [dy / l, -dx / l];
        let axis = n[0].abs() > 1.0 - 1e-12 || n[1].abs() > 1.0 - 1e-12;
        if axis {
            let tol = 1e-9 * l;
            let is_corner = |p: &P| {
                corners
                    .iter()
                    .any(|c| (c[0] - p[0]).hypot(c[1] - p[1]) <= tol)
            };
            let lo = [a[0].min(b[0]), a[1].min(b[1])];
            let hi = [a[0].max(b[0]), a[1].max(b[1])];
            // The end at the low / high coordinate along the edge.
            let (end_lo, end_hi) = if (a[0] - lo[0]).abs() + (a[1] - lo[1]).abs() <= tol {
                (a, b)
            } else {
                (b, a)
            };
            let (mut min, mut max) = (lo, hi);
            for k in 0..2 {
                if n[k] > 0.5 {
                    max[k] += delta;
                } else if n[k] < -0.5 {
                    min[k] -= delta;
                } else {
                    if is_corner(end_lo) {
                        min[k] -= delta;
                    }
                    if is_corner(end_hi) {
                        max[k] += delta;
                    }
                }
            }
            return Selection::Box { min, max };
        }
    }
    Selection::NearPolyline {
        points: line.to_vec(),
        distance: Some(delta),
    }
}

/// The PD problem of a scene at its own spacing (`pd.dx`, or the outline's width / `pd.nx`).
pub fn problem_from_scene(scene: &Scene) -> Result<PdProblem> {
    Ok(labelled_problem_from_scene(scene)?.0)
}

/// [`problem_from_scene`] and, for each of the problem's boundary conditions, the name of
/// the scene's boundary group it comes from (`pin` for the two pins of a pure-traction
/// scene).
pub fn labelled_problem_from_scene(scene: &Scene) -> Result<(PdProblem, Vec<String>)> {
    let (pd, geo) = pd_and_geometry(scene)?;
    let o = geo.outline.as_ref().map(|o| &o.points[..]).unwrap_or(&[]);
    let (lo, hi) = (
        o.iter().map(|p| p.x).fold(f64::INFINITY, f64::min),
        o.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max),
    );
    let (dx, field) = match (pd.dx, pd.nx) {
        (Some(dx), _) => (dx, "pd.dx"),
        (None, Some(nx)) => ((hi - lo) / nx as f64, "the body's width / pd.nx"),
        (None, None) => bail!("{}: pd: give `dx` or `nx`", scene.file_label().display()),
    };
    labelled_problem_at(scene, dx, field)
}

/// The PD problem of full-PD growth: the whole body at the windows' spacing
/// (`coupling.side / coupling.n`), so that it resolves the crack as PD-BEM's windows do.
pub fn full_pd_problem(scene: &Scene) -> Result<PdProblem> {
    let co = scene.coupling.as_ref().with_context(|| {
        format!(
            "{}: full-PD growth takes dx = coupling.side / coupling.n: add `coupling`",
            scene.file_label().display()
        )
    })?;
    Ok(labelled_problem_at(scene, co.dx(), "coupling.side / coupling.n")?.0)
}

fn pd_and_geometry(scene: &Scene) -> Result<(&ScenePd, SceneGeometry)> {
    let Some(pd) = &scene.pd else {
        bail!("{}: no `pd` section", scene.file_label().display())
    };
    Ok((pd, SceneGeometry::of(scene)))
}

/// A pure-traction scene's pins hold one coarse node each: a `pd.refine_zones` zone that
/// splits a pin's cell is refused (its children would all be held, or none).
fn refuse_zones_on_pins(scene: &Scene, pd: &ScenePd, pins: &[P]) -> Result<()> {
    for (i, z) in pd.refine_zones.iter().enumerate() {
        let zone = pdbem_pd::refine_zone::RefineZone {
            centre: [z.centre.0, z.centre.1],
            half_size: z.half_size,
            levels: z.levels,
        };
        if let Some(p) = pins.iter().find(|&&p| zone.contains(p, (1.0, 0.0))) {
            bail!(
                "{}: pd.refine_zones.{i}: the zone splits the cell at ({}, {}), where a pure-traction scene pins the body (the middle of the bottom and top rows): keep the zones off the pins, or hold the body with a displacement condition",
                scene.file_label().display(),
                p[0],
                p[1]
            );
        }
    }
    Ok(())
}

/// The zones of `pd.refine_zones` on the problem's grid: a zone that holds no grid cell
/// with a point in the body is an error naming the scene's field (the library names its
/// own, `refine_zones[k]`). Other problems with the grid are left to the model's build.
fn zones_on_the_grid(scene: &Scene, problem: &PdProblem) -> Result<()> {
    if problem.refine_zones.is_empty() || problem.validate().is_err() {
        return Ok(());
    }
    match pdbem_pd::mixed::build_grid(problem) {
        Err(pdbem_pd::PdError::InvalidInput { field, reason })
            if field.starts_with("refine_zones[") =>
        {
            let k = field
                .trim_start_matches("refine_zones[")
                .trim_end_matches(']');
            bail!(
                "{}: pd.refine_zones.{k}: {reason}",
                scene.file_label().display()
            )
        }
        _ => Ok(()),
    }
}

/// The PD problem of a scene at grid spacing `dx` (m), set by the scene's field
/// `spacing_field` (named in the advice of a refusal), with the boundary conditions' group
/// names ([`labelled_problem_from_scene`]). A pre-crack whose ligament the grid cannot
/// resolve is refused ([`super::ligament::refuse_unresolved`]).
fn labelled_problem_at(
    scene: &Scene,
    dx: f64,
    spacing_field: &str,
) -> Result<(PdProblem, Vec<String>)> {
    let (pd, geo) = pd_and_geometry(scene)?;
    let Some(outline) = &geo.outline else {
        bail!(
            "{}: body.outline: stand-alone PD needs a finite body",
            scene.file_label().display()
        )
    };
    let pts: Vec<P> = outline.points.iter().map(|p| [p.x, p.y]).collect();
    let (mut lo, mut hi) = (pts[0], pts[0]);
    for p in &pts {
        lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    let holes = geo
        .holes
        .iter()
        .map(|(_, h)| match h {
            HoleShape::Circle { center, radius } => Hole::Circle {
                centre: [center.x, center.y],
                radius: *radius,
            },
            HoleShape::Polygon(p) => Hole::Polygon {
                points: p.iter().map(|q| [q.x, q.y]).collect(),
            },
        })
        .collect();
    let failure = pd_failure(scene, pd)?;
    let zones = scene.coupling.is_none();
    super::ligament::refuse_unresolved(scene, &geo, dx, spacing_field, zones)?;
    let wanted: Option<&Vec<String>> = pd.pre_cracks.as_ref();
    let delta = pd.horizon_factor * dx;
    let cracks = geo
        .cracks
        .iter()
        .filter(|c| wanted.is_none_or(|w| w.contains(&c.name)))
        .map(|c| through_boundary_layer(&geo, &c.points, 0.99 * delta, 1e-6 * dx))
        .collect();
    let mut boundary = Vec::new();
    let mut labels = Vec::new();
    let mut has_displacement = false;
    let corners: Vec<P> = geo
        .outline
        .as_ref()
        .map(|o| o.points.iter().map(|p| [p.x, p.y]).collect())
        .unwrap_or_default();
    for (k, bc) in scene.boundary.iter().enumerate() {
        let lines = group_polylines(scene, &geo, &bc.on);
        if lines.is_empty() {
            bail!(
                "{}: boundary.{k}.on = '{}': no outline edge, patch or hole of that name",
                scene.file_label().display(),
                bc.on
            );
        }
        for line in lines {
            let disp = |c: Component| match c {
                Component::Displacement(v) => Some(v),
                _ => None,
            };
            let (ux, uy) = (disp(bc.x), disp(bc.y));
            if ux.is_some() || uy.is_some() {
                has_displacement = true;
                labels.push(bc.on.clone());
                boundary.push(PdBc::Displacement {
                    on: outward_strip(&line, delta, &corners),
                    ux,
                    uy,
                    layer: Layer::Fictitious,
                });
            }
            let trac = |c: Component| match c {
                Component::Traction(v) => v,
                _ => 0.0,
            };
            let t = [trac(bc.x), trac(bc.y)];
            for (edge, traction) in traction_pieces(&line, t, bc.normal, bc.shear) {
                // One node column deep (seed 000 section 2.3): a deeper layer moves the
                // resultant inward (a cantilever tip load over delta deflects ~4 % less).
                // The transfer functions spread over the horizon instead (seed 001).
                labels.push(bc.on.clone());
                boundary.push(PdBc::Traction {
                    edge,
                    traction,
                    depth: (pd.traction == PdTraction::BodyForceLayer).then_some(dx),
                });
            }
        }
    }
    // Tractions out of balance along a rigid motion no displacement condition holds have
    // no equilibrium: the two pins below would carry the resultant (the run solving a
    // body pinned at two nodes), or the solvers fail to converge with no reason given.
    // Refused as the BEM, coupled and growth modes refuse them (setup::balance, issue
    // 17). Explicit dynamics has no pins: its free body accelerates, as it should.
    if !matches!(pd.solver, PdSolver::Explicit(_)) {
        super::bem::check_balance_where_meshable(scene)?;
    }
    if !has_displacement {
        // One real node each (nodes sit at lo + (i + 1/2) dx): bottom middle (x, y) and top
        // middle (x), away from mid-height cracks; the loads are self-equilibrated.
        let snap = |v: f64, l: f64| l + (((v - l) / dx - 0.5).round() + 0.5) * dx;
        let xc = snap(0.5 * (lo[0] + hi[0]), lo[0]);
        let (yb, yt) = (snap(lo[1] + 0.5 * dx, lo[1]), snap(hi[1] - 0.5 * dx, lo[1]));
        let r = 0.25 * dx;
        refuse_zones_on_pins(scene, pd, &[[xc, yb], [xc, yt]])?;
        labels.extend(["pin".to_string(), "pin".to_string()]);
        boundary.push(PdBc::Displacement {
            on: Selection::Circle {
                centre: [xc, yb],
                radius: r,
            },
            ux: Some(0.0),
            uy: Some(0.0),
            layer: Layer::Real,
        });
        boundary.push(PdBc::Displacement {
            on: Selection::Circle {
                centre: [xc, yt],
                radius: r,
            },
            ux: Some(0.0),
            uy: None,
            layer: Layer::Real,
        });
    }
    let problem = PdProblem {
        region: Region {
            outline: pts,
            holes,
        },
        dx,
        horizon_factor: pd.horizon_factor,
        thickness: scene.material.thickness,
        youngs_modulus: scene.material.e,
        plane: pd_plane(scene),
        material: pd_material(scene, pd),
        failure,
        cracks,
        boundary,
        surface_correction: pd.surface_correction,
        crack_face_correction: pd.crack_face_correction.unwrap_or(false),
        traction: match pd.traction {
            PdTraction::BodyForceLayer => TractionLoad::BodyForceLayer,
            PdTraction::TransferFunction => TractionLoad::TransferFunction,
        },
        refine_zones: pd
            .refine_zones
            .iter()
            .map(|z| pdbem_pd::refine_zone::RefineZone {
                centre: [z.centre.0, z.centre.1],
                half_size: z.half_size,
                levels: z.levels,
            })
            .collect(),
        ..Default::default()
    };
    zones_on_the_grid(scene, &problem)?;
    Ok((problem, labels))
}
