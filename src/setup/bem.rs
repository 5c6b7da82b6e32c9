//! From a scene to a BEM model: mesh (loops, holes, cracks, patches), per-element boundary
//! conditions at a load factor, solver parameters and the remote field of infinite bodies.
//! Element sizes follow the one rule of [`super::sizing`].
//!
//! Infinite bodies are solved by superposition (DESIGN.md): holes and crack faces carry
//! minus the remote traction, and the remote field is added back in post-processing.

use super::sizing::{circle_elements, LocalSizes, Sizing};
use crate::geometry::{circle_polygon, on_segment, P2};
use crate::scene::shapes::{HoleShape, SceneGeometry};
use crate::scene::{Component, Faces, Plane, Scene};
use anyhow::{bail, Context, Result};
use pdbem_bem::mesh::{CrackSpec, FaceMode, LoopSpec, TipRefinement};
use pdbem_bem::post::Background;
use pdbem_bem::{Bc, Material, Mesh, MeshBuilder, SolveParams};

/// Everything a BEM solve needs.
pub struct BemSetup {
    /// The mesh.
    pub mesh: Mesh,
    /// Per-element conditions at the requested load factor.
    pub bcs: Vec<[Bc; 2]>,
    /// Solver parameters.
    pub params: SolveParams,
    /// Remote field (infinite bodies) scaled by the load factor.
    pub background: Background,
    /// Material.
    pub material: Material,
}

/// BEM material of a scene.
pub fn material(scene: &Scene) -> Result<Material> {
    let plane = match scene.material.plane {
        Plane::Stress => pdbem_bem::Plane::Stress,
        Plane::Strain => pdbem_bem::Plane::Strain,
    };
    Material::new(scene.material.e, scene.material.nu, plane).context("material")
}

/// Builds the model at load `factor`, with every element size divided by `refine`
/// (2 for the fine level of a Richardson pair). A finite body whose tractions nothing
/// balances is an error ([`super::balance`]).
pub fn build(scene: &Scene, factor: f64, refine: f64) -> Result<BemSetup> {
    let geo = SceneGeometry::of(scene);
    let mat = material(scene)?;
    let mesh = mesh_builder(scene, &geo, refine)?
        .build()
        .with_context(|| format!("{}: meshing", scene.file_label().display()))?;
    let remote = geo.remote.map(|s| s.map(|v| v * factor));
    let bcs = conditions(scene, &mesh, factor, remote, MissingGroup::Error)?;
    let params = SolveParams {
        infinite: geo.outline.is_none(),
        estimate_condition: scene.bem.condition_estimate,
        ..Default::default()
    };
    if !params.infinite {
        super::balance::check(scene, &mesh, &bcs)?;
    }
    Ok(BemSetup {
        mesh,
        bcs,
        params,
        background: Background {
            stress: remote.unwrap_or([0.0; 3]),
        },
        material: mat,
    })
}

/// The scene's whole body (outline, holes, cracks, no PD window) at unit load, checked
/// as in [`super::balance::check`] (which [`build`] runs); nothing to check for an
/// infinite plate.
pub fn check_balance(scene: &Scene) -> Result<()> {
    if SceneGeometry::of(scene).outline.is_none() {
        return Ok(());
    }
    build(scene, 1.0, 1.0).map(|_| ())
}

/// [`check_balance`] for a body another solver discretises (stand-alone PD): a body the
/// BEM mesher or its conditions would refuse although the scene's validation passed it
/// (none of the shipped cases: a crack tip closer to another boundary than the BEM
/// resolves) is left unchecked rather than refused for a BEM reason.
pub fn check_balance_where_meshable(scene: &Scene) -> Result<()> {
    match whole_body_where_meshable(scene) {
        Some((mesh, bcs)) => super::balance::check(scene, &mesh, &bcs),
        None => Ok(()),
    }
}

/// The scene's whole body meshed at unit load with its conditions, for the balance of a
/// body another solver discretises; `None` for an infinite plate and for a body the BEM
/// mesher or its conditions would refuse although the scene's validation passed it. The
/// mesh takes the default BEM sizes: the scene's `bem` section is not what that solver
/// runs (a stand-alone PD scene with `bem.element_size: 1e-9` left its loads unchecked).
pub fn whole_body_where_meshable(scene: &Scene) -> Option<(Mesh, Vec<[Bc; 2]>)> {
    let geo = SceneGeometry::of(scene);
    geo.outline.as_ref()?;
    let mut scene = scene.clone();
    scene.bem = crate::scene::BemSettings::default();
    let scene = &scene;
    let mesh = mesh_builder(scene, &geo, 1.0).ok()?.build().ok()?;
    let bcs = conditions(scene, &mesh, 1.0, None, MissingGroup::Error).ok()?;
    Some((mesh, bcs))
}

/// The loops, cracks and size field of the static BEM mesh at refinement `refine`
/// ([`mesh_builder`]; BEM-only growth re-meshes from it).
pub struct LocalModel {
    /// Outline (default-size edges at the far size when [`LocalSizes::far`] is set) and
    /// hole loops.
    pub loops: Vec<LoopSpec>,
    /// Cracks: faces capped at the base size where the tip sources grade them, else the
    /// scene's sizes.
    pub cracks: Vec<CrackSpec>,
    /// The local sizes (tip sources and features).
    pub local: LocalSizes,
}

/// The [`LocalModel`] of `scene` at refinement `refine`.
pub fn local_model(scene: &Scene, geo: &SceneGeometry, refine: f64) -> Result<LocalModel> {
    let mut loops = loops(scene, geo, refine);
    let sizing = Sizing::of(scene, geo, &loops, refine)?;
    let local = LocalSizes::of(scene, geo, &loops, refine)?;
    if let (Some(far), Some(outline)) = (local.far, loops.first_mut().filter(|l| !l.is_hole)) {
        for (g, size) in outline
            .edge_groups
            .iter()
            .zip(outline.edge_sizes.iter_mut())
        {
            if !scene.bem.group_sizes.contains_key(g) {
                *size = far;
            }
        }
    }
    let mut cracks = crack_specs(scene, geo, &sizing, refine);
    for (i, spec) in cracks.iter_mut().enumerate() {
        let c = &scene.cracks[i];
        if !scene.bem.group_sizes.contains_key(&c.name) && scene.bem.tip_refinement.is_none() {
            // The tip zones are sources of the field; the faces grow to the base size.
            spec.element_size = sizing.base;
        }
    }
    Ok(LocalModel {
        loops,
        cracks,
        local,
    })
}

/// The mesh builder of the static BEM model at refinement `refine`: loops and cracks with
/// the local-feature sizes of [`LocalSizes`] (tip zones, and default-size outline edges
/// coarsened far from every feature).
pub fn mesh_builder(scene: &Scene, geo: &SceneGeometry, refine: f64) -> Result<MeshBuilder> {
    let m = local_model(scene, geo, refine)?;
    let mut b = MeshBuilder::new();
    for l in m.loops {
        b.add_loop(l);
    }
    for spec in m.cracks {
        b.add_crack(spec);
    }
    b.set_size_field(m.local.field);
    Ok(b)
}

/// Whether the crack named `crack` has a condition on one of its faces alone
/// (`<crack>.upper` or `<crack>.lower` in `scene.boundary`): there the crack-opening fit
/// is biased and K is the interaction integral's
/// ([`crate::run_bem::level::tip_result`]).
pub fn loaded_on_one_face(scene: &Scene, crack: &str) -> bool {
    let faces = [format!("{crack}.upper"), format!("{crack}.lower")];
    scene.boundary.iter().any(|b| faces.contains(&b.on))
}

/// The outline (split at the patches) and hole loops of `scene` at refinement `refine`.
pub fn loops(scene: &Scene, geo: &SceneGeometry, refine: f64) -> Vec<LoopSpec> {
    let base = scene.bem.base_size(geo) / refine;
    let size_of = |group: &str| {
        scene
            .bem
            .group_sizes
            .get(group)
            .map(|s| s / refine)
            .unwrap_or(base)
    };
    let mut out = Vec::new();
    if let Some(outline) = &geo.outline {
        let (points, groups) = split_at_patches(scene, &outline.points, &outline.groups);
        let sizes = groups.iter().map(|g| size_of(g)).collect();
        out.push(LoopSpec {
            points,
            edge_groups: groups,
            edge_sizes: sizes,
            is_hole: false,
        });
    }
    let per_circle = circle_elements(scene, refine);
    for (name, shape) in &geo.holes {
        let points: Vec<P2> = match shape {
            HoleShape::Circle { center, radius } => {
                circle_polygon(center, *radius, per_circle, true)
            }
            HoleShape::Polygon(p) => p.clone(),
        };
        let n = points.len();
        let size = match shape {
            HoleShape::Circle { .. } => f64::INFINITY,
            HoleShape::Polygon(_) => size_of(name),
        };
        out.push(LoopSpec {
            points,
            edge_groups: vec![name.clone(); n],
            edge_sizes: vec![size; n],
            is_hole: true,
        });
    }
    out
}

/// The crack specifications of `scene` at the sizes of `sizing`, with the scene's tip
/// refinement.
pub fn crack_specs(
    scene: &Scene,
    geo: &SceneGeometry,
    sizing: &Sizing,
    refine: f64,
) -> Vec<CrackSpec> {
    scene
        .cracks
        .iter()
        .zip(&geo.cracks)
        .enumerate()
        .map(|(i, (c, line))| CrackSpec {
            name: c.name.clone(),
            points: line.points.clone(),
            faces: face_mode(c.faces),
            element_size: sizing.cracks[i],
            tip: scene.bem.tip_refinement.as_ref().map(|t| TipRefinement {
                size: t.element_size / refine,
                radius: t.radius,
            }),
        })
        .collect()
}

/// The BEM face mode of a scene crack.
pub fn face_mode(f: Faces) -> FaceMode {
    match f {
        Faces::Coincident => FaceMode::Coincident,
        Faces::Gap(g) => FaceMode::Gap(g),
    }
}

/// Splits the outline at the end points of `body.patches` and names the pieces inside a
/// patch by the patch name.
pub fn split_at_patches(scene: &Scene, pts: &[P2], groups: &[String]) -> (Vec<P2>, Vec<String>) {
    if scene.body.patches.is_empty() {
        return (pts.to_vec(), groups.to_vec());
    }
    let n = pts.len();
    let mut out_p = Vec::new();
    let mut out_g = Vec::new();
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        let d = b - a;
        let len2 = d.norm_squared();
        let mut cuts = vec![0.0, 1.0];
        for p in &scene.body.patches {
            for q in [P2::new(p.from.0, p.from.1), P2::new(p.to.0, p.to.1)] {
                let t = (q - a).dot(&d) / len2;
                if t > 1e-12 && t < 1.0 - 1e-12 && (a + t * d - q).norm() <= 1e-9 * len2.sqrt() {
                    cuts.push(t);
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|x, y| (*x - *y).abs() < 1e-12);
        for w in cuts.windows(2) {
            let mid = a + 0.5 * (w[0] + w[1]) * d;
            out_p.push(a + w[0] * d);
            let name = scene
                .body
                .patches
                .iter()
                .find(|p| on_segment(&mid, &P2::new(p.from.0, p.from.1), &P2::new(p.to.0, p.to.1)))
                .map(|p| p.name.clone())
                .unwrap_or_else(|| groups[i].clone());
            out_g.push(name);
        }
    }
    (out_p, out_g)
}

/// What to do with a boundary condition whose group has no element in the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MissingGroup {
    /// A scene error (BEM alone: every named group is meshed).
    Error,
    /// Skip it (coupled runs: a group wholly inside a PD window is carried by PD).
    Skip,
}

/// Per-element conditions at load `factor`; traction-free where nothing is said; infinite
/// bodies (`remote`) add minus the remote traction on every element.
pub fn conditions(
    scene: &Scene,
    mesh: &Mesh,
    factor: f64,
    remote: Option<[f64; 3]>,
    missing: MissingGroup,
) -> Result<Vec<[Bc; 2]>> {
    let mut bcs = vec![[Bc::Traction(0.0), Bc::Traction(0.0)]; mesh.len()];
    for (k, bc) in scene.boundary.iter().enumerate() {
        let groups: Vec<usize> = (0..mesh.groups.len())
            .filter(|&g| scene.covers(&bc.on, &mesh.groups[g]))
            .collect();
        if groups.is_empty() {
            if missing == MissingGroup::Skip {
                continue;
            }
            bail!(
                "{}: boundary.{k}.on = '{}': no such group in the mesh",
                scene.file_label().display(),
                bc.on
            );
        }
        let elements = (0..mesh.len()).filter(|&i| groups.contains(&mesh.elements[i].group));
        for i in elements {
            let e = &mesh.elements[i];
            for (c, comp) in [bc.x, bc.y].iter().enumerate() {
                match comp {
                    Component::Free => {}
                    Component::Displacement(v) => bcs[i][c] = Bc::Displacement(v * factor),
                    Component::Traction(v) => bcs[i][c] = Bc::Traction(v * factor),
                }
            }
            let (tn, ts) = (bc.normal.unwrap_or(0.0), bc.shear.unwrap_or(0.0));
            if tn != 0.0 || ts != 0.0 {
                let t = (e.normal * tn + e.tangent * ts) * factor;
                bcs[i] = [Bc::Traction(t.x), Bc::Traction(t.y)];
            }
        }
    }
    if let Some(s) = remote {
        for (i, e) in mesh.elements.iter().enumerate() {
            let n = e.normal;
            let t = [s[0] * n.x + s[2] * n.y, s[2] * n.x + s[1] * n.y];
            for c in 0..2 {
                if let Bc::Traction(v) = bcs[i][c] {
                    bcs[i][c] = Bc::Traction(v - t[c]);
                }
            }
        }
    }
    Ok(bcs)
}
