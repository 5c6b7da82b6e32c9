//! Stand-alone PD solve of a scene (issue 3): grid the body, cut the pre-cracks, apply the
//! scene's conditions (displacements on fictitious layers of depth delta, tractions as body
//! forces in a boundary layer one node column deep, seed 000 section 2.3), solve with the scene's solver, and
//! report (`mode: "pd"`).
//!
//! Three kinds of scene:
//! - elastic (`failure: Elastic`): one equilibrium at the final load factor;
//! - crack initiation (cracks + `CriticalStretch` / `FromGc`, several load steps): the load
//!   is ramped from `load.initial` by `load.step` with brittle breaking until the crack runs
//!   by two horizons ([`pdbem_pd::measure::ramp_to_initiation`]); the initiation load is
//!   reported in Pa (factor times the largest applied traction) and the kink angle from the
//!   damage in the annulus delta..4 delta around each tip;
//! - damage with the tanh degradation (seed 000): the scene's solver drives the load to the
//!   final factor.
//!
//! Pure-traction scenes get two pins (the real node at the bottom middle: both components;
//! the one at the top middle: x) so the implicit tangent is regular; the loads are
//! self-equilibrated, so the pins carry no reaction.

use crate::output::csv::{num, CsvTable};
use crate::plot::ScatterField;
use crate::runner::report::save_plot;
use crate::runner::{RunContext, RunSummary};
use crate::scene::shapes::{HoleShape, SceneGeometry};
use crate::scene::{Component, Failure, PdSolver, Plane, Scene};
use anyhow::{bail, Context, Result};
use pdbem_pd::measure::{crack_tips, kink_angle, ramp_to_initiation, RampParams};
use pdbem_pd::problem::{BoundaryCondition as PdBc, Hole, Layer, Region, Selection};
use pdbem_pd::solvers::{adr, implicit, switching, Convergence};
use pdbem_pd::{PdModel, PdProblem};
use serde_json::json;
use std::time::Instant;

type P = [f64; 2];

/// The outline edges (or patch pieces) of a group as polylines.
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
        let n = o.points.len();
        for i in 0..n {
            if o.groups[i] == name || name == "outline" {
                let (a, b) = (o.points[i], o.points[(i + 1) % n]);
                out.push(vec![[a.x, a.y], [b.x, b.y]]);
            }
        }
    }
    for (hn, shape) in &geo.holes {
        if hn == name {
            let pts: Vec<P> = match shape {
                HoleShape::Circle { center, radius } => {
                    crate::geometry::circle_polygon(center, *radius, 128, false)
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

/// The PD problem of a scene.
pub fn problem_from_scene(scene: &Scene) -> Result<PdProblem> {
    let Some(pd) = &scene.pd else {
        bail!("{}: no `pd` section", scene.file_label().display())
    };
    let geo = SceneGeometry::of(scene);
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
    let dx = match (pd.dx, pd.nx) {
        (Some(dx), _) => dx,
        (None, Some(nx)) => (hi[0] - lo[0]) / nx as f64,
        (None, None) => bail!("{}: pd: give `dx` or `nx`", scene.file_label().display()),
    };
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
    let failure = match &pd.failure {
        Failure::Elastic => pdbem_pd::Failure::None,
        Failure::CriticalStretch(s0) => pdbem_pd::Failure::CriticalStretch { s0: *s0 },
        Failure::FromGc => {
            let g_c = scene
                .material
                .fracture
                .as_ref()
                .and_then(|f| f.g_c)
                .with_context(|| {
                    format!(
                        "{}: pd.failure = FromGc needs material.fracture.g_c",
                        scene.file_label().display()
                    )
                })?;
            pdbem_pd::Failure::FractureEnergy { g_c }
        }
        Failure::Degradation { s_m, s_c, beta } => pdbem_pd::Failure::Degradation {
            s_m: *s_m,
            s_c: *s_c,
            beta: *beta,
        },
    };
    let wanted: Option<&Vec<String>> = pd.pre_cracks.as_ref();
    let delta = pd.horizon_factor * dx;
    let cracks = geo
        .cracks
        .iter()
        .filter(|c| wanted.is_none_or(|w| w.contains(&c.name)))
        .map(|c| through_boundary_layer(&geo, &c.points, 0.99 * delta, 1e-6 * dx))
        .collect();
    let mut boundary = Vec::new();
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
            let mut t = [trac(bc.x), trac(bc.y)];
            if let (Some(tn), [a, b, ..]) = (bc.normal, line.as_slice()) {
                // Outward normal of a counter-clockwise outline edge: right-hand normal.
                let (dx_, dy_) = (b[0] - a[0], b[1] - a[1]);
                let l = dx_.hypot(dy_);
                t = [t[0] + tn * dy_ / l, t[1] - tn * dx_ / l];
            }
            if t != [0.0, 0.0] {
                // One node column deep (seed 000 section 2.3): a deeper layer moves the
                // resultant inward (a cantilever tip load over delta deflects ~4 % less).
                boundary.push(PdBc::Traction {
                    edge: line.clone(),
                    traction: t,
                    depth: Some(dx),
                });
            }
        }
    }
    if !has_displacement {
        // One real node each (nodes sit at lo + (i + 1/2) dx): bottom middle (x, y) and top
        // middle (x), away from mid-height cracks; the loads are self-equilibrated.
        let snap = |v: f64, l: f64| l + (((v - l) / dx - 0.5).round() + 0.5) * dx;
        let xc = snap(0.5 * (lo[0] + hi[0]), lo[0]);
        let (yb, yt) = (snap(lo[1] + 0.5 * dx, lo[1]), snap(hi[1] - 0.5 * dx, lo[1]));
        let r = 0.25 * dx;
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
    Ok(PdProblem {
        region: Region {
            outline: pts,
            holes,
        },
        dx,
        horizon_factor: pd.horizon_factor,
        thickness: scene.material.thickness,
        youngs_modulus: scene.material.e,
        plane: match scene.material.plane {
            Plane::Stress => pdbem_pd::Plane::Stress,
            Plane::Strain => pdbem_pd::Plane::Strain,
        },
        failure,
        cracks,
        boundary,
        surface_correction: pd.surface_correction,
        crack_face_correction: pd.crack_face_correction.unwrap_or(false),
        ..Default::default()
    })
}

/// Largest applied traction magnitude (Pa) at load factor 1.
fn traction_scale(scene: &Scene) -> Option<f64> {
    scene
        .boundary
        .iter()
        .flat_map(|b| [b.x, b.y])
        .filter_map(|c| match c {
            Component::Traction(v) => Some(v.abs()),
            _ => None,
        })
        .chain(scene.boundary.iter().filter_map(|b| b.normal.map(f64::abs)))
        .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))))
}

/// Solves `scene` with peridynamics over the whole body.
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<RunSummary> {
    let t0 = Instant::now();
    let file = scene.file_label();
    let problem = problem_from_scene(scene)?;
    let mut model = PdModel::new(&problem).with_context(|| format!("{}: pd", file.display()))?;
    ctx.log(&format!(
        "{}: PD model with {} real nodes, {} bonds",
        scene.name,
        model.n_real(),
        model.n_bonds()
    ));
    let pd = scene.pd.as_ref().context("no pd section")?;
    let factors = scene.load.factors();
    let last = factors.last().copied().unwrap_or(1.0);
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "pd".into(),
        ..Default::default()
    };
    let geo = SceneGeometry::of(scene);
    let brittle = matches!(pd.failure, Failure::CriticalStretch(_) | Failure::FromGc);
    let info = if brittle && !problem.cracks.is_empty() && factors.len() > 1 {
        let tips: Vec<_> = geo
            .cracks
            .iter()
            .flat_map(|c| {
                crack_tips(
                    &c.points.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>(),
                    c.mouth,
                )
            })
            .collect();
        let delta = problem.horizon();
        let ramp = RampParams {
            start: scene.load.initial,
            step: if scene.load.step > 0.0 {
                scene.load.step
            } else {
                0.05 * scene.load.initial
            },
            max_load: last,
            run_length: 2.0 * delta,
            grow_to: 5.0 * delta,
            max_rounds: 200,
        };
        let init = ramp_to_initiation(&mut model, &tips, &ramp)
            .with_context(|| format!("{}: load ramp", file.display()))?;
        let scale = traction_scale(scene).unwrap_or(1.0);
        summary.extra.insert(
            "first_break_load".into(),
            json!(init.first_break_load.map(|f| f * scale)),
        );
        summary.extra.insert(
            "initiation_load".into(),
            json!(init.initiation_load.map(|f| f * scale)),
        );
        summary
            .extra
            .insert("initiation_load_factor".into(), json!(init.initiation_load));
        let kinks: Vec<Option<f64>> = tips
            .iter()
            .map(|t| kink_angle(&model, *t, delta, 4.0 * delta))
            .collect();
        summary.extra.insert(
            "kink_deg".into(),
            json!(kinks.iter().flatten().copied().next()),
        );
        summary
            .extra
            .insert("kink_deg_per_tip".into(), json!(kinks));
        init.info
    } else {
        let conv = |tol: f64| Convergence::Displacement { e0: tol };
        match &pd.solver {
            PdSolver::Implicit(p) => implicit::solve(
                &mut model,
                &implicit::ImplicitParams {
                    target_load: last,
                    steps: factors.len().max(1),
                    convergence: conv(p.tolerance),
                    max_iters: p.max_iter,
                    ..Default::default()
                },
            ),
            PdSolver::Adr(p) => adr::solve(
                &mut model,
                &adr::AdrParams {
                    target_load: last,
                    steps: factors.len().max(1),
                    convergence: conv(p.tolerance),
                    max_iters: p.max_iter,
                    safety: p.safety_factor.max(1.0),
                    ..Default::default()
                },
            ),
            PdSolver::Switching(p) => switching::solve(
                &mut model,
                &switching::SwitchingParams {
                    target_load: last,
                    implicit_steps: p.implicit_steps,
                    explicit_steps: p.explicit_steps,
                    convergence: conv(p.tolerance),
                    max_newton_iters: p.max_newton,
                    max_adr_iters: p.max_adr,
                    ..Default::default()
                },
            ),
        }
        .with_context(|| format!("{}: PD solve", file.display()))?
    };
    let first_break = info
        .steps
        .iter()
        .find(|s| s.broken_bonds > 0)
        .map(|s| s.load);
    if !summary.extra.contains_key("first_break_load") {
        let scale = traction_scale(scene).unwrap_or(1.0);
        summary.extra.insert(
            "first_break_load".into(),
            json!(first_break.map(|f| f * scale)),
        );
    }
    summary.extra.insert("nodes".into(), json!(model.n_real()));
    summary
        .extra
        .insert("bonds".into(), json!(model.n_bonds() / 2));
    summary
        .extra
        .insert("broken_bonds".into(), json!(model.broken_bonds()));
    summary
        .extra
        .insert("iterations".into(), json!(info.iterations));
    summary.extra.insert("phases".into(), json!(info.phases));
    summary
        .extra
        .insert("switch_points".into(), json!(info.switch_points));
    summary.extra.insert(
        "time_s".into(),
        json!({"implicit": info.time_implicit_s, "explicit": info.time_explicit_s,
               "assembly": info.time_assembly_s, "factorization": info.time_factorization_s}),
    );
    write_fields(scene, ctx, &model, &mut summary)?;
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(summary)
}

/// Node CSV and damage / displacement plots.
fn write_fields(
    scene: &Scene,
    ctx: &RunContext,
    model: &PdModel,
    summary: &mut RunSummary,
) -> Result<()> {
    let n = model.n_real();
    let (x, u, phi) = (model.positions(), model.displacements(), model.damage());
    let mut t = CsvTable::new(&["x", "y", "ux", "uy", "damage"]);
    for i in 0..n {
        t.push(vec![
            num(x[i][0]),
            num(x[i][1]),
            num(u[i][0]),
            num(u[i][1]),
            num(phi[i]),
        ]);
    }
    ctx.writer.write_csv("nodes.csv", &t)?;
    if !scene.outputs.plots {
        return Ok(());
    }
    let geo = SceneGeometry::of(scene);
    let mut loops = Vec::new();
    if let Some(o) = &geo.outline {
        let mut l: Vec<(f64, f64)> = o.points.iter().map(|p| (p.x, p.y)).collect();
        l.push(l[0]);
        loops.push(l);
    }
    let points: Vec<(f64, f64)> = (0..n).map(|i| (x[i][0], x[i][1])).collect();
    let damage = ScatterField {
        title: format!("{}: damage", scene.name),
        unit: "m".into(),
        value_label: "damage phi (-)".into(),
        points: points.clone(),
        values: phi[..n].to_vec(),
        range: Some((0.0, 1.0)),
        loops: loops.clone(),
        marker_px: 0,
    };
    save_plot(
        &ctx.writer,
        "damage",
        &damage,
        &scene.outputs.formats,
        summary,
    )?;
    let umag = ScatterField {
        title: format!("{}: displacement magnitude", scene.name),
        unit: "m".into(),
        value_label: "|u| (m)".into(),
        points,
        values: (0..n).map(|i| u[i][0].hypot(u[i][1])).collect(),
        range: None,
        loops,
        marker_px: 0,
    };
    save_plot(
        &ctx.writer,
        "displacement",
        &umag,
        &scene.outputs.formats,
        summary,
    )?;
    Ok(())
}
