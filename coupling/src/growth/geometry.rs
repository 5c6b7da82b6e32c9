//! The geometry iteration of Algorithm 2 on a [`Growth`] run (seed 002 section 2.3.3,
//! Fig. 9, Algorithm 2 steps 7 and 10): [`Growth::plan`] works out the moved windows
//! ([`crate::growth::relocate::moved_spec`]), the extended cracks
//! ([`crate::growth::relocate::extend_crack`]) and the merges, and whether the result
//! would cut the BEM body ([`crate::growth::topology`]); [`Growth::apply`] rebuilds mesh,
//! BEM factorization and windows and transfers the state
//! ([`crate::growth::transfer`]).

use std::time::Instant;

use pdbem_bem::post::FieldEvaluator;
use pdbem_bem::V2;

use crate::error::CouplingError;
use crate::growth::driver::{build_geometry, Growth};
use crate::growth::merge::resolve_overlaps;
use crate::growth::polyline;
use crate::growth::records::{Observer, RelocationPlan, RelocationRecord, Scenario};
use crate::growth::relocate::{extend_crack, moved_spec};
use crate::growth::tips::{entry_point, towards_tip, TipState};
use crate::growth::topology::cuts_body;
use crate::growth::transfer::transfer_state;
use crate::setup::Layout;
use crate::window::Window;

impl<S: Scenario> Growth<'_, S> {
    /// The geometry of the next relocation of tips `which`: windows moved along the growth
    /// directions, cracks extended along the traced paths, overlapping windows merged.
    /// Nothing changes until [`Growth::apply`].
    pub fn plan(&self, which: &[usize]) -> Result<RelocationPlan, CouplingError> {
        let mut layout = self.setup.layout.clone();
        let mut moves = Vec::new();
        for &t in which {
            moves.push((t, self.plan_move(t, &mut layout)?));
        }
        let names: Vec<String> = self.tips.iter().map(|t| t.spec.name.clone()).collect();
        let mut owner: Vec<usize> = self.tips.iter().map(|t| t.window).collect();
        let merges = resolve_overlaps(&mut layout.windows, &mut owner, &names, &self.body)?;
        let cuts_body = cuts_body(&layout, &self.body);
        Ok(RelocationPlan {
            layout,
            owner,
            moves,
            merges,
            cuts_body,
        })
    }

    /// Carries out a relocation plan at load `load` (step `step`): mesh rebuilt and
    /// refactored, windows rebuilt with their state transferred, tips re-traced. Returns
    /// one record per relocated tip.
    pub fn apply(
        &mut self,
        plan: RelocationPlan,
        step: usize,
        load: f64,
        observer: &mut dyn Observer,
    ) -> Result<Vec<RelocationRecord>, CouplingError> {
        let t0 = Instant::now();
        let names: Vec<String> = self.tips.iter().map(|t| t.spec.name.clone()).collect();
        if plan.cuts_body {
            return Err(CouplingError::Relocation {
                tip: plan
                    .moves
                    .first()
                    .map_or_else(String::new, |m| names[m.0].clone()),
                reason: "the moved windows and the cracks would cut the BEM body in two".into(),
            });
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
        let (mut problem, bem) = build_geometry(
            &layout,
            &self.setup,
            self.scenario,
            self.params.trigger_ratio,
        )?;
        let old = std::mem::take(&mut self.problem.windows);
        let sol = self
            .last
            .as_ref()
            .ok_or_else(|| CouplingError::Relocation {
                tip: moves
                    .first()
                    .map_or_else(String::new, |m| names[m.0].clone()),
                reason: "no solution to take the new window's state from".into(),
            })?;
        let ev = FieldEvaluator::new(
            &self.problem.mesh,
            &self.problem.material,
            &sol.solution,
            self.problem.background,
        );
        let mut x0 = Vec::new();
        let mut infos = Vec::new();
        for wm in problem.windows.iter_mut() {
            let (x, info) = transfer_state(&old, &ev, wm, load);
            x0.extend(x);
            infos.push(info);
        }
        let old_paths: Vec<Vec<V2>> = self.tips.iter().map(TipState::path_points).collect();
        self.problem = problem;
        self.bem = bem;
        self.setup.layout = layout;
        self.start = Some((x0, load));
        self.geometries += 1;
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
        let rebuild_s = t0.elapsed().as_secs_f64();
        let mut records = Vec::new();
        for (t, (from, tip_at, added)) in moves {
            let w = self.tips[t].window;
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
                elements: self.problem.mesh.len(),
                rebuild_s,
            };
            observer.relocation(&rec);
            records.push(rec);
        }
        Ok(records)
    }

    /// [`Growth::plan`] then [`Growth::apply`] for tips `which` (an error if the plan
    /// would cut the BEM body).
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

    /// New window and extended crack of tip `t` written into `layout`; returns the old
    /// window centre, the tip position and the elements added per face.
    fn plan_move(&self, t: usize, layout: &mut Layout) -> Result<(V2, V2, usize), CouplingError> {
        let tip = &self.tips[t];
        let w = &self.problem.windows[tip.window].window;
        let dx = w.spec.dx;
        let spec_crack = &layout.cracks[tip.spec.crack];
        let line = towards_tip(&spec_crack.points, tip.spec.at_end);
        let dir = self.growth_direction(t, &line)?;
        let pos = tip.position();
        let spec = moved_spec(
            w,
            pos,
            dir,
            self.params.move_distance,
            self.params.trigger_ratio,
            &self.body,
            &tip.spec.name,
        )?;
        let new = Window::place(tip.window, spec.clone(), &self.body)?;
        let s_entry = polyline::entry_length(&line, w).unwrap_or(0.0);
        // Until its first extension a crack is meshed by size (capped at dx in windows).
        let base_size = (!spec_crack.segment_elements).then(|| spec_crack.element_size.min(dx));
        let (mut pts, added) = extend_crack(
            &line,
            s_entry,
            &tip.path_points(),
            &new,
            self.params.elements_per_extension,
            base_size,
            &tip.spec.name,
        )?;
        if !tip.spec.at_end {
            pts.reverse();
        }
        layout.cracks[tip.spec.crack].points = pts;
        layout.cracks[tip.spec.crack].segment_elements = true;
        let from = w.spec.center;
        layout.windows[tip.window] = spec;
        Ok((from, pos, added))
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
                .map(|s| crate::window::segment_distance(*p, s[0], s[1]).0)
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}
