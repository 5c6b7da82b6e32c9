//! What a run of a scene will build: BEM elements, unknowns and dense-matrix bytes, PD
//! nodes and bonds. Computed from the very models `run` builds ([`super::bem::build`],
//! [`super::pd`], [`super::coupled::prepare`], [`super::growth::input`]), before any
//! system is assembled or solved, so `pdbem check` prints what `pdbem run` will use.
//!
//! Growth runs are counted at their initial geometry: BEM-only and PD-BEM growth add
//! crack elements as the cracks grow.

use anyhow::{Context, Result};
use pdbem_bem::system::{footprint as bem_footprint, BemFootprint};
use pdbem_coupling::growth::Scenario;
use pdbem_pd::refine::{set_up, set_up_static, Body};
use pdbem_pd::{PdModel, PdProblem};

use crate::runner::mode::{mode_of, Mode};
use crate::scene::pd::PdSolver;
use crate::scene::{GrowthMode, Scene};

/// The sizes of a run.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Footprint {
    /// BEM system of the largest level solved (the fine level of a Richardson pair),
    /// if the run has a BEM body.
    pub bem: Option<BemFootprint>,
    /// BEM elements of every level, coarse first (one entry without Richardson).
    pub bem_levels: Vec<usize>,
    /// PD nodes, real and virtual, over the whole body or all windows.
    pub pd_nodes: usize,
    /// Real PD nodes (what `summary.json` calls `nodes` / `pd_nodes`).
    pub pd_real: usize,
    /// PD bonds, directed (each pair twice), as `summary.json` counts them.
    pub pd_bonds: usize,
    /// Entries of the tangent's sparse Cholesky factor of a stand-alone implicit or
    /// switching run (its symbolic analysis, within the memory budget).
    pub pd_factor: Option<usize>,
    /// What the run will note about the model before solving it (windowed tips that no
    /// interaction-integral contour fits around).
    pub notes: Vec<String>,
}

impl Footprint {
    /// One line per model, for `pdbem check`.
    pub fn describe(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let Some(b) = &self.bem {
            let levels = if self.bem_levels.len() > 1 {
                format!(
                    " (Richardson levels: {} elements)",
                    self.bem_levels
                        .iter()
                        .map(|n| n.to_string())
                        .collect::<Vec<_>>()
                        .join(" and ")
                )
            } else {
                String::new()
            };
            out.push(format!(
                "  BEM: {} elements, {} unknowns, dense matrix {}{levels}",
                b.elements,
                b.unknowns,
                bytes_text(b.matrix_bytes)
            ));
        }
        if self.pd_nodes > 0 {
            out.push(format!(
                "  PD: {} nodes ({} real), {} directed bonds",
                self.pd_nodes, self.pd_real, self.pd_bonds
            ));
        }
        if let Some(n) = self.pd_factor {
            out.push(format!(
                "  PD tangent: sparse Cholesky factor of {n} entries ({})",
                bytes_text(8 * n)
            ));
        }
        out.extend(self.notes.iter().map(|n| format!("  note: {n}")));
        out
    }
}

/// The note on the refined body a `pd.refinement` scene starts from: its static regions
/// and, for the static solve and ramp, Eq. 15 on the pre-cracks split as the run will split
/// them ([`pdbem_pd::refine::set_up`]; explicit dynamics splits the static regions only,
/// [`pdbem_pd::refine::set_up_static`]), each split within the memory budget.
fn refined_start(
    scene: &Scene,
    r: &crate::scene::PdRefinement,
    problem: &PdProblem,
) -> Result<String> {
    let dynamic = crate::run_dynamic::is_dynamic(scene);
    let settings = if dynamic {
        crate::run_adaptive::settings(r, &problem.cracks)
    } else {
        crate::run_refined::settings(r, &problem.cracks)
    };
    let mut body = Body::from_problem(problem).with_context(|| pd_ctx(scene))?;
    body.keep_horizon = settings.keep_horizon;
    let split = if dynamic {
        set_up_static(&mut body, &settings)
    } else {
        set_up(&mut body, &settings)
    }
    .with_context(|| pd_ctx(scene))?;
    if dynamic {
        // What the run refuses before its first step (`crate::run_adaptive::run`).
        let p = crate::run_dynamic::params(scene)?;
        pdbem_pd::refine::dynamics::check_plan(&body, &p, &settings).map_err(|e| {
            anyhow::anyhow!("{}: adaptive dynamics: {e}", scene.file_label().display())
        })?;
    }
    Ok(format!(
        "pd.refinement: the set-up splits {split} particles: {} particles and {} directed bonds at the start (the criteria split more as they fire)",
        body.len(),
        body.dh.bonds.len()
    ))
}

/// Bytes as KiB / MiB / GiB with three significant digits.
pub fn bytes_text(b: usize) -> String {
    let b = b as f64;
    let (v, unit) = if b >= 1024f64.powi(3) {
        (b / 1024f64.powi(3), "GiB")
    } else if b >= 1024f64.powi(2) {
        (b / 1024f64.powi(2), "MiB")
    } else {
        (b / 1024.0, "KiB")
    };
    format!("{v:.3} {unit}")
}

/// The footprint of a validated scene, from the models its mode builds.
pub fn of(scene: &Scene) -> Result<Footprint> {
    let file = scene.file_label();
    let mut f = Footprint::default();
    match mode_of(scene) {
        Mode::Bem => bem_levels(scene, &mut f)?,
        Mode::Pd => {
            let dynamic = crate::run_dynamic::is_dynamic(scene);
            let problem = if dynamic {
                crate::run_dynamic::problem(scene)?
            } else {
                super::pd::problem_from_scene(scene)?
            };
            let cells = scene.pd.as_ref().and_then(|pd| {
                pd.refinement
                    .as_ref()
                    .filter(|r| r.on_cells(&pd.failure, &pd.solver))
            });
            let model = match cells {
                Some(r) => {
                    let crit = crate::run_pd::cell_criteria(r);
                    let (model, split) = pdbem_pd::adapt::ramp::set_up(&problem, &crit)
                        .with_context(|| pd_ctx(scene))?;
                    f.notes.push(format!(
                        "pd.refinement: the set-up splits {} cells of the grid: {} real nodes at the start (the criteria split more as they fire, up to max_level {})",
                        split.levels().len(),
                        model.n_real(),
                        crit.max_level
                    ));
                    model
                }
                None => PdModel::new(&problem).with_context(|| pd_ctx(scene))?,
            };
            add_pd(&mut f, &model);
            if !dynamic {
                super::ligament::refuse_loaded_loose_nodes(scene, &model)?;
            } else if scene.pd.as_ref().is_some_and(|pd| pd.refinement.is_none()) {
                crate::run_dynamic::check_grid(scene, &model)?;
            }
            f.notes
                .extend(crate::pd_loads::set_up_notes(scene, &problem, dynamic));
            f.pd_factor = tangent_factor(scene, &model)?;
            if let Some(r) = scene.pd.as_ref().and_then(|pd| pd.refinement.as_ref()) {
                if cells.is_none() {
                    f.notes.push(refined_start(scene, r, &problem)?);
                }
            }
        }
        Mode::Coupled => {
            let setup = super::coupled::prepare(scene)?;
            let p = &setup.problem;
            f.bem = Some(bem_footprint(&p.mesh, &p.bcs, &p.bem_params));
            f.bem_levels = vec![p.mesh.len()];
            for w in &p.windows {
                add_pd(&mut f, &w.model);
            }
            f.notes = setup.notes.clone();
            f.notes
                .extend(super::coupled::tips_without_contour(scene, &setup));
        }
        Mode::Growth => match scene.growth.as_ref().map(|g| g.mode).unwrap_or_default() {
            GrowthMode::BemOnly => {
                let s = super::bem::build(scene, 1.0, 1.0)?;
                f.bem = Some(bem_footprint(&s.mesh, &s.bcs, &s.params));
                f.bem_levels = vec![s.mesh.len()];
            }
            GrowthMode::FullPd => {
                let problem = super::pd::full_pd_problem(scene)?;
                let model = PdModel::new(&problem).with_context(|| pd_ctx(scene))?;
                super::ligament::refuse_loaded_loose_nodes(scene, &model)?;
                add_pd(&mut f, &model);
            }
            GrowthMode::PdBem => {
                let input = super::growth::input(scene)?;
                f.notes = super::coupled::coupling_notes(scene, &input.setup.layout);
                let growth = input.growth().with_context(|| {
                    format!("{}: PD-BEM growth setup", scene.file_label().display())
                })?;
                let p = growth.problem();
                let bcs = input
                    .scenario
                    .bem_conditions(&p.mesh)
                    .map_err(|e| anyhow::anyhow!("{}: BEM conditions: {e}", file.display()))?;
                f.bem = Some(bem_footprint(&p.mesh, &bcs, &p.bem_params));
                f.bem_levels = vec![p.mesh.len()];
                for w in &p.windows {
                    add_pd(&mut f, &w.model);
                }
                f.notes.extend(super::growth::mesh_growth_note(
                    scene,
                    p.mesh.len(),
                    growth.tips().len(),
                )?);
            }
        },
    }
    Ok(f)
}

/// The factor entries of the tangent a stand-alone implicit or switching run factors
/// (`None` for other runs); its pattern and factor over the memory budget are an error
/// naming `pd.solver`, as the run would fail with.
fn tangent_factor(scene: &Scene, model: &PdModel) -> Result<Option<usize>> {
    let Some(pd) = &scene.pd else {
        return Ok(None);
    };
    let particles = pd
        .refinement
        .as_ref()
        .is_some_and(|r| !r.on_cells(&pd.failure, &pd.solver));
    // The crack-initiation ramp factors Newton tangents under every solver.
    let factors = matches!(pd.solver, PdSolver::Implicit(_) | PdSolver::Switching(_))
        || scene.runs_pd_initiation_ramp();
    if particles || !factors {
        return Ok(None);
    }
    let budget = pdbem_pd::tangent::factor_budget();
    model
        .new_tangent()
        .and_then(|t| t.factor_entries_within(budget))
        .map(Some)
        .map_err(|e| {
            anyhow::anyhow!(
                "{}: pd.solver: {e}; use pd.solver: Adr (no factor), a larger pd.dx, or raise --max-memory",
                scene.file_label().display()
            )
        })
}

fn pd_ctx(scene: &Scene) -> String {
    format!("{}: pd", scene.file_label().display())
}

fn add_pd(f: &mut Footprint, m: &PdModel) {
    f.pd_nodes += m.n_nodes();
    f.pd_real += m.n_real();
    f.pd_bonds += m.n_bonds();
}

/// The BEM levels of a static BEM run (two with `bem.richardson`).
fn bem_levels(scene: &Scene, f: &mut Footprint) -> Result<()> {
    let factor = super::final_factor(scene);
    let refines: &[f64] = if scene.bem.richardson {
        &[1.0, 2.0]
    } else {
        &[1.0]
    };
    for &r in refines {
        let s = super::bem::build(scene, factor, r)?;
        f.bem_levels.push(s.mesh.len());
        f.bem = Some(bem_footprint(&s.mesh, &s.bcs, &s.params));
    }
    Ok(())
}
