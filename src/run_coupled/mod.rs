//! Static PD-BEM coupled solve of a scene (issue 4, seed 002 section 2.3, Algorithm 1).
//!
//! From the scene: the BEM body (outline with patches, holes, cracks) with the PD windows
//! cut out ([`pdbem_coupling::setup::build`]), the PD windows (`coupling.placement`: one
//! square per crack tip with axes along the crack, a centred and rotated square, or an
//! axis-aligned region that may lie against the outline), and Algorithm 1
//! ([`pdbem_coupling::solve`]). Returns a [`RunSummary`] with `mode: "coupled"`,
//! `pd_nodes`, `coupling` (iterations, residual, converged, relaxation history, time per
//! phase), CMOD of edge cracks and, for a tip inside a window, K_I / K_II / J from the
//! interaction integral on a circle of BEM interior points around the window, or a note
//! saying why no such circle fits (the window reaches too close to the boundary). Every
//! K and CMOD carries an error estimate against the BEM alone ([`estimate`]).
//!
//! Outputs: `interface.csv` (PD input and BEM output at every coupled virtual node),
//! `coupling_history.csv`, `pd_nodes.csv`, plots `displacement` (BEM interior points and
//! PD nodes together), `interface_error`, `convergence`.

pub mod estimate;

use std::time::Instant;

use crate::geometry::point_segment_projection;
use anyhow::{Context, Result};
use pdbem_bem::post::sif::{analyze_tips, SifOptions};
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::V2;
use pdbem_coupling::post::{WindowContour, WindowTipSif};
use pdbem_coupling::{CoupledSolution, CouplingInfo};
use serde_json::json;

use crate::geometry::P2;
use crate::output::csv::{num, CsvTable};
use crate::plot::{ScatterField, Series, SeriesStyle, XyPlot};
use crate::runner::context::RunContext;
use crate::runner::report::save_plot;
use crate::runner::summary::{RunSummary, TipResult};
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;
use crate::setup::coupled::{prepare, CoupledSetup, WindowTip};

/// The result of a coupled solve.
pub struct CoupledOutcome {
    /// Setup (windows hold their final PD state).
    pub setup: CoupledSetup,
    /// Interface state and BEM solution.
    pub solution: CoupledSolution,
    /// Iteration record.
    pub info: CouplingInfo,
}

/// Solves a prepared setup.
pub fn solve_setup(mut setup: CoupledSetup) -> Result<CoupledOutcome> {
    let (solution, info) = match pdbem_coupling::solve(&mut setup.problem, &setup.params) {
        Ok(r) => r,
        // A thin strip of BEM body under a window, or a nearly incompressible body, is the
        // likely cause of a stall: say so (setup::coupled::coupling_notes).
        Err(e) if !setup.notes.is_empty() => {
            return Err(anyhow::Error::new(e).context(format!(
                "coupled solve (likely cause: {})",
                setup.notes.join("; ")
            )))
        }
        Err(e) => return Err(anyhow::Error::new(e).context("coupled solve")),
    };
    Ok(CoupledOutcome {
        setup,
        solution,
        info,
    })
}

/// Solves `scene` without writing anything: summary and outcome.
pub fn solve(scene: &Scene) -> Result<(RunSummary, CoupledOutcome)> {
    let t0 = Instant::now();
    let setup = prepare(scene)?;
    crate::setup::fit_stations::require(scene, &setup.problem.mesh, "the coupled BEM body's mesh")?;
    let out = solve_setup(setup)?;
    let mut summary = summarize(scene, &out)?;
    estimate::attach(scene, &out, &mut summary);
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
    if scene.outputs.vtk {
        write_vtk(ctx, &out)?;
    }
    if scene.outputs.csv {
        write_tables(ctx, &out)?;
    }
    if scene.outputs.plots {
        write_plots(scene, ctx, &out, &mut summary)?;
    }
    let pb = &out.setup.problem;
    let ld = crate::load_displacement::LoadDisplacement::from_bem(
        scene,
        &pb.mesh,
        &out.solution.solution,
        out.setup.factor,
    );
    crate::load_displacement::write(scene, ctx, &ld, &mut summary)?;
    Ok(summary)
}

/// Interaction-integral SIFs of a windowed tip on a circle around its window, clear of
/// the scene's outline and holes ([`pdbem_coupling::post::window_tip_sif`] with the
/// default contour); an error that says why when no such circle exists.
pub fn window_tip_sif(
    out: &CoupledOutcome,
    scene: &Scene,
    tip: &WindowTip,
) -> Result<WindowTipSif, pdbem_coupling::CouplingError> {
    let boundaries = crate::setup::coupled::contour_boundaries(scene);
    pdbem_coupling::post::window_tip_sif(
        &out.setup.problem,
        &out.solution,
        tip.window,
        tip.position,
        tip.direction,
        &boundaries,
        &WindowContour::default(),
    )
}

/// One note per window whose bonds broke (beyond the pre-cracks' cuts) or softened (the
/// tanh law past `s_m`) in the solve. A static coupled solve keeps the scene's cracks as
/// given in the BEM, so K and the CMOD then belong to a body the window has cracked
/// further, and their reference errors measure that crack, not the solve: the SENT plate
/// with `CriticalStretch(0.001)` broke 1148 pairs and gave K_I +129 % against Tada, and
/// the only note was the contour J's disagreement with G, which blamed the mesh.
fn damage_notes(out: &CoupledOutcome) -> Vec<String> {
    out.setup
        .problem
        .windows
        .iter()
        .enumerate()
        .filter_map(|(k, w)| {
            let m = &w.model;
            let broken = m.broken_bonds();
            let softened = match m.law() {
                pdbem_pd::material::BondLaw::Degrading { .. } => {
                    let st = m.state();
                    st.s_hist
                        .iter()
                        .zip(&st.intact)
                        .filter(|(h, i)| **h > 0.0 && **i != 0)
                        .count()
                        / 2
                }
                _ => 0,
            };
            let more = if softened > 0 {
                format!(" and softened {softened} more")
            } else {
                String::new()
            };
            (broken + softened > 0).then(|| {
                format!(
                    "PD window {k} broke {broken} bond pairs{more}: the PD crack grew inside the window beyond the scene's crack, which the BEM keeps as given, so K, the CMOD and their reference errors belong to that further-cracked body; for the scene's crack use `pd.failure: Elastic` (or loads below the bonds' onset), to follow the crack a `growth` section"
                )
            })
        })
        .collect()
}

/// The summary of a coupled solve (without reference values; the runner adds them).
pub fn summarize(scene: &Scene, out: &CoupledOutcome) -> Result<RunSummary> {
    let pb = &out.setup.problem;
    let sol = &out.solution.solution;
    let mut tips = Vec::new();
    let mut notes = Vec::new();
    for t in &out.setup.tips {
        let WindowTipSif { k1, k2, j, .. } = match window_tip_sif(out, scene, t) {
            Ok(sif) => sif,
            Err(e) => {
                notes.push(format!("tip {}: no K reported: {e}", t.name));
                continue;
            }
        };
        tips.push(TipResult {
            name: t.name.clone(),
            position: [t.position.x, t.position.y],
            k1,
            k2,
            kink_deg: pdbem_bem::post::kink_angle(k1, k2).to_degrees(),
            k1_j: Some(k1),
            k2_j: Some(k2),
            j: Some(j),
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
        let one_face = crate::run_bem::level::one_face_loaded(scene, t.crack, &pb.mesh);
        tips.push(crate::run_bem::tip_result(&pb.mesh, &t, one_face));
    }
    notes.extend(damage_notes(out));
    let cracks = crate::run_bem::level::crack_results(&pb.mesh, sol);
    let pd_nodes: usize = pb.windows.iter().map(|w| w.model.n_real()).sum();
    let info = &out.info;
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "coupled".into(),
        elements: Some(pb.mesh.len()),
        tips,
        cracks,
        notes: out
            .setup
            .notes
            .iter()
            .chain(&info.notes)
            .cloned()
            .chain(notes)
            .collect(),
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
            "ordering": format!("{:?}", out.setup.params.ordering),
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

/// `pd_nodes.vtu`: the real nodes of every window with displacement, damage and window
/// index, and `boundary.vtu`: the BEM body's elements (outline, holes, cracks and the
/// window interfaces) with displacement, traction and group (ParaView, `outputs.vtk`).
fn write_vtk(ctx: &RunContext, out: &CoupledOutcome) -> Result<()> {
    use crate::vtk::Field;
    let (mut x, mut u, mut d, mut w) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (wi, win) in out.setup.problem.windows.iter().enumerate() {
        let n = win.model.n_real();
        x.extend_from_slice(&win.model.positions()[..n]);
        u.extend_from_slice(&win.model.displacements()[..n]);
        d.extend_from_slice(&win.model.damage()[..n]);
        w.extend(std::iter::repeat_n(wi as f64, n));
    }
    let bytes = crate::vtk::point_cloud(
        &x,
        vec![
            ("displacement", Field::Vectors(u)),
            ("damage", Field::Scalars(d)),
            ("window", Field::Scalars(w)),
        ],
    )
    .map_err(anyhow::Error::msg)?;
    ctx.writer.write_bytes("pd_nodes.vtu", &bytes)?;
    let pb = &out.setup.problem;
    let body = crate::run_bem::boundary_vtu(&pb.mesh, &out.solution.solution)?;
    ctx.writer.write_bytes("boundary.vtu", &body)?;
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
        field.groups.push(0);
    }
    for w in &pb.windows {
        let (pos, du) = (w.model.positions(), w.model.displacements());
        for i in 0..w.model.n_real() {
            field.points.push((pos[i][0], pos[i][1]));
            field.values.push(du[i][0].hypot(du[i][1]));
            field.groups.push(1);
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
