//! One solved level of a static BEM run: mesh and conditions from [`crate::setup::bem`],
//! the Burton-Miller system assembled and factored once, the solution, and the tip and
//! crack results (crack-opening fit and interaction integral, CMOD).

use crate::runner::summary::{CrackResult, TipResult};
use crate::scene::Scene;
use crate::setup::bem::{self as bem_setup, BemSetup};
use anyhow::{Context, Result};
use pdbem_bem::post::sif::{analyze_tips, cmod, SifOptions};
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::{BemSystem, PairCache, Solution};
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
    solve_level_with(scene, factor, refine, None)
}

/// The same, reusing the element-pair blocks of an earlier mesh held in `pairs` and
/// leaving this mesh's there ([`PairCache`]: a sequence of related meshes, such as the
/// geometries of BEM-only growth).
pub fn solve_level_with(
    scene: &Scene,
    factor: f64,
    refine: f64,
    pairs: Option<&mut PairCache>,
) -> Result<Level> {
    let setup = bem_setup::build(scene, factor, refine)?;
    let file = scene.file_label();
    let sys = BemSystem::new_with_cache(
        &setup.mesh,
        &setup.material,
        &setup.bcs,
        &setup.params,
        pairs,
    )
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
        .map(|t| tip_result(&setup.mesh, t, one_face_loaded(scene, t.crack, &setup.mesh)))
        .collect();
    let cracks = crack_results(&setup.mesh, &solution);
    Ok(Level {
        info: sys.info().clone(),
        setup,
        solution,
        tips,
        cracks,
        solve_s,
    })
}

/// `TipResult::k_source` of a K from the interaction integral.
pub const INTEGRAL_SOURCE: &str = "interaction_integral";

/// Whether crack `crack` of `mesh` has a condition on one of its faces alone
/// ([`bem_setup::loaded_on_one_face`]).
pub fn one_face_loaded(scene: &Scene, crack: usize, mesh: &pdbem_bem::Mesh) -> bool {
    bem_setup::loaded_on_one_face(scene, &mesh.cracks[crack].name)
}

/// The runner's tip record of a BEM tip analysis (name `<crack>.end` / `<crack>.start`;
/// primary K from the crack-opening fit, or from the interaction integral with a note
/// when the fit had no station or the crack is loaded on one face, `one_face`). A
/// reported level holds enough stations at every tip ([`crate::setup::fit_stations`]);
/// the fallback serves the coarse level of an error estimate, whose K only enters
/// |K(h) - K(2h)|.
///
/// A condition on one face alone adds a term linear in r to the tangential opening,
/// which the fit's $\sqrt{r}$, $r^{3/2}$ terms do not hold: on a Griffith crack with one
/// face pressed the fit's K_II was 19 % low at every refinement (0.160 against the
/// integral's 0.197 and the exact $\frac{\kappa-1}{\kappa+1} p \sqrt{a/\pi}$ = 0.1975),
/// so there the interaction integral (path independent with the face terms,
/// `pdbem_bem::post::face_traction`) is the primary K and the fit is kept as
/// `k1_cod`, `k2_cod`.
pub fn tip_result(
    mesh: &pdbem_bem::Mesh,
    t: &pdbem_bem::post::TipResult,
    one_face: bool,
) -> TipResult {
    let end = if t.at_end { "end" } else { "start" };
    let name = format!("{}.{end}", mesh.cracks[t.crack].name);
    if t.cod_points == 0 || !(t.k1_cod.is_finite() && t.k2_cod.is_finite()) {
        return interaction_fallback(name, t);
    }
    if one_face {
        return one_face_result(name, t);
    }
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
        j: Some(t.j),
        ..Default::default()
    }
}

/// The tip record of a crack loaded on one face: K from the interaction integral, the
/// crack-opening fit kept as `k1_cod`, `k2_cod`, and a note that says so.
fn one_face_result(name: String, t: &pdbem_bem::post::TipResult) -> TipResult {
    let note = format!(
        "tip {name}: k1, k2 are the interaction-integral values (contour radius {:.3e} m): a \
         condition on one face of the crack adds a term linear in r to the opening, which the \
         crack-opening fit does not hold (its K_II 19 % low on a Griffith crack with one face \
         pressed, at any refinement); the fit's values are k1_cod, k2_cod",
        t.contour_radius
    );
    TipResult {
        k1_cod: Some(t.k1_cod),
        k2_cod: Some(t.k2_cod),
        ..integral_result(name, t, note)
    }
}

/// The tip record when the crack-opening fit has no station (the tip's length scale, the
/// crack or the ligament ahead, is so short that `bem.cod_fit_fraction` of it holds no
/// crack-face collocation point): K from the interaction integral, no `k1_cod`, and a
/// note that says so.
fn interaction_fallback(name: String, t: &pdbem_bem::post::TipResult) -> TipResult {
    let note = format!(
        "tip {name}: k1, k2 are the interaction-integral values (contour radius {:.3e} m): \
         the crack-opening fit has no crack-face station within its fit length \
         (bem.cod_fit_fraction of the crack length or of the ligament ahead of the tip, \
         whichever is shorter)",
        t.contour_radius
    );
    integral_result(name, t, note)
}

/// The tip record with K from the interaction integral and `note`.
fn integral_result(name: String, t: &pdbem_bem::post::TipResult, note: String) -> TipResult {
    TipResult {
        name,
        position: t.position,
        k1: t.k1_m,
        k2: t.k2_m,
        kink_deg: pdbem_bem::post::kink_angle(t.k1_m, t.k2_m).to_degrees(),
        k_source: Some(INTEGRAL_SOURCE.into()),
        k1_j: Some(t.k1_m),
        k2_j: Some(t.k2_m),
        j: Some(t.j),
        notes: vec![note],
        ..Default::default()
    }
}

/// One result per crack of `mesh`: its name and, for a crack with a mouth on the outline,
/// its CMOD in `solution`.
pub fn crack_results(mesh: &pdbem_bem::Mesh, solution: &Solution) -> Vec<CrackResult> {
    mesh.cracks
        .iter()
        .enumerate()
        .map(|(i, c)| CrackResult {
            name: c.name.clone(),
            cmod: cmod(mesh, solution, i),
            ..Default::default()
        })
        .collect()
}

/// The tangential stress around the closed loop `name` of `outputs.boundary_stress` (a
/// hole or `outline`) at every element midpoint of `level`, with its peak; `None` when
/// no loop of the mesh carries that group.
pub fn hoop(scene: &Scene, level: &Level, name: &str) -> Option<(Vec<(pdbem_bem::V2, f64)>, f64)> {
    let mesh = &level.setup.mesh;
    let l = mesh.loops.iter().position(|r| {
        r.clone()
            .any(|i| scene.covers(name, &mesh.groups[mesh.elements[i].group]))
    })?;
    let ev = FieldEvaluator::new(
        mesh,
        &level.setup.material,
        &level.solution,
        level.setup.background,
    );
    let values = ev.boundary_hoop_stress(l);
    let peak = values
        .iter()
        .map(|(_, s)| *s)
        .fold(f64::NEG_INFINITY, f64::max);
    Some((values, peak))
}
