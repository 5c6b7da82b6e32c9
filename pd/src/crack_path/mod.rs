//! Crack-tip tracking on a damage field: the macro crack connected to an
//! entry point, its tip and its smoothed path (seed 002 section 2.3.2 and
//! Algorithm 2 step 5: "the farthest point of the macro crack, phi > 0.38,
//! from the crack's entry into the window is the tip").
//!
//! Entry points:
//! - [`trace_crack`]: on a [`PdModel`] (real nodes, current damage).
//! - [`trace_crack_in`]: the same on plain arrays (positions, damage, `dx`),
//!   for callers that keep their own fields.
//! - [`trace_crack_beyond`]: on plain arrays, with the tip continuing a
//!   previous tip (growth tracking over load steps).
//! - [`crack_clusters`]: every macro crack of a field (its connected
//!   components), with no entry point.
//!
//! Both return a [`CrackPath`]; [`PathParams`] sets the threshold and the
//! lengths, all in units of the grid spacing `dx`.
//!
//! Algorithm:
//! 1. Candidates: real nodes with damage $\varphi > $ `threshold`.
//! 2. Graph: two candidates are linked when they are at most `link` apart
//!    (1.5 dx joins the 8 lattice neighbours).
//! 3. Seeds: candidates within `entry_radius` of the entry point; each seed
//!    starts at its distance from the entry. Dijkstra over the graph gives the
//!    shortest in-crack distance from the entry to every connected node.
//! 4. Tip: the connected node with the largest in-crack distance (the
//!    farthest point along the path, so a crack that turns back towards the
//!    entry still has its tip at the far end). Given the previous tip
//!    ([`trace_crack_beyond`]), only nodes beyond it count: those whose
//!    shortest in-crack route from the entry may pass through the connected
//!    node $q$ nearest the previous tip (within [`BEYOND_DX`]):
//!    $d_e(q) + d_q(n) \le d_e(n) + $ `BEYOND_DX` dx. A second crack that
//!    joins the path behind the tip (a branch from elsewhere in the body)
//!    then never takes the tip over, however far it reaches; the tip does not
//!    move back either.
//! 5. Path: the predecessor chain from the tip back to a seed, with the
//!    entry point prepended, resampled every `spacing` along its length.
//! 6. Smoothing: a broken-bond band is about two node rows wide and the
//!    chain zig-zags inside it. Every resampled point except the entry is
//!    moved across the path (normal to the chord over `smoothing` before
//!    and after it) to the kernel-weighted centroid of the connected
//!    candidates within `smoothing` of it, repeated until it stops moving (a
//!    mean shift), which puts it on the centre line of the band; the along-path position is kept, so the
//!    tip keeps its reach. The entry point stays where it was given (the
//!    coupling attaches the BEM crack there).
//!
//! The result is deterministic (ties broken by node index) and does not
//! depend on the number of threads.
//!
//! Files of the module:
//! - `mod.rs`: [`PathParams`], [`CrackPath`], the entry points and the tracing steps.
//! - `search`: steps 1-4: candidates, in-crack shortest paths (Dijkstra), the chain back
//!   from the tip, the tip beyond a previous tip.
//! - `smooth`: steps 5-6: resampling and centring the path across the band (mean shift).
//! - `cell_hash`: the uniform cell hash of the fixed-radius neighbour queries.

mod cell_hash;
mod search;
mod smooth;

use serde::Serialize;

use crate::damage::MACRO_CRACK_DAMAGE;
use crate::error::PdError;
use crate::geometry::P2;
use crate::model::PdModel;
use cell_hash::CellHash;
use search::{chain_to_tip, crack_nodes, shortest_paths, tip_beyond};
use smooth::{centre_across, point_at_length, polyline_length, resample};

/// Parameters of the tip tracker. Lengths are multiples of the grid spacing.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PathParams {
    /// Damage above which a node belongs to the macro crack (seed 002
    /// section 2.1: 0.38).
    pub threshold: f64,
    /// Link distance between crack nodes (dx); 1.5 joins the 8 lattice
    /// neighbours of a node.
    pub link: f64,
    /// Crack nodes within this distance of the entry point start the path
    /// (dx). 2 covers the two node rows on either side of a crack line
    /// that ends at the entry.
    pub entry_radius: f64,
    /// Spacing of the returned polyline points (dx).
    pub spacing: f64,
    /// Radius of the centroid used to centre the path across the damage band
    /// (dx); 2 spans the band of a straight crack (two rows) with one row of
    /// margin.
    pub smoothing: f64,
}

impl Default for PathParams {
    fn default() -> Self {
        PathParams {
            threshold: MACRO_CRACK_DAMAGE,
            link: 1.5,
            entry_radius: 2.0,
            spacing: 1.0,
            smoothing: 2.0,
        }
    }
}

impl PathParams {
    /// Check every field; the message names the field and its constraint.
    pub fn validate(&self) -> Result<(), PdError> {
        if !(self.threshold > 0.0 && self.threshold < 1.0) {
            return Err(PdError::invalid(
                "path.threshold",
                format!("damage threshold {} must lie in (0, 1)", self.threshold),
            ));
        }
        for (name, v, min) in [
            ("path.link", self.link, 1.0),
            ("path.entry_radius", self.entry_radius, 0.5),
            ("path.spacing", self.spacing, 0.1),
            ("path.smoothing", self.smoothing, 0.0),
        ] {
            if !(v.is_finite() && v >= min) {
                return Err(PdError::invalid(
                    name,
                    format!("{v} dx is below the minimum {min} dx (or not finite)"),
                ));
            }
        }
        Ok(())
    }
}

/// The traced macro crack.
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct CrackPath {
    /// The smoothed polyline from the entry point (first) to the tip (last).
    /// A single point (the entry) when no crack node is connected to it.
    pub points: Vec<P2>,
    /// Indices of the macro-crack nodes connected to the entry (unordered).
    pub nodes: Vec<usize>,
    /// Index of the tip node (the farthest connected node along the crack).
    pub tip_node: Option<usize>,
    /// Length of [`Self::points`] (m).
    pub length: f64,
}

impl CrackPath {
    /// The tip: the last point of the path (the entry when no crack is
    /// connected to it).
    pub fn tip(&self) -> P2 {
        *self
            .points
            .last()
            .expect("a path has at least the entry point")
    }

    /// Whether a macro crack is connected to the entry.
    pub fn is_empty(&self) -> bool {
        self.tip_node.is_none()
    }

    /// Unit direction of the crack at the tip: the chord from the path point
    /// `back` (m) behind the tip, measured along the path, to the tip. `None`
    /// for a path shorter than a point.
    pub fn tip_direction(&self, back: f64) -> Option<P2> {
        let tip = self.tip();
        let from = point_at_length(&self.points, (self.length - back).max(0.0));
        let d = [tip[0] - from[0], tip[1] - from[1]];
        let l = d[0].hypot(d[1]);
        (l > 0.0).then(|| [d[0] / l, d[1] / l])
    }
}

/// Trace the macro crack of `model` connected to `entry` (real nodes only,
/// current damage). See the module docs for the algorithm.
pub fn trace_crack(model: &PdModel, entry: P2, params: &PathParams) -> Result<CrackPath, PdError> {
    let n = model.n_real();
    let phi = model.damage();
    trace_crack_in(
        &model.positions()[..n],
        &phi[..n],
        model.grid().dx,
        entry,
        params,
    )
}

/// Trace the macro crack connected to `entry` on plain arrays: node
/// positions, their damage (same length) and the grid spacing `dx` (m).
pub fn trace_crack_in(
    positions: &[P2],
    damage: &[f64],
    dx: f64,
    entry: P2,
    params: &PathParams,
) -> Result<CrackPath, PdError> {
    trace(positions, damage, dx, entry, None, params)
}

/// The macro cracks of a damage field: the connected components of the nodes
/// with damage above `params.threshold`, linked within `params.link` dx
/// (steps 1-2 of the module docs), each as node indices in increasing order,
/// the components ordered by their first node. For failure checks that do not
/// depend on which tip is tracked (a crack cutting the body from outline to
/// outline).
pub fn crack_clusters(
    positions: &[P2],
    damage: &[f64],
    dx: f64,
    params: &PathParams,
) -> Result<Vec<Vec<usize>>, PdError> {
    let (cand, pts) = crack_nodes(positions, damage, dx, params)?;
    let link = params.link * dx;
    let hash = CellHash::new(&pts, link);
    let mut seen = vec![false; pts.len()];
    let mut clusters = Vec::new();
    for start in 0..pts.len() {
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let (mut stack, mut members) = (vec![start], Vec::new());
        while let Some(k) = stack.pop() {
            members.push(cand[k]);
            hash.for_each_within(&pts, pts[k], link, |j| {
                if !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            });
        }
        members.sort_unstable();
        clusters.push(members);
    }
    Ok(clusters)
}

/// Slack of the beyond-the-previous-tip test (dx): the in-crack route from
/// the entry to a tip candidate may be this much shorter than the route
/// through the previous tip. Both routes run inside a band two node rows
/// wide, so a candidate ahead of the previous tip on the other row is a few
/// tenths of dx off; a branch leaving the path more than 1.5 dx behind the
/// previous tip is twice its distance off and is excluded.
pub const BEYOND_DX: f64 = 3.0;

/// [`trace_crack_in`] with the tip restricted to the part of the crack
/// beyond `previous_tip` (a tip traced earlier on the same, since grown,
/// crack): see step 4 of the module docs.
pub fn trace_crack_beyond(
    positions: &[P2],
    damage: &[f64],
    dx: f64,
    entry: P2,
    previous_tip: P2,
    params: &PathParams,
) -> Result<CrackPath, PdError> {
    trace(positions, damage, dx, entry, Some(previous_tip), params)
}

fn trace(
    positions: &[P2],
    damage: &[f64],
    dx: f64,
    entry: P2,
    previous_tip: Option<P2>,
    params: &PathParams,
) -> Result<CrackPath, PdError> {
    let (cand, pts) = crack_nodes(positions, damage, dx, params)?;
    let hash = CellHash::new(&pts, params.link * dx);
    let Some(mut search) = shortest_paths(&pts, &hash, entry, params, dx) else {
        return Ok(CrackPath {
            points: vec![entry],
            ..Default::default()
        });
    };
    if let Some(p) = previous_tip {
        search.tip = tip_beyond(&pts, &hash, &search, p, params.link * dx, BEYOND_DX * dx);
    }
    let chain = chain_to_tip(&pts, &search, entry);
    let raw = resample(&chain, params.spacing * dx);
    let connected: Vec<P2> = search.reached.iter().map(|&k| pts[k]).collect();
    let points = centre_across(&raw, &connected, params.smoothing * dx);
    let length = polyline_length(&points);
    let mut nodes: Vec<usize> = search.reached.iter().map(|&k| cand[k]).collect();
    nodes.sort_unstable();
    Ok(CrackPath {
        points,
        nodes,
        tip_node: Some(cand[search.tip]),
        length,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{PdProblem, Region};

    /// Unit grid `nx x ny` (dx = 1, nodes at cell centres) with damage 0.5
    /// on the nodes for which `band` holds.
    fn field(nx: usize, ny: usize, band: impl Fn(f64, f64) -> bool) -> (Vec<P2>, Vec<f64>) {
        let mut pos = Vec::new();
        let mut phi = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let p = [i as f64 + 0.5, j as f64 + 0.5];
                phi.push(if band(p[0], p[1]) { 0.5 } else { 0.1 });
                pos.push(p);
            }
        }
        (pos, phi)
    }

    fn max_offset_from_line(points: &[P2], y: f64) -> f64 {
        points.iter().map(|p| (p[1] - y).abs()).fold(0.0, f64::max)
    }

    #[test]
    fn straight_two_row_band_is_centred_and_reaches_the_tip() {
        // A crack along y = 10 from x = 0 to x = 12: the rows y = 9.5 and
        // 10.5 are damaged. Centred path: on y = 10 within 1e-12 except the
        // entry, tip at the farthest node x = 11.5.
        let (pos, phi) = field(30, 20, |x, y| x < 12.0 && (y - 10.0).abs() < 1.0);
        let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 10.0], &PathParams::default()).unwrap();
        // Measured: 0.034 dx next to the entry (the band starts there), 1e-9
        // from x = 4 on.
        assert!(
            max_offset_from_line(&p.points, 10.0) < 0.05,
            "{:?}",
            p.points
        );
        assert!((p.tip()[0] - 11.5).abs() < 1e-12, "tip {:?}", p.tip());
        assert_eq!(p.nodes.len(), 24);
        assert!((p.length - 11.5).abs() < 0.01, "length {}", p.length);
        let d = p.tip_direction(3.0).unwrap();
        assert!((d[0] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn kinked_band_is_followed_to_its_far_end() {
        // Horizontal to x = 10, then up at 45 degrees (one-node-wide band
        // along y = 10 + (x - 10), two rows wide on the flat part).
        let (pos, phi) = field(30, 30, |x, y| {
            (x < 10.0 && (y - 10.0).abs() < 1.0)
                || ((10.0..20.0).contains(&x) && (y - x).abs() < 1.0)
        });
        let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 10.0], &PathParams::default()).unwrap();
        let t = p.tip();
        assert!(t[0] > 19.0 && (t[1] - t[0]).abs() < 1.0, "tip {t:?}");
        let d = p.tip_direction(4.0).unwrap();
        let ang = d[1].atan2(d[0]).to_degrees();
        assert!((ang - 45.0).abs() < 5.0, "tip direction {ang} deg");
    }

    #[test]
    fn crack_not_connected_to_the_entry_is_ignored() {
        // A damaged blob far from the entry; the entry has no crack near it.
        let (pos, phi) = field(20, 20, |x, y| {
            (x - 15.0).abs() < 2.0 && (y - 15.0).abs() < 2.0
        });
        let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 5.0], &PathParams::default()).unwrap();
        assert!(p.is_empty());
        assert_eq!(p.points, vec![[0.0, 5.0]]);
        assert_eq!(p.length, 0.0);
    }

    #[test]
    fn gap_of_two_cells_stops_the_path() {
        // Band broken between x = 8 and x = 10: two cells, more than the
        // 1.5 dx link, so the tip stays at x = 7.5.
        let (pos, phi) = field(30, 20, |x, y| {
            (x < 8.0 || (10.0..20.0).contains(&x)) && (y - 10.0).abs() < 1.0
        });
        let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 10.0], &PathParams::default()).unwrap();
        assert!((p.tip()[0] - 7.5).abs() < 1e-12);
    }

    #[test]
    fn branch_longest_along_the_crack_wins() {
        // Main band to x = 15; a short branch down at x = 5 (6 long). The
        // farthest point along the crack is the end of the main band.
        let (pos, phi) = field(30, 30, |x, y| {
            (x < 15.0 && (y - 20.0).abs() < 1.0) || ((x - 5.0).abs() < 1.0 && y > 13.0 && y < 20.0)
        });
        let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 20.0], &PathParams::default()).unwrap();
        assert!((p.tip()[0] - 14.5).abs() < 1e-12, "tip {:?}", p.tip());
    }

    #[test]
    fn a_crack_joining_behind_the_previous_tip_does_not_take_the_tip_over() {
        // Main band along y = 20 to x = 15 (entry at x = 0); a second crack
        // joins it at x = 3 and runs down to y = 0, 22 dx along the crack
        // from the entry against the main band's 14.5. Traced from scratch
        // its end is the farthest point; traced beyond the previous tip at
        // x = 10 the tip stays on the main band, at its end.
        let (pos, phi) = field(30, 30, |x, y| {
            (x < 15.0 && (y - 20.0).abs() < 1.0) || ((x - 3.0).abs() < 1.0 && y < 20.0)
        });
        let prm = PathParams::default();
        let free = trace_crack_in(&pos, &phi, 1.0, [0.0, 20.0], &prm).unwrap();
        assert!(free.tip()[1] < 1.0, "from scratch: tip {:?}", free.tip());
        let on = trace_crack_beyond(&pos, &phi, 1.0, [0.0, 20.0], [10.0, 20.0], &prm).unwrap();
        assert!((on.tip()[0] - 14.5).abs() < 1e-12, "tip {:?}", on.tip());
        assert!(
            max_offset_from_line(&on.points, 20.0) < 0.6,
            "{:?}",
            on.points
        );
        // A previous tip at the end of the band: the tip stays there, and
        // one at the entry gives the trace from scratch.
        let end = trace_crack_beyond(&pos, &phi, 1.0, [0.0, 20.0], [14.5, 20.0], &prm).unwrap();
        assert!((end.tip()[0] - 14.5).abs() < 1e-12, "tip {:?}", end.tip());
        let entry = trace_crack_beyond(&pos, &phi, 1.0, [0.0, 20.0], [0.0, 20.0], &prm).unwrap();
        assert_eq!(entry, free);
    }

    #[test]
    fn a_fork_just_behind_the_previous_tip_still_continues_it() {
        // The band forks 1 dx behind the previous tip (x = 9, tip at x = 10):
        // both arms are beyond it within BEYOND_DX, and the longer one (down,
        // 12 dx against 5 along y = 20) is the tip.
        let (pos, phi) = field(30, 30, |x, y| {
            (x < 15.0 && (y - 20.0).abs() < 1.0) || ((x - 9.0).abs() < 1.0 && y < 20.0 && y > 7.0)
        });
        let prm = PathParams::default();
        let on = trace_crack_beyond(&pos, &phi, 1.0, [0.0, 20.0], [10.0, 20.0], &prm).unwrap();
        assert!(on.tip()[1] < 8.0, "tip {:?}", on.tip());
    }

    #[test]
    fn clusters_are_the_connected_cracks() {
        // Two bands two cells apart (more than the 1.5 dx link) and a band
        // touching the first diagonally (linked): two clusters.
        let (pos, phi) = field(20, 20, |x, y| {
            (x < 8.0 && (y - 10.0).abs() < 1.0)
                || ((10.0..16.0).contains(&x) && (y - 10.0).abs() < 1.0)
                || ((x - 8.5).abs() < 0.6 && (y - 11.5).abs() < 0.6)
        });
        let c = crack_clusters(&pos, &phi, 1.0, &PathParams::default()).unwrap();
        assert_eq!(c.len(), 2, "{c:?}");
        assert_eq!((c[0].len(), c[1].len()), (17, 12));
        assert!(c[0].contains(&(11 * 20 + 8)));
    }

    #[test]
    fn bad_input_is_reported_with_numbers() {
        let (pos, phi) = field(4, 4, |_, _| false);
        let e = trace_crack_in(&pos, &phi[..3], 1.0, [0.0, 0.0], &PathParams::default());
        assert!(matches!(
            e,
            Err(PdError::LengthMismatch {
                expected: 16,
                got: 3,
                ..
            })
        ));
        let bad = PathParams {
            threshold: 1.5,
            ..Default::default()
        };
        assert!(trace_crack_in(&pos, &phi, 1.0, [0.0, 0.0], &bad).is_err());
    }

    #[test]
    fn model_pre_crack_is_traced_along_its_line() {
        // 20 x 10 cells, dx = 1, pre-crack along y = 5 from the left edge to
        // x = 8 (between node rows): the pre-cut damage is about 0.39 next
        // to the line, above the 0.38 threshold; the traced tip lies within
        // 1.5 dx of the pre-crack tip and the path on the line.
        let p = PdProblem {
            region: Region::rectangle([0.0, 0.0], [20.0, 10.0]),
            dx: 1.0,
            youngs_modulus: 1.0,
            cracks: vec![vec![[-1.0, 5.0], [8.0, 5.0]]],
            ..Default::default()
        };
        let m = PdModel::new(&p).unwrap();
        let path = trace_crack(&m, [0.0, 5.0], &PathParams::default()).unwrap();
        assert!(!path.is_empty());
        // Measured: tip node at x = 6.5 (the nodes at x = 7.5 beside the
        // pre-crack tip lose fewer than 0.38 of their bonds).
        assert!((path.tip()[0] - 8.0).abs() <= 1.5, "tip {:?}", path.tip());
        assert!(
            max_offset_from_line(&path.points, 5.0) < 0.05,
            "{:?}",
            path.points
        );
    }
}
