//! From a scene to the static coupled model (issue 4, seed 002 section 2.3): the BEM body
//! (outline with patches, holes, cracks at the one sizing rule of [`super::sizing`]) with
//! the PD windows cut out ([`pdbem_coupling::setup::build`]), the PD windows
//! (`coupling.placement`: one square per crack tip with axes along the crack, a centred and
//! rotated square, or an axis-aligned region that may lie against the outline), their PD
//! settings and the Algorithm 1 parameters. PD-BEM growth starts from the same pieces.

use anyhow::{bail, Context, Result};
use pdbem_bem::mesh::LoopSpec;
use pdbem_bem::post::Background;
use pdbem_bem::{Bc, Mesh, SolveParams, V2};
use pdbem_coupling::pd_window::{EdgeCondition, PdSettings};
use pdbem_coupling::setup::{Layout, MacroCrack};
use pdbem_coupling::window::{SideKind, Window, WindowSpec};

use crate::geometry::point_segment_projection;
use pdbem_coupling::{Acceleration, CoupledProblem, CouplingParams, PdSolve};
use pdbem_pd::solvers::{adr, implicit, Convergence};

use super::bem::{face_mode, material};
use super::sizing::Sizing;
use super::{final_factor, pd_failure, pd_material, pd_plane};
use crate::scene::shapes::SceneGeometry;
use crate::scene::{
    Component, Coupling, CouplingOrdering, DisplacementMap, PdModelKind, PdSettings as ScenePd,
    PdSolver, Placement, Plane, Relaxation, Scene,
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
    /// Notes on the set-up ([`coupling_notes`]).
    pub notes: Vec<String>,
}

/// Builds the coupled problem of `scene` (validated, with `pd` and `coupling`); a body
/// whose tractions nothing balances is an error ([`super::bem::check_balance`]).
pub fn prepare(scene: &Scene) -> Result<CoupledSetup> {
    let file = scene.file_label();
    let (Some(co), Some(pd)) = (&scene.coupling, &scene.pd) else {
        bail!("{}: coupled mode needs `pd` and `coupling`", file.display());
    };
    // The whole body (BEM and windows) must be held or in balance.
    super::bem::check_balance(scene)?;
    let geo = SceneGeometry::of(scene);
    let factor = final_factor(scene);
    let (specs, tips) = window_specs(scene, &geo, co, pd)?;
    let body = macro_body(scene, &geo, &tips, co.dx())?;
    let layout = Layout {
        outline: body.outline,
        holes: body.holes,
        cracks: body.cracks,
        windows: specs,
        pd: pd_settings(scene, pd)?,
    };
    let notes = coupling_notes(scene, &layout);
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
        notes,
    })
}

/// The notes on where the coupling iteration can stall: windows over thin strips of BEM
/// body ([`thin_strip_notes`]) and a nearly incompressible body ([`incompressible_note`]).
/// `pdbem check` prints them, the run's summary keeps them, and a coupled solve that fails
/// names them as its likely cause.
pub fn coupling_notes(scene: &Scene, layout: &Layout) -> Vec<String> {
    let mut notes = thin_strip_notes(layout);
    notes.extend(incompressible_note(scene));
    notes
}

/// The ratio of the 2-D bulk modulus to the shear modulus, 1 / (1 - 2 nu) in plane
/// strain, from which a body with state-based windows counts as nearly incompressible
/// (nu = 0.48 in plane strain).
pub const NEAR_INCOMPRESSIBLE: f64 = 25.0;

/// A note on a plane-strain body with state-based PD windows whose 2-D bulk modulus is
/// at least [`NEAR_INCOMPRESSIBLE`] times its shear modulus: the windows stiffen as nu
/// nears 0.5, and the Dirichlet-Neumann iteration between them and the BEM body slows and
/// then stalls. Measured on `coupled_sent_a5_state_based` in plane strain (IQN-ILS,
/// psi = 1e-4), CMOD against the BEM alone (same elements) and iterations: +0.59 % (11)
/// at nu = 0.3, +0.39 % (9) at 0.4, -0.14 % (11) at 0.45, -1.03 % (12) at 0.48, -1.70 %
/// (15) at 0.49, -2.05 % (23) at 0.495, -3.09 % (28) at 0.497, each within the run's
/// error estimate; no convergence in 50 at 0.499 (nor by Aitken in 500, nor with n =
/// 40). Bond-based windows fix nu = 1/4 in plane strain; plane stress keeps the ratio
/// (1 + nu) / (1 - nu) below 3.
pub fn incompressible_note(scene: &Scene) -> Option<String> {
    let pd = scene.pd.as_ref()?;
    let nu = scene.material.nu;
    let ratio = 1.0 / (1.0 - 2.0 * nu);
    let applies = pd.model == PdModelKind::StateBased
        && scene.material.plane == Plane::Strain
        && ratio >= NEAR_INCOMPRESSIBLE;
    applies.then(|| {
        format!(
            "material.nu = {nu} in plane strain: the body is nearly incompressible (its 2-D bulk modulus is {ratio:.0} times the shear modulus, 1 / (1 - 2 nu)); the state-based PD windows stiffen as nu nears 0.5 and the coupling iteration slows, then stalls (the SENT plate of coupled_sent_a5_state_based: CMOD -1.0 % from the BEM alone at nu = 0.48, -1.7 % at 0.49, -3.1 % at 0.497, within the runs' error estimates, against +0.6 % at 0.3; 15 iterations at 0.49, 28 at 0.497, none converged at 0.499); the BEM alone takes any nu below 0.5"
        )
    })
}

/// Notes on windows that leave a strip of BEM body thinner than a quarter of their side
/// between a side and the outline (`pdbem_coupling::growth::relocate::MIN_STRIP`): there
/// the Dirichlet-Neumann iteration can stall (docs/growth_modes.md, the tension plate's
/// window stalled at a residual of 1 for strips of 0.27-0.4 m of a 2 m side).
pub fn thin_strip_notes(layout: &Layout) -> Vec<String> {
    let outline = &layout.outline.points;
    layout
        .windows
        .iter()
        .enumerate()
        .flat_map(|(i, w)| {
            pdbem_coupling::growth::relocate::thin_strips(w, outline)
                .into_iter()
                .map(move |(strip, side, normal)| {
                    format!(
                        "window {i} (centre ({:.4}, {:.4})) leaves a strip of BEM body {strip:.4} m wide ({:.2} of its {side:.4} m side) between its {} and the outline: the coupling iteration can stall on strips under a quarter side; place the window against that edge or at least {:.4} m from it",
                        w.center.x,
                        w.center.y,
                        strip / side,
                        side_name(normal),
                        0.25 * side
                    )
                })
        })
        .collect()
}

/// A window side by its outward `normal`: "top side" and the like when it is along an
/// axis, else "side facing (nx, ny)".
fn side_name(normal: V2) -> String {
    let named = [
        (V2::new(1.0, 0.0), "right"),
        (V2::new(-1.0, 0.0), "left"),
        (V2::new(0.0, 1.0), "top"),
        (V2::new(0.0, -1.0), "bottom"),
    ];
    match named.iter().find(|(n, _)| (n - normal).norm() < 1e-9) {
        Some((_, name)) => format!("{name} side"),
        None => format!("side facing ({:.3}, {:.3})", normal.x, normal.y),
    }
}

/// The closed polygons (outline and holes) a windowed tip's interaction-integral contour
/// keeps clear of ([`pdbem_coupling::post::window_tip_sif`]).
pub fn contour_boundaries(scene: &Scene) -> Vec<Vec<V2>> {
    let geo = SceneGeometry::of(scene);
    let mut out: Vec<Vec<V2>> = Vec::new();
    if let Some(o) = &geo.outline {
        out.push(o.points.to_vec());
    }
    for (_, h) in &geo.holes {
        out.push(h.polygon().to_vec());
    }
    out
}

/// One line per windowed tip that will get no K because no interaction-integral contour
/// fits around its window ([`pdbem_coupling::post::contour_radius`]): the window and the
/// body alone decide it, so `pdbem check` reports what the run will note.
pub fn tips_without_contour(scene: &Scene, setup: &CoupledSetup) -> Vec<String> {
    let boundaries = contour_boundaries(scene);
    let contour = pdbem_coupling::post::WindowContour::default();
    setup
        .tips
        .iter()
        .filter_map(|t| {
            pdbem_coupling::post::contour_radius(
                &setup.problem,
                t.window,
                t.position,
                &boundaries,
                &contour,
            )
            .err()
            .map(|e| format!("tip {}: no K reported: {e}", t.name))
        })
        .collect()
}

/// Window specifications and the tips they hold.
pub fn window_specs(
    scene: &Scene,
    geo: &SceneGeometry,
    co: &Coupling,
    pd: &ScenePd,
) -> Result<(Vec<WindowSpec>, Vec<WindowTip>)> {
    let dx = co.dx();
    let m = pd.horizon_factor;
    let square = |center: V2, angle: f64| WindowSpec {
        center,
        angle,
        dx,
        nx: co.n,
        ny: co.n,
        horizon_factor: m,
    };
    let all_tips: Vec<(String, V2, V2)> =
        geo.cracks.iter().flat_map(|c| c.tip_directions()).collect();
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
            let dx = co.dx();
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

/// The macro body of a coupled scene: outline (split at the patches), holes and cracks at
/// the sizes of the one rule ([`super::sizing`]).
#[derive(Debug, Clone, PartialEq)]
pub struct MacroBody {
    /// Outer loop (counter-clockwise).
    pub outline: LoopSpec,
    /// Hole loops.
    pub holes: Vec<LoopSpec>,
    /// Cracks.
    pub cracks: Vec<MacroCrack>,
}

/// The macro body of `scene` (an error for an infinite plate). A crack with a tip in a
/// window (`tips`) is meshed at the windows' spacing `dx` unless `bem.group_sizes` names
/// it: next to a window the BEM crack faces take the interface's resolution (the coupled
/// mesh never makes them finer, `pdbem_coupling::setup::build`, and window relocations
/// extend them by elements of that size).
pub fn macro_body(
    scene: &Scene,
    geo: &SceneGeometry,
    tips: &[WindowTip],
    dx: f64,
) -> Result<MacroBody> {
    let loops = super::bem::loops(scene, geo, 1.0);
    let sizing = Sizing::of(scene, geo, &loops, 1.0)?;
    let mut loops = loops.into_iter();
    let Some(outline) = loops.next().filter(|l| !l.is_hole) else {
        bail!(
            "{}: coupled mode needs a finite body (infinite plates are BEM or PD only)",
            scene.file_label().display()
        );
    };
    let cracks = scene
        .cracks
        .iter()
        .zip(&geo.cracks)
        .zip(&sizing.cracks)
        .map(|((c, line), &h)| {
            let in_window = tips
                .iter()
                .any(|t| t.name.rsplit_once('.').is_some_and(|(n, _)| n == c.name));
            let given = scene.bem.group_sizes.contains_key(&c.name);
            MacroCrack {
                name: c.name.clone(),
                points: line.points.clone(),
                faces: face_mode(c.faces),
                element_size: if in_window && !given { dx } else { h },
                segment_elements: false,
            }
        })
        .collect();
    Ok(MacroBody {
        outline,
        holes: loops.collect(),
        cracks,
    })
}

/// PD settings of the windows of a coupled scene.
pub fn pd_settings(scene: &Scene, pd: &ScenePd) -> Result<PdSettings> {
    Ok(PdSettings {
        youngs_modulus: scene.material.e,
        thickness: scene.material.thickness,
        plane: pd_plane(scene),
        material: pd_material(scene, pd),
        failure: pd_failure(scene, pd)?,
        surface_correction: pd.surface_correction,
        // The surface correction already includes the bulk factor.
        bulk_correction: !pd.surface_correction,
        crack_face_correction: pd.crack_face_correction.unwrap_or(true),
        refine: scene.coupling.as_ref().and_then(|c| c.refine).map(|r| {
            pdbem_coupling::pd_window::WindowRefine {
                half_size: r.half_size,
                levels: r.levels,
            }
        }),
    })
}

/// Algorithm 1 parameters of a coupled scene.
pub fn params_of(co: &Coupling, pd: &ScenePd) -> CouplingParams {
    let acceleration = match co.relaxation {
        Relaxation::Constant(w) => Acceleration::Constant(w),
        Relaxation::Aitken(w) => Acceleration::Aitken(w),
        Relaxation::IqnIls { w0 } => Acceleration::IqnIls(w0),
    };
    let displacement_map = match co.displacement_map {
        DisplacementMap::Copy => pdbem_coupling::DisplacementMap::Copy,
        DisplacementMap::Interior => pdbem_coupling::DisplacementMap::Interior,
        DisplacementMap::Taylor => pdbem_coupling::DisplacementMap::Taylor,
    };
    let pd_solve = match &pd.solver {
        // Explicit dynamics is refused with `coupling` by validation.
        PdSolver::Explicit(_) => PdSolve::default(),
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
        ordering: match co.ordering {
            CouplingOrdering::DisplacementToPd => pdbem_coupling::Ordering::DisplacementToPd,
            CouplingOrdering::TractionToPd => pdbem_coupling::Ordering::TractionToPd,
        },
        ..Default::default()
    }
}

/// Whether the closed polygon `points` turns at vertex `v` (a corner of the outline, not
/// a vertex between two pieces of one straight edge).
fn turns(points: &[V2], v: usize) -> bool {
    let n = points.len();
    let (prev, next) = (points[(v + n - 1) % n], points[(v + 1) % n]);
    let (e1, e2) = (points[v] - prev, next - points[v]);
    (e1.x * e2.y - e1.y * e2.x).abs() > 1e-9 * e1.norm() * e2.norm()
}

/// Scene conditions on the outline pieces that lie along window `w`'s outer sides, each
/// with whether it goes on past its ends ([`EdgeCondition::continues`]).
pub fn outer_conditions(
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
            // The outline vertex at each end of the piece along t, and whether the edge
            // runs on past the window's corner there.
            let (v_lo, v_hi) = if s0 <= s1 {
                (i, (i + 1) % n)
            } else {
                ((i + 1) % n, i)
            };
            let continues = [
                s0.min(s1) < -tol || turns(&outline.points, v_lo),
                s0.max(s1) > (b - a).norm() + tol || turns(&outline.points, v_hi),
            ];
            for bc in scene
                .boundary
                .iter()
                .filter(|bc| scene.covers(&bc.on, &outline.edge_groups[i]))
            {
                let mut c = EdgeCondition {
                    from,
                    to,
                    traction: [None; 2],
                    displacement: [None; 2],
                    continues,
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
    super::bem::conditions(scene, mesh, factor, None, super::bem::MissingGroup::Skip)
}

#[cfg(test)]
mod tests {
    use pdbem_coupling::growth::Scenario;
    use pdbem_coupling::window::{Body, SideKind, Window, WindowSpec};

    use super::*;

    /// The shear plate's bottom clamp (x = 0-10 m) under a 3 m window at x = 8.5-11.5 m:
    /// its piece goes on past the window's corner (the clamp runs on) but not past
    /// x = 10 m, where the clamp ends inside the edge (a free surface follows).
    #[test]
    fn a_clamp_that_ends_inside_an_edge_does_not_go_on_past_its_end() {
        let scene = Scene::load("cases/growth_shear_edge.ron").unwrap();
        let input = crate::setup::growth::input(&scene).unwrap();
        let body = Body {
            outline: input.setup.layout.outline.points.clone(),
            holes: vec![],
        };
        let spec = WindowSpec {
            center: V2::new(10.0, 1.5),
            angle: 0.0,
            dx: 0.1,
            nx: 30,
            ny: 30,
            horizon_factor: 3.015,
        };
        let w = Window::place(0, spec, &body).unwrap();
        assert_eq!(w.sides[0], SideKind::Outer);
        let out = input.scenario.outer_conditions(&w);
        assert_eq!(out.len(), 1, "{out:?}");
        let c = &out[0];
        let ends = [c.from, c.to].map(|p| p.x);
        assert!(
            (ends[0] - 8.5).abs() < 1e-9 && (ends[1] - 10.0).abs() < 1e-9,
            "{ends:?}"
        );
        assert_eq!(c.continues, [true, false]);
        // At a corner of the outline the condition goes on round it.
        let spec = WindowSpec {
            center: V2::new(1.5, 1.5),
            ..w.spec.clone()
        };
        let corner = Window::place(0, spec, &body).unwrap();
        let out = input.scenario.outer_conditions(&corner);
        let bottom = (out.iter())
            .find(|c| c.from.y.abs() < 1e-9 && c.to.y.abs() < 1e-9)
            .expect("the clamp's piece");
        let at_corner = if bottom.from.x < bottom.to.x { 0 } else { 1 };
        assert!(bottom.continues[at_corner], "{bottom:?}");
    }

    /// The SENT plate's tip window grown to a 9 m side over the 10 m high strip: it
    /// leaves 0.5 m of BEM body above and below it, and the notes say which side is which
    /// (the window is turned with the crack, -90 degrees, so its own frame would not).
    #[test]
    fn thin_strip_notes_name_the_side() {
        let mut scene = Scene::load("cases/coupled_sent_a5_state_based.ron").unwrap();
        if let Some(c) = scene.coupling.as_mut() {
            c.side = 9.0;
        }
        let setup = prepare(&scene).unwrap();
        let strips: Vec<_> = setup.notes.iter().filter(|n| n.contains("strip")).collect();
        assert_eq!(strips.len(), 2, "{strips:?}");
        for (note, side) in strips.iter().zip(["top side", "bottom side"]) {
            assert!(
                note.contains(&format!(
                    "0.5000 m wide (0.06 of its 9.0000 m side) between its {side}"
                )),
                "{note}"
            );
        }
        assert_eq!(side_name(V2::new(0.6, 0.8)), "side facing (0.600, 0.800)");
    }
}
