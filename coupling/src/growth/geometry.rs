//! The geometry iteration of Algorithm 2 on a [`Growth`] run (seed 002 section 2.3.3,
//! Fig. 9, Algorithm 2 steps 7 and 10): [`Growth::plan`] works out the moved windows
//! ([`crate::growth::relocate::moved_spec`]; a window holding several moved tips covers
//! all of them), the extended cracks ([`crate::growth::relocate::extend_crack`]), the
//! merges, the tips whose window a hole stops, and whether the result would cut the BEM
//! body ([`crate::growth::topology`]); [`Growth::apply`] rebuilds mesh,
//! BEM factorization and windows and transfers the state
//! ([`crate::growth::transfer`]).

use std::time::Instant;

use pdbem_bem::V2;

use crate::error::CouplingError;
use crate::growth::driver::{build_geometry, Growth};
use crate::growth::fine_zone;
use crate::growth::merge::{cover_box, merge_specs, resolve_overlaps};
use crate::growth::observer::Observer;
use crate::growth::polyline;
use crate::growth::records::{RelocationPlan, RelocationRecord, Scenario};
use crate::growth::relocate::{extend_crack, moved_spec, turned_to_outline};
use crate::growth::tips::{
    entry_point, hole_name, margins, passed_margin, towards_tip, TipEnd, TipState,
};
use crate::growth::topology::cuts_body;
use crate::setup::Layout;
use crate::window::{Window, WindowSpec};

/// Per moved tip: (tip, (old window centre, tip position, BEM elements added per face)).
type Moves = Vec<(usize, (V2, V2, usize))>;

/// What [`Growth::plan_window`] decides: moves, tips blocked by a hole (with its name),
/// tips at the outline.
type WindowPlan = (Moves, Vec<(usize, String)>, Vec<usize>);

impl<S: Scenario> Growth<'_, S> {
    /// The geometry of the next relocation of tips `which`: windows moved along the growth
    /// directions, cracks extended along the traced paths, overlapping windows merged.
    /// Nothing changes until [`Growth::apply`].
    ///
    /// The tips of one window move it together: each gives a moved window
    /// ([`moved_spec`]); the new window is the smallest rectangle covering all of them and,
    /// for the window's other tips, their entry and the trigger distance around them within
    /// the old window ([`cover_box`]); every moved tip's crack is then extended into that
    /// window. A tip whose moved window would lie over a hole is left out and ends at the
    /// hole ([`RelocationPlan::blocked`]); if the covering window lies over a hole, all
    /// the window's moved tips do. A tip for which no window containing it with its margin
    /// fits inside the body (the outline is closer than the window's reach, e.g. a rotated
    /// window near an edge) has reached the outline ([`RelocationPlan::at_outline`]).
    pub fn plan(&self, which: &[usize]) -> Result<RelocationPlan, CouplingError> {
        let mut layout = self.setup.layout.clone();
        let mut moves = Vec::new();
        let mut blocked = Vec::new();
        let mut at_outline = Vec::new();
        let mut windows: Vec<usize> = Vec::new();
        for &t in which {
            if !windows.contains(&self.tips[t].window) {
                windows.push(self.tips[t].window);
            }
        }
        for w in windows {
            let group: Vec<usize> = which
                .iter()
                .copied()
                .filter(|&t| self.tips[t].window == w)
                .collect();
            let (m, b, o) = self.plan_window(w, &group, &mut layout)?;
            moves.extend(m);
            blocked.extend(b);
            at_outline.extend(o);
        }
        let names: Vec<String> = self.tips.iter().map(|t| t.spec.name.clone()).collect();
        let mut owner: Vec<usize> = self.tips.iter().map(|t| t.window).collect();
        let merges = resolve_overlaps(&mut layout.windows, &mut owner, &names, &self.body)?;
        let cuts_body = !moves.is_empty() && cuts_body(&layout, &self.body);
        Ok(RelocationPlan {
            layout,
            owner,
            moves,
            blocked,
            at_outline,
            merges,
            cuts_body,
        })
    }

    /// Carries out a relocation plan at load `load` (step `step`): blocked tips ended at
    /// their hole (noted through the observer), then, unless no tip moves, mesh rebuilt and
    /// refactored, windows rebuilt with their state transferred, tips re-traced. Returns
    /// one record per relocated tip (none when every tip was blocked).
    pub fn apply(
        &mut self,
        plan: RelocationPlan,
        step: usize,
        load: f64,
        observer: &mut dyn Observer,
    ) -> Result<Vec<RelocationRecord>, CouplingError> {
        let t0 = Instant::now();
        let names: Vec<String> = self.tips.iter().map(|t| t.spec.name.clone()).collect();
        for (t, hole) in &plan.blocked {
            let p = self.tips[*t].position();
            observer.note(&format!(
                "tip {} ended at ({:.4}, {:.4}): its window cannot move on, hole {hole} is in \
                 the way",
                names[*t], p.x, p.y
            ));
            self.tips[*t].ended = Some(TipEnd::Hole(hole.clone()));
        }
        if plan.moves.is_empty() {
            return Ok(Vec::new());
        }
        observer.before_relocation(step, &self.problem.windows);
        if plan.merges > 0 {
            observer.note(&format!(
                "step {step}: {} window merge(s) after relocating {:?}",
                plan.merges,
                plan.moves
                    .iter()
                    .map(|m| names[m.0].as_str())
                    .collect::<Vec<_>>()
            ));
        }
        let RelocationPlan {
            layout,
            owner,
            moves,
            ..
        } = plan;
        let (problem, bem) = build_geometry(
            &layout,
            &self.setup,
            self.scenario,
            self.params.trigger_ratio,
            &mut self.pairs,
        )?;
        // The last solution belongs to the old mesh: it serves the transfer and goes, so
        // nothing pairs it with the new mesh (element indices differ).
        let sol = self.last.take().ok_or_else(|| CouplingError::Relocation {
            tip: moves
                .first()
                .map_or_else(String::new, |m| names[m.0].clone()),
            reason: "no solution to take the new window's state from".into(),
        })?;
        let old_paths: Vec<Vec<V2>> = self.tips.iter().map(TipState::path_points).collect();
        let old_windows: Vec<Window> = (self.tips.iter())
            .map(|tip| self.problem.windows[tip.window].window.clone())
            .collect();
        let infos = self.install_geometry(layout, problem, bem, &sol, load);
        for (t, &o) in owner.iter().enumerate() {
            self.tips[t].window = o;
            let spec = &self.tips[t].spec;
            let line = towards_tip(&self.setup.layout.cracks[spec.crack].points, spec.at_end);
            let (entry, macro_tip) =
                entry_point(&self.problem.windows[o].window, &line, &spec.name)?;
            self.tips[t].entry = entry;
            self.tips[t].macro_tip = macro_tip;
        }
        self.retrace()?;
        for (t, _) in &moves {
            self.check_precrack_in_fine_cells(*t)?;
        }
        let shared_by = moves.len();
        let rebuild_s = t0.elapsed().as_secs_f64() / shared_by as f64;
        let mut records = Vec::new();
        for (t, (from, tip_at, added)) in moves {
            let w = self.tips[t].window;
            let new = &self.problem.windows[w].window;
            let turned_deg = new.turned_from(&old_windows[t]).then(|| {
                [
                    old_windows[t].spec.angle.to_degrees(),
                    new.spec.angle.to_degrees(),
                ]
            });
            let rec = RelocationRecord {
                step,
                load,
                tip: names[t].clone(),
                from,
                to: self.problem.windows[w].window.spec.center,
                tip_at,
                elements_added: added,
                precrack_deviation: max_distance(&self.tips[t].path_points(), &old_paths[t]),
                transfer: infos[w],
                corners: self.problem.windows[w].window.corners(),
                turned_deg,
                elements: self.problem.mesh.len(),
                rebuild_s,
                rebuild_shared_by: shared_by,
                bem_assembly_s: self.bem.assembly_s(),
                bem_factor_s: self.bem.factor_s(),
                bem_pairs_reused: self.bem.reused_pairs() as f64
                    / (self.problem.mesh.len() as f64).powi(2),
            };
            if let Some(note) = turn_note(&rec) {
                observer.note(&note);
            }
            observer.relocation(&rec);
            records.push(rec);
        }
        Ok(records)
    }

    /// A moved refined window's pre-crack must end in its fine cells
    /// ([`fine_zone::precrack_in_fine_cells`]; the reason: [`fine_zone::outside_reason`]).
    fn check_precrack_in_fine_cells(&self, t: usize) -> Result<(), CouplingError> {
        let tip = &self.tips[t];
        let wm = &self.problem.windows[tip.window];
        let (Some(r), false) = (
            self.setup.layout.pd.refine,
            fine_zone::precrack_in_fine_cells(wm, tip.macro_tip),
        ) else {
            return Ok(());
        };
        Err(CouplingError::Relocation {
            tip: tip.spec.name.clone(),
            reason: fine_zone::outside_reason(
                &wm.window,
                tip.macro_tip,
                r,
                self.params.move_distance,
            ),
        })
    }

    /// [`Growth::plan`] then [`Growth::apply`] for tips `which`.
    pub fn relocate(
        &mut self,
        which: &[usize],
        step: usize,
        load: f64,
        observer: &mut dyn Observer,
    ) -> Result<Vec<RelocationRecord>, CouplingError> {
        let plan = self.plan(which)?;
        self.apply(plan, step, load, observer)
    }

    /// Growth direction of tip `t` (unit): the chord of its traced path over the direction
    /// length, else the last crack segment.
    fn growth_direction(&self, t: usize, line: &[V2]) -> Result<V2, CouplingError> {
        let tip = &self.tips[t];
        let dx = self.problem.windows[tip.window].window.spec.dx;
        tip.path
            .tip_direction(self.params.direction_length * dx)
            .map(|d| V2::new(d[0], d[1]))
            .or_else(|| polyline::unit(line[line.len() - 2], line[line.len() - 1]))
            .ok_or_else(|| CouplingError::Relocation {
                tip: tip.spec.name.clone(),
                reason: "no growth direction (zero-length path and crack end)".into(),
            })
    }

    /// The unchanged spec of window `w` when its tip `t` triggered at the end of its fine
    /// cells (not at its margin) in a window against the outline whose refinement zone
    /// then moves on ([`fine_zone::zone_moves_on`]): the window is rebuilt where it is,
    /// its pre-crack extended along the traced path and its zone re-centred on the tip
    /// (a re-zoning, recorded as a relocation from the window's centre to itself). Such a
    /// window cannot move on towards the outline, and its zone must follow the tip to the
    /// free edge the crack runs to (module docs of [`fine_zone`]).
    fn rezone_in_place(&self, w: usize, t: usize) -> Option<WindowSpec> {
        let wm = &self.problem.windows[w];
        let r = self.setup.layout.pd.refine?;
        let tip = &self.tips[t];
        let at_margin = passed_margin(
            &wm.window,
            tip.position(),
            tip.entry,
            self.params.trigger_ratio,
        );
        (fine_zone::against_outline(wm)
            && !at_margin
            && fine_zone::zone_moves_on(wm, r, &tip.path_points()).is_some())
        .then(|| wm.window.spec.clone())
    }

    /// Moves window `w` for its triggered tips `group` (see [`Growth::plan`]): the new
    /// window and the extended cracks are written into `layout`. Returns per moved tip
    /// (tip, (old window centre, tip position, BEM elements added per face)), the tips
    /// blocked by a hole with the hole's name, and the tips at the outline (no window
    /// around them fits in the body).
    fn plan_window(
        &self,
        w: usize,
        group: &[usize],
        layout: &mut Layout,
    ) -> Result<WindowPlan, CouplingError> {
        let old = &self.problem.windows[w].window;
        let dx = old.spec.dx;
        let holes = self.hole_names();
        let mut blocked = Vec::new();
        let mut at_outline = Vec::new();
        let mut specs: Vec<WindowSpec> = Vec::new();
        let mut movers = Vec::new();
        for &t in group {
            if let Some(spec) = self.rezone_in_place(w, t) {
                specs.push(spec);
                movers.push(t);
                continue;
            }
            let tip = &self.tips[t];
            let line = towards_tip(
                &self.setup.layout.cracks[tip.spec.crack].points,
                tip.spec.at_end,
            );
            let dir = self.growth_direction(t, &line)?;
            match moved_spec(
                old,
                tip.position(),
                dir,
                self.params.move_distance,
                self.params.trigger_ratio,
                &self.body,
                &tip.spec.name,
            ) {
                Ok(s) => {
                    specs.push(match self.setup.layout.pd.refine {
                        Some(r) => fine_zone::follow_tip(
                            old,
                            s,
                            tip.position(),
                            dir,
                            r,
                            &self.body,
                            self.params.trigger_ratio,
                        ),
                        None => s,
                    });
                    movers.push(t);
                }
                Err(CouplingError::OverHole { hole, .. }) => {
                    blocked.push((t, hole_name(&holes, hole)));
                }
                Err(CouplingError::OutsideBody { .. } | CouplingError::CrossesBoundary { .. }) => {
                    match self.turned_at_outline(w, t, dir) {
                        Some(s) => {
                            specs.push(s);
                            movers.push(t);
                        }
                        None => at_outline.push(t),
                    }
                }
                Err(e) => return Err(e),
            }
        }
        let Some(first) = specs.first() else {
            return Ok((Vec::new(), blocked, at_outline));
        };
        let mut spec = first.clone();
        for s in &specs[1..] {
            spec = merge_specs(&spec, s).map_err(|reason| CouplingError::Relocation {
                tip: self.tips[movers[0]].spec.name.clone(),
                reason,
            })?;
        }
        let (_, trigger) = margins(old, self.params.trigger_ratio);
        for (t, tip) in self.tips.iter().enumerate() {
            if tip.window == w && !movers.contains(&t) {
                spec = cover_box(&spec, old, tip.position(), tip.entry, trigger);
            }
        }
        let new = match Window::place(w, spec.clone(), &self.body) {
            Ok(n) => n,
            Err(CouplingError::OverHole { hole, .. }) => {
                let h = hole_name(&holes, hole);
                blocked.extend(movers.iter().map(|&t| (t, h.clone())));
                return Ok((Vec::new(), blocked, at_outline));
            }
            Err(CouplingError::OutsideBody { .. } | CouplingError::CrossesBoundary { .. }) => {
                at_outline.extend(movers.iter().copied());
                return Ok((Vec::new(), blocked, at_outline));
            }
            Err(e) => {
                return Err(CouplingError::Relocation {
                    tip: self.tips[movers[0]].spec.name.clone(),
                    reason: format!(
                        "the moved window centred at ({:.4}, {:.4}) ({} x {} nodes) is not \
                         admissible: {e}",
                        spec.center.x, spec.center.y, spec.nx, spec.ny
                    ),
                })
            }
        };
        let mut moves = Moves::new();
        for &t in &movers {
            let tip = &self.tips[t];
            let crack = &layout.cracks[tip.spec.crack];
            let line = towards_tip(&crack.points, tip.spec.at_end);
            let s_entry = polyline::entry_length(&line, old).unwrap_or(0.0);
            // Until its first extension a crack is meshed by size (capped at dx in windows).
            let base_size = (!crack.segment_elements).then(|| crack.element_size.min(dx));
            let path = tip.path_points();
            let (mut pts, added) = extend_crack(
                &line,
                s_entry,
                &path,
                &new,
                self.params.elements_per_extension,
                base_size,
                &tip.spec.name,
            )?;
            if new.turned_from(old) {
                // No bond state carries over to a turned lattice: the pre-crack runs to
                // the traced tip ([`turned_to_outline`]).
                extend_to_tip(&mut pts, &path, dx);
            }
            if !tip.spec.at_end {
                pts.reverse();
            }
            layout.cracks[tip.spec.crack].points = pts;
            layout.cracks[tip.spec.crack].segment_elements = true;
            moves.push((t, (old.spec.center, tip.position(), added)));
        }
        layout.windows[w] = spec;
        Ok((moves, blocked, at_outline))
    }

    /// The moved window of tip `t` (growing along `dir`) turned to lie against the
    /// outline ([`turned_to_outline`]), when its window `w` holds no other tip and the
    /// turned window overlaps no other window: windows merge only at one orientation
    /// ([`merge_specs`]), so a turn into another window would end the run with an error
    /// where the tip can instead end at the outline.
    fn turned_at_outline(&self, w: usize, t: usize, dir: V2) -> Option<WindowSpec> {
        if self.tips.iter().filter(|tip| tip.window == w).count() != 1 {
            return None;
        }
        let tip = self.tips[t].position();
        let turned = turned_to_outline(&self.problem.windows[w].window, tip, dir, &self.body)?;
        let spec = moved_spec(
            &turned,
            tip,
            dir,
            self.params.move_distance,
            self.params.trigger_ratio,
            &self.body,
            &self.tips[t].spec.name,
        )
        .ok()?;
        let placed = Window::place(w, spec.clone(), &self.body).ok()?;
        let clear = (self.problem.windows.iter().enumerate())
            .all(|(i, o)| i == w || !placed.overlaps(&o.window));
        clear.then_some(spec)
    }

    /// Names of the holes (the BEM group of each hole's edges).
    pub(super) fn hole_names(&self) -> Vec<String> {
        self.setup
            .layout
            .holes
            .iter()
            .enumerate()
            .map(|(i, h)| {
                h.edge_groups
                    .first()
                    .cloned()
                    .unwrap_or_else(|| i.to_string())
            })
            .collect()
    }
}

/// The note of a relocation that turned its window to lie against the outline; None for
/// any other.
pub(crate) fn turn_note(r: &RelocationRecord) -> Option<String> {
    let [from, to] = r.turned_deg?;
    Some(format!(
        "step {}: the window of tip {} turned from {from:.2} to {to:.2} degrees to lie \
         against the outline (a window touches it only along whole sides): its state came \
         from the old nodes' displacements and the BEM field, without bond states, and its \
         pre-crack runs to the traced tip",
        r.step, r.tip
    ))
}

/// Appends the traced tip (the last point of `path`) to the pre-crack `pts` when it lies
/// more than a hundredth of `dx` beyond its end.
fn extend_to_tip(pts: &mut Vec<V2>, path: &[V2], dx: f64) {
    if let (Some(&end), Some(&tip)) = (pts.last(), path.last()) {
        if (tip - end).norm() > 1e-2 * dx {
            pts.push(tip);
        }
    }
}

/// Largest distance from the points of `a` to the polyline `b` (m); 0 when either is
/// shorter than a segment.
fn max_distance(a: &[V2], b: &[V2]) -> f64 {
    if b.len() < 2 {
        return 0.0;
    }
    a.iter()
        .map(|p| {
            b.windows(2)
                .map(|s| pdbem_geometry::point_segment_projection(p, &s[0], &s[1]).0)
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use pdbem_pd::crack_path::CrackPath;

    use super::*;
    use crate::growth::fixtures::{plate_setup, PlateScenario};
    use crate::growth::observer::Silent;
    use crate::growth::{GrowthParams, LoadSteps};

    /// A traced path through `pts`, every 0.05 m.
    fn path(pts: &[V2]) -> CrackPath {
        let fine = polyline::resample_spacing(pts, 0.0, pdbem_geometry::polyline_length(pts), 0.05);
        CrackPath {
            points: fine.iter().map(|p| [p.x, p.y]).collect(),
            nodes: Vec::new(),
            tip_node: Some(0),
            length: pdbem_geometry::polyline_length(pts),
        }
    }

    #[test]
    fn two_tips_of_one_window_moving_at_once_both_move() {
        // Two parallel cracks 0.4 m apart ending at x = 9.5; their windows merge into
        // [9, 10] x [4.3, 5.7] (20 x 28 nodes), entries at (9, 4.8) and (9, 5.2).
        let setup = plate_setup(
            (20.0, 10.0),
            vec![],
            vec![
                vec![V2::new(7.0, 4.8), V2::new(9.5, 4.8)],
                vec![V2::new(7.0, 5.2), V2::new(9.5, 5.2)],
            ],
            None,
        );
        let loads = LoadSteps {
            initial: 1.0,
            step: 0.0,
            count: 1,
        };
        let mut g = Growth::new(setup, &PlateScenario, GrowthParams::new(loads, 0.5)).unwrap();
        assert_eq!(g.problem().windows.len(), 1);
        assert_eq!((g.tips[0].window, g.tips[1].window), (0, 0));
        g.solve_at(0, 1.0, &mut Silent).unwrap();
        // Both tips past the margin in the same iteration, diverging: c0 down to
        // (9.8, 4.5), c1 up to (9.8, 5.5). Alone each would move the window by
        // (0.35, -+0.35): [9.35, 10.35] x [3.95, 5.35] and [9.35, 10.35] x [4.65, 6.05].
        g.tips[0].path = path(&[V2::new(9.0, 4.8), V2::new(9.5, 4.8), V2::new(9.8, 4.5)]);
        g.tips[1].path = path(&[V2::new(9.0, 5.2), V2::new(9.5, 5.2), V2::new(9.8, 5.5)]);
        let before = g.layout().cracks.clone();
        let recs = g.relocate(&[0, 1], 0, 1.0, &mut Silent).unwrap();
        assert_eq!(recs.len(), 2);
        // No solution of the new geometry yet (the old one does not fit its mesh).
        assert!(g.last_solution().is_none() && g.cmod("c0").is_none());
        assert!(recs.iter().all(|r| r.elements_added == 5), "{recs:?}");
        // One window covering both moved windows: [9.35, 10.35] x [3.95, 6.05].
        assert_eq!(g.problem().windows.len(), 1);
        let w = &g.problem().windows[0].window;
        assert_eq!((w.spec.nx, w.spec.ny), (20, 42));
        assert!(
            (w.spec.center - V2::new(9.85, 5.0)).norm() < 1e-9,
            "{:?}",
            w.spec.center
        );
        for (t, (y, tip)) in [(4.8, V2::new(9.8, 4.5)), (5.2, V2::new(9.8, 5.5))]
            .into_iter()
            .enumerate()
        {
            assert!(w.contains(tip, 0.0), "tip {t} outside the window");
            assert_eq!(g.tips[t].window, 0);
            // Each crack's BEM part now runs to the new window: it enters at x = 9.35.
            assert!(
                (g.tips[t].entry - V2::new(9.35, y)).norm() < 1e-9,
                "entry of tip {t}: {:?}",
                g.tips[t].entry
            );
            let pts = &g.layout().cracks[t].points;
            assert!(pts.len() > before[t].points.len());
            assert!(
                pts.iter().any(|p| (p - V2::new(9.35, y)).norm() < 1e-9),
                "crack {t}: {pts:?}"
            );
            // Its pre-crack follows the path to one dx short of the tip.
            let end = *pts.last().unwrap();
            assert!((end - tip).norm() < 0.06, "crack {t} ends at {end:?}");
            // The BEM faces reach the new window.
            let mesh = &g.problem().mesh;
            let gi = mesh.group(&format!("c{t}.upper")).unwrap();
            let reach = mesh
                .group_elements(gi)
                .flat_map(|e| [mesh.elements[e].a.x, mesh.elements[e].b.x])
                .fold(f64::NEG_INFINITY, f64::max);
            assert!(
                (reach - 9.35).abs() < 1e-9,
                "crack {t} faces reach x = {reach}"
            );
        }
        g.solve_at(0, 1.0, &mut Silent).unwrap();
        let sol = &g.last_solution().unwrap().solution;
        assert_eq!(sol.u.len(), g.problem().mesh.elements.len());
    }
}
