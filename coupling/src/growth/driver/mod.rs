//! Algorithm 2 of seed 002 (section 2.3.2, Fig. 8): load steps, each iterated by
//! Algorithm 1 on the current geometry, with the geometry iteration (section 2.3.3,
//! Fig. 9) whenever a tip passes its window margin.
//!
//! [`Growth::run`] does, for every load factor $f_k$ = `initial + k step`:
//! 1. Algorithm 1 at $f_k$ on the factored BEM system of the current geometry
//!    ([`crate::iteration::solve_prepared`], warm-started from the last interface state
//!    scaled to $f_k$, and within a load step on one geometry from the IQN-ILS secant
//!    columns of the solve before; a relocation or a new try at a step starts the
//!    columns afresh). After every iteration the active tips are traced; a tip past its
//!    window margin or at the outline stops the iteration (step 6).
//! 2. Tips that reached the outline end the run (structural failure, step 9), as do two
//!    edge cracks that meet, or a tip past its margin for which no window around it fits
//!    inside the body. A window touches the outline only along whole sides, so a window
//!    turned with its crack that would cross the outline is turned to the orientation of
//!    the outline edge ahead of the tip first ([`crate::growth::relocate::turned_to_outline`]:
//!    one tip per window; its state from displacements, not bond states).
//!    A window whose crack runs to it from the outline may move onto the outline: the
//!    BEM body is then cut apart and the window alone holds the cut-off piece
//!    ([`crate::floating`]) until the crack crosses the window to the outline. Tips at a
//!    hole or running into another crack end and the run goes on with the others (the
//!    run ends when no tip is left).
//! 3. Tips past their margin are relocated ([`Growth::relocate`], steps 7 and 10): new
//!    window (one covering all the tips of a window that moves), extended cracks,
//!    overlapping windows merged, mesh rebuilt and refactored, state transferred; then 1.
//!    again at the same load. A tip whose window cannot move on because a hole is in the
//!    way ends at that hole ([`TipEnd::Hole`], noted through the observer) and the others
//!    go on. A tip ended at a hole (either way) is joined to it (`join`): the geometry is
//!    rebuilt with its crack running on to the hole rim and solved again at the same load
//!    before the step is recorded; a join that cuts the body apart ends the run with
//!    structural failure. When every tip has ended and the body holds, a note says so.
//! 4. Otherwise the step converged (interface residual below psi and no bond broke in the
//!    last PD solves) and is recorded; the load grows.
//!
//! 5. A step whose coupling does not converge is tried again from the state it started
//!    from with more iterations, IQN-ILS or a lower weight, then half the load increment
//!    (`backoff`); when none solves it the run ends with
//!    [`GrowthResult::failure_reason`](crate::growth::GrowthResult::failure_reason) and the
//!    steps before it. After every step that does not end the run the windows' kept
//!    solvers are dropped and the observer is offered a checkpoint
//!    ([`crate::growth::checkpoint`]); [`Growth::resume`] goes on from one.
//!
//! The scene-specific parts (BEM conditions of a mesh, conditions on window sides lying on
//! the outline, both at load factor 1) come from a [`Scenario`]; progress goes to an
//! [`Observer`](crate::growth::Observer), so the crate stays free of I/O.
//!
//! Files of the module:
//! - `mod.rs`: [`Growth`], its construction and accessors, the geometry build, tip tracing
//!   and paths.
//! - `run`: the strain watch, [`Growth::solve_at`] and the load-step loop [`Growth::run`].
//! - `backoff`: the retries of a load step whose coupling does not converge.
//! - `state`: the run's state between load steps ([`Growth::state`],
//!   [`Growth::set_state`], [`Growth::resume`]).
//! - `ends`: tips and runs that end (outline, hole, other crack, ligament), damage beyond
//!   the tips, and the stray-damage watch: damage in a window more than
//!   [`STRAY_REACH`](crate::growth::records::STRAY_REACH) horizons from every crack it
//!   tracks is a second crack PD-BEM does not follow; recorded per step
//!   ([`StepResult::stray`](crate::growth::records::StepResult::stray)), noted, and with
//!   `end_on_overstrain` it ends the run after the first such step, like the strain
//!   watch outside the windows.
//! - `held`: a crack held by bonds that cannot break (the no-fail band, a refined
//!   window's coarse cells) after a converged step; recorded per step
//!   ([`StepResult::held`](crate::growth::records::StepResult::held)), noted per run of
//!   such steps, and the end of the run when the tracker sees no tip that a move could
//!   free.
//! - `join`: a tip that ended at a hole joins it in the BEM geometry (its crack runs on
//!   to the hole rim, [`join_name`]).

mod backoff;
mod ends;
mod held;
mod join;
mod run;
mod state;
mod step;

pub use join::join_name;

use pdbem_bem::post::sif::cmod;
use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::{PairCache, V2};
use pdbem_pd::crack_path::CrackPath;

use crate::error::CouplingError;
use crate::growth::fine_zone::protect_coarse;
use crate::growth::merge::resolve_overlaps;
use crate::growth::params::{check_bond_law, GrowthParams};
use crate::growth::polyline;
use crate::growth::records::{GrowthSetup, Scenario};
use crate::growth::tips::{entry_point, protect_band, towards_tip, track, TipEnd, TipState};
use crate::growth::transfer::{transfer_state, TransferInfo};
use crate::iteration::{CoupledProblem, CoupledSolution, PreparedBem};
use crate::relaxation::SecantColumns;
use crate::setup::{build, Layout};
use crate::window::{Body, Window};

/// A growth run in progress: the current geometry, its factored BEM system, the windows
/// and the tips. [`Growth::run`] drives it; [`Growth::solve_at`] and [`Growth::relocate`]
/// are its two moves, public for tests and studies.
pub struct Growth<'s, S: Scenario> {
    pub(super) scenario: &'s S,
    pub(super) params: GrowthParams,
    pub(super) setup: GrowthSetup,
    pub(super) body: Body,
    pub(super) problem: CoupledProblem,
    pub(super) bem: PreparedBem,
    pub(super) tips: Vec<TipState>,
    /// Interface state to start from and the load it belongs to.
    pub(super) start: Option<(Vec<f64>, f64)>,
    /// IQN-ILS secant columns of the last solve in the current load step, reused by the
    /// next solve of the step (after a relocation: by interface index, module docs).
    pub(super) secants: SecantColumns,
    pub(super) last: Option<CoupledSolution>,
    /// Arc length of each tip along its crack polyline at each record: (s, step, load).
    pub(super) progress: Vec<Vec<(f64, usize, f64)>>,
    /// Arc length of the initial tip along its crack (oriented towards the tip).
    pub(super) initial_s: Vec<f64>,
    /// Initial tip positions.
    pub(super) initial_tip: Vec<V2>,
    /// Tip positions before the last solve (where joined cracks are cut to meet).
    pub(super) before: Vec<V2>,
    pub(super) geometries: usize,
    /// Element-pair blocks of the last BEM assembly, reused by the next (relocations
    /// change only the crack faces near the tips and the window interfaces).
    pub(super) pairs: PairCache,
    /// Set by [`Growth::resume`]: the records and the step [`Growth::run`] goes on from.
    pub(super) resume_from: Option<state::ResumePoint>,
    /// Number of the scene's cracks: the layout's cracks after them join tips to holes
    /// ([`join_name`]).
    pub(super) scene_cracks: usize,
}

/// Builds mesh, windows (with their no-fail bands) and the factored BEM system of a
/// layout.
pub(super) fn build_geometry<S: Scenario>(
    layout: &Layout,
    setup: &GrowthSetup,
    scenario: &S,
    ratio: f64,
    pairs: &mut PairCache,
) -> Result<(CoupledProblem, PreparedBem), CouplingError> {
    let built = build(layout, |_, w| scenario.outer_conditions(w))?;
    let bcs =
        scenario
            .bem_conditions(&built.mesh)
            .map_err(|message| CouplingError::InvalidGrowth {
                field: "scenario",
                message,
            })?;
    let mut problem = CoupledProblem {
        mesh: built.mesh,
        material: setup.material,
        bcs,
        bem_params: setup.bem_params.clone(),
        background: setup.background,
        thickness: setup.thickness,
        windows: built.windows,
    };
    for wm in problem.windows.iter_mut() {
        protect_band(wm, ratio);
        protect_coarse(wm);
    }
    let bem = PreparedBem::with_cache(&mut problem, Some(pairs))?;
    Ok((problem, bem))
}

impl<'s, S: Scenario> Growth<'s, S> {
    /// Puts a rebuilt geometry (`layout`, its `problem` and `bem`) in place: every window
    /// of `problem` takes its state from the current windows and the BEM field of `sol`,
    /// the last solution on the current mesh ([`transfer_state`]); the coupling restarts
    /// at `load` from those interface values. Returns where each window's state came from.
    pub(super) fn install_geometry(
        &mut self,
        layout: Layout,
        mut problem: CoupledProblem,
        bem: PreparedBem,
        sol: &CoupledSolution,
        load: f64,
    ) -> Vec<TransferInfo> {
        let ev = FieldEvaluator::new(
            &self.problem.mesh,
            &self.problem.material,
            &sol.solution,
            self.problem.background,
        );
        let mut x0 = Vec::new();
        let mut infos = Vec::new();
        for wm in problem.windows.iter_mut() {
            let (x, info) = transfer_state(&self.problem.windows, &ev, wm, load);
            x0.extend(x);
            infos.push(info);
        }
        self.problem = problem;
        self.bem = bem;
        self.setup.layout = layout;
        self.start = Some((x0, load));
        // The secant columns belong to the old interface: measured on the tension plate,
        // reusing them by interface index saved 1-2 of the 8-9 first iterations of a
        // moved window but stalled the coupling (e near 1 for 40 iterations) once the
        // moved window cut the BEM body apart.
        self.secants = SecantColumns::default();
        self.geometries += 1;
        infos
    }

    /// Validates the parameters, builds the initial geometry and assigns the tips to
    /// their windows (overlapping windows merged).
    pub fn new(
        mut setup: GrowthSetup,
        scenario: &'s S,
        params: GrowthParams,
    ) -> Result<Self, CouplingError> {
        params.validate()?;
        check_bond_law(&setup.layout.pd.failure)?;
        let body = Body {
            outline: setup.layout.outline.points.clone(),
            holes: setup
                .layout
                .holes
                .iter()
                .map(|h| h.points.clone())
                .collect(),
        };
        let names: Vec<String> = setup.tips.iter().map(|t| t.name.clone()).collect();
        let mut owner = tip_windows(&setup, &body)?;
        resolve_overlaps(&mut setup.layout.windows, &mut owner, &names, &body)?;
        let mut pairs = PairCache::default();
        let (problem, bem) = build_geometry(
            &setup.layout,
            &setup,
            scenario,
            params.trigger_ratio,
            &mut pairs,
        )?;
        let mut tips = Vec::new();
        let mut initial_s = Vec::new();
        for (t, spec) in setup.tips.iter().enumerate() {
            let line = towards_tip(&setup.layout.cracks[spec.crack].points, spec.at_end);
            let w = &problem.windows[owner[t]].window;
            let (entry, macro_tip) = entry_point(w, &line, &spec.name)?;
            initial_s.push(pdbem_geometry::polyline_length(&line));
            tips.push(TipState {
                spec: spec.clone(),
                window: owner[t],
                entry,
                macro_tip,
                path: CrackPath {
                    points: vec![[entry.x, entry.y]],
                    ..Default::default()
                },
                ended: None,
            });
        }
        let n = tips.len();
        let scene_cracks = setup.layout.cracks.len();
        let initial_tip: Vec<V2> = tips.iter().map(|t| t.macro_tip).collect();
        let mut g = Growth {
            scenario,
            params,
            setup,
            body,
            problem,
            bem,
            tips,
            start: None,
            secants: SecantColumns::default(),
            last: None,
            progress: vec![Vec::new(); n],
            initial_s,
            before: initial_tip.clone(),
            initial_tip,
            geometries: 1,
            pairs,
            resume_from: None,
            scene_cracks,
        };
        g.retrace()?;
        Ok(g)
    }

    /// The current coupled problem (mesh, windows with their PD state).
    pub fn problem(&self) -> &CoupledProblem {
        &self.problem
    }

    /// The current macro layout.
    pub fn layout(&self) -> &Layout {
        &self.setup.layout
    }

    /// The tips.
    pub fn tips(&self) -> &[TipState] {
        &self.tips
    }

    /// The body (outline and holes).
    pub fn body(&self) -> &Body {
        &self.body
    }

    /// The last coupled solution (interface state and BEM solution) of the current
    /// geometry: None before the first solve and after a relocation until the next one.
    pub fn last_solution(&self) -> Option<&CoupledSolution> {
        self.last.as_ref()
    }

    /// Number of geometries built so far (1 + relocations with a rebuild).
    pub fn geometries(&self) -> usize {
        self.geometries
    }

    /// BEM unknowns of the current geometry (what `pdbem check` reports for it).
    pub fn bem_unknowns(&self) -> usize {
        self.bem.unknowns()
    }

    /// CMOD (m) of the crack named `crack` in the last solution (None without a solution
    /// or a mouth).
    pub fn cmod(&self, crack: &str) -> Option<f64> {
        let sol = self.last.as_ref()?;
        let i = self
            .problem
            .mesh
            .cracks
            .iter()
            .position(|c| c.name == crack)?;
        cmod(&self.problem.mesh, &sol.solution, i)
    }

    /// CMOD of the first crack of the mesh that has one.
    fn first_cmod(&self) -> Option<f64> {
        let sol = self.last.as_ref()?;
        (0..self.problem.mesh.cracks.len()).find_map(|i| cmod(&self.problem.mesh, &sol.solution, i))
    }

    /// The whole crack path of tip `t` from its initial position: the macro polyline from
    /// the initial tip to the window entry, then the traced PD path (ended on the outline
    /// by [`polyline::end_on_outline`] when the tip reached it); each point with the step
    /// and load at which the tip first reached it.
    pub fn tip_path(&self, t: usize) -> Vec<(V2, usize, f64)> {
        let w = &self.problem.windows[self.tips[t].window].window;
        let full = self.joined(t, self.traced_path(t)).0;
        let s0 = pdbem_geometry::polyline_project(&full, &self.initial_tip[t]);
        let total = pdbem_geometry::polyline_length(&full);
        let first = self.progress[t].first().map_or((0, 0.0), |p| (p.1, p.2));
        // The path starts at the initial tip itself: the traced PD path runs through
        // node positions, up to half a spacing beside the crack line (on the seed plate
        // its projection lay 0.049 m from the tip).
        let mut out = vec![(self.initial_tip[t], first.0, first.1)];
        let mut s = s0;
        let dx = w.spec.dx;
        while s + dx < total {
            s += dx;
            let (k, f) = self.progress[t]
                .iter()
                .find(|p| p.0 >= s - 1e-9)
                .or(self.progress[t].last())
                .map_or(first, |p| (p.1, p.2));
            out.push((pdbem_geometry::point_at(&full, s), k, f));
        }
        if total > s0 {
            let (k, f) = self.progress[t].last().map_or(first, |p| (p.1, p.2));
            out.push((pdbem_geometry::point_at(&full, total), k, f));
        }
        out
    }

    /// The macro polyline of tip `t` up to its window entry, then its traced PD path.
    fn traced_path(&self, t: usize) -> Vec<V2> {
        let tip = &self.tips[t];
        let line = towards_tip(
            &self.setup.layout.cracks[tip.spec.crack].points,
            tip.spec.at_end,
        );
        let w = &self.problem.windows[tip.window].window;
        let s_entry =
            polyline::entry_length(&line, w).unwrap_or(pdbem_geometry::polyline_length(&line));
        let mut full = polyline::head(&line, s_entry);
        full.extend(tip.path_points());
        full
    }

    /// Length (m) by which the reported path of tip `t` is continued beyond its traced
    /// path to reach the outline or hole it ended at ([`Self::joined`]; 0 for a tip
    /// still growing).
    pub fn join_length(&self, t: usize) -> f64 {
        self.joined(t, self.traced_path(t)).1
    }

    /// The path `full` of tip `t` ended on what the tip reached: on the outline by
    /// [`polyline::end_on_outline`] (the fan of the last horizon dropped), then joined to
    /// the outline or the hole it ended at by [`polyline::join_boundary`]; with the length
    /// that join added (m).
    pub fn joined(&self, t: usize, mut full: Vec<V2>) -> (Vec<V2>, f64) {
        let tip = &self.tips[t];
        let w = &self.problem.windows[tip.window].window;
        let chord = polyline::OUTLINE_CHORD_DX * w.spec.dx;
        let boundary = match &tip.ended {
            Some(TipEnd::Outline) => {
                full = polyline::end_on_outline(&full, &self.body.outline, w.delta(), chord);
                &self.body.outline
            }
            Some(TipEnd::Hole(name)) => {
                let names = self.hole_names();
                match names.iter().position(|n| n == name) {
                    Some(i) if i < self.body.holes.len() => &self.body.holes[i],
                    _ => return (full, 0.0),
                }
            }
            _ => return (full, 0.0),
        };
        polyline::join_boundary(&full, boundary, chord)
    }

    /// Arc length of tip `t` along its crack (polyline to the entry + traced path).
    fn tip_arc(&self, t: usize) -> f64 {
        let tip = &self.tips[t];
        let line = towards_tip(
            &self.setup.layout.cracks[tip.spec.crack].points,
            tip.spec.at_end,
        );
        let w = &self.problem.windows[tip.window].window;
        let s_entry = polyline::entry_length(&line, w).unwrap_or(0.0);
        if tip.path.is_empty() {
            pdbem_geometry::polyline_length(&line)
        } else {
            s_entry + tip.path.length
        }
    }

    fn record_progress(&mut self, step: usize, load: f64) {
        for t in 0..self.tips.len() {
            let s = self.tip_arc(t).max(self.initial_s[t]);
            self.progress[t].push((s, step, load));
        }
    }

    /// Traces every active tip in its window (a held crack down to a lower threshold,
    /// [`Growth::follow_held`]).
    pub(super) fn retrace(&mut self) -> Result<(), CouplingError> {
        for t in 0..self.tips.len() {
            if !self.tips[t].active() {
                continue;
            }
            let w = self.tips[t].window;
            self.tips[t].path = track(
                &self.problem.windows[w],
                w,
                self.tips[t].entry,
                &self.params.path,
            )?;
            self.follow_held(t)?;
        }
        Ok(())
    }
}
/// Window of every tip: the window containing its crack end.
fn tip_windows(setup: &GrowthSetup, body: &Body) -> Result<Vec<usize>, CouplingError> {
    setup
        .tips
        .iter()
        .map(|t| {
            let pts = &setup.layout.cracks[t.crack].points;
            let p = if t.at_end {
                *pts.last().expect("points")
            } else {
                pts[0]
            };
            setup
                .layout
                .windows
                .iter()
                .enumerate()
                .find(|(i, s)| {
                    Window::place(*i, (*s).clone(), body).is_ok_and(|w| w.contains(p, -1e-9))
                })
                .map(|(i, _)| i)
                .ok_or_else(|| CouplingError::Relocation {
                    tip: t.name.clone(),
                    reason: format!("no window contains the tip ({:.4}, {:.4})", p.x, p.y),
                })
        })
        .collect()
}
