//! From a growth scene to the inputs of the three growth engines:
//! - PD-BEM (seed 002 Algorithm 2, [`input`]): the macro layout exactly as a static
//!   coupled solve has it ([`super::coupled`]), one window per crack tip, the load steps
//!   and growth settings, and the [`Scenario`] that gives the driver the scene's
//!   conditions on every rebuilt mesh (all at load factor 1);
//! - BEM-only ([`bem_only_input`]): the static BEM model's loops and cracks, K_c, the
//!   conditions with every group meshed;
//! - BEM-only and full PD: the crack [`Front`] of the scene ([`front`]); full PD's model
//!   is [`super::pd::full_pd_problem`].

use anyhow::{bail, Context, Result};
use pdbem_bem::mesh::LoopSpec;
use pdbem_bem::post::Background;
use pdbem_bem::{Bc, Mesh, SolveParams};
use pdbem_coupling::growth::bem_only::{BemOnlyBody, BemOnlyParams};
use pdbem_coupling::growth::front::{Front, FrontCrack};
use pdbem_coupling::growth::{Growth, GrowthParams, GrowthSetup, LoadSteps, Scenario, TipSpec};
use pdbem_coupling::pd_window::EdgeCondition;
use pdbem_coupling::setup::Layout;
use pdbem_coupling::window::Window;
use pdbem_coupling::CouplingParams;

use super::bem::{conditions, material, MissingGroup};
use super::coupled::{macro_body, outer_conditions, params_of, pd_settings, window_specs};
use super::sizing::{LocalSizes, Sizing};
use crate::scene::pd::Failure;
use crate::scene::shapes::{HoleShape, SceneGeometry};
use crate::scene::{GrowthMode, Plane, Scene};

/// The scene seen by the growth driver (all values at load factor 1).
pub struct SceneScenario<'a> {
    scene: &'a Scene,
    outline: LoopSpec,
}

impl Scenario for SceneScenario<'_> {
    fn bem_conditions(&self, mesh: &Mesh) -> std::result::Result<Vec<[Bc; 2]>, String> {
        conditions(self.scene, mesh, 1.0, None, MissingGroup::Skip).map_err(|e| format!("{e:#}"))
    }

    fn outer_conditions(&self, window: &Window) -> Vec<EdgeCondition> {
        outer_conditions(self.scene, &self.outline, window, 1.0)
    }
}

/// The growth driver's input from a scene: setup, parameters and the scenario.
pub struct PdBemInput<'a> {
    /// Initial macro model.
    pub setup: GrowthSetup,
    /// Algorithm 2 parameters.
    pub params: GrowthParams,
    /// The scene's conditions.
    pub scenario: SceneScenario<'a>,
}

impl PdBemInput<'_> {
    /// The growth run at its initial geometry (for studies and tests that drive
    /// [`Growth::solve_at`] and [`Growth::relocate`] themselves).
    pub fn growth(&self) -> Result<Growth<'_, SceneScenario<'_>>> {
        Ok(Growth::new(
            self.setup.clone(),
            &self.scenario,
            self.params.clone(),
        )?)
    }
}

/// Builds the growth input of `scene` (with `pd`, `coupling` and `growth`).
pub fn input(scene: &Scene) -> Result<PdBemInput<'_>> {
    let file = scene.file_label();
    let (Some(co), Some(pd), Some(gr)) = (&scene.coupling, &scene.pd, &scene.growth) else {
        bail!(
            "{}: PD-BEM growth needs `pd`, `coupling` and `growth`",
            file.display()
        );
    };
    if gr.mode != GrowthMode::PdBem {
        bail!(
            "{}: growth.mode is {:?}, not PdBem",
            file.display(),
            gr.mode
        );
    }
    super::bem::check_balance(scene)?;
    let geo = SceneGeometry::of(scene);
    let (windows, wtips) = window_specs(scene, &geo, co, pd)?;
    let body = macro_body(scene, &geo, &wtips, co.dx())?;
    let cracks = body.cracks;
    let tips = wtips
        .iter()
        .map(|t| {
            let (crack, end) = t.name.rsplit_once('.').unwrap_or((t.name.as_str(), "end"));
            let index = cracks
                .iter()
                .position(|c| c.name == crack)
                .with_context(|| format!("{}: tip {} has no crack", file.display(), t.name))?;
            Ok(TipSpec {
                name: t.name.clone(),
                crack: index,
                at_end: end == "end",
            })
        })
        .collect::<Result<Vec<_>>>()?;
    if tips.is_empty() {
        bail!(
            "{}: PD-BEM growth: no crack tip lies in a window (coupling.placement = AtTips puts one on every tip)",
            file.display()
        );
    }
    let outline = body.outline;
    let layout = Layout {
        outline: outline.clone(),
        holes: body.holes,
        cracks,
        windows,
        pd: pd_settings(scene, pd)?,
    };
    let setup = GrowthSetup {
        layout,
        tips,
        material: material(scene)?,
        bem_params: SolveParams {
            estimate_condition: false,
            ..Default::default()
        },
        background: Background::default(),
        thickness: scene.material.thickness,
    };
    let loads = LoadSteps {
        initial: scene.load.initial,
        step: scene.load.step,
        count: scene.load.count,
    };
    let mut params = GrowthParams::new(loads, gr.move_distance.unwrap_or(0.25 * co.side));
    params.trigger_ratio = gr.trigger_ratio;
    params.elements_per_extension = gr.elements_per_extension;
    params.path.threshold = gr.damage_threshold;
    params.end_on_overstrain = gr.overstrain == crate::scene::OverstrainAction::End;
    // Algorithm 1 settings from the scene; the PD solver stays the staggered one of
    // `GrowthParams::new` (one break round per coupling iteration), whatever `pd.solver`.
    params.coupling = CouplingParams {
        pd_solve: params.coupling.pd_solve.clone(),
        ..params_of(co, pd)
    };
    Ok(PdBemInput {
        setup,
        params,
        scenario: SceneScenario { scene, outline },
    })
}

/// The crack front of a scene for the BEM-only and full-PD engines: outline, holes and
/// cracks as the scene geometry has them, circular holes as the polygons of the BEM mesh
/// (`bem.elements_per_circle`), so that a crack the front takes onto a hole ends on an
/// edge of the meshed hole.
pub fn front(scene: &Scene) -> Front {
    let geo = SceneGeometry::of(scene);
    let per_circle = super::sizing::circle_elements(scene, 1.0);
    let holes = geo
        .holes
        .iter()
        .map(|(n, h)| {
            let shape = match h {
                HoleShape::Circle { center, radius } => HoleShape::Polygon(
                    crate::geometry::circle_polygon(center, *radius, per_circle, true),
                ),
                other => other.clone(),
            };
            (n.clone(), shape)
        })
        .collect();
    let cracks = geo
        .cracks
        .iter()
        .map(|c| FrontCrack {
            name: c.name.clone(),
            points: c.points.clone(),
            mouth: c.mouth,
        })
        .collect();
    Front::new(geo.outline.map(|o| o.points), holes, cracks)
}

/// The scene's conditions for BEM-only growth: every group meshed (a missing one is an
/// error) and, on an infinite plate, minus the remote traction on every element.
pub struct BemOnlyScenario<'a> {
    scene: &'a Scene,
    remote: Option<[f64; 3]>,
}

impl Scenario for BemOnlyScenario<'_> {
    fn bem_conditions(&self, mesh: &Mesh) -> std::result::Result<Vec<[Bc; 2]>, String> {
        conditions(self.scene, mesh, 1.0, self.remote, MissingGroup::Error)
            .map_err(|e| format!("{e:#}"))
    }

    fn outer_conditions(&self, _window: &Window) -> Vec<EdgeCondition> {
        Vec::new()
    }
}

/// The input of BEM-only growth.
pub struct BemOnlyInput<'a> {
    /// The body every geometry shares.
    pub body: BemOnlyBody,
    /// The initial crack front.
    pub front: Front,
    /// Toughness, load factors, increment, snapshot steps.
    pub params: BemOnlyParams,
    /// The scene's conditions.
    pub scenario: BemOnlyScenario<'a>,
}

/// The BEM-only growth input of `scene` (with `growth`): the static BEM model's loops and
/// cracks ([`super::bem::local_model`]) with its local-feature tip rule for every
/// re-meshed geometry ([`LocalSizes::tip_rule`]), K_c from [`toughness`].
pub fn bem_only_input(scene: &Scene) -> Result<BemOnlyInput<'_>> {
    let (k_c, _) = toughness(scene)?;
    super::bem::check_balance(scene)?;
    let geo = SceneGeometry::of(scene);
    let body = bem_only_body(scene, &geo)?;
    let gr = scene.growth.as_ref();
    let params = BemOnlyParams {
        k_c,
        loads: scene.load.factors(),
        da: gr.and_then(|g| g.da),
        snapshot_steps: gr.map(|g| g.snapshot_steps.clone()).unwrap_or_default(),
        fail_step: None,
    };
    Ok(BemOnlyInput {
        body,
        front: front(scene),
        params,
        scenario: BemOnlyScenario {
            scene,
            remote: geo.remote,
        },
    })
}

/// The LEFM body of a scene: what BEM-only growth re-meshes and what the K record along
/// the path of every mode solves (`pdbem_coupling::growth::sif_path`).
pub fn bem_only_body(scene: &Scene, geo: &SceneGeometry) -> Result<BemOnlyBody> {
    let rule = LocalSizes::tip_rule(scene, geo, 1.0);
    let (loops, cracks, features) = if rule.is_some() {
        let m = super::bem::local_model(scene, geo, 1.0)?;
        (m.loops, m.cracks, m.local.features)
    } else {
        let loops = super::bem::loops(scene, geo, 1.0);
        let sizing = Sizing::of(scene, geo, &loops, 1.0)?;
        let cracks = super::bem::crack_specs(scene, geo, &sizing, 1.0);
        (loops, cracks, Default::default())
    };
    Ok(BemOnlyBody {
        loops,
        cracks,
        material: material(scene)?,
        params: SolveParams {
            infinite: geo.outline.is_none(),
            estimate_condition: scene.bem.condition_estimate,
            ..Default::default()
        },
        background: Background {
            stress: geo.remote.unwrap_or([0.0; 3]),
        },
        fit_fraction: scene.bem.cod_fit_fraction,
        sizing: rule,
        field: features,
        integral_cracks: scene
            .cracks
            .iter()
            .filter(|c| super::bem::loaded_on_one_face(scene, &c.name))
            .map(|c| c.name.clone())
            .collect(),
        contour: (
            scene.bem.j_contour.radius_fraction,
            scene.bem.j_contour.points,
        ),
    })
}

/// The BEM scenario of a scene (every group meshed; an infinite plate loaded by minus
/// the remote traction on every element).
pub fn bem_only_scenario(scene: &Scene) -> BemOnlyScenario<'_> {
    BemOnlyScenario {
        scene,
        remote: SceneGeometry::of(scene).remote,
    }
}

/// G_c (J/m^2) of PMB bonds breaking at stretch `s0` with horizon `delta` (REFERENCES.md:
/// s0 = sqrt(4 pi G_c / (9 E delta)) in plane stress, sqrt(5 pi G_c / (12 E delta)) in
/// plane strain, solved for G_c).
pub fn gc_from_stretch(e: f64, delta: f64, s0: f64, plane: Plane) -> f64 {
    match plane {
        Plane::Stress => 9.0 * e * delta * s0 * s0 / (4.0 * std::f64::consts::PI),
        Plane::Strain => 12.0 * e * delta * s0 * s0 / (5.0 * std::f64::consts::PI),
    }
}

/// Toughness K_c (Pa m^0.5) of the LEFM criterion, and where it came from:
/// `material.fracture` (k_c, or sqrt(E' G_c)), else the PD failure law of the scene
/// (`pd.failure: CriticalStretch(s0)` at the horizon of the PD-BEM windows, the material
/// the PD modes break: G_c = 9 E delta s0^2 / (4 pi), K_c = sqrt(E' G_c)), as `pdbem bench
/// growth` does. An error says what to give when neither exists.
pub fn toughness(scene: &Scene) -> Result<(f64, Option<String>)> {
    if let Some(k) = scene.material.k_c() {
        return Ok((k, None));
    }
    let file = scene.file_label();
    let derived = match (&scene.pd, &scene.coupling) {
        (Some(pd), Some(co)) => match pd.failure {
            Failure::CriticalStretch(s0) => Some((pd.horizon_factor * co.dx(), s0)),
            _ => None,
        },
        _ => None,
    };
    let Some((delta, s0)) = derived else {
        bail!(
            "{}: material.fracture: BEM-only growth needs g_c (J/m^2) or k_c (Pa m^0.5) \
             (or pd.failure: CriticalStretch with a coupling section to derive them from)",
            file.display()
        );
    };
    let m = &scene.material;
    let g_c = gc_from_stretch(m.e, delta, s0, m.plane);
    let k_c = pdbem_bem::analytic::griffith_k_c(g_c, m.e_prime());
    let note = format!(
        "K_c = {k_c:.4e} Pa m^0.5 derived from the PD failure law: critical stretch s0 = {s0} \
         at the window horizon delta = {delta:.4e} m gives G_c = {g_c:.4e} J/m^2 \
         (REFERENCES.md), K_c = sqrt(E' G_c)"
    );
    Ok((k_c, Some(note)))
}

/// The memory budget against PD-BEM growth's growing mesh: each window relocation adds
/// `2 growth.elements_per_extension` BEM elements per tip (both faces), and the dense
/// system of N elements takes 8 (2N)^2 bytes, so the budget holds
/// N_max = sqrt(budget / 8) / 2 elements. An error when not one relocation of every tip
/// fits beside the `elements` of the first mesh (the crack could not grow; the run's BEM
/// system refuses the rebuild, `pdbem_bem::system::set_system_budget`); a note when the
/// relocations the budget holds, at least max(move_distance, dx) each, reach less far than
/// the body's bounding-box diagonal: a longer path ends the run there (`complete: false`).
/// Before, such a run grew the mesh until the machine killed it (elements_per_extension =
/// 10000 on `growth_tension_edge`: 24 GB in 90 s).
pub fn mesh_growth_note(scene: &Scene, elements: usize, tips: usize) -> Result<Option<String>> {
    let (Some(gr), Some(co)) = (&scene.growth, &scene.coupling) else {
        return Ok(None);
    };
    let budget = super::estimate::budget() as f64;
    let most = (budget / 8.0).sqrt() / 2.0;
    let per = 2.0 * gr.elements_per_extension as f64 * tips as f64;
    let gib = |n: f64| 8.0 * (2.0 * n).powi(2) / 1073741824.0;
    let first = elements as f64 + per;
    if first > most {
        bail!(
            "{}: growth.elements_per_extension = {}: the first window relocation would take the BEM mesh from {elements} to {first:.0} elements ({tips} tip(s), both faces; a {:.3} GiB dense system), over the memory budget of {:.3} GiB ({most:.0} elements): the crack could not grow; lower it (the seed's 5) or raise the budget with --max-memory",
            scene.file_label().display(),
            gr.elements_per_extension,
            gib(first),
            budget / 1073741824.0
        );
    }
    let relocations = ((most - elements as f64) / per).floor();
    let advance = gr.move_distance.unwrap_or(0.25 * co.side).max(co.dx());
    let reach = relocations * advance;
    let geo = SceneGeometry::of(scene);
    let Some(outline) = &geo.outline else {
        return Ok(None);
    };
    let (lo, hi) = crate::geometry::bounding_box(&outline.points);
    let diagonal = (hi - lo).norm();
    Ok((reach < diagonal).then(|| {
        format!(
            "growth.elements_per_extension = {}: each window relocation adds {per:.0} BEM elements ({tips} tip(s), both faces), and the memory budget of {:.3} GiB holds {most:.0} (the first mesh has {elements}): about {relocations:.0} relocations, {reach:.3e} m of crack at {advance:.3e} m each, against the body's {diagonal:.3e} m diagonal; a longer path ends the run there (complete: false). Lower it or raise --max-memory",
            gr.elements_per_extension,
            budget / 1073741824.0
        )
    }))
}
