//! Adaptive explicit dynamics of a scene (`pd.refinement` with `pd.solver: Explicit`,
//! issue 20 items 3-4; [`pdbem_pd::refine::run_dynamic`], seed 004 section 3 and Fig. 5):
//! the scene's grid becomes dual-horizon state-based particles, the static regions of
//! `pd.refinement` and the particles the pre-cracks damage past `critical_damage`
//! (Eq. 15) split before the first step, and every `check_every` steps the particles past
//! phi_c (Eq. 15) or, with `strain_factor` alpha, past the accumulated strain alpha s_c
//! (Eq. 16) split into four children carrying their parent's velocity (Eq. 30 masses).
//! Velocity Verlet from rest under the loads held from t = 0 (as [`crate::run_dynamic`],
//! no pins), every bond past its owner's critical stretch (Eq. 11) breaking in its step.
//!
//! Outputs: those of [`crate::run_dynamic`] (`dynamics.csv` with a last column
//! `particles`, the energy plots, the damage snapshots, the final particle table and
//! plots, the `dynamics` entry of `summary.json`), plus `refinements.csv` (one row per
//! split event), the plot `particles` (particle count against time) and the summary's
//! `particles` entry (start, most, final).

use std::time::Instant;

use anyhow::{Context, Result};
use pdbem_pd::dynamics::DynamicRecord;
use pdbem_pd::refine::{self, AdaptiveObserver, Body, Refinement, SplitEvent};
use serde_json::json;

use crate::dynamic_notes as notes;
use crate::output::csv::{num, CsvTable};
use crate::plot::{Series, SeriesStyle, XyPlot};
use crate::run_dynamic::{energy_plot, log_result, params, problem, snapshot_plot, table};
use crate::runner::context::RunContext;
use crate::runner::report::save_plot;
use crate::runner::summary::RunSummary;
use crate::scene::{PdRefinement, Scene};

/// The library settings of the scene's `pd.refinement` for adaptive dynamics.
pub fn settings(r: &PdRefinement, cracks: &[Vec<[f64; 2]>]) -> Refinement {
    Refinement {
        strain_factor: r.strain_factor,
        ..crate::run_refined::settings(r, cracks)
    }
}

/// Records (with the particle count at each), split events and damage snapshots.
#[derive(Default)]
struct Recorder {
    records: Vec<DynamicRecord>,
    particles: Vec<Option<usize>>,
    current: Option<usize>,
    splits: Vec<SplitEvent>,
    snapshots: Vec<(f64, Vec<[f64; 2]>, Vec<f64>)>,
}

impl AdaptiveObserver for Recorder {
    fn record(&mut self, r: &DynamicRecord) {
        self.records.push(*r);
        self.particles.push(self.current);
    }

    fn split(&mut self, e: &SplitEvent) {
        self.current = Some(e.particles);
        self.splits.push(*e);
    }

    fn snapshot(&mut self, time: f64, body: &Body) {
        self.current = Some(body.len());
        self.snapshots
            .push((time, body.positions().to_vec(), body.damage()));
    }
}

/// Runs the adaptive dynamics of `scene` and writes its outputs (module docs).
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<RunSummary> {
    let t0 = Instant::now();
    crate::run_dynamic::check(scene)?;
    let file = scene.file_label();
    let p = params(scene)?;
    let problem = problem(scene)?;
    let r = scene
        .pd
        .as_ref()
        .and_then(|pd| pd.refinement.as_ref())
        .context("no pd.refinement")?;
    ctx.log(&format!(
        "{}: explicit dynamics with adaptive refinement (check every {} steps)",
        scene.name, r.check_every
    ));
    let overload = crate::pd_loads::early_notes(scene, &problem, true, ctx);
    let mut rec = Recorder::default();
    let (body, info) = refine::run_dynamic(
        &problem,
        &p,
        &settings(r, &problem.cracks),
        r.check_every,
        &mut rec,
    )
    .map_err(|e| anyhow::anyhow!("{}: adaptive dynamics: {e}", file.display()))?;
    log_result(ctx, &info.dynamics);
    ctx.log(&format!(
        "  particles: {} at the start, {} at most, {} refinements ({:.2} s)",
        info.particles.0, info.particles.1, info.refinements, info.refine_s
    ));
    let particles: Vec<usize> = rec
        .particles
        .iter()
        .map(|n| n.unwrap_or(info.particles.0))
        .collect();
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "pd".into(),
        notes: overload,
        ..Default::default()
    };
    ctx.writer
        .write_csv("dynamics.csv", &table(&rec.records, Some(&particles)))?;
    ctx.writer
        .write_csv("refinements.csv", &split_table(&rec.splits))?;
    if scene.outputs.plots {
        for (name, balance) in [("energy", false), ("energy_balance", true)] {
            let fig = energy_plot(scene, &rec.records, balance);
            save_plot(
                &ctx.writer,
                name,
                &fig,
                &scene.outputs.formats,
                &mut summary,
            )?;
        }
        let fig = particle_plot(scene, &rec.records, &particles);
        save_plot(
            &ctx.writer,
            "particles",
            &fig,
            &scene.outputs.formats,
            &mut summary,
        )?;
        for (time, x, phi) in &rec.snapshots {
            snapshot_plot(scene, ctx, x, *time, phi, &mut summary)?;
        }
    }
    let phi = body.damage();
    crate::pd_fields::write_fields(scene, ctx, (body.positions(), &body.u, &phi), &mut summary)?;
    let last = rec.records.last().copied().unwrap_or_default();
    let e = &mut summary.extra;
    e.insert(
        "dynamics".into(),
        crate::run_dynamic::summary_entry(&info.dynamics, &last),
    );
    summary
        .notes
        .extend(notes::energy_balance_note(&rec.records));
    let x = body.positions();
    let held = notes::held_by_velocity(&p, x, problem.horizon());
    let loose = notes::loose_pieces(&body.pieces(p.load), x, &problem, |i| held[i]);
    let s0 = (0..body.len())
        .find(|&k| body.level[k] == 0)
        .and_then(|k| body.critical_stretch(k));
    summary.notes.extend(notes::loose_pieces_notes(
        &loose, &problem, s0, p.load, &last,
    ));
    let mut angles = crate::run_dynamic::deflections(&problem, x, &phi);
    if loose.torn_most() {
        angles.iter_mut().for_each(|a| *a = None);
    }
    crate::run_dynamic::log_deflections(ctx, &angles);
    e.insert("deflection_deg".into(), json!(angles));
    e.insert("refinement".into(), json!(true));
    e.insert(
        "particles".into(),
        json!({"start": info.particles.0, "max": info.particles.1, "final": body.len()}),
    );
    e.insert("nodes".into(), json!(body.len()));
    e.insert("bonds_at_start".into(), json!(info.bonds / 2));
    e.insert("refinements".into(), json!(info.refinements));
    e.insert("refinement_wall_time_s".into(), json!(info.refine_s));
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(summary)
}

/// `refinements.csv`: one row per split event.
fn split_table(splits: &[SplitEvent]) -> CsvTable {
    let mut t = CsvTable::new(&["step", "time", "split", "particles", "dt_c", "wall_s"]);
    for e in splits {
        t.push(vec![
            e.step.to_string(),
            num(e.time),
            e.split.to_string(),
            e.particles.to_string(),
            num(e.dt_c),
            num(e.wall_s),
        ]);
    }
    t
}

/// The particle count against time (us).
fn particle_plot(scene: &Scene, records: &[DynamicRecord], particles: &[usize]) -> XyPlot {
    let mut p = XyPlot::new(
        format!("{}: particles", scene.name),
        "time (us)",
        "particles",
    );
    let pts = records
        .iter()
        .zip(particles)
        .map(|(r, &n)| (r.time * 1e6, n as f64))
        .collect();
    p.series
        .push(Series::new("particles", pts, SeriesStyle::Line));
    p
}
