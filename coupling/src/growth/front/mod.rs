//! The crack front of a growth run: the crack polylines as they grow, their tips, what
//! stopped each tip, and whether the body has come apart. Shared by the BEM-only and the
//! full-PD modes.
//!
//! - [`Front::new`]: the body's outline and holes and its cracks; tips are named
//!   `<crack>.start` (first point, when it is not a mouth on the outline) and `<crack>.end`.
//! - [`Front::step_ahead`] (BEM-only): extend a tip by a straight increment and stop it at
//!   the outline or a hole (the increment is clipped there: the crack joins it) or at
//!   another crack (coalescence, stopped before it), see [`Obstacle`].
//! - [`Front::set_tip`], [`Front::stop`] (full PD): the tip position comes from the damage
//!   tracker; the caller decides when it has reached something.
//! - [`Front::separated`]: failure. Cracks that coalesced form one group; a group that
//!   touches the outline at two points or more (mouths of edge cracks and tips stopped on
//!   the outline) cuts the body in two (seed 002 Alg. 2 step 9: "the crack exceeds the
//!   boundary of the whole structure"). A tip of an interior crack that reaches the outline
//!   stops, and the run goes on until the crack has also run out at its other end.
//!   Tips stopped at a hole join it (the crack runs onto the hole's polygon, also when it
//!   passes the hole within the margin: onto the nearest point), and groups that close a
//!   chain of cuts through the holes (outline - hole - outline, a hole back to itself)
//!   cut the body too (`cut.rs`).

mod cut;
pub(crate) use cut::BoundaryGraph;

use pdbem_geometry::{
    point_segment_distance, polyline_length, ray_circle, ray_polygon, ray_segment, HoleShape, P2,
};

/// One crack of the front.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrontCrack {
    /// Crack name.
    pub name: String,
    /// Polyline, first point to last (m).
    pub points: Vec<P2>,
    /// The first point lies on the outline (an edge crack).
    pub mouth: bool,
}

/// One crack tip.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrontTip {
    /// `<crack>.end` or `<crack>.start`.
    pub name: String,
    /// Index into [`Front::cracks`].
    pub crack: usize,
    /// The tip is the last point of the polyline (else the first).
    pub at_end: bool,
    /// Position at the start of the run (m).
    pub initial: P2,
    /// Why the tip stopped: `outline`, `hole:<name>`, `coalescence:<crack>`.
    pub ended: Option<String>,
}

/// What the increment of a tip ran into.
#[derive(Debug, Clone, PartialEq)]
pub enum Obstacle {
    /// Nothing: the tip moved by the full increment.
    None,
    /// The outer boundary: the tip moved onto it and stopped.
    Outline,
    /// A hole (its group name): the tip moved onto it and stopped.
    Hole(String),
    /// Another crack (its name): the tip stopped before it.
    Crack(String),
}

/// The cracks, tips and outline contacts of a growth run.
#[derive(Debug, Clone)]
pub struct Front {
    /// Cracks in scene order.
    pub cracks: Vec<FrontCrack>,
    /// Tips, start before end per crack, in scene order (the order of the BEM mesh).
    pub tips: Vec<FrontTip>,
    outline: Option<Vec<P2>>,
    holes: Vec<(String, HoleShape)>,
    /// Group of each crack (union-find parent).
    parent: Vec<usize>,
}

/// The part of a [`Front`] a growth run changes (cracks, tips, which cracks joined), for
/// growth checkpoints; the outline and holes come from the scene again.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FrontState {
    /// Cracks as grown.
    pub cracks: Vec<FrontCrack>,
    /// Tips with their ends.
    pub tips: Vec<FrontTip>,
    /// Union-find parent of each crack.
    pub parent: Vec<usize>,
}

impl Front {
    /// What a checkpoint keeps of the front.
    pub fn state(&self) -> FrontState {
        FrontState {
            cracks: self.cracks.clone(),
            tips: self.tips.clone(),
            parent: self.parent.clone(),
        }
    }

    /// Takes the cracks, tips and joins of `state` (a checkpoint of a run on the same
    /// body); refused when the numbers of cracks or tips differ.
    pub fn restore(&mut self, state: &FrontState) -> Result<(), String> {
        if state.cracks.len() != self.cracks.len()
            || state.tips.len() != self.tips.len()
            || state.parent.len() != self.parent.len()
        {
            return Err(format!(
                "the checkpoint has {} cracks and {} tips, the scene {} and {}",
                state.cracks.len(),
                state.tips.len(),
                self.cracks.len(),
                self.tips.len()
            ));
        }
        self.cracks.clone_from(&state.cracks);
        self.tips.clone_from(&state.tips);
        self.parent.clone_from(&state.parent);
        Ok(())
    }

    /// The front of a body: its outline (counter-clockwise; `None` for an infinite
    /// plate), its holes with their group names, and its cracks (each with at least two
    /// points).
    pub fn new(
        outline: Option<Vec<P2>>,
        holes: Vec<(String, HoleShape)>,
        cracks: Vec<FrontCrack>,
    ) -> Front {
        let mut tips = Vec::new();
        for (i, c) in cracks.iter().enumerate() {
            if !c.mouth {
                tips.push(FrontTip {
                    name: format!("{}.start", c.name),
                    crack: i,
                    at_end: false,
                    initial: c.points[0],
                    ended: None,
                });
            }
            tips.push(FrontTip {
                name: format!("{}.end", c.name),
                crack: i,
                at_end: true,
                initial: *c.points.last().unwrap_or(&P2::zeros()),
                ended: None,
            });
        }
        Front {
            parent: (0..cracks.len()).collect(),
            cracks,
            tips,
            outline,
            holes,
        }
    }

    /// Bounding box of the outline, the holes and the cracks as they are now (m); a unit
    /// box round the origin for an empty front.
    pub fn bounds(&self) -> (P2, P2) {
        let mut pts: Vec<P2> = Vec::new();
        if let Some(o) = &self.outline {
            pts.extend(o.iter().copied());
        }
        for (_, h) in &self.holes {
            pts.extend(h.polygon());
        }
        for c in &self.cracks {
            pts.extend(c.points.iter().copied());
        }
        if pts.is_empty() {
            return (P2::new(-1.0, -1.0), P2::new(1.0, 1.0));
        }
        pdbem_geometry::bounding_box(&pts)
    }

    /// True when `p` lies in the body: inside the outline (any point of an infinite
    /// plate) and not inside a hole.
    pub fn contains(&self, p: &P2) -> bool {
        let in_outline = self
            .outline
            .as_ref()
            .is_none_or(|o| pdbem_geometry::point_in_polygon(p, o));
        in_outline && !self.holes.iter().any(|(_, h)| h.contains(p, 0.0))
    }

    /// Position of tip `t` (m).
    pub fn tip_position(&self, t: usize) -> P2 {
        let tip = &self.tips[t];
        let pts = &self.cracks[tip.crack].points;
        if tip.at_end {
            pts[pts.len() - 1]
        } else {
            pts[0]
        }
    }

    /// Unit direction ahead of tip `t` (along its last segment).
    pub fn tip_direction(&self, t: usize) -> P2 {
        let tip = &self.tips[t];
        let pts = &self.cracks[tip.crack].points;
        let n = pts.len();
        let d = if tip.at_end {
            pts[n - 1] - pts[n - 2]
        } else {
            pts[0] - pts[1]
        };
        d / d.norm().max(1e-300)
    }

    /// Positions of all tips, in tip order (the `tips` of a step record).
    pub fn tip_positions(&self) -> Vec<[f64; 2]> {
        (0..self.tips.len())
            .map(|t| {
                let p = self.tip_position(t);
                [p.x, p.y]
            })
            .collect()
    }

    /// Indices of the tips still growing.
    pub fn active(&self) -> Vec<usize> {
        (0..self.tips.len())
            .filter(|&t| self.tips[t].ended.is_none())
            .collect()
    }

    /// Index of the tip on crack `crack` at its end (`at_end`) or start.
    pub fn tip_index(&self, crack: usize, at_end: bool) -> Option<usize> {
        self.tips
            .iter()
            .position(|t| t.crack == crack && t.at_end == at_end)
    }

    /// Moves tip `t` to `p`, appending it to the polyline (full PD: the tracked tip).
    pub fn set_tip(&mut self, t: usize, p: P2) {
        let (c, at_end) = (self.tips[t].crack, self.tips[t].at_end);
        let pts = &mut self.cracks[c].points;
        if at_end {
            pts.push(p);
        } else {
            pts.insert(0, p);
        }
    }

    /// Replaces the grown part of tip `t` (beyond its initial position) by `path`, given
    /// from the initial tip outwards (full PD: the traced crack path).
    pub fn set_path(&mut self, t: usize, path: &[P2]) {
        let (c, at_end, initial) = (
            self.tips[t].crack,
            self.tips[t].at_end,
            self.tips[t].initial,
        );
        let pts = &mut self.cracks[c].points;
        let k = pts
            .iter()
            .position(|p| (p - initial).norm() == 0.0)
            .unwrap_or(if at_end { pts.len() - 1 } else { 0 });
        let grown = path.iter().filter(|p| (*p - initial).norm() > 0.0);
        if at_end {
            pts.truncate(k + 1);
            pts.extend(grown);
        } else {
            let rest = pts.split_off(k);
            pts.clear();
            pts.extend(grown.rev());
            pts.extend(rest);
        }
    }

    /// Stops tip `t` for `why` (the obstacle it reached); coalescence joins the groups.
    pub fn stop(&mut self, t: usize, why: &Obstacle) {
        let reason = match why {
            Obstacle::None => return,
            Obstacle::Outline => "outline".to_string(),
            Obstacle::Hole(h) => format!("hole:{h}"),
            Obstacle::Crack(c) => {
                if let Some(j) = self.cracks.iter().position(|k| &k.name == c) {
                    self.join(self.tips[t].crack, j);
                }
                format!("coalescence:{c}")
            }
        };
        self.tips[t].ended = Some(reason);
    }

    pub(super) fn root(&self, mut i: usize) -> usize {
        while self.parent[i] != i {
            i = self.parent[i];
        }
        i
    }

    fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.parent[rb] = ra;
        }
    }

    /// Length grown at tip `t` so far (m): arc length from its initial position.
    pub fn extension(&self, t: usize) -> f64 {
        let tip = &self.tips[t];
        let pts = &self.cracks[tip.crack].points;
        let k = pts
            .iter()
            .position(|p| (p - tip.initial).norm() == 0.0)
            .unwrap_or(0);
        if tip.at_end {
            polyline_length(&pts[k..])
        } else {
            polyline_length(&pts[..=k])
        }
    }

    /// The outline polygon (counter-clockwise), `None` for an infinite plate.
    pub fn outline_points(&self) -> Option<&[P2]> {
        self.outline.as_deref()
    }

    /// Distance (m) from `p` to the outline (infinite for an infinite plate).
    pub fn outline_distance(&self, p: &P2) -> f64 {
        self.outline
            .as_ref()
            .map_or(f64::INFINITY, |o| pdbem_geometry::polygon_distance(p, o))
    }

    /// Distances (m) from `p` to the boundary of every hole, in the front's order (see
    /// [`Front::hole_names`]).
    pub fn hole_distances(&self, p: &P2) -> Vec<f64> {
        self.holes
            .iter()
            .map(|(_, h)| h.boundary_distance(p))
            .collect()
    }

    /// The holes' group names, in the front's order.
    pub fn hole_names(&self) -> Vec<&str> {
        self.holes.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// The boundary polygon of the hole named `name`.
    pub fn hole_polygon(&self, name: &str) -> Option<Vec<P2>> {
        self.holes
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, h)| h.polygon())
    }

    /// The nearest hole to `p` within `d` (m), by group name.
    pub fn hole_within(&self, p: &P2, d: f64) -> Option<String> {
        self.holes
            .iter()
            .map(|(n, h)| (n, h.boundary_distance(p)))
            .filter(|(_, dist)| *dist <= d)
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(n, _)| n.clone())
    }

    /// The nearest other crack to `p` within `d` (m), by name; the crack of tip `t` counts
    /// only away from the tip (beyond `d` along its own polyline).
    pub fn crack_within(&self, t: usize, p: &P2, d: f64) -> Option<String> {
        let own = self.tips[t].crack;
        let mut best: Option<(f64, &str)> = None;
        for (i, c) in self.cracks.iter().enumerate() {
            let pts = self.far_part(i, own, t, d);
            for w in pts.windows(2) {
                let dist = point_segment_distance(p, &w[0], &w[1]);
                if dist <= d && best.is_none_or(|(b, _)| dist < b) {
                    best = Some((dist, &c.name));
                }
            }
        }
        best.map(|(_, n)| n.to_string())
    }

    /// The polyline of crack `i` without the part within `d` of tip `t` when it is the
    /// tip's own crack.
    fn far_part(&self, i: usize, own: usize, t: usize, d: f64) -> Vec<P2> {
        let pts = &self.cracks[i].points;
        if i != own {
            return pts.clone();
        }
        let tip = self.tip_position(t);
        let keep: Vec<P2> = if self.tips[t].at_end {
            let cut = pts
                .iter()
                .rposition(|q| (q - tip).norm() > 2.0 * d)
                .unwrap_or(0);
            pts[..=cut].to_vec()
        } else {
            let cut = pts
                .iter()
                .position(|q| (q - tip).norm() > 2.0 * d)
                .unwrap_or(pts.len() - 1);
            pts[cut..].to_vec()
        };
        keep
    }

    /// Extends tip `t` by `da` (m) in direction `dir` (unit) unless something is in the
    /// way within `da + margin`: the outline or a hole (the increment is clipped onto it
    /// and the tip stops there: the crack joins it), another crack (the tip stops where it
    /// is). Returns what it met.
    pub fn step_ahead(&mut self, t: usize, dir: P2, da: f64, margin: f64) -> Obstacle {
        let tip = self.tip_position(t);
        let reach = da + margin;
        let first = self.first_ahead(t, dir).filter(|(s, _)| *s <= reach);
        let end = tip + dir * da;
        let hit = match first {
            Some((s, Obstacle::Outline)) => {
                self.set_tip(t, tip + dir * s);
                Obstacle::Outline
            }
            Some((s, Obstacle::Hole(h))) => {
                self.set_tip(t, tip + dir * s);
                Obstacle::Hole(h)
            }
            Some((_, other)) => other,
            None => match self.crack_within(t, &end, margin) {
                Some(c) => Obstacle::Crack(c),
                None => match self.hole_within(&end, margin) {
                    Some(h) => {
                        // Passing the hole within the margin: the crack joins it at the
                        // point of its boundary nearest to the tip.
                        if let Some(poly) = self.hole_polygon(&h) {
                            let q = crate::growth::polyline::nearest_on_polygon(&tip, &poly);
                            if (q - tip).norm() > 0.0 {
                                self.set_tip(t, q);
                            }
                        }
                        Obstacle::Hole(h)
                    }
                    None => {
                        self.set_tip(t, end);
                        Obstacle::None
                    }
                },
            },
        };
        self.stop(t, &hit);
        hit
    }

    /// Distance (m) from tip `t` along `dir` (unit) to the first outline, hole or crack
    /// the ray meets; None when it meets nothing.
    pub fn room_ahead(&self, t: usize, dir: P2) -> Option<f64> {
        self.first_ahead(t, dir).map(|(s, _)| s)
    }

    /// The first outline, hole or crack the ray from tip `t` along `dir` meets, with its
    /// distance.
    fn first_ahead(&self, t: usize, dir: P2) -> Option<(f64, Obstacle)> {
        let tip = self.tip_position(t);
        let to_outline = self
            .outline
            .as_ref()
            .and_then(|o| ray_polygon(&tip, &dir, o));
        let to_hole = self
            .holes
            .iter()
            .filter_map(|(n, h)| ray_hole(&tip, &dir, h).map(|s| (s, n.clone())))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let to_crack = self.ray_cracks(t, &tip, &dir);
        [
            to_outline.map(|s| (s, Obstacle::Outline)),
            to_hole.map(|(s, n)| (s, Obstacle::Hole(n))),
            to_crack.map(|(s, n)| (s, Obstacle::Crack(n))),
        ]
        .into_iter()
        .flatten()
        .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// First crossing of the ray from `tip` along `dir` with another crack (or the far part
    /// of its own): distance and crack name.
    fn ray_cracks(&self, t: usize, tip: &P2, dir: &P2) -> Option<(f64, String)> {
        let own = self.tips[t].crack;
        let h = 1e-9 * self.scale();
        let mut best: Option<(f64, String)> = None;
        for (i, c) in self.cracks.iter().enumerate() {
            for w in self.far_part(i, own, t, h).windows(2) {
                if let Some(s) = ray_segment(tip, dir, &w[0], &w[1]) {
                    if best.as_ref().is_none_or(|(b, _)| s < *b) {
                        best = Some((s, c.name.clone()));
                    }
                }
            }
        }
        best
    }

    fn scale(&self) -> f64 {
        let mut pts: Vec<P2> = self.outline.clone().unwrap_or_default();
        pts.extend(self.cracks.iter().flat_map(|c| c.points.iter().copied()));
        pdbem_geometry::scale_of(&pts).max(1e-300)
    }
}

/// Nearest crossing of the ray with a hole (circles exact).
pub fn ray_hole(o: &P2, d: &P2, h: &HoleShape) -> Option<f64> {
    match h {
        HoleShape::Circle { center, radius } => ray_circle(o, d, center, *radius),
        HoleShape::Polygon(p) => ray_polygon(o, d, p),
    }
}

#[cfg(test)]
mod tests;
