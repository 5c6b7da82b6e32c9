//! Crack tips of a growth run: which crack end each window holds, where the crack enters
//! the window, the tracked tip (seed 002 Algorithm 2 step 5) and the tests of steps 6 and
//! 8-9 (the tip passed the window margin; the tip reached the outline, a hole or another
//! crack).
//!
//! The tip is the farthest macro-crack node ($\varphi >$ threshold) along the crack from
//! its entry into the window ([`pdbem_pd::crack_path::trace_crack`]). Along the interface
//! sides a band of $(1 - r)$ times the window side ($r$ = trigger ratio, 0.9 in seed 002
//! section 2.3.3) has unbreakable bonds ([`protect_band`]): within one PD solve a crack
//! under load control can run through the whole window, and without the band it would
//! run into the coupling layer, whose virtual nodes know nothing of it. The window moves
//! once the tip comes within the band plus a horizon and a dx of an interface side
//! ([`margins`]), which is short of where a crack arrested by the band ends. Sides on the outer boundary get no
//! band and no trigger: the crack runs to the boundary and the run ends in failure.

use pdbem_bem::V2;
use pdbem_pd::crack_path::{trace_crack, CrackPath, PathParams};

use crate::error::CouplingError;
use crate::growth::polyline;
use crate::setup::WindowModel;
use crate::window::{Body, SideKind, Window};
use pdbem_geometry::polygon_distance;

/// A crack end followed by a window.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TipSpec {
    /// Name (`<crack>.end` / `<crack>.start`).
    pub name: String,
    /// Index of its crack in the layout.
    pub crack: usize,
    /// The tip is the last point of the crack polyline (else the first).
    pub at_end: bool,
}

/// Why a tip stopped.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum TipEnd {
    /// It reached the outer boundary: the body is cut (seed 002 Algorithm 2 step 9).
    Outline,
    /// It reached the named hole (the BEM group of the hole's edges), or its window could
    /// not move on because the hole was in the way.
    Hole(String),
    /// It ran into the crack of the named tip.
    Coalescence(String),
}

impl std::fmt::Display for TipEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TipEnd::Outline => write!(f, "outline"),
            TipEnd::Hole(h) => write!(f, "hole:{h}"),
            TipEnd::Coalescence(t) => write!(f, "coalescence:{t}"),
        }
    }
}

/// The tracked state of one tip.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TipState {
    /// Which crack end.
    pub spec: TipSpec,
    /// Window holding it.
    pub window: usize,
    /// Where its crack enters the window (the end of the BEM crack) (m).
    pub entry: V2,
    /// The macro-crack tip of the current geometry (end of the pre-crack) (m).
    pub macro_tip: V2,
    /// Last traced path in the window, from the entry to the tip.
    pub path: CrackPath,
    /// Why it stopped, once it did.
    pub ended: Option<TipEnd>,
}

impl TipState {
    /// The tip position: the traced tip, or the macro tip while no macro crack is traced
    /// from the entry (m).
    pub fn position(&self) -> V2 {
        if self.path.is_empty() {
            self.macro_tip
        } else {
            let t = self.path.tip();
            V2::new(t[0], t[1])
        }
    }

    /// Whether the tip still grows.
    pub fn active(&self) -> bool {
        self.ended.is_none()
    }

    /// The traced path as points (m).
    pub fn path_points(&self) -> Vec<V2> {
        self.path
            .points
            .iter()
            .map(|p| V2::new(p[0], p[1]))
            .collect()
    }
}

/// The crack polyline oriented from its far end to the tip.
pub fn towards_tip(points: &[V2], at_end: bool) -> Vec<V2> {
    let mut line = points.to_vec();
    if !at_end {
        line.reverse();
    }
    line
}

/// Where the crack (oriented towards the tip) enters window `w`, and the macro tip.
pub fn entry_point(w: &Window, line_to_tip: &[V2], tip: &str) -> Result<(V2, V2), CouplingError> {
    let macro_tip = *line_to_tip.last().expect("a crack has points");
    let s = polyline::entry_length(line_to_tip, w).ok_or_else(|| CouplingError::Relocation {
        tip: tip.to_string(),
        reason: format!(
            "its crack never enters window centred at ({:.4}, {:.4})",
            w.spec.center.x, w.spec.center.y
        ),
    })?;
    Ok((pdbem_geometry::point_at(line_to_tip, s), macro_tip))
}

/// Traces the macro crack of window model `wm` (index `window`) from `entry`.
pub fn track(
    wm: &WindowModel,
    window: usize,
    entry: V2,
    params: &PathParams,
) -> Result<CrackPath, CouplingError> {
    trace_crack(&wm.model, [entry.x, entry.y], params).map_err(|e| CouplingError::pd(window, e))
}

/// The margins of window `w` for trigger ratio `ratio`: the width of the no-fail band
/// along its interface sides, $(1 - r)$ times the shorter side, and the trigger distance,
/// that band plus a horizon plus dx (m). A crack arrested by the band has its last nodes
/// past the damage threshold up to a horizon and half a dx from it (measured on the
/// shear case: 0.346 m for delta = 0.3015 m, dx = 0.1 m), since their bonds into the band
/// do not break; the extra dx makes sure such a crack moves the window on.
pub fn margins(w: &Window, ratio: f64) -> (f64, f64) {
    let (lx, ly) = w.size();
    let band = (1.0 - ratio) * lx.min(ly);
    (band, band + w.delta() + w.spec.dx)
}

/// Whether the tip at `tip` has passed the window margin (seed 002 Algorithm 2 step 6):
/// within the trigger distance ([`margins`]) of an interface side, and farther than that
/// distance from the entry (a crack that has not grown out of its entry does not trigger).
pub fn passed_margin(w: &Window, tip: V2, entry: V2, ratio: f64) -> bool {
    let (_, trigger) = margins(w, ratio);
    (tip - entry).norm() > trigger && near_interface_side(w, tip, trigger)
}

/// Whether `p` lies within `distance` of an interface side of `w` (or beyond it).
pub fn near_interface_side(w: &Window, p: V2, distance: f64) -> bool {
    let (lx, ly) = w.size();
    let q = w.to_local(p);
    let near = [
        q.y < distance,
        q.x > lx - distance,
        q.y > ly - distance,
        q.x < distance,
    ];
    (0..4).any(|k| near[k] && w.sides[k] == SideKind::Interface)
}

/// No-fail band of a window (seed 002 section 2.3.3 moves the window once the crack
/// passes 0.9 of it; the band keeps the crack from running into the coupling layer
/// before that): every bond with an end within the band width of an interface side, or
/// beyond it (the virtual nodes), stays intact. Returns the directed bonds marked.
pub fn protect_band(wm: &mut WindowModel, ratio: f64) -> usize {
    let (band, _) = margins(&wm.window, ratio);
    let w = wm.window.clone();
    wm.model
        .protect_bonds(|x| near_interface_side(&w, V2::new(x[0], x[1]), band))
}

/// What the tip reached, if anything: the outline or a hole within `reach` (m).
/// `hole_names[i]` names hole `i` of the body.
pub fn reached_boundary(body: &Body, hole_names: &[String], tip: V2, reach: f64) -> Option<TipEnd> {
    if polygon_distance(&tip, &body.outline) <= reach {
        return Some(TipEnd::Outline);
    }
    body.holes
        .iter()
        .position(|h| polygon_distance(&tip, h) <= reach)
        .map(|i| TipEnd::Hole(hole_name(hole_names, i)))
}

/// Name of hole `i`: `hole_names[i]`, else its index.
pub fn hole_name(hole_names: &[String], i: usize) -> String {
    hole_names.get(i).cloned().unwrap_or_else(|| i.to_string())
}

/// Whether the crack of `tip` ran into the crack of `other` (same window): the tip lies
/// within `reach` (m) of a node of the other's traced crack, or the two traced cracks of
/// different macro cracks share a node. Once two cracks join, the damage is one connected
/// set and each trace runs on through the other crack to its entry, so the tip is then no
/// longer near a node of the other's crack that is not its own; the shared nodes tell.
/// Two tips of one crack share their nodes from the start and join only by proximity.
pub fn ran_into(tip: &TipState, other: &TipState, positions: &[[f64; 2]], reach: f64) -> bool {
    if tip.path.is_empty() || other.path.nodes.is_empty() {
        return false;
    }
    if joined(tip, other) {
        return true;
    }
    let t = tip.position();
    other
        .path
        .nodes
        .iter()
        .filter(|&&k| tip.path.nodes.binary_search(&k).is_err())
        .any(|&k| (V2::new(positions[k][0], positions[k][1]) - t).norm() <= reach)
}

/// Whether the traced cracks of two tips of different macro cracks are one connected set.
pub fn joined(tip: &TipState, other: &TipState) -> bool {
    tip.spec.crack != other.spec.crack && shares_node(&tip.path.nodes, &other.path.nodes)
}

/// Cuts the traced path of a tip whose crack joined another's at the meeting point, which
/// the joint trace no longer shows: half-way along the path between where the two tips
/// were before (`before`, `other_before`), projected on the path. The nodes stay.
pub fn cut_at_meeting(tip: &mut TipState, before: V2, other_before: V2) {
    let line = tip.path_points();
    let s = 0.5
        * (pdbem_geometry::polyline_project(&line, &before)
            + pdbem_geometry::polyline_project(&line, &other_before));
    if s >= tip.path.length {
        return;
    }
    let mut points = polyline::head(&line, s);
    points.push(pdbem_geometry::point_at(&line, s));
    tip.path.points = points.iter().map(|p| [p.x, p.y]).collect();
    tip.path.length = pdbem_geometry::polyline_length(&points);
}

/// Whether two sorted node lists have a node in common.
fn shares_node(a: &[usize], b: &[usize]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::fixtures::window;

    fn body() -> Body {
        Body {
            outline: vec![
                V2::new(0.0, 0.0),
                V2::new(20.0, 0.0),
                V2::new(20.0, 10.0),
                V2::new(0.0, 10.0),
            ],
            holes: vec![vec![
                V2::new(15.0, 2.0),
                V2::new(16.0, 2.0),
                V2::new(16.0, 3.0),
                V2::new(15.0, 3.0),
            ]],
        }
    }

    #[test]
    fn margin_is_measured_from_interface_sides_away_from_the_entry() {
        // Window [9.5, 10.5] x [7.5, 8.5] (dx = 0.05, delta = 0.15075), crack entering
        // from the top at (10, 8.5): band 0.1 m, trigger 0.30075 m from a side.
        let w = window(10.0, 8.0);
        let (band, trigger) = margins(&w, 0.9);
        assert!((band - 0.1).abs() < 1e-12 && (trigger - 0.30075).abs() < 1e-12);
        let entry = V2::new(10.0, 8.5);
        assert!(passed_margin(&w, V2::new(10.0, 7.79), entry, 0.9));
        assert!(!passed_margin(&w, V2::new(10.0, 7.81), entry, 0.9));
        // Close to the entry side: no trigger.
        assert!(!passed_margin(&w, V2::new(10.0, 8.45), entry, 0.9));
    }

    #[test]
    fn boundary_and_hole_are_detected() {
        let b = body();
        let names = vec!["h".to_string()];
        assert_eq!(
            reached_boundary(&b, &names, V2::new(10.0, 0.04), 0.075),
            Some(TipEnd::Outline)
        );
        assert_eq!(
            reached_boundary(&b, &names, V2::new(15.5, 1.95), 0.075),
            Some(TipEnd::Hole("h".into()))
        );
        assert_eq!(TipEnd::Hole("h".into()).to_string(), "hole:h");
        assert_eq!(
            reached_boundary(&b, &[], V2::new(15.5, 1.95), 0.075),
            Some(TipEnd::Hole("0".into()))
        );
        assert_eq!(
            reached_boundary(&b, &names, V2::new(10.0, 5.0), 0.075),
            None
        );
        assert_eq!(
            TipEnd::Coalescence("c.end".into()).to_string(),
            "coalescence:c.end"
        );
    }

    #[test]
    fn entry_of_an_edge_crack_into_its_window() {
        let w = window(10.0, 8.0);
        let line = towards_tip(&[V2::new(10.0, 10.0), V2::new(10.0, 8.0)], true);
        let (e, t) = entry_point(&w, &line, "c.end").unwrap();
        assert!((e - V2::new(10.0, 8.5)).norm() < 1e-12);
        assert!((t - V2::new(10.0, 8.0)).norm() < 1e-12);
    }

    fn traced(crack: usize, nodes: Vec<usize>, tip: [f64; 2]) -> TipState {
        TipState {
            spec: TipSpec {
                name: format!("c{crack}"),
                crack,
                at_end: true,
            },
            window: 0,
            entry: V2::zeros(),
            macro_tip: V2::zeros(),
            path: CrackPath {
                points: vec![[0.0, 0.0], tip],
                tip_node: nodes.first().copied(),
                nodes,
                length: tip[0].hypot(tip[1]),
            },
            ended: None,
        }
    }

    #[test]
    fn joined_cracks_coalesce_by_shared_nodes_and_one_crack_does_not() {
        // Nodes 0..10 on a line, dx = 1.
        let pos: Vec<[f64; 2]> = (0..10).map(|k| [k as f64, 0.0]).collect();
        // Separate and apart: no coalescence.
        let a = traced(0, vec![0, 1, 2], [2.0, 0.0]);
        let b = traced(1, vec![7, 8, 9], [7.0, 0.0]);
        assert!(!ran_into(&a, &b, &pos, 1.5));
        // Separate but the tip within reach of the other crack.
        let a = traced(0, vec![0, 1, 2, 3, 4, 5], [5.0, 0.0]);
        let b = traced(1, vec![7, 8, 9], [7.0, 0.0]);
        assert!(ran_into(&a, &b, &pos, 2.5));
        // Joined: each trace holds all nodes and the tip sits at the other's entry.
        let all: Vec<usize> = (0..10).collect();
        let a = traced(0, all.clone(), [9.0, 0.0]);
        let b = traced(1, all.clone(), [0.0, 0.0]);
        assert!(ran_into(&a, &b, &pos, 1.5) && ran_into(&b, &a, &pos, 1.5));
        // Two tips of one crack share their nodes from the start.
        let a = traced(0, all.clone(), [9.0, 0.0]);
        let b = traced(0, all, [0.0, 0.0]);
        assert!(!ran_into(&a, &b, &pos, 1.5));
        assert!(shares_node(&[1, 4, 6], &[2, 6]) && !shares_node(&[1, 4], &[2, 5, 7]));
    }

    #[test]
    fn a_joined_path_is_cut_half_way_between_the_tips_before() {
        let mut a = traced(0, (0..10).collect(), [9.0, 0.0]);
        a.path.points = (0..10).map(|k| [k as f64, 0.0]).collect();
        cut_at_meeting(&mut a, V2::new(3.0, 0.2), V2::new(7.0, -0.2));
        assert!((a.position() - V2::new(5.0, 0.0)).norm() < 1e-12);
        assert!((a.path.length - 5.0).abs() < 1e-12);
        assert_eq!(a.path.points.len(), 6);
    }
}
