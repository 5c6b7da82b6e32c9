//! BEM solve of a scene (issue 2): mesh the scene ([`crate::bem_setup`]), assemble and
//! factor the Burton-Miller system once, solve, and post-process SIFs (crack-opening fit
//! and interaction integral), kink angles, CMOD, hoop stress on holes and interior points.
//!
//! `bem.richardson`: the scene is solved at h and h/2 and every SIF and CMOD is
//! extrapolated as $2 q_{h/2} - q_h$ (O(h) convergence of constant elements); the raw
//! values of both levels go to `summary.json` under `richardson`. The two levels share no
//! matrix (every entry depends on h), so the coarse level costs about 1/8 of the fine one.
//!
//! The primary `k1`, `k2` are the crack-opening fit; `k1_j`, `k2_j` the interaction integral.

use crate::bem_setup::{self, BemSetup};
use crate::output::csv::{num, CsvTable};
use crate::runner::{CrackResult, RunContext, RunSummary, TipResult};
use crate::scene::Scene;
use anyhow::{Context, Result};
use pdbem_bem::post::sif::{analyze_tips, cmod, SifOptions};
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::{BemSystem, Solution, V2};
use serde_json::json;
use std::time::Instant;

/// One solved mesh level.
pub struct Level {
    /// Mesh, conditions and material.
    pub setup: BemSetup,
    /// Boundary solution.
    pub solution: Solution,
    /// Tip results (names `<crack>.end` / `<crack>.start`).
    pub tips: Vec<TipResult>,
    /// Per crack: name and CMOD (None without a mouth).
    pub cracks: Vec<CrackResult>,
    /// Assembly, factorization and solve timings, condition estimate.
    pub info: pdbem_bem::SolveInfo,
    /// Wall time of the substitution (s).
    pub solve_s: f64,
}

/// Solves `scene` at load `factor` with element sizes divided by `refine`.
pub fn solve_level(scene: &Scene, factor: f64, refine: f64) -> Result<Level> {
    let setup = bem_setup::build(scene, factor, refine)?;
    let file = scene.file_label();
    let sys = BemSystem::new(&setup.mesh, &setup.material, &setup.bcs, &setup.params)
        .with_context(|| format!("{}: BEM assembly", file.display()))?;
    let t0 = Instant::now();
    let solution = sys
        .solve()
        .with_context(|| format!("{}: BEM solve", file.display()))?;
    let solve_s = t0.elapsed().as_secs_f64();
    let ev = FieldEvaluator::new(&setup.mesh, &setup.material, &solution, setup.background);
    let opts = SifOptions {
        fit_fraction: scene.bem.cod_fit_fraction,
        contour_fraction: scene.bem.j_contour.radius_fraction,
        contour_points: scene.bem.j_contour.points,
    };
    let raw = analyze_tips(&setup.mesh, &ev, &solution, &opts)
        .with_context(|| format!("{}: crack-tip post-processing", file.display()))?;
    let tips = raw
        .iter()
        .map(|t| {
            let name = format!(
                "{}.{}",
                setup.mesh.cracks[t.crack].name,
                if t.at_end { "end" } else { "start" }
            );
            TipResult {
                name,
                position: t.position,
                k1: t.k1_cod,
                k2: t.k2_cod,
                kink_deg: pdbem_bem::post::kink_angle(t.k1_cod, t.k2_cod).to_degrees(),
                k1_cod: Some(t.k1_cod),
                k2_cod: Some(t.k2_cod),
                k1_j: Some(t.k1_m),
                k2_j: Some(t.k2_m),
                ..Default::default()
            }
        })
        .collect();
    let cracks = setup
        .mesh
        .cracks
        .iter()
        .enumerate()
        .map(|(i, c)| CrackResult {
            name: c.name.clone(),
            cmod: cmod(&setup.mesh, &solution, i),
            ..Default::default()
        })
        .collect();
    Ok(Level {
        info: sys.info().clone(),
        setup,
        solution,
        tips,
        cracks,
        solve_s,
    })
}

/// The last load factor of the scene (BEM is linear: one solve at the final load).
pub fn final_factor(scene: &Scene) -> f64 {
    scene.load.factors().last().copied().unwrap_or(1.0)
}

/// Richardson extrapolation 2 fine - coarse of every tip and crack value.
fn extrapolate(coarse: &Level, fine: &Level) -> (Vec<TipResult>, Vec<CrackResult>) {
    let ex = |c: f64, f: f64| 2.0 * f - c;
    let exo = |c: Option<f64>, f: Option<f64>| Some(ex(c?, f?));
    let tips = fine
        .tips
        .iter()
        .zip(&coarse.tips)
        .map(|(f, c)| {
            let (k1, k2) = (ex(c.k1, f.k1), ex(c.k2, f.k2));
            TipResult {
                name: f.name.clone(),
                position: f.position,
                k1,
                k2,
                kink_deg: pdbem_bem::post::kink_angle(k1, k2).to_degrees(),
                k1_cod: Some(k1),
                k2_cod: Some(k2),
                k1_j: exo(c.k1_j, f.k1_j),
                k2_j: exo(c.k2_j, f.k2_j),
                ..Default::default()
            }
        })
        .collect();
    let cracks = fine
        .cracks
        .iter()
        .zip(&coarse.cracks)
        .map(|(f, c)| CrackResult {
            name: f.name.clone(),
            cmod: exo(c.cmod, f.cmod),
            ..Default::default()
        })
        .collect();
    (tips, cracks)
}

/// Solves the scene (with Richardson if asked) without writing anything.
pub fn solve(scene: &Scene) -> Result<(RunSummary, Level)> {
    let t0 = Instant::now();
    let factor = final_factor(scene);
    let coarse = solve_level(scene, factor, 1.0)?;
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "bem".into(),
        elements: Some(coarse.setup.mesh.len()),
        tips: coarse.tips.clone(),
        cracks: coarse.cracks.clone(),
        ..Default::default()
    };
    let level = if scene.bem.richardson {
        let fine = solve_level(scene, factor, 2.0)?;
        let (tips, cracks) = extrapolate(&coarse, &fine);
        summary.extra.insert(
            "richardson".into(),
            json!({
                "elements": [coarse.setup.mesh.len(), fine.setup.mesh.len()],
                "tips_h": coarse.tips, "tips_h2": fine.tips,
                "cracks_h": coarse.cracks, "cracks_h2": fine.cracks,
            }),
        );
        summary.elements = Some(fine.setup.mesh.len());
        summary.tips = tips;
        summary.cracks = cracks;
        fine
    } else {
        coarse
    };
    let info = &level.info;
    summary.extra.insert("load_factor".into(), json!(factor));
    summary
        .extra
        .insert("assembly_s".into(), json!(info.assembly_s));
    summary
        .extra
        .insert("factor_s".into(), json!(info.factor_s));
    summary.extra.insert("solve_s".into(), json!(level.solve_s));
    summary
        .extra
        .insert("unknowns".into(), json!(info.unknowns));
    summary
        .extra
        .insert("rigid_modes".into(), json!(info.rigid_modes));
    if info.condition.is_finite() {
        summary
            .extra
            .insert("condition_estimate".into(), json!(info.condition));
    }
    summary.plot_nodes = level
        .setup
        .mesh
        .elements
        .iter()
        .map(|e| (e.mid.x, e.mid.y))
        .collect();
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok((summary, level))
}

/// Solves `scene` with the BEM alone and writes the BEM-specific outputs (boundary values,
/// hoop stress along requested holes, interior points) through `ctx.writer`.
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<RunSummary> {
    ctx.log(&format!("{}: BEM solve", scene.name));
    let (mut summary, level) = solve(scene)?;
    let mesh = &level.setup.mesh;
    let ev = FieldEvaluator::new(
        mesh,
        &level.setup.material,
        &level.solution,
        level.setup.background,
    );
    ctx.writer
        .write_csv("boundary.csv", &boundary_table(&level))?;
    for name in &scene.outputs.boundary_stress {
        let Some(g) = mesh.group(name) else { continue };
        let Some(l) = mesh
            .loops
            .iter()
            .position(|r| r.clone().any(|i| mesh.elements[i].group == g))
        else {
            continue;
        };
        let hoop = ev.boundary_hoop_stress(l);
        let mut t = CsvTable::new(&["x", "y", "sigma_tt"]);
        let mut peak = f64::NEG_INFINITY;
        for (p, s) in &hoop {
            t.push(vec![num(p.x), num(p.y), num(*s)]);
            peak = peak.max(*s);
        }
        ctx.writer.write_csv(&format!("hoop_{name}.csv"), &t)?;
        summary
            .extra
            .insert(format!("hoop_peak_{name}"), json!(peak));
        if summary.extra.get("hoop_peak").is_none() {
            summary.extra.insert("hoop_peak".into(), json!(peak));
        }
    }
    if !scene.bem.interior_points.is_empty() {
        let pts: Vec<V2> = scene
            .bem
            .interior_points
            .iter()
            .map(|p| V2::new(p.0, p.1))
            .collect();
        let u = ev.displacements(&pts);
        let s = ev.stresses(&pts);
        let mut t = CsvTable::new(&["x", "y", "ux", "uy", "sxx", "syy", "sxy"]);
        for ((p, u), s) in pts.iter().zip(&u).zip(&s) {
            t.push(vec![
                num(p.x),
                num(p.y),
                num(u[0]),
                num(u[1]),
                num(s[0]),
                num(s[1]),
                num(s[2]),
            ]);
        }
        ctx.writer.write_csv("interior.csv", &t)?;
    }
    Ok(summary)
}

fn boundary_table(level: &Level) -> CsvTable {
    let mesh = &level.setup.mesh;
    let mut t = CsvTable::new(&[
        "element", "group", "x", "y", "nx", "ny", "length", "ux", "uy", "tx", "ty",
    ]);
    for (i, e) in mesh.elements.iter().enumerate() {
        let (u, tr) = (level.solution.u[i], level.solution.t[i]);
        t.push(vec![
            i.to_string(),
            mesh.groups[e.group].clone(),
            num(e.mid.x),
            num(e.mid.y),
            num(e.normal.x),
            num(e.normal.y),
            num(e.h),
            num(u[0]),
            num(u[1]),
            num(tr[0]),
            num(tr[1]),
        ]);
    }
    t
}
