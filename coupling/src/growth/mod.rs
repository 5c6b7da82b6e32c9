//! # Crack growth with moving PD windows (seed 002 Algorithm 2, sections 2.3.2-2.3.3)
//!
//! Load steps, each solved by Algorithm 1 to convergence on a BEM system factored once
//! per geometry (the load factor only scales the right-hand side,
//! [`crate::iteration::PreparedBem`]). After every iteration the macro crack in each
//! window ($\varphi > 0.38$ connected to the crack's entry into the window,
//! [`pdbem_pd::crack_path`]) gives the tip. When a tip passes the window margin the window
//! moves by the move distance along the growth direction, both BEM crack faces are
//! extended along the smoothed PD path by a set number of elements, the BEM system is
//! rebuilt and refactored, and the new window starts from the old PD state where the
//! grids overlap (broken bonds included) and from the BEM field elsewhere, at the same
//! load. Several tips each have a window, solved in parallel; windows that would overlap
//! are merged into one rectangle.
//!
//! How the crack is kept inside its window (choices of this implementation, measured on
//! `cases/growth_tension_edge.ron`, where the crack runs under load control at up to 30
//! times K_c):
//! - The PD windows are solved with [`crate::iteration::PdSolve::Staggered`]: bonds break
//!   only at converged interface states, the most stretched first
//!   ([`pdbem_pd::breaking`]), a few rounds with the interface held; the step converges when
//!   the residual is below psi and no bond breaks. Breaking inside every PD solve lets
//!   the crack run through the whole window in one solve and spread damage sideways.
//! - A band of $(1 - r)$ times the window side along the interface sides ($r$ = trigger
//!   ratio, 0.9 in the seed) has unbreakable bonds, so no damage reaches the coupling
//!   layer; the window moves once the tip is within the band plus a horizon and a dx of
//!   an interface side ([`tips::margins`]).
//! - Structural failure (Algorithm 2 step 9): a tip reaching the outline or two edge
//!   cracks meeting. A window may move onto the outline when its crack runs to it from
//!   the outline: the remaining ligament then lies wholly in the window, the BEM body is
//!   cut apart ([`topology`], noted) and the coupling holds the cut-off piece by its
//!   equilibrium ([`crate::floating`]) until the crack crosses the window. A coupling
//!   breakdown (divergence, no convergence) while the windows alone hold a cut-off part,
//!   or while a tip runs towards the outline in a window on it, is the PD ligament giving
//!   way under load control: structural failure, with the breakdown in the note. A tip
//!   reaching a hole or another crack ends; the others go on. Windows may not lie over a
//!   hole, so a tip growing towards one ends at it ([`TipEnd::Hole`]) when its window
//!   cannot move on without covering it ([`Growth::plan`]). Its crack is then joined to
//!   the hole, in the reported path and in the geometry: a crack `<tip>.hole` from the tip
//!   through the window side to the hole rim, a PD pre-crack in the window and BEM faces
//!   with two mouths outside it ([`driver::join_name`]); the run goes on with the joined
//!   body, and a join that closes a chain of cuts through the holes is structural failure
//!   ([`topology::join_cuts`]).
//! - A window's PD equilibrium with frozen bonds is Newton's, with ADR when Newton fails
//!   ([`pdbem_pd::solvers::frozen`]).
//! - Reported paths of tips that reached the outline end by the rule of the full-PD mode
//!   ([`polyline::end_on_outline`]): the last horizon, where the damage fans out over a
//!   ligament shorter than a bond, is replaced by the path's approach continued to the
//!   outline.
//! - Two cracks that join are one connected damage set; each trace then runs on through
//!   the other crack, so the paths are cut half-way between where the tips were before
//!   ([`tips::cut_at_meeting`]).
//! - A window holding several tips (windows merged) moves for all of its tips past the
//!   margin at once: the new window covers each one's moved window and the window's
//!   other tips, and every moved tip's crack is extended into it.
//!
//! Map:
//! - [`driver`]: [`Growth`] (the run: [`Growth::run`], [`Growth::solve_at`]).
//! - [`geometry`]: the geometry iteration ([`Growth::plan`], [`Growth::apply`],
//!   [`Growth::relocate`]).
//! - [`compare`]: path comparison between growth runs (Hausdorff-type deviation of two
//!   tip paths over their common reach, [`compare::path_deviation`]).
//! - [`bem_only`]: BEM-only growth (SIF, MCS kink, fixed increment; [`bem_only::run`]).
//! - [`full_pd`]: full-PD growth, the whole body at the window resolution
//!   ([`full_pd::run`]), the reference PD-BEM is compared with.
//! - [`checkpoint`]: the serialisable state of a run after a load step (resume).
//! - [`sif_path`]: the fracture-mechanics record along the path of every mode (K_I, K_II,
//!   K_eq, kink, G, load, CMOD against crack length; [`sif_path::SifRow`]).
//! - [`verdict`]: the end-of-step verdict of the BEM-only and full-PD engines.
//! - [`criterion`]: maximum circumferential stress kink and equivalent K (BEM-only growth).
//! - [`events`]: what the BEM-only and full-PD engines report ([`events::EngineObserver`]).
//! - [`front`]: the crack front of the BEM-only and full-PD engines ([`front::Front`]:
//!   crack polylines, tips, obstacles, separation).
//! - [`history`]: the mode-independent record of a growth run ([`history::GrowthHistory`]:
//!   tip paths, steps, relocations, snapshots), what PD-BEM, BEM-only and full-PD growth
//!   all produce.
//! - [`summary`]: the PD-BEM run ([`Growth`], [`GrowthResult`]) as a [`history::GrowthHistory`]
//!   ([`summary::history_of`]), with window damage snapshots.
//! - [`records`]: the [`Scenario`] trait, the setup and the records.
//! - [`observer`]: the progress [`Observer`] of PD-BEM growth.
//! - [`params`]: [`GrowthParams`], [`LoadSteps`].
//! - [`tips`]: tip specs and state, tracking, the margin and end tests.
//! - [`fine_zone`]: refined windows: only fine bonds break, the window moves before its tip
//!   leaves the fine cells.
//! - [`relocate`]: the moved window and the extended crack (the geometry iteration).
//! - [`transfer`]: the new window's initial state.
//! - [`merge`]: merging overlapping windows.
//! - [`topology`]: whether cracks and windows cut the BEM body apart (noted).
//! - [`polyline`]: small polyline helpers.

pub mod bem_only;
pub mod checkpoint;
pub mod compare;
pub mod criterion;
pub mod driver;
pub mod events;
pub mod fine_zone;
pub mod front;
pub mod full_pd;
pub mod geometry;
pub mod history;
pub mod merge;
pub mod observer;
pub mod overstrain;
pub mod params;
pub mod polyline;
pub mod records;
pub use observer::{Observer, Silent};
pub mod relocate;
pub mod sif_path;
pub mod summary;
pub mod tips;
pub mod topology;
pub mod transfer;
pub mod verdict;

pub use driver::Growth;
pub use params::{GrowthParams, LoadSteps};
pub use records::{
    Failure, GrowthResult, GrowthSetup, IterationEvent, RelocationPlan, RelocationRecord, Scenario,
    SolveOutcome, StepResult,
};
pub use tips::{TipEnd, TipSpec, TipState};
pub use transfer::TransferInfo;

/// Shared test fixtures: the seed 002 plate (20 m x 10 m) and a 1 m window in it; a
/// rectangular plate scene ([`fixtures::PlateScenario`], [`fixtures::plate_setup`]) for
/// growth runs.
#[cfg(test)]
pub(crate) mod fixtures {
    use pdbem_bem::mesh::{FaceMode, LoopSpec};
    use pdbem_bem::post::Background;
    use pdbem_bem::{Bc, Material, Mesh, SolveParams, V2};

    use crate::growth::records::{GrowthSetup, Scenario, StepResult};
    use crate::growth::tips::TipSpec;
    use crate::pd_window::{EdgeCondition, PdSettings};
    use crate::setup::{Layout, MacroCrack};
    use crate::window::{Body, Window, WindowSpec};

    /// A converged step record `k` at load `load` with nothing else to say (no moves,
    /// no overstrain, no stray damage, nothing held).
    pub(crate) fn step_result(k: usize, load: f64) -> StepResult {
        StepResult {
            step: k,
            load,
            iterations: 1,
            residual: 0.0,
            converged: true,
            broken_bonds: 0,
            tips: Vec::new(),
            cmod: None,
            relocations: 0,
            wall_s: 0.0,
            pd_s: 0.0,
            overstrain: None,
            stray: None,
            held: None,
            window_solves: Default::default(),
        }
    }

    /// The 20 m x 10 m plate of seed 002 section 3.2.
    pub(crate) fn body() -> Body {
        Body {
            outline: vec![
                V2::new(0.0, 0.0),
                V2::new(20.0, 0.0),
                V2::new(20.0, 10.0),
                V2::new(0.0, 10.0),
            ],
            holes: vec![],
        }
    }

    /// A 20 x 20 window of dx = 0.05 m centred at (cx, cy).
    pub(crate) fn window(cx: f64, cy: f64) -> Window {
        Window::place(0, window_spec(V2::new(cx, cy)), &body()).unwrap()
    }

    /// The spec of [`window`].
    pub(crate) fn window_spec(center: V2) -> WindowSpec {
        WindowSpec {
            center,
            angle: 0.0,
            dx: 0.05,
            nx: 20,
            ny: 20,
            horizon_factor: 3.015,
        }
    }

    /// A plate `[0, w] x [0, h]` (edges `bottom`, `right`, `top`, `left`): the left edge
    /// fixed, a traction of 1 MPa (times the load factor) along x on the right edge, the
    /// rest free. E = 1 GPa, nu = 1/3, plane stress, thickness 1 m.
    pub(crate) struct PlateScenario;

    impl Scenario for PlateScenario {
        fn bem_conditions(&self, mesh: &Mesh) -> Result<Vec<[Bc; 2]>, String> {
            Ok(mesh
                .elements
                .iter()
                .map(|e| match mesh.groups[e.group].as_str() {
                    "left" => [Bc::Displacement(0.0), Bc::Displacement(0.0)],
                    "right" => [Bc::Traction(1e6), Bc::Traction(0.0)],
                    _ => [Bc::Traction(0.0), Bc::Traction(0.0)],
                })
                .collect())
        }

        fn outer_conditions(&self, _window: &Window) -> Vec<EdgeCondition> {
            Vec::new()
        }
    }

    /// Growth setup of a `w x h` plate ([`PlateScenario`]) with holes `holes` (polygons,
    /// named `hole<i>`), cracks `cracks` (named `c<i>`, tip at the last point) and one
    /// window ([`window_spec`]) at each tip; PD bonds break at stretch `s0` (None: never).
    pub(crate) fn plate_setup(
        (w, h): (f64, f64),
        holes: Vec<Vec<V2>>,
        cracks: Vec<Vec<V2>>,
        s0: Option<f64>,
    ) -> GrowthSetup {
        let outline = vec![
            V2::new(0.0, 0.0),
            V2::new(w, 0.0),
            V2::new(w, h),
            V2::new(0.0, h),
        ];
        let tips = (0..cracks.len())
            .map(|i| TipSpec {
                name: format!("c{i}.end"),
                crack: i,
                at_end: true,
            })
            .collect();
        let layout = Layout {
            outline: LoopSpec {
                points: outline,
                edge_groups: ["bottom", "right", "top", "left"].map(String::from).into(),
                edge_sizes: vec![0.5; 4],
                is_hole: false,
            },
            holes: holes
                .into_iter()
                .enumerate()
                .map(|(i, points)| LoopSpec {
                    edge_groups: vec![format!("hole{i}"); points.len()],
                    edge_sizes: vec![f64::INFINITY; points.len()],
                    points,
                    is_hole: true,
                })
                .collect(),
            windows: cracks
                .iter()
                .map(|c| window_spec(*c.last().expect("points")))
                .collect(),
            cracks: cracks
                .into_iter()
                .enumerate()
                .map(|(i, points)| MacroCrack {
                    name: format!("c{i}"),
                    points,
                    faces: FaceMode::Coincident,
                    element_size: 0.1,
                    segment_elements: false,
                })
                .collect(),
            pd: PdSettings {
                youngs_modulus: 1e9,
                thickness: 1.0,
                plane: pdbem_pd::Plane::Stress,
                failure: s0.map_or(pdbem_pd::Failure::None, |s0| {
                    pdbem_pd::Failure::CriticalStretch { s0 }
                }),
                surface_correction: false,
                bulk_correction: false,
                material: pdbem_pd::PdMaterial::Pmb,
                crack_face_correction: false,
                refine: None,
            },
        };
        GrowthSetup {
            layout,
            tips,
            material: Material::new(1e9, 1.0 / 3.0, pdbem_bem::Plane::Stress).unwrap(),
            bem_params: SolveParams {
                estimate_condition: false,
                ..Default::default()
            },
            background: Background::default(),
            thickness: 1.0,
        }
    }
}
