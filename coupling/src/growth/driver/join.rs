//! Cracks that reach a hole join it in the BEM geometry (issue 18 item 5).
//!
//! A PD-BEM tip ends at a hole when its window cannot move on without covering the hole,
//! or when the tip comes within the boundary reach of it ([`TipEnd::Hole`]). Its reported
//! path is continued to the hole's boundary polygon by
//! [`crate::growth::polyline::join_boundary`] (the
//! chord of its last 3 dx). The geometry is joined the same way: the stretch from the
//! tip to that rim point becomes a crack of the macro layout of its own, named
//! `<tip>.hole` ([`join_name`]), from the tip (in the window) through the window side to
//! the rim. [`crate::setup::build`] splits it at the window like every crack
//! ([`crate::window::Window::split_crack`]): inside the window it is a PD pre-crack from
//! the tip to the side (bonds across it cut on top of the transferred bond states), and
//! outside a BEM crack from the window side to the rim. Both of its BEM ends lie on
//! loops (the window's interface loop and the hole), so the mesher treats them as mouths,
//! the way an edge crack's mouth meets the outline: the hole's boundary element is split
//! at the junction, the crack faces meet a hole node, and neither end is a tip (no SIF,
//! no tip refinement). Where the joining crack leaves the window it is snapped to an
//! interface element end ([`snap_to_element_end`]), so the window keeps one interface
//! element per node row.
//!
//! The run goes on with the joined geometry (same load, windows' state transferred,
//! [`crate::growth::transfer`]) while other tips live. A join that closes a chain of cuts
//! (a crack from the outline into a hole and another from the hole to the outline, or a
//! crack from a hole back to it) cuts the body apart: the run ends with structural
//! failure naming the tip and the hole ([`join_cuts`]).

use pdbem_bem::V2;

use super::step::StepRun;
use super::Growth;
use crate::error::CouplingError;
use crate::growth::observer::Observer;
use crate::growth::records::Scenario;
use crate::growth::relocate::snap_to_element_end;
use crate::growth::tips::{TipEnd, TipState};
use crate::growth::topology::join_cuts;
use crate::setup::{Layout, MacroCrack};

/// Name of the crack that joins tip `tip` to the hole it ended at.
pub fn join_name(tip: &str) -> String {
    format!("{tip}.hole")
}

/// What [`Growth::join_holes`] did.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Joined {
    /// No tip was waiting to be joined (or no solution to transfer from yet).
    Nothing,
    /// The geometry was rebuilt with the joining cracks of these tips.
    Rebuilt(Vec<usize>),
    /// The join of this tip would cut the body apart (structural failure).
    Cuts(usize),
}

impl<S: Scenario> Growth<'_, S> {
    /// Tips that ended at a hole whose joining crack is not in the layout yet, with the
    /// hole's index in the body.
    pub(super) fn pending_joins(&self) -> Vec<(usize, usize)> {
        let names = self.hole_names();
        self.tips
            .iter()
            .enumerate()
            .filter_map(|(t, tip)| match &tip.ended {
                Some(TipEnd::Hole(h)) => {
                    let i = names.iter().position(|n| n == h)?;
                    let name = join_name(&tip.spec.name);
                    let done = self.setup.layout.cracks.iter().any(|c| c.name == name);
                    (!done && i < self.body.holes.len()).then_some((t, i))
                }
                _ => None,
            })
            .collect()
    }

    /// The joining crack of tip `t` (ended at a hole): from the tip, through the
    /// window side where the segment to the rim point leaves the window (snapped to an
    /// interface element end), to the rim point of the reported path.
    fn join_line(&self, t: usize) -> Result<Vec<V2>, CouplingError> {
        let tip = &self.tips[t];
        let w = &self.problem.windows[tip.window].window;
        let from = tip.position();
        let (joined, _) = self.joined(t, self.traced_path(t));
        let rim = *joined.last().unwrap_or(&from);
        let fail = |reason: String| CouplingError::Relocation {
            tip: tip.spec.name.clone(),
            reason,
        };
        let dx = w.spec.dx;
        if (rim - from).norm() < 0.5 * dx {
            // Already at the rim: the crack meets the hole within half a spacing.
            return Err(fail(format!(
                "the tip at ({:.4}, {:.4}) lies within half a spacing of the hole rim \
                 ({:.4}, {:.4}): no room for a joining crack",
                from.x, from.y, rim.x, rim.y
            )));
        }
        let Some((_, exit)) = w.chord(from, rim) else {
            return Err(fail("the tip lies outside its window".into()));
        };
        if (rim - exit).norm() < 0.5 * dx {
            return Err(fail(format!(
                "the window reaches the hole rim at ({:.4}, {:.4}): the remaining ligament \
                 lies in PD and the crack cannot be joined in BEM",
                rim.x, rim.y
            )));
        }
        let side = snap_to_element_end(w, exit);
        Ok(vec![from, side, rim])
    }

    /// The layout with the joining cracks of `tips` appended.
    fn joined_layout(&self, tips: &[usize]) -> Result<Layout, CouplingError> {
        let mut layout = self.setup.layout.clone();
        for &t in tips {
            let tip = &self.tips[t];
            let crack = &self.setup.layout.cracks[tip.spec.crack];
            let dx = self.problem.windows[tip.window].window.spec.dx;
            layout.cracks.push(MacroCrack {
                name: join_name(&tip.spec.name),
                points: self.join_line(t)?,
                faces: crack.faces,
                element_size: crack.element_size.min(dx),
                segment_elements: false,
            });
        }
        Ok(layout)
    }

    /// Joins every tip that ended at a hole to it (module docs): the layout gets their
    /// joining cracks, the geometry is rebuilt and refactored, the windows take their
    /// state from the old ones (the same specs: exact) and the BEM field at load `load`,
    /// and the next solve starts from there. Does nothing before the first solution of
    /// the current geometry. Returns [`Joined::Cuts`] (nothing rebuilt) when a join would
    /// cut the body apart.
    pub(crate) fn join_holes(
        &mut self,
        load: f64,
        observer: &mut dyn Observer,
    ) -> Result<Joined, CouplingError> {
        let pending = self.pending_joins();
        if pending.is_empty() || self.last.is_none() {
            return Ok(Joined::Nothing);
        }
        let tips: Vec<usize> = pending.iter().map(|p| p.0).collect();
        let layout = self.joined_layout(&tips)?;
        let first = self.setup.layout.cracks.len();
        if let Some(k) = join_cuts(&layout, &self.body, first) {
            return Ok(Joined::Cuts(tips[k]));
        }
        let (problem, bem) = super::build_geometry(
            &layout,
            &self.setup,
            self.scenario,
            self.params.trigger_ratio,
            &mut self.pairs,
        )?;
        let Some(sol) = self.last.take() else {
            return Ok(Joined::Nothing);
        };
        self.install_geometry(layout, problem, bem, &sol, load);
        for &(t, h) in &pending {
            let tip: &TipState = &self.tips[t];
            let k = tips.iter().position(|&x| x == t).unwrap_or(0);
            let crack = &self.setup.layout.cracks[first + k];
            let rim = *crack.points.last().unwrap_or(&tip.position());
            observer.note(&format!(
                "tip {} ended at hole {}: its crack is joined to the hole rim at ({:.4}, {:.4}) \
                 in the BEM geometry ({:.3e} m from the tip; PD pre-crack to the window side, \
                 BEM crack on to the rim, no tip at the hole); the body holds",
                tip.spec.name,
                self.hole_names().get(h).cloned().unwrap_or_default(),
                rim.x,
                rim.y,
                pdbem_geometry::polyline_length(&crack.points),
            ));
        }
        self.retrace()?;
        Ok(Joined::Rebuilt(tips))
    }

    /// The step run `run` ended by tip `t`, whose join to its hole would cut the body
    /// apart (structural failure; the note names the tip and the hole).
    pub(super) fn cut_by_join(
        &self,
        t: usize,
        mut run: StepRun,
        observer: &mut dyn Observer,
    ) -> StepRun {
        let tip = &self.tips[t];
        let hole = match &tip.ended {
            Some(TipEnd::Hole(h)) => h.clone(),
            _ => String::new(),
        };
        let p = tip.position();
        observer.note(&format!(
            "tip {} ended at hole {hole} at ({:.4}, {:.4}): its crack joined to the hole \
             closes a chain of cracks through the holes and the outline, which cuts the \
             body apart: structural failure",
            tip.spec.name, p.x, p.y
        ));
        run.cut = Some(t);
        run
    }

    /// The note of a run whose every tip has ended without structural failure, when some
    /// ended at a hole: their cracks are joined to it and the body holds.
    pub(super) fn holds_note(&self) -> Option<String> {
        let at_holes: Vec<String> = self
            .tips
            .iter()
            .filter(|t| matches!(t.ended, Some(TipEnd::Hole(_))))
            .map(|t| {
                format!(
                    "{} ({})",
                    t.spec.name,
                    t.ended.as_ref().map_or(String::new(), ToString::to_string)
                )
            })
            .collect();
        (!at_holes.is_empty()).then(|| {
            format!(
                "every tip ended and the body holds: {} ended at a hole and joined it in the \
                 BEM geometry (no structural failure; the final fields, K and VTK are those \
                 of the joined body)",
                at_holes.join(", ")
            )
        })
    }
}
