//! Static PD-BEM coupled solve of a scene (issue 4, seed 002 section 2.3, Algorithm 1).
//!
//! From the scene: the BEM body (outline with patches, holes, cracks) with the PD windows
//! cut out ([`pdbem_coupling::setup::build`]), the PD windows (`coupling.placement`: one
//! square per crack tip with axes along the crack, a centred and rotated square, or an
//! axis-aligned region that may lie against the outline), and Algorithm 1
//! ([`pdbem_coupling::solve`]). Returns a [`RunSummary`] with `mode: "coupled"`,
//! `pd_nodes`, `coupling` (iterations, residual, converged, relaxation history, time per
//! phase), CMOD of edge cracks and, for a tip inside a window, K_I / K_II / J from the
//! interaction integral on a circle of BEM interior points around the window.
//!
//! Outputs: `interface.csv` (PD input and BEM output at every coupled virtual node),
//! `coupling_history.csv`, `pd_nodes.csv`, plots `displacement` (BEM interior points and
//! PD nodes together), `interface_error`, `convergence`.

use std::time::Instant;

use anyhow::{bail, Context, Result};
use pdbem_bem::mesh::{FaceMode, LoopSpec};
use pdbem_bem::post::sif::{analyze_tips, cmod, interaction_integral, SifOptions};
use pdbem_bem::post::{Background, FieldEvaluator};
use pdbem_bem::{Bc, Mesh, SolveParams, V2};
use pdbem_coupling::pd_window::{EdgeCondition, PdSettings};
use pdbem_coupling::setup::{Layout, MacroCrack};
use pdbem_coupling::window::{SideKind, Window, WindowSpec};
use pdbem_coupling::{
    Acceleration, CoupledProblem, CoupledSolution, CouplingInfo, CouplingParams, PdSolve,
};
use pdbem_pd::solvers::{adr, implicit, Convergence};
use serde_json::json;

use crate::bem_setup::{material, outline_size, DEFAULT_ELEMENTS_PER_CIRCLE};
use crate::geometry::{circle_polygon, point_segment_projection, polygon_distance, P2};
use crate::output::csv::{num, CsvTable};
use crate::plot::{ScatterField, Series, SeriesStyle, XyPlot};
use crate::run_bem::final_factor;
use crate::runner::report::save_plot;
use crate::runner::{CrackResult, RunContext, RunSummary, TipResult};
use crate::scene::shapes::{HoleShape, SceneGeometry};
use crate::scene::{
    Component, Coupling, DisplacementMap, Faces, Failure, PdSettings as ScenePd, PdSolver,
    Placement, Relaxation, Scene,
};

/// A crack tip inside a window.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowTip {
    /// Tip name (`<crack>.end` / `<crack>.start`).
    pub name: String,
    /// Position (m).
    pub position: V2,
    /// Unit crack direction at the tip (pointing out of the crack).
    pub direction: V2,
    /// Window holding it.
    pub window: usize,
}

/// Everything a coupled solve needs, built from a scene.
pub struct CoupledSetup {
    /// The coupled problem (BEM body + windows).
    pub problem: CoupledProblem,
    /// Algorithm 1 parameters from `coupling`.
    pub params: CouplingParams,
    /// Tips inside windows.
    pub tips: Vec<WindowTip>,
    /// Load factor the conditions were scaled by.
    pub factor: f64,
}

/// The result of a coupled solve.
pub struct CoupledOutcome {
    /// Setup (windows hold their final PD state).
    pub setup: CoupledSetup,
    /// Interface state and BEM solution.
    pub solution: CoupledSolution,
    /// Iteration record.
    pub info: CouplingInfo,
}

/// Builds the coupled problem of `scene` (validated, with `pd` and `coupling`).
pub fn prepare(scene: &Scene) -> Result<CoupledSetup> {
    let file = scene.file_label();
    let (Some(co), Some(pd)) = (&scene.coupling, &scene.pd) else {
        bail!("{}: coupled mode needs `pd` and `coupling`", file.display());
    };
    let geo = SceneGeometry::of(scene);
    if geo.outline.is_none() {
        bail!(
            "{}: coupled mode needs a finite body (infinite plates are BEM or PD only)",
            file.display()
        );
    }
    let factor = final_factor(scene);
    let (specs, tips) = window_specs(scene, &geo, co, pd)?;
    let layout = Layout {
        outline: outline_spec(scene, &geo),
        holes: hole_specs(scene, &geo),
        cracks: crack_specs(scene, &geo),
        windows: specs,
        pd: pd_settings(scene, pd),
    };
    let outer_loop = layout.outline.clone();
    let built = pdbem_coupling::build(&layout, |_, w| {
        outer_conditions(scene, &outer_loop, w, factor)
    })
    .with_context(|| format!("{}: coupling setup", file.display()))?;
    let bcs = conditions(scene, &built.mesh, factor)?;
    let problem = CoupledProblem {
        mesh: built.mesh,
        material: material(scene)?,
        bcs,
        bem_params: SolveParams {
            estimate_condition: false,
            ..Default::default()
        },
        background: Background::default(),
        thickness: scene.material.thickness,
        windows: built.windows,
    };
    Ok(CoupledSetup {
        problem,
        params: params_of(co, pd),
        tips,
        factor,
    })
}

/// Solves a prepared setup.
pub fn solve_setup(mut setup: CoupledSetup) -> Result<CoupledOutcome> {
    let (solution, info) =
        pdbem_coupling::solve(&mut setup.problem, &setup.params).context("coupled solve")?;
    Ok(CoupledOutcome {
        setup,
        solution,
        info,
    })
}

/// Solves `scene` without writing anything: summary and outcome.
pub fn solve(scene: &Scene) -> Result<(RunSummary, CoupledOutcome)> {
    let t0 = Instant::now();
    let out = solve_setup(prepare(scene)?)?;
    let mut summary = summarize(scene, &out)?;
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok((summary, out))
}

/// Solves `scene` by PD-BEM coupling and writes the coupled outputs through `ctx.writer`.
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<RunSummary> {
    ctx.log(&format!("{}: PD-BEM coupled solve", scene.name));
    let (mut summary, out) = solve(scene)?;
    ctx.log(&format!(
        "{}: {} iterations ({}), residual {:.2e}",
        scene.name,
        out.info.iterations,
        out.info.scheme,
        out.info.residuals.last().copied().unwrap_or(f64::NAN)
    ));
    if scene.outputs.csv {
        write_tables(ctx, &out)?;
    }
    if scene.outputs.plots {
        write_plots(scene, ctx, &out, &mut summary)?;
    }
    Ok(summary)
}

fn p(v: &P2) -> V2 {
    V2::new(v.x, v.y)
}

/// Window specifications and the tips they hold.
pub(crate) fn window_specs(
    scene: &Scene,
    geo: &SceneGeometry,
    co: &Coupling,
    pd: &ScenePd,
) -> Result<(Vec<WindowSpec>, Vec<WindowTip>)> {
    let dx = co.side / co.n as f64;
    let m = pd.horizon_factor;
    let square = |center: V2, angle: f64| WindowSpec {
        center,
        angle,
        dx,
        nx: co.n,
        ny: co.n,
        horizon_factor: m,
    };
    let all_tips: Vec<(String, V2, V2)> = geo
        .cracks
        .iter()
        .flat_map(|c| {
            let n = c.points.len();
            let mut t = Vec::new();
            if !c.mouth {
                t.push((
                    format!("{}.start", c.name),
                    p(&c.points[0]),
                    p(&(c.points[0] - c.points[1]).normalize()),
                ));
            }
            t.push((
                format!("{}.end", c.name),
                p(&c.points[n - 1]),
                p(&(c.points[n - 1] - c.points[n - 2]).normalize()),
            ));
            t
        })
        .collect();
    let specs = match &co.placement {
        Placement::AtTips => {
            if all_tips.is_empty() {
                bail!(
                    "{}: coupling.placement = AtTips but the scene has no crack tip",
                    scene.file_label().display()
                );
            }
            all_tips
                .iter()
                .map(|(_, t, d)| square(*t, d.y.atan2(d.x)))
                .collect()
        }
        Placement::Centered { center, angle_deg } => {
            vec![square(V2::new(center.0, center.1), angle_deg.to_radians())]
        }
        Placement::Region {
            x0,
            y0,
            width,
            height,
        } => {
            let dx = width / co.n as f64;
            vec![WindowSpec {
                center: V2::new(x0 + 0.5 * width, y0 + 0.5 * height),
                angle: 0.0,
                dx,
                nx: co.n,
                ny: (height / dx).round().max(1.0) as usize,
                horizon_factor: m,
            }]
        }
    };
    let tips = all_tips
        .into_iter()
        .filter_map(|(name, position, direction)| {
            let window = specs.iter().position(|s| inside_spec(s, position))?;
            Some(WindowTip {
                name,
                position,
                direction,
                window,
            })
        })
        .collect();
    Ok((specs, tips))
}

fn inside_spec(s: &WindowSpec, x: V2) -> bool {
    let (sn, cs) = s.angle.sin_cos();
    let d = x - s.center;
    let (lx, ly) = (d.x * cs + d.y * sn, -d.x * sn + d.y * cs);
    let (hw, hh) = (0.5 * s.nx as f64 * s.dx, 0.5 * s.ny as f64 * s.dx);
    lx.abs() < hw && ly.abs() < hh
}

/// Element size of a group: `bem.group_sizes`, else the outline default.
fn size_of(scene: &Scene, geo: &SceneGeometry, group: &str) -> f64 {
    scene
        .bem
        .group_sizes
        .get(group)
        .copied()
        .unwrap_or_else(|| outline_size(scene, geo))
}

/// Outline loop with patches split out (as `bem_setup` does).
pub(crate) fn outline_spec(scene: &Scene, geo: &SceneGeometry) -> LoopSpec {
    let o = geo.outline.as_ref().expect("finite body checked");
    let n = o.points.len();
    let (mut points, mut groups) = (Vec::new(), Vec::new());
    for i in 0..n {
        let (a, b) = (p(&o.points[i]), p(&o.points[(i + 1) % n]));
        let mut cuts = vec![0.0, 1.0];
        for pt in &scene.body.patches {
            for q in [V2::new(pt.from.0, pt.from.1), V2::new(pt.to.0, pt.to.1)] {
                let (d, t) = point_segment_projection(&q, &a, &b);
                if d <= 1e-9 * (b - a).norm() && t > 1e-12 && t < 1.0 - 1e-12 {
                    cuts.push(t);
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|x, y| (*x - *y).abs() < 1e-12);
        for w in cuts.windows(2) {
            let mid = a + 0.5 * (w[0] + w[1]) * (b - a);
            points.push(a + w[0] * (b - a));
            let name = scene
                .body
                .patches
                .iter()
                .find(|pt| {
                    let (f, t) = (V2::new(pt.from.0, pt.from.1), V2::new(pt.to.0, pt.to.1));
                    point_segment_projection(&mid, &f, &t).0 <= 1e-9 * (t - f).norm()
                })
                .map(|pt| pt.name.clone())
                .unwrap_or_else(|| o.groups[i].clone());
            groups.push(name);
        }
    }
    let edge_sizes = groups.iter().map(|g| size_of(scene, geo, g)).collect();
    LoopSpec {
        points,
        edge_groups: groups,
        edge_sizes,
        is_hole: false,
    }
}

pub(crate) fn hole_specs(scene: &Scene, geo: &SceneGeometry) -> Vec<LoopSpec> {
    let per_circle = scene
        .bem
        .elements_per_circle
        .unwrap_or(DEFAULT_ELEMENTS_PER_CIRCLE);
    geo.holes
        .iter()
        .map(|(name, h)| {
            let (pts, size) = match h {
                HoleShape::Circle { center, radius } => (
                    circle_polygon(center, *radius, per_circle, true),
                    f64::INFINITY,
                ),
                HoleShape::Polygon(q) => (q.clone(), size_of(scene, geo, name)),
            };
            let n = pts.len();
            LoopSpec {
                points: pts.iter().map(p).collect(),
                edge_groups: vec![name.clone(); n],
                edge_sizes: vec![size; n],
                is_hole: true,
            }
        })
        .collect()
}

pub(crate) fn crack_specs(scene: &Scene, geo: &SceneGeometry) -> Vec<MacroCrack> {
    scene
        .cracks
        .iter()
        .zip(&geo.cracks)
        .map(|(c, line)| MacroCrack {
            name: c.name.clone(),
            points: line.points.iter().map(p).collect(),
            faces: match c.faces {
                Faces::Coincident => FaceMode::Coincident,
                Faces::Gap(g) => FaceMode::Gap(g),
            },
            element_size: size_of(scene, geo, &c.name),
            segment_elements: false,
        })
        .collect()
}

pub(crate) fn pd_settings(scene: &Scene, pd: &ScenePd) -> PdSettings {
    let plane = match scene.material.plane {
        crate::scene::Plane::Stress => pdbem_pd::Plane::Stress,
        crate::scene::Plane::Strain => pdbem_pd::Plane::Strain,
    };
    let failure = match &pd.failure {
        Failure::Elastic => pdbem_pd::Failure::None,
        Failure::CriticalStretch(s0) => pdbem_pd::Failure::CriticalStretch { s0: *s0 },
        Failure::FromGc => pdbem_pd::Failure::FractureEnergy {
            g_c: scene
                .material
                .fracture
                .as_ref()
                .and_then(|f| f.g_c)
                .unwrap_or(f64::NAN),
        },
        Failure::Degradation { s_m, s_c, beta } => pdbem_pd::Failure::Degradation {
            s_m: *s_m,
            s_c: *s_c,
            beta: *beta,
        },
    };
    PdSettings {
        youngs_modulus: scene.material.e,
        thickness: scene.material.thickness,
        plane,
        failure,
        surface_correction: pd.surface_correction,
        // The surface correction already includes the bulk factor.
        bulk_correction: !pd.surface_correction,
        crack_face_correction: pd.crack_face_correction.unwrap_or(true),
    }
}

pub(crate) fn params_of(co: &Coupling, pd: &ScenePd) -> CouplingParams {
    let acceleration = match co.relaxation {
        Relaxation::Constant(w) => Acceleration::Constant(w),
        Relaxation::Aitken(w) => Acceleration::Aitken(w),
        Relaxation::IqnIls { w0, .. } => Acceleration::IqnIls(w0),
    };
    let displacement_map = match co.displacement_map {
        DisplacementMap::Copy => pdbem_coupling::DisplacementMap::Copy,
        DisplacementMap::Interior => pdbem_coupling::DisplacementMap::Interior,
        DisplacementMap::Taylor => pdbem_coupling::DisplacementMap::Taylor,
    };
    let pd_solve = match &pd.solver {
        PdSolver::Switching(s) => match PdSolve::default() {
            PdSolve::Switching(mut p) => {
                p.max_newton_iters = s.max_newton;
                p.max_adr_iters = s.max_adr;
                PdSolve::Switching(p)
            }
            other => other,
        },
        PdSolver::Implicit(s) => PdSolve::Implicit(implicit::ImplicitParams {
            target_load: 1.0,
            steps: 1,
            convergence: Convergence::Residual { tol: 1e-9 },
            max_iters: s.max_iter,
            ..Default::default()
        }),
        PdSolver::Adr(s) => PdSolve::Adr(adr::AdrParams {
            target_load: 1.0,
            steps: 1,
            convergence: Convergence::Displacement { e0: s.tolerance },
            max_iters: s.max_iter,
            safety: s.safety_factor,
            ..Default::default()
        }),
    };
    CouplingParams {
        acceleration,
        psi: co.psi,
        max_iter: co.max_iter,
        displacement_map,
        pd_solve,
        ..Default::default()
    }
}

/// Scene conditions on the outline pieces that lie along window `w`'s outer sides.
pub(crate) fn outer_conditions(
    scene: &Scene,
    outline: &LoopSpec,
    w: &Window,
    factor: f64,
) -> Vec<EdgeCondition> {
    let mut out = Vec::new();
    let n = outline.points.len();
    let tol = w.tol();
    for k in (0..4).filter(|&k| w.sides[k] == SideKind::Outer) {
        let (a, b) = w.side(k);
        let t = (b - a).normalize();
        for i in 0..n {
            let (p0, p1) = (outline.points[i], outline.points[(i + 1) % n]);
            if point_segment_projection(&p0, &a, &b).0 > tol
                && point_segment_projection(&a, &p0, &p1).0 > tol
            {
                continue;
            }
            // Overlap of edge i with side k along t.
            let (s0, s1) = ((p0 - a).dot(&t), (p1 - a).dot(&t));
            let lo = s0.min(s1).max(0.0);
            let hi = s0.max(s1).min((b - a).norm());
            let collinear = [p0, p1]
                .iter()
                .all(|q| ((q - a) - (q - a).dot(&t) * t).norm() <= tol);
            if !collinear || hi - lo <= tol {
                continue;
            }
            let (from, to) = (a + lo * t, a + hi * t);
            let e = (p1 - p0).normalize();
            let normal = V2::new(e.y, -e.x);
            for bc in scene
                .boundary
                .iter()
                .filter(|bc| bc.on == outline.edge_groups[i])
            {
                let mut c = EdgeCondition {
                    from,
                    to,
                    traction: [None; 2],
                    displacement: [None; 2],
                };
                for (j, comp) in [bc.x, bc.y].iter().enumerate() {
                    match comp {
                        Component::Free => {}
                        Component::Traction(v) => c.traction[j] = Some(v * factor),
                        Component::Displacement(v) => c.displacement[j] = Some(v * factor),
                    }
                }
                let (tn, ts) = (bc.normal.unwrap_or(0.0), bc.shear.unwrap_or(0.0));
                if tn != 0.0 || ts != 0.0 {
                    let tr = (normal * tn + e * ts) * factor;
                    c.traction = [Some(tr.x), Some(tr.y)];
                }
                out.push(c);
            }
        }
    }
    out
}

/// Per-element BEM conditions at load `factor` (traction-free where nothing is said;
/// groups wholly inside a window are skipped: PD carries them).
fn conditions(scene: &Scene, mesh: &Mesh, factor: f64) -> Result<Vec<[Bc; 2]>> {
    crate::bem_setup::conditions(
        scene,
        mesh,
        factor,
        None,
        crate::bem_setup::MissingGroup::Skip,
    )
}

/// Interaction-integral SIFs of a windowed tip on a circle around its window.
pub fn window_tip_sif(
    out: &CoupledOutcome,
    scene: &Scene,
    tip: &WindowTip,
) -> Option<(f64, f64, f64, f64)> {
    let pb = &out.setup.problem;
    let w = &pb.windows[tip.window].window;
    let half_diag = w
        .corners()
        .iter()
        .map(|c| (c - tip.position).norm())
        .fold(0.0, f64::max);
    let geo = SceneGeometry::of(scene);
    let mut clearance = f64::INFINITY;
    if let Some(o) = &geo.outline {
        let pts: Vec<V2> = o.points.iter().map(p).collect();
        clearance = clearance.min(polygon_distance(&tip.position, &pts));
    }
    for (_, h) in &geo.holes {
        let pts: Vec<V2> = h.polygon().iter().map(p).collect();
        clearance = clearance.min(polygon_distance(&tip.position, &pts));
    }
    let r_min = 1.1 * half_diag;
    let r_max = 0.9 * clearance;
    if r_min >= r_max {
        return None;
    }
    let radius = (1.25 * half_diag).min(0.5 * (r_min + r_max).max(r_min));
    let ev = FieldEvaluator::new(
        &pb.mesh,
        &pb.material,
        &out.solution.solution,
        pb.background,
    );
    let h = w.spec.dx;
    let (k1, k2, j) = interaction_integral(&ev, tip.position, tip.direction, radius, 64, h);
    Some((k1, k2, j, radius))
}

/// The summary of a coupled solve (without reference values; the runner adds them).
pub fn summarize(scene: &Scene, out: &CoupledOutcome) -> Result<RunSummary> {
    let pb = &out.setup.problem;
    let sol = &out.solution.solution;
    let mut tips = Vec::new();
    for t in &out.setup.tips {
        let Some((k1, k2, j, r)) = window_tip_sif(out, scene, t) else {
            continue;
        };
        let _ = (j, r);
        tips.push(TipResult {
            name: t.name.clone(),
            position: [t.position.x, t.position.y],
            k1,
            k2,
            kink_deg: pdbem_bem::post::kink_angle(k1, k2).to_degrees(),
            k1_j: Some(k1),
            k2_j: Some(k2),
            ..Default::default()
        });
    }
    let ev = FieldEvaluator::new(&pb.mesh, &pb.material, sol, pb.background);
    let opts = SifOptions {
        fit_fraction: scene.bem.cod_fit_fraction,
        contour_fraction: scene.bem.j_contour.radius_fraction,
        contour_points: scene.bem.j_contour.points,
    };
    for t in analyze_tips(&pb.mesh, &ev, sol, &opts).context("BEM tips")? {
        tips.push(crate::run_bem::tip_result(&pb.mesh, &t));
    }
    let cracks = pb
        .mesh
        .cracks
        .iter()
        .enumerate()
        .map(|(i, c)| CrackResult {
            name: c.name.clone(),
            cmod: cmod(&pb.mesh, sol, i),
            ..Default::default()
        })
        .collect();
    let pd_nodes: usize = pb.windows.iter().map(|w| w.model.n_real()).sum();
    let info = &out.info;
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "coupled".into(),
        elements: Some(pb.mesh.len()),
        tips,
        cracks,
        ..Default::default()
    };
    summary.extra.insert("pd_nodes".into(), json!(pd_nodes));
    summary
        .extra
        .insert("load_factor".into(), json!(out.setup.factor));
    summary.extra.insert(
        "coupling".into(),
        json!({
            "scheme": info.scheme,
            "iterations": info.iterations,
            "residual": info.residuals.last(),
            "converged": info.converged,
            "psi": out.setup.params.psi,
            "residual_history": info.residuals,
            "relaxation_history": info.weights,
            "backoffs": info.backoffs,
            "interface_unknowns": info.interface_unknowns,
            "pd_iterations": info.pd_iterations,
            "windows": pb.windows.len(),
            "displacement_map": format!("{:?}", out.setup.params.displacement_map),
            "traction_map": format!("{:?}", out.setup.params.traction_map),
            "timings": info.timings,
        }),
    );
    summary.plot_nodes = pb
        .mesh
        .elements
        .iter()
        .map(|e| (e.mid.x, e.mid.y))
        .collect();
    Ok(summary)
}

fn write_tables(ctx: &RunContext, out: &CoupledOutcome) -> Result<()> {
    let mut t = CsvTable::new(&["window", "x", "y", "ux_pd", "uy_pd", "ux_bem", "uy_bem"]);
    let mut k = 0;
    for (wi, w) in out.setup.problem.windows.iter().enumerate() {
        for x in &w.interface.positions {
            let (a, b) = (&out.solution.x_pd, &out.solution.x_bem);
            t.push(vec![
                wi.to_string(),
                num(x.x),
                num(x.y),
                num(a[2 * k]),
                num(a[2 * k + 1]),
                num(b[2 * k]),
                num(b[2 * k + 1]),
            ]);
            k += 1;
        }
    }
    ctx.writer.write_csv("interface.csv", &t)?;
    let mut h = CsvTable::new(&["iteration", "residual", "weight"]);
    for (i, r) in out.info.residuals.iter().enumerate() {
        let w = out.info.weights.get(i).copied().flatten();
        h.push(vec![
            (i + 1).to_string(),
            num(*r),
            w.map(num).unwrap_or_default(),
        ]);
    }
    ctx.writer.write_csv("coupling_history.csv", &h)?;
    let mut n = CsvTable::new(&["window", "x", "y", "ux", "uy", "damage"]);
    for (wi, w) in out.setup.problem.windows.iter().enumerate() {
        let d = w.model.damage();
        let (pos, u) = (w.model.positions(), w.model.displacements());
        for i in 0..w.model.n_real() {
            n.push(vec![
                wi.to_string(),
                num(pos[i][0]),
                num(pos[i][1]),
                num(u[i][0]),
                num(u[i][1]),
                num(d[i]),
            ]);
        }
    }
    ctx.writer.write_csv("pd_nodes.csv", &n)?;
    Ok(())
}

/// BEM interior sample points: a grid over the body, outside windows, holes and a band of
/// one element size along the boundary.
pub fn bem_sample_points(scene: &Scene, out: &CoupledOutcome, per_side: usize) -> Vec<V2> {
    let pb = &out.setup.problem;
    let geo = SceneGeometry::of(scene);
    let (lo, hi) = geo.bounds();
    let ext = hi - lo;
    let h = ext.x.max(ext.y) / per_side as f64;
    let (nx, ny) = ((ext.x / h).ceil() as usize, (ext.y / h).ceil() as usize);
    let mut pts = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let x = V2::new(
                lo.x + (i as f64 + 0.5) * ext.x / nx as f64,
                lo.y + (j as f64 + 0.5) * ext.y / ny as f64,
            );
            let near = pb
                .mesh
                .elements
                .iter()
                .any(|e| point_segment_projection(&x, &e.a, &e.b).0 < 0.5 * h.max(e.h));
            let in_window = pb.windows.iter().any(|w| w.window.contains(x, 0.0));
            if geo.contains(&P2::new(x.x, x.y)) && !near && !in_window {
                pts.push(x);
            }
        }
    }
    pts
}

fn write_plots(
    scene: &Scene,
    ctx: &RunContext,
    out: &CoupledOutcome,
    summary: &mut RunSummary,
) -> Result<()> {
    let formats = &scene.outputs.formats;
    let pb = &out.setup.problem;
    let pts = bem_sample_points(scene, out, 60);
    let ev = FieldEvaluator::new(
        &pb.mesh,
        &pb.material,
        &out.solution.solution,
        pb.background,
    );
    let u = ev.displacements(&pts);
    let mut field = ScatterField {
        title: format!("{}: |u| over BEM interior points and PD nodes", scene.name),
        unit: "m".into(),
        value_label: "|u| (m)".into(),
        ..Default::default()
    };
    for (x, v) in pts.iter().zip(&u) {
        field.points.push((x.x, x.y));
        field.values.push(v[0].hypot(v[1]));
    }
    for w in &pb.windows {
        let (pos, du) = (w.model.positions(), w.model.displacements());
        for i in 0..w.model.n_real() {
            field.points.push((pos[i][0], pos[i][1]));
            field.values.push(du[i][0].hypot(du[i][1]));
        }
        let c = w.window.corners();
        field.loops.push(c.iter().map(|q| (q.x, q.y)).collect());
    }
    save_plot(&ctx.writer, "displacement", &field, formats, summary)?;
    let (a, b) = (&out.solution.x_pd, &out.solution.x_bem);
    let scale = b
        .chunks(2)
        .map(|c| c[0].hypot(c[1]))
        .fold(0.0_f64, f64::max)
        .max(1e-300);
    let err: Vec<(f64, f64)> = a
        .chunks(2)
        .zip(b.chunks(2))
        .enumerate()
        .map(|(k, (p, q))| (k as f64, (p[0] - q[0]).hypot(p[1] - q[1]) / scale))
        .collect();
    let mut ip = XyPlot::new(
        format!(
            "{}: interface mismatch |u_PD - u_BEM| / max |u_BEM|",
            scene.name
        ),
        "coupled virtual node (-)",
        "relative mismatch (-)",
    );
    ip.series
        .push(Series::new("final iteration", err, SeriesStyle::Markers));
    save_plot(&ctx.writer, "interface_error", &ip, formats, summary)?;
    let mut cp = XyPlot::new(
        format!(
            "{}: Algorithm 1 convergence ({})",
            scene.name, out.info.scheme
        ),
        "iteration (-)",
        "relative interface residual (-)",
    );
    cp.log_y = true;
    let res = out
        .info
        .residuals
        .iter()
        .enumerate()
        .map(|(i, r)| ((i + 1) as f64, *r))
        .collect();
    cp.series
        .push(Series::new("e_k", res, SeriesStyle::LineMarkers));
    cp.series.push(Series::new(
        "psi",
        vec![
            (1.0, out.setup.params.psi),
            (out.info.iterations.max(2) as f64, out.setup.params.psi),
        ],
        SeriesStyle::Line,
    ));
    save_plot(&ctx.writer, "convergence", &cp, formats, summary)?;
    Ok(())
}
