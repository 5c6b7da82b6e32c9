//! Algorithm 2 of seed 002 (section 2.3.2, Fig. 8): load steps, each iterated by
//! Algorithm 1 on the current geometry, with the geometry iteration (section 2.3.3,
//! Fig. 9) whenever a tip passes its window margin.
//!
//! [`Growth::run`] does, for every load factor $f_k$ = `initial + k step`:
//! 1. Algorithm 1 at $f_k$ on the factored BEM system of the current geometry
//!    ([`crate::iteration::solve_prepared`], warm-started from the last interface state
//!    scaled to $f_k$). After every iteration the active tips are traced; a tip past its
//!    window margin or at the outline stops the iteration (step 6).
//! 2. Tips that reached the outline end the run (structural failure, step 9), as do two
//!    edge cracks that meet, or a tip past its margin for which no window around it fits
//!    inside the body (the outline is within the window's reach of a rotated window).
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
//!    go on.
//! 4. Otherwise the step converged (interface residual below psi and no bond broke in the
//!    last PD solves) and is recorded; the load grows.
//!
//! The scene-specific parts (BEM conditions of a mesh, conditions on window sides lying on
//! the outline, both at load factor 1) come from a [`Scenario`]; progress goes to an
//! [`Observer`], so the crate stays free of I/O.

use std::ops::ControlFlow;
use std::time::Instant;

use pdbem_bem::post::field::FieldEvaluator;
use pdbem_bem::post::sif::cmod;
use pdbem_bem::{PairCache, V2};
use pdbem_pd::crack_path::CrackPath;

use crate::error::CouplingError;
use crate::growth::merge::resolve_overlaps;
use crate::growth::overstrain::{self, Hotspot};
use crate::growth::params::GrowthParams;
use crate::growth::polyline;
use crate::growth::records::{
    Failure, GrowthResult, GrowthSetup, IterationEvent, Observer, Scenario, SolveOutcome,
    StepResult,
};
use crate::growth::tips::{
    cut_at_meeting, entry_point, joined, passed_margin, protect_band, ran_into, reached_boundary,
    towards_tip, track, TipEnd, TipState,
};
use crate::growth::topology::cuts_body;
use crate::iteration::{solve_prepared, CoupledProblem, CoupledSolution, PreparedBem, StepOptions};
use crate::setup::{build, Layout};
use crate::window::{Body, SideKind, Window};

/// Spread-out candidates of the strain watch per step ([`overstrain::search`]: at least
/// four horizons apart, then every sample within that distance of the four most strained
/// of them): the interior field costs one pass over the elements per sample, the ranking
/// none. Measured in [`overstrain`].
const OVERSTRAIN_SAMPLES: usize = 32;

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
    }
    let bem = PreparedBem::with_cache(&mut problem, Some(pairs))?;
    Ok((problem, bem))
}

impl<'s, S: Scenario> Growth<'s, S> {
    /// Validates the parameters, builds the initial geometry and assigns the tips to
    /// their windows (overlapping windows merged).
    pub fn new(
        mut setup: GrowthSetup,
        scenario: &'s S,
        params: GrowthParams,
    ) -> Result<Self, CouplingError> {
        params.validate()?;
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
            last: None,
            progress: vec![Vec::new(); n],
            initial_s,
            before: initial_tip.clone(),
            initial_tip,
            geometries: 1,
            pairs,
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

    /// BEM unknowns of the current geometry.
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

    /// The most strained point of the BEM body away from the windows in the last solution
    /// ([`overstrain`]; the field is evaluated at the [`OVERSTRAIN_SAMPLES`] samples behind
    /// the elements of largest boundary strain, and around the most strained of them);
    /// None without a solution, windows or a failure law.
    fn overstrain(&self) -> Option<Hotspot> {
        let sol = self.last.as_ref()?;
        let windows = &self.problem.windows;
        let first = windows.first()?;
        let delta = first.window.delta();
        let onset = Some(first.model.law().damage_onset()).filter(|s| s.is_finite())?;
        let mesh = &self.problem.mesh;
        let skip: Vec<usize> = windows
            .iter()
            .filter_map(|w| mesh.group(&w.group))
            .collect();
        let boxes: Vec<&Window> = windows.iter().map(|w| &w.window).collect();
        let tips: Vec<V2> = self.tips.iter().map(TipState::position).collect();
        let (w, h) = first.window.size();
        let clear = 0.5 * w.max(h);
        let samples = overstrain::sample_points(mesh, &skip, &boxes, &tips, delta, clear);
        let ranks = overstrain::boundary_strains(mesh, &self.problem.material, &sol.solution);
        let size = overstrain::SearchSize {
            candidates: OVERSTRAIN_SAMPLES,
            spread: 4.0 * delta,
            refined: 4,
        };
        let pb = &self.problem;
        let eval = FieldEvaluator::new(mesh, &pb.material, &sol.solution, pb.background);
        overstrain::search(&eval, &samples, &ranks, onset, size)
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
        if tip.ended == Some(TipEnd::Outline) {
            let chord = polyline::OUTLINE_CHORD_DX * w.spec.dx;
            full = polyline::end_on_outline(&full, &self.body.outline, w.delta(), chord);
        }
        let s0 = pdbem_geometry::polyline_project(&full, &self.initial_tip[t]);
        let total = pdbem_geometry::polyline_length(&full);
        let first = self.progress[t].first().map_or((0, 0.0), |p| (p.1, p.2));
        let mut out = vec![(pdbem_geometry::point_at(&full, s0), first.0, first.1)];
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

    /// Traces every active tip in its window.
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
        }
        Ok(())
    }

    /// Algorithm 1 at load factor `load` on the current geometry (step `step`, for the
    /// observer), stopped early when a tip needs attention (past its window margin or at
    /// the outline or a hole). Updates the tips' traces.
    pub fn solve_at(
        &mut self,
        step: usize,
        load: f64,
        observer: &mut dyn Observer,
    ) -> Result<SolveOutcome, CouplingError> {
        let start = self
            .start
            .as_ref()
            .map(|(x, f)| x.iter().map(|v| v * load / f).collect());
        let holes = self.hole_names();
        let tips = &self.tips;
        let (body, params) = (&self.body, &self.params);
        let mut positions: Vec<V2> = tips.iter().map(TipState::position).collect();
        let mut trace_error: Option<CouplingError> = None;
        let mut monitor = |rep: &crate::iteration::IterationReport<'_>| {
            let mut stop = false;
            for (t, tip) in tips.iter().enumerate().filter(|(_, t)| t.active()) {
                let wm = &rep.windows[tip.window];
                match track(wm, tip.window, tip.entry, &params.path) {
                    Ok(p) if !p.is_empty() => {
                        positions[t] = V2::new(p.tip()[0], p.tip()[1]);
                        stop |= needs_attention(
                            &wm.window,
                            tip.entry,
                            positions[t],
                            (body, &holes),
                            params,
                        );
                    }
                    Ok(_) => {}
                    Err(e) => {
                        trace_error = Some(e);
                        stop = true;
                    }
                }
            }
            observer.iteration(&IterationEvent {
                step,
                load,
                iteration: rep.iteration,
                residual: rep.residual,
                bonds_broken: rep.bonds_broken,
                tips: &positions,
            });
            if stop {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        };
        let opts = StepOptions {
            load_scale: load,
            start,
            monitor: Some(&mut monitor),
        };
        let (sol, info) = solve_prepared(&mut self.problem, &self.bem, &params.coupling, opts)?;
        if let Some(e) = trace_error {
            return Err(e);
        }
        self.start = Some((sol.x_pd.clone(), load));
        self.last = Some(sol);
        self.before = self.tips.iter().map(TipState::position).collect();
        self.retrace()?;
        Ok(SolveOutcome {
            converged: info.converged,
            iterations: info.iterations,
            residual: info.residuals.last().copied().unwrap_or(f64::NAN),
            bonds_broken: info.bonds_broken.iter().sum(),
            pd_s: info.timings.pd_s,
        })
    }

    /// Ends tips that reached the outline, a hole or another crack; returns the tip that
    /// cut the body (reached the outline), if any.
    fn end_tips(&mut self, observer: &mut dyn Observer) -> Option<usize> {
        let mut cut = None;
        let holes = self.hole_names();
        for t in 0..self.tips.len() {
            if !self.tips[t].active() || self.tips[t].path.is_empty() {
                continue;
            }
            let dx = self.problem.windows[self.tips[t].window].window.spec.dx;
            let reach = self.params.boundary_reach * dx;
            let p = self.tips[t].position();
            let mut met = None;
            let end = reached_boundary(&self.body, &holes, p, reach).or_else(|| {
                let wm = &self.problem.windows[self.tips[t].window];
                self.tips
                    .iter()
                    .enumerate()
                    .filter(|&(o, other)| o != t && other.window == self.tips[t].window)
                    .find(|(_, other)| ran_into(&self.tips[t], other, wm.model.positions(), reach))
                    .map(|(o, other)| {
                        if joined(&self.tips[t], other) {
                            met = Some(o);
                        }
                        TipEnd::Coalescence(other.spec.name.clone())
                    })
            });
            if let Some(o) = met {
                let (before, other_before) = (self.before[t], self.before[o]);
                cut_at_meeting(&mut self.tips[t], before, other_before);
            }
            let p = self.tips[t].position();
            if let Some(end) = end {
                let msg = format!(
                    "tip {} ended at ({:.4}, {:.4}): reached {end}",
                    self.tips[t].spec.name, p.x, p.y
                );
                observer.note(&msg);
                let cuts = match &end {
                    TipEnd::Outline => true,
                    TipEnd::Coalescence(other) => self.joins_outline(t, other),
                    TipEnd::Hole(_) => false,
                };
                if cuts && cut.is_none() {
                    cut = Some(t);
                }
                self.tips[t].ended = Some(end);
            }
        }
        cut
    }

    /// Whether tip `t` running into the crack of tip `other` joins two cracks that both
    /// start on the outline (two edge cracks meeting cut the body).
    fn joins_outline(&self, t: usize, other: &str) -> bool {
        let on_outline = |tip: &TipState| {
            let line = towards_tip(
                &self.setup.layout.cracks[tip.spec.crack].points,
                tip.spec.at_end,
            );
            let tol = self.problem.windows[tip.window].window.tol().max(1e-12);
            pdbem_geometry::polygon_distance(&line[0], &self.body.outline) <= tol
        };
        let Some(o) = self.tips.iter().find(|o| o.spec.name == other) else {
            return false;
        };
        on_outline(&self.tips[t]) && on_outline(o)
    }

    /// When the coupling breaks down (diverges or stops converging) while the remaining
    /// ligament of a part of the body lies in PD, that ligament has given way (the load
    /// exceeds what it carries; under load control no equilibrium is left):
    /// - the cracks and windows cut the BEM body apart ([`cuts_body`]): the first active
    ///   tip in a window;
    /// - or a tip's window lies on the outline and the tip is closer to it than the
    ///   crack's entry into the window (the crack runs towards the outline through PD):
    ///   that tip.
    ///
    /// Otherwise None. Returns the tip and a one-line account of the breakdown.
    fn ligament_gave_way(&self, e: &CouplingError) -> Option<(usize, String)> {
        let what = match e {
            CouplingError::Diverged {
                reason, iterations, ..
            } => format!("coupling diverged after {iterations} iterations: {reason}"),
            CouplingError::NoConvergence {
                iterations, last, ..
            } => format!("coupling residual {last:.3e} after {iterations} iterations"),
            _ => return None,
        };
        if cuts_body(&self.setup.layout, &self.body) {
            let t = self.tips.iter().position(TipState::active)?;
            return Some((t, what));
        }
        let t = (0..self.tips.len()).find(|&t| self.runs_to_outline_in_pd(t))?;
        Some((t, what))
    }

    /// Whether active tip `t` lies in a window on the outline and is closer to the
    /// outline than its crack's entry into that window.
    fn runs_to_outline_in_pd(&self, t: usize) -> bool {
        let tip = &self.tips[t];
        let w = &self.problem.windows[tip.window].window;
        let to_outline = |p: V2| pdbem_geometry::polygon_distance(&p, &self.body.outline);
        tip.active()
            && w.sides.contains(&SideKind::Outer)
            && to_outline(tip.position()) < to_outline(tip.entry)
    }

    /// A note for every active tip whose window has damage just under the threshold
    /// reaching more than [`UNDER_THRESHOLD_REACH`] dx beyond the tracked tip: the crack
    /// ran on but the tracker did not follow it (the window never moves). On the regular
    /// lattice with m = 3 a node beside a straight crack between two node rows has
    /// damage 0.409 once every bond across is broken, but 0.365 while the bonds reaching
    /// three rows across still hold, which is what a crack opening of less than
    /// 3 dx s0 leaves (small strains). The 0.38 threshold of seed 002 then misses the
    /// crack; the note points to `growth.damage_threshold`.
    fn damage_beyond_tips(&self) -> Vec<String> {
        let mut notes = Vec::new();
        for tip in self.tips.iter().filter(|t| t.active()) {
            let wm = &self.problem.windows[tip.window];
            let mut low = self.params.path;
            low.threshold *= UNDER_THRESHOLD_FACTOR;
            let Ok(wide) = track(wm, tip.window, tip.entry, &low) else {
                continue;
            };
            let beyond = wide.length - tip.path.length;
            let dx = wm.window.spec.dx;
            if beyond > UNDER_THRESHOLD_REACH * dx {
                notes.push(format!(
                    "tip {}: damage above {:.3} (but under the tracking threshold {}) \
                     reaches {:.3e} m = {:.1} dx beyond the tracked tip; the crack ran on \
                     without the tracker following it. Lower growth.damage_threshold \
                     (a fresh crack between node rows has damage about 0.365 at m = 3)",
                    tip.spec.name,
                    low.threshold,
                    self.params.path.threshold,
                    beyond,
                    beyond / dx
                ));
            }
        }
        notes
    }

    /// Tips past their window margin.
    fn triggered(&self) -> Vec<usize> {
        (0..self.tips.len())
            .filter(|&t| {
                let tip = &self.tips[t];
                let w = &self.problem.windows[tip.window].window;
                tip.active()
                    && !tip.path.is_empty()
                    && passed_margin(w, tip.position(), tip.entry, self.params.trigger_ratio)
            })
            .collect()
    }

    /// Broken bond pairs over all windows.
    fn broken_bonds(&self) -> usize {
        self.problem
            .windows
            .iter()
            .map(|w| w.model.broken_bonds())
            .sum()
    }

    /// Runs Algorithm 2 (see the module docs).
    pub fn run(&mut self, observer: &mut dyn Observer) -> Result<GrowthResult, CouplingError> {
        let mut out = GrowthResult::default();
        self.record_progress(0, self.params.loads.initial);
        for k in 0..self.params.loads.count {
            let load = self.params.loads.factor(k);
            let t0 = Instant::now();
            let (mut iterations, mut pd_s, mut relocations) = (0, 0.0, 0);
            let mut gave_way = false;
            let (converged, residual, cut) = loop {
                let o = match self.solve_at(k, load, observer) {
                    Ok(o) => o,
                    Err(e) => match self.ligament_gave_way(&e) {
                        Some((t, what)) => {
                            observer.note(&format!(
                                "step {k} (load {load}): the PD ligament ahead of tip {} \
                                 gave way ({what}): structural failure",
                                self.tips[t].spec.name
                            ));
                            gave_way = true;
                            break (false, f64::NAN, Some(t));
                        }
                        None => return Err(step_error(k, load, e)),
                    },
                };
                iterations += o.iterations;
                pd_s += o.pd_s;
                if o.bonds_broken > 0 && out.initiation_load.is_none() {
                    out.initiation_load = Some(load);
                }
                if let Some(t) = self.end_tips(observer) {
                    break (false, o.residual, Some(t));
                }
                let which = self.triggered();
                if which.is_empty() {
                    if o.converged {
                        break (true, o.residual, None);
                    }
                    // Stopped for a tip that has now ended: iterate on with the others.
                    continue;
                }
                if relocations >= self.params.max_relocations_per_step {
                    return Err(CouplingError::Relocation {
                        tip: self.tips[which[0]].spec.name.clone(),
                        reason: format!(
                            "more than {relocations} relocations in step {k} (load {load}); lower the load step"
                        ),
                    });
                }
                self.record_progress(k, load);
                let plan = self.plan(&which)?;
                if let Some(&t) = plan.at_outline.first() {
                    let p = self.tips[t].position();
                    observer.note(&format!(
                        "tip {} at ({:.4}, {:.4}): no window around it fits inside the body, \
                         the outer boundary is within the window's reach: the crack reaches \
                         it, structural failure",
                        self.tips[t].spec.name, p.x, p.y
                    ));
                    self.tips[t].ended = Some(TipEnd::Outline);
                    break (false, o.residual, Some(t));
                }
                if plan.cuts_body {
                    let t = which[0];
                    let p = self.tips[t].position();
                    observer.note(&format!(
                        "tip {} at ({:.4}, {:.4}): its moved window reaches the outline and \
                         the cracks cut the BEM body apart; the windows alone hold the \
                         cut-off part",
                        self.tips[t].spec.name, p.x, p.y
                    ));
                }
                let recs = self.apply(plan, k, load, observer)?;
                if recs.is_empty() {
                    // Every triggered tip ended at a hole: iterate on with the others.
                    if o.converged || self.tips.iter().all(|t| !t.active()) {
                        break (o.converged, o.residual, None);
                    }
                    continue;
                }
                relocations += recs.len();
                out.relocations.extend(recs);
            };
            self.record_progress(k, load);
            let rec = StepResult {
                step: k,
                load,
                iterations,
                residual,
                converged,
                broken_bonds: self.broken_bonds(),
                tips: self.tips.iter().map(TipState::position).collect(),
                // The last solution of a step whose ligament gave way is not an equilibrium.
                cmod: if gave_way { None } else { self.first_cmod() },
                relocations,
                wall_s: t0.elapsed().as_secs_f64(),
                pd_s,
                // Only an equilibrium says how strained the body is.
                overstrain: if converged { self.overstrain() } else { None },
            };
            observer.step(&rec);
            observer.state(&rec, &self.problem, self.last.as_ref());
            out.steps.push(rec);
            if let Some(t) = cut {
                let name = self.tips[t].spec.name.clone();
                out.notes.push(if gave_way {
                    format!(
                        "structural failure at step {k} (load {load}): the PD ligament at tip \
                         {name} gave way (the coupling broke down with the remaining ligament in \
                         the window)"
                    )
                } else if let Some(TipEnd::Coalescence(other)) = &self.tips[t].ended {
                    format!(
                        "structural failure at step {k} (load {load}): tip {name} joined the \
                         crack of tip {other}; both cracks start on the outer boundary, so \
                         together they cut the body"
                    )
                } else {
                    format!(
                        "structural failure at step {k} (load {load}): tip {name} reached the \
                         outer boundary"
                    )
                });
                out.failure = Some(Failure {
                    step: k,
                    load,
                    tip: name,
                });
                break;
            }
            if self.tips.iter().all(|t| !t.active()) {
                out.notes
                    .push(format!("every tip ended by step {k} (load {load})"));
                break;
            }
        }
        for t in &self.tips {
            if let Some(e) = &t.ended {
                out.notes.push(format!("tip {} ended: {e}", t.spec.name));
            }
        }
        out.notes.extend(self.damage_beyond_tips());
        Ok(out)
    }
}

/// Fraction of the damage threshold down to which [`Growth::damage_beyond_tips`] looks.
const UNDER_THRESHOLD_FACTOR: f64 = 0.8;

/// Reach beyond the tracked tip (dx) at which [`Growth::damage_beyond_tips`] notes it.
const UNDER_THRESHOLD_REACH: f64 = 3.0;

/// Whether a traced tip at `p` (entry `entry`) in `w` is past the margin or at the outline
/// or a hole (`body` with its hole names).
fn needs_attention(
    w: &Window,
    entry: V2,
    p: V2,
    (body, holes): (&Body, &[String]),
    params: &GrowthParams,
) -> bool {
    passed_margin(w, p, entry, params.trigger_ratio)
        || reached_boundary(body, holes, p, params.boundary_reach * w.spec.dx).is_some()
}

/// Adds the step and load to an error of a step.
fn step_error(step: usize, load: f64, e: CouplingError) -> CouplingError {
    match e {
        CouplingError::NoConvergence { .. } | CouplingError::Diverged { .. } => {
            CouplingError::InvalidStep {
                message: format!("load step {step} (load factor {load}): {e}"),
            }
        }
        other => other,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::fixtures::{plate_setup, PlateScenario};
    use crate::growth::params::LoadSteps;

    /// Collects the notes.
    #[derive(Default)]
    struct Notes(Vec<String>);

    impl Observer for Notes {
        fn note(&mut self, message: &str) {
            self.0.push(message.to_string());
        }
    }

    /// A 10 m x 5 m plate with an edge crack from (5, 0) up to (5, `tip_y`), its window
    /// (1 m) centred at (5, `window_y`).
    fn edge_crack_plate(tip_y: f64, window_y: f64) -> Growth<'static, PlateScenario> {
        let crack = vec![V2::new(5.0, 0.0), V2::new(5.0, tip_y)];
        let mut setup = plate_setup((10.0, 5.0), vec![], vec![crack], Some(3e-3));
        setup.layout.windows[0].center = V2::new(5.0, window_y);
        let loads = LoadSteps {
            initial: 1.0,
            step: 0.5,
            count: 1,
        };
        Growth::new(setup, &PlateScenario, GrowthParams::new(loads, 0.5)).unwrap()
    }

    #[test]
    fn a_coupling_breakdown_while_the_crack_runs_to_the_outline_in_pd_ends_the_run() {
        let stall = CouplingError::NoConvergence {
            iterations: 50,
            last: 2e-3,
            psi: 1e-4,
            residuals: vec![],
        };
        // The window's top side lies on the top edge; the tip (0.7 m from it) is nearer
        // to it than the crack's entry at the window's bottom (1 m): the ligament ahead
        // of the tip is in PD, and a stall means it gave way.
        let g = edge_crack_plate(4.3, 4.5);
        assert!(g.problem.windows[0].window.sides.contains(&SideKind::Outer));
        let (t, what) = g.ligament_gave_way(&stall).expect("the ligament gave way");
        assert_eq!(t, 0);
        assert!(
            what.contains("coupling residual 2.000e-3 after 50 iterations"),
            "{what}"
        );
        // Other errors are not a breakdown of the coupling.
        let other = CouplingError::InvalidStep {
            message: "bad".into(),
        };
        assert!(g.ligament_gave_way(&other).is_none());
        // The window inside the body: the ligament is in BEM, the stall is an error.
        let inside = edge_crack_plate(3.0, 3.0);
        assert!(!inside.problem.windows[0]
            .window
            .sides
            .contains(&SideKind::Outer));
        assert!(inside.ligament_gave_way(&stall).is_none());
    }

    #[test]
    fn tip_growing_into_a_hole_ends_there() {
        // A 10 m x 5 m plate pulled along x, an edge crack from (5, 0) up to (5, 1.5) and
        // a hole of radius 0.5 m centred at (5, 3.3) straight ahead. The 1 m window
        // follows the crack up until it cannot move on without covering the hole.
        let hole: Vec<V2> = (0..16)
            .map(|k| {
                let a = -(k as f64) * std::f64::consts::TAU / 16.0;
                V2::new(5.0 + 0.5 * a.cos(), 3.3 + 0.5 * a.sin())
            })
            .collect();
        let setup = plate_setup(
            (10.0, 5.0),
            vec![hole],
            vec![vec![V2::new(5.0, 0.0), V2::new(5.0, 1.5)]],
            Some(3e-3),
        );
        let loads = LoadSteps {
            initial: 1.0,
            step: 0.5,
            count: 4,
        };
        let mut params = GrowthParams::new(loads, 0.5);
        // The scenes' relaxation (Aitken from 0.3 diverges here once bonds break).
        params.coupling.acceleration = crate::iteration::Acceleration::IqnIls(0.5);
        let mut g = Growth::new(setup, &PlateScenario, params).unwrap();
        let mut notes = Notes::default();
        let out = g.run(&mut notes).unwrap();
        // Measured: the window moves three times in step 0 (the tip at y = 1.725, 1.975,
        // 2.225); with the tip at y = 2.525 the next window would cover the hole, whose
        // lowest point is at y = 2.8.
        assert_eq!(g.tips()[0].ended, Some(TipEnd::Hole("hole0".into())));
        let tip = g.tips()[0].position();
        assert!(tip.y > 2.0 && tip.y < 2.8, "tip at {tip:?}");
        assert!(out.failure.is_none());
        assert!(!out.relocations.is_empty());
        assert!(
            notes
                .0
                .iter()
                .any(|n| n.contains("c0.end") && n.contains("hole0")),
            "{:?}",
            notes.0
        );
        assert!(
            out.notes.iter().any(|n| n.contains("every tip ended")),
            "{:?}",
            out.notes
        );
    }
}
