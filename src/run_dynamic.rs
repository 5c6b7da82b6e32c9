//! Stand-alone PD explicit dynamics of a scene (`pd.solver: Explicit`, issue 20 item 4;
//! [`pdbem_pd::dynamics`], seed 004 section 2.3): the body from rest under the scene's
//! loads held from t = 0 (a step load; the final load factor of `load`), velocity Verlet
//! with bond breaking every step, until `end_time`.
//!
//! No pins: a pure-traction body flies free under its self-equilibrated loads (the
//! quasi-static solvers' two pins would be constraints the seed does not have).
//!
//! Outputs: `dynamics.csv` (per record: time, energies, broken bonds, crack tip,
//! branched), the energy-time plots `energy` (strain and fracture) and `energy_balance`
//! (with the work of the loads and the kinetic energy), a damage plot `damage_t<time>us` per
//! requested snapshot, the final node table and damage / displacement plots
//! ([`crate::pd_fields`]) and the `dynamics` entry of `summary.json`.
//!
//! [`check`] (run by `pdbem check` and before every run) refuses a `dt` above the stable
//! step of a patch of the scene's grid and material, and a run whose steps times bonds
//! exceed the work bound, before anything is built at full size; [`check_grid`] (`pdbem
//! check`, on the grid the run builds) refuses what the run's own plan would.

use anyhow::{bail, Context, Result};
use pdbem_pd::dynamics::{
    self, critical_time_step, DynamicRecord, DynamicsObserver, ExplicitParams, RegionVelocity,
};
use pdbem_pd::{PdModel, PdProblem, Region, Selection};
use serde_json::json;

use crate::dynamic_notes as notes;
use crate::output::csv::{num, CsvTable};
use crate::plot::{ScatterField, Series, SeriesStyle, XyPlot};
use crate::runner::context::RunContext;
use crate::runner::report::save_plot;
use crate::runner::summary::RunSummary;
use crate::scene::shapes::SceneGeometry;
use crate::scene::{PdSolver, Scene};
use crate::setup::pd::labelled_problem_from_scene;

/// The explicit parameters of `scene`, `None` when it does not ask for dynamics.
pub(crate) fn explicit(scene: &Scene) -> Option<&crate::scene::ExplicitParams> {
    match &scene.pd.as_ref()?.solver {
        PdSolver::Explicit(p) => Some(p),
        _ => None,
    }
}

/// Whether `scene` runs explicit dynamics.
pub fn is_dynamic(scene: &Scene) -> bool {
    explicit(scene).is_some() && scene.coupling.is_none()
}

/// The library parameters of a validated explicit scene.
pub(crate) fn params(scene: &Scene) -> Result<ExplicitParams> {
    let p = explicit(scene).context("pd.solver is not Explicit")?;
    let density = scene
        .material
        .density
        .context("material.density: Explicit dynamics needs the mass density")?;
    Ok(ExplicitParams {
        density,
        end_time: p.end_time,
        dt: p.dt,
        safety_factor: p.safety_factor,
        output_every: p.output_every,
        snapshots: p.snapshots.clone(),
        load: scene.load.factors().last().copied().unwrap_or(1.0),
        velocities: p
            .velocities
            .iter()
            .map(|r| RegionVelocity {
                region: Selection::Box {
                    min: [r.min.0, r.min.1],
                    max: [r.max.0, r.max.1],
                },
                velocity: [r.velocity.0, r.velocity.1],
                hold: r.hold,
            })
            .collect(),
        ..Default::default()
    })
}

/// The scene's PD problem without the pins of a pure-traction scene.
pub(crate) fn problem(scene: &Scene) -> Result<PdProblem> {
    let (mut problem, labels) = labelled_problem_from_scene(scene)?;
    let keep: Vec<bool> = labels.iter().map(|l| l != "pin").collect();
    let mut k = keep.iter();
    problem.boundary.retain(|_| *k.next().unwrap_or(&true));
    Ok(problem)
}

/// The stable step bound (s) of `patch`'s refined particles for the smallest particles
/// `r.max_level` can make: the Gershgorin bound of the unrefined particles
/// ([`pdbem_pd::refine::dynamics::critical_time_step`]) halved per level (the bound scales with
/// the spacing at a fixed horizon factor), as the run's own bound.
pub fn patch_time_step(
    patch: &PdProblem,
    r: &crate::scene::PdRefinement,
    density: f64,
) -> Result<f64> {
    let body = pdbem_pd::refine::Body::from_problem(patch)?;
    Ok(
        pdbem_pd::refine::dynamics::critical_time_step(&body, density)
            / f64::from(1u32 << r.max_level),
    )
}

/// Refuses `pd.solver.dt` above the stable step of a patch of the scene's grid (a square
/// of 8 horizons with the scene's spacing, material and corrections, its edges and
/// corners included; with `pd.refinement` the refined particles' bound for the smallest
/// particles `max_level` can make, [`patch_time_step`]) and a run of more than [`dynamics::MAX_BOND_STEPS`] bond updates
/// (steps times the estimated directed bonds). Does nothing for other scenes.
pub fn check(scene: &Scene) -> Result<()> {
    if !is_dynamic(scene) {
        return Ok(());
    }
    let file = scene.file_label();
    let p = params(scene)?;
    let full = problem(scene)?;
    let side = 8.0 * full.horizon();
    let cells = (side / full.dx).ceil();
    let patch = PdProblem {
        region: Region::rectangle([0.0, 0.0], [cells * full.dx, cells * full.dx]),
        cracks: Vec::new(),
        boundary: Vec::new(),
        grid_origin: None,
        ..full.clone()
    };
    let model = PdModel::new(&patch).with_context(|| format!("{}: pd", file.display()))?;
    let dt_c = match scene.pd.as_ref().and_then(|pd| pd.refinement.as_ref()) {
        Some(r) => patch_time_step(&patch, r, p.density)
            .with_context(|| format!("{}: pd.refinement", file.display()))?,
        None => critical_time_step(&model, p.density),
    };
    if let Some(dt) = p.dt {
        if dt > dt_c {
            bail!(
                "{}: pd.solver.dt = {dt:.4e} s exceeds the stable time step dt_c = {dt_c:.4e} s of this grid and material (sqrt(4 rho / max stiffness row sum), docs/scene.md `ExplicitParams`): take dt <= dt_c, or leave dt out for {} dt_c",
                file.display(),
                p.safety_factor
            );
        }
    }
    let dt = p.dt.unwrap_or(p.safety_factor * dt_c);
    let steps = (p.end_time / dt).ceil();
    let o = &full.region.outline;
    let area = 0.5
        * o.iter()
            .zip(o.iter().cycle().skip(1))
            .map(|(a, b)| a[0] * b[1] - b[0] * a[1])
            .sum::<f64>()
            .abs();
    let bonds_per_node = model.n_bonds() as f64 / model.n_nodes() as f64;
    // With `pd.refinement`, the children of its static regions too (split before the
    // first step).
    let refined = scene
        .pd
        .as_ref()
        .and_then(|pd| pd.refinement.as_ref())
        .map_or(0.0, |r| {
            let geo = crate::scene::shapes::SceneGeometry::of(scene);
            crate::setup::refined_size::refined_children(r, &geo, full.dx, full.horizon_factor).1
        });
    let bonds = area / (full.dx * full.dx) * bonds_per_node + refined;
    let work = steps * bonds;
    if steps > dynamics::MAX_STEPS as f64 || work > dynamics::MAX_BOND_STEPS {
        let refinement = if refined > 0.0 {
            ", lower pd.refinement.max_level or shrink its regions"
        } else {
            ""
        };
        bail!(
            "{}: pd.solver.end_time = {} s takes {steps:.3e} steps of dt = {dt:.3e} s over about {bonds:.3e} directed bonds ({work:.3e} bond updates; limits {} steps, {:.0e} updates): shorten end_time, raise dt{refinement} or coarsen pd.dx",
            file.display(),
            p.end_time,
            dynamics::MAX_STEPS,
            dynamics::MAX_BOND_STEPS
        );
    }
    check_refinement_checks(scene, steps)
}

/// Refuses what the run on the uniform grid `model` (built from [`problem`]) would refuse
/// before its first step: the library's own [`dynamics::plan`] (the stable step of this
/// grid, which a crack or a corner can put below the patch's of [`check`]; a step past
/// `end_time`; a velocity box that holds no node), run by `pdbem check`.
pub fn check_grid(scene: &Scene, model: &PdModel) -> Result<()> {
    dynamics::plan(model, &params(scene)?)
        .map(|_| ())
        .map_err(|e| anyhow::anyhow!("{}: pd.solver: {e}", scene.file_label().display()))
}

/// Adaptive dynamics checks its criteria every `check_every` steps: a run of fewer steps
/// would never check them, so the refinement it asks for could not happen.
fn check_refinement_checks(scene: &Scene, steps: f64) -> Result<()> {
    let Some(r) = scene.pd.as_ref().and_then(|pd| pd.refinement.as_ref()) else {
        return Ok(());
    };
    let criteria = r.critical_damage.is_some() || r.strain_factor.is_some();
    if criteria && r.check_every as f64 > steps {
        bail!(
            "{}: pd.refinement.check_every = {} exceeds the run's {steps:.0} time steps: the criteria would never be checked; take a smaller check_every (the seed's 10)",
            scene.file_label().display(),
            r.check_every
        );
    }
    Ok(())
}

/// Records and damage snapshots of a run.
#[derive(Default)]
struct Recorder {
    records: Vec<DynamicRecord>,
    snapshots: Vec<(f64, Vec<f64>)>,
}

impl DynamicsObserver for Recorder {
    fn record(&mut self, r: &DynamicRecord) {
        self.records.push(*r);
    }

    fn snapshot(&mut self, time: f64, model: &PdModel) {
        let n = model.n_real();
        self.snapshots.push((time, model.damage()[..n].to_vec()));
    }
}

/// Runs the explicit dynamics of `scene` and writes its outputs (module docs).
pub fn run(scene: &Scene, ctx: &RunContext) -> Result<RunSummary> {
    let t0 = std::time::Instant::now();
    check(scene)?;
    let file = scene.file_label();
    let p = params(scene)?;
    let problem = problem(scene)?;
    let mut model = PdModel::new(&problem).with_context(|| format!("{}: pd", file.display()))?;
    ctx.log(&format!(
        "{}: explicit dynamics, {} real nodes, {} bonds",
        scene.name,
        model.n_real(),
        model.n_bonds() / 2
    ));
    let overload = crate::pd_loads::early_notes(scene, &problem, true, ctx);
    let mut rec = Recorder::default();
    let info = dynamics::run(&mut model, &p, &problem.cracks, &mut rec)
        .map_err(|e| anyhow::anyhow!("{}: pd.solver: {e}", file.display()))?;
    log_result(ctx, &info);
    let mut summary = RunSummary {
        scene: scene.name.clone(),
        mode: "pd".into(),
        notes: overload,
        ..Default::default()
    };
    ctx.writer
        .write_csv("dynamics.csv", &table(&rec.records, None))?;
    if scene.outputs.plots {
        for (name, balance) in [("energy", false), ("energy_balance", true)] {
            save_plot(
                &ctx.writer,
                name,
                &energy_plot(scene, &rec.records, balance),
                &scene.outputs.formats,
                &mut summary,
            )?;
        }
        let x = &model.positions()[..model.n_real()];
        for (time, phi) in &rec.snapshots {
            snapshot_plot(scene, ctx, x, *time, phi, &mut summary)?;
        }
    }
    let n = model.n_real();
    let (x, u, phi) = (model.positions(), model.displacements(), model.damage());
    crate::pd_fields::write_fields(scene, ctx, (&x[..n], &u[..n], &phi[..n]), &mut summary)?;
    let last = rec.records.last().copied().unwrap_or_default();
    summary
        .extra
        .insert("dynamics".into(), summary_entry(&info, &last));
    summary
        .notes
        .extend(notes::loaded_edge_damage_note(&problem, &x[..n], &phi[..n]));
    summary
        .notes
        .extend(notes::energy_balance_note(&rec.records));
    let held = notes::held_by_velocity(&p, x, problem.horizon());
    let loose = notes::loose_pieces(&model.pieces(), x, &problem, |i| held[i]);
    let s0 = Some(model.law().damage_onset()).filter(|s| s.is_finite());
    summary.notes.extend(notes::loose_pieces_notes(
        &loose, &problem, s0, p.load, &last,
    ));
    let mut angles = deflections(&problem, &x[..n], &phi[..n]);
    if loose.torn_most() {
        angles.iter_mut().for_each(|a| *a = None);
    }
    log_deflections(ctx, &angles);
    summary.extra.insert("deflection_deg".into(), json!(angles));
    summary.extra.insert("nodes".into(), json!(model.n_real()));
    summary
        .extra
        .insert("bonds".into(), json!(model.n_bonds() / 2));
    summary
        .extra
        .insert("broken_bonds".into(), json!(model.broken_bonds()));
    summary.wall_time_s = t0.elapsed().as_secs_f64();
    Ok(summary)
}

/// The console lines of a finished run: when the crack branched and reached the boundary.
pub(crate) fn log_result(ctx: &RunContext, info: &dynamics::DynamicsInfo) {
    let us = |t: Option<f64>| {
        t.map_or("not within the run".to_string(), |t| {
            format!("{:.1} us", t * 1e6)
        })
    };
    ctx.log(&format!(
        "  {} steps of {:.3e} s (stable step {:.3e} s)",
        info.steps, info.dt, info.dt_c
    ));
    ctx.log(&format!("  crack branched: {}", us(info.branch_time)));
    ctx.log(&format!(
        "  crack tip at the boundary: {}",
        us(info.boundary_time)
    ));
}

/// The console line of the deflection angles.
pub(crate) fn log_deflections(ctx: &RunContext, angles: &[Option<f64>]) {
    let a: Vec<String> = angles
        .iter()
        .map(|a| a.map_or("-".into(), |a| format!("{a:.1}")))
        .collect();
    ctx.log(&format!(
        "  crack deflection from each pre-crack tip (deg): {}",
        a.join(", ")
    ));
}

/// `dynamics.csv`: one row per record; with `particles` (an adaptive run: the particle
/// count at each record) a last column `particles`.
pub(crate) fn table(records: &[DynamicRecord], particles: Option<&[usize]>) -> CsvTable {
    let mut head = vec![
        "step",
        "time",
        "kinetic",
        "strain",
        "external_work",
        "fracture",
        "broken_bonds",
        "tip_x",
        "tip_y",
        "branched",
    ];
    if particles.is_some() {
        head.push("particles");
    }
    let mut t = CsvTable::new(&head);
    let opt = |v: Option<f64>| v.map_or(String::new(), num);
    for (k, r) in records.iter().enumerate() {
        let mut row = vec![
            r.step.to_string(),
            num(r.time),
            num(r.kinetic),
            num(r.strain),
            num(r.external_work),
            num(r.fracture),
            r.broken_bonds.to_string(),
            opt(r.tip.map(|p| p[0])),
            opt(r.tip.map(|p| p[1])),
            u8::from(r.branched).to_string(),
        ];
        if let Some(n) = particles {
            row.push(n.get(k).map_or(String::new(), |n| n.to_string()));
        }
        t.push(row);
    }
    t
}

/// The deflection angle (degrees, [`dynamics::angle::deflection_angle`]) of the crack
/// grown from the last point of each pre-crack of `problem`, from the damage `phi` at
/// the reference positions `x`: damage above 0.4, from 2 horizons of the base grid to a
/// fifth of the body's bounding-box diagonal from the tip; `None` where nothing grew.
pub(crate) fn deflections(problem: &PdProblem, x: &[[f64; 2]], phi: &[f64]) -> Vec<Option<f64>> {
    let o = &problem.region.outline;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in o {
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    let r_max = 0.2 * (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let r_min = 2.0 * problem.horizon();
    problem
        .cracks
        .iter()
        .filter(|c| c.len() >= 2)
        .map(|c| {
            let (a, b) = (c[c.len() - 2], c[c.len() - 1]);
            let dir = [b[0] - a[0], b[1] - a[1]];
            dynamics::angle::deflection_angle(x, phi, b, dir, 0.4, (r_min, r_max))
        })
        .collect()
}

/// The `dynamics` entry of `summary.json` from the run's info and its last record.
pub(crate) fn summary_entry(
    info: &dynamics::DynamicsInfo,
    last: &DynamicRecord,
) -> serde_json::Value {
    json!({
        "steps": info.steps, "dt_s": info.dt, "dt_c_s": info.dt_c,
        "end_time_s": info.end_time, "branch_time_s": info.branch_time,
        "branch_point": info.branch_point, "boundary_time_s": info.boundary_time,
        "records": info.records, "stepping_wall_time_s": info.wall_time_s,
        "final": {"kinetic_J": last.kinetic, "strain_J": last.strain,
                  "external_work_J": last.external_work, "fracture_J": last.fracture,
                  "tip": last.tip},
    })
}

/// Energies against time (us): `balance` false gives the strain and fracture energy (seed
/// 004 Figs. 10 and 13, on a scale where they can be read), true the whole balance (the
/// work of the loads, kinetic, strain and fracture energy).
pub(crate) fn energy_plot(scene: &Scene, records: &[DynamicRecord], balance: bool) -> XyPlot {
    let title = if balance {
        format!("{}: energy balance", scene.name)
    } else {
        format!("{}: strain and fracture energy", scene.name)
    };
    let mut p = XyPlot::new(title, "time (us)", "energy (J)");
    let series = |f: fn(&DynamicRecord) -> f64| -> Vec<(f64, f64)> {
        records.iter().map(|r| (r.time * 1e6, f(r))).collect()
    };
    let mut add = |label: &str, f: fn(&DynamicRecord) -> f64| {
        p.series
            .push(Series::new(label, series(f), SeriesStyle::Line));
    };
    if balance {
        add("work of the loads", |r| r.external_work);
        add("kinetic energy", |r| r.kinetic);
    }
    add("strain energy", |r| r.strain);
    add("fracture energy", |r| r.fracture);
    p
}

/// The damage plot `damage_t<time>us` of one snapshot: damage `phi` at the reference
/// positions `x`.
pub(crate) fn snapshot_plot(
    scene: &Scene,
    ctx: &RunContext,
    x: &[[f64; 2]],
    time: f64,
    phi: &[f64],
    summary: &mut RunSummary,
) -> Result<()> {
    let geo = SceneGeometry::of(scene);
    let loops = geo
        .outline
        .as_ref()
        .map(|o| {
            let mut l: Vec<(f64, f64)> = o.points.iter().map(|p| (p.x, p.y)).collect();
            l.push(l[0]);
            vec![l]
        })
        .unwrap_or_default();
    let us = time * 1e6;
    let fig = ScatterField {
        title: format!("{}: damage at t = {us:.3} us", scene.name),
        unit: "m".into(),
        value_label: "damage phi (-)".into(),
        points: x.iter().map(|p| (p[0], p[1])).collect(),
        values: phi.to_vec(),
        range: Some((0.0, 1.0)),
        loops,
        marker_px: 0,
        ..Default::default()
    };
    let stem = format!(
        "damage_t{}us",
        format!("{us:.3}")
            .trim_end_matches('0')
            .trim_end_matches('.')
    );
    save_plot(&ctx.writer, &stem, &fig, &scene.outputs.formats, summary)
}
