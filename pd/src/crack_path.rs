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

use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};

use pdbem_geometry as g;
use serde::Serialize;

use crate::damage::MACRO_CRACK_DAMAGE;
use crate::error::PdError;
use crate::geometry::{from_g, to_g_all, P2};
use crate::model::PdModel;

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
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
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
        let from = from_g(g::point_at(
            &to_g_all(&self.points),
            (self.length - back).max(0.0),
        ));
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
    let length = g::polyline_length(&to_g_all(&points));
    let mut nodes: Vec<usize> = search.reached.iter().map(|&k| cand[k]).collect();
    nodes.sort_unstable();
    Ok(CrackPath {
        points,
        nodes,
        tip_node: Some(cand[search.tip]),
        length,
    })
}

/// The farthest reached candidate beyond the previous tip `p` (module docs,
/// step 4): $d_e(q) + d_q(n) \le d_e(n) + $ `slack`, with $q$ the reached
/// candidate nearest `p` and $d_q$ the in-crack distance from it. $q$
/// itself always qualifies.
fn tip_beyond(pts: &[P2], hash: &CellHash, s: &Search, p: P2, link: f64, slack: f64) -> usize {
    let q = *s
        .reached
        .iter()
        .min_by(|&&a, &&b| {
            dist2(pts[a], p)
                .total_cmp(&dist2(pts[b], p))
                .then(a.cmp(&b))
        })
        .expect("a search reaches its seeds");
    let dq = dijkstra(pts, hash, &[(q, 0.0)], link).dist;
    let mut tip = q;
    for &n in &s.reached {
        let beyond = s.dist[q] + dq[n] <= s.dist[n] + slack;
        if beyond && (s.dist[n], std::cmp::Reverse(n)) > (s.dist[tip], std::cmp::Reverse(tip)) {
            tip = n;
        }
    }
    tip
}

/// The candidates (step 1 of the module docs): indices and positions of the
/// nodes with damage above the threshold, after checking the inputs.
fn crack_nodes(
    positions: &[P2],
    damage: &[f64],
    dx: f64,
    params: &PathParams,
) -> Result<(Vec<usize>, Vec<P2>), PdError> {
    params.validate()?;
    if damage.len() != positions.len() {
        return Err(PdError::LengthMismatch {
            what: "damage",
            expected: positions.len(),
            got: damage.len(),
        });
    }
    if !(dx > 0.0 && dx.is_finite()) {
        return Err(PdError::invalid(
            "dx",
            format!("grid spacing {dx} m must be positive"),
        ));
    }
    let cand: Vec<usize> = (0..positions.len())
        .filter(|&i| damage[i] > params.threshold)
        .collect();
    let pts = cand.iter().map(|&i| positions[i]).collect();
    Ok((cand, pts))
}

/// Result of the Dijkstra search over the candidate graph.
struct Search {
    /// Predecessor of each reached candidate (`usize::MAX` for a seed).
    pred: Vec<usize>,
    /// In-crack distance of each candidate from the entry (infinite if not
    /// reached).
    dist: Vec<f64>,
    /// Candidates reached from the seeds, in order of distance.
    reached: Vec<usize>,
    /// The reached candidate farthest along the crack.
    tip: usize,
}

/// A heap entry ordered by smallest distance first, then smallest index.
#[derive(PartialEq)]
struct Item(f64, usize);

impl Eq for Item {}

impl Ord for Item {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}

impl PartialOrd for Item {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

/// Dijkstra from the seeds near `entry`; `None` when there is no seed.
fn shortest_paths(
    pts: &[P2],
    hash: &CellHash,
    entry: P2,
    params: &PathParams,
    dx: f64,
) -> Option<Search> {
    let r_entry = params.entry_radius * dx;
    let seeds: Vec<(usize, f64)> = pts
        .iter()
        .enumerate()
        .map(|(k, p)| (k, dist2(*p, entry).sqrt()))
        .filter(|(_, d)| *d <= r_entry)
        .collect();
    if seeds.is_empty() {
        return None;
    }
    let s = dijkstra(pts, hash, &seeds, params.link * dx);
    // The farthest candidate; of equal distances the first settled (the
    // smallest index).
    let mut far = s.reached[0];
    for &k in &s.reached {
        if s.dist[k] > s.dist[far] {
            far = k;
        }
    }
    Some(Search { tip: far, ..s })
}

/// Dijkstra over the candidates linked within `link` from `seeds` (candidate,
/// starting distance); `tip` is left at the first seed settled.
fn dijkstra(pts: &[P2], hash: &CellHash, seeds: &[(usize, f64)], link: f64) -> Search {
    let n = pts.len();
    let mut dist = vec![f64::INFINITY; n];
    let mut pred = vec![usize::MAX; n];
    let mut heap = BinaryHeap::new();
    for &(k, d) in seeds {
        if d < dist[k] {
            dist[k] = d;
            heap.push(Item(d, k));
        }
    }
    let mut done = vec![false; n];
    let mut reached = Vec::new();
    while let Some(Item(d, k)) = heap.pop() {
        if done[k] {
            continue;
        }
        done[k] = true;
        reached.push(k);
        hash.for_each_within(pts, pts[k], link, |j| {
            let nd = d + dist2(pts[k], pts[j]).sqrt();
            if !done[j] && nd < dist[j] {
                dist[j] = nd;
                pred[j] = k;
                heap.push(Item(nd, j));
            }
        });
    }
    let tip = reached.first().copied().unwrap_or(usize::MAX);
    Search {
        pred,
        dist,
        reached,
        tip,
    }
}

/// The entry followed by the node positions from the seed to the tip.
fn chain_to_tip(pts: &[P2], s: &Search, entry: P2) -> Vec<P2> {
    let mut chain = Vec::new();
    let mut k = s.tip;
    while k != usize::MAX {
        chain.push(pts[k]);
        k = s.pred[k];
    }
    chain.push(entry);
    chain.reverse();
    chain.dedup_by(|a, b| dist2(*a, *b) == 0.0);
    chain
}

/// Points every `h` along the polyline, keeping both end points.
fn resample(line: &[P2], h: f64) -> Vec<P2> {
    let g_line = to_g_all(line);
    let total = g::polyline_length(&g_line);
    if line.len() < 2 || total == 0.0 {
        return line[..1].to_vec();
    }
    let n = ((total / h).round() as usize).max(1);
    (0..=n)
        .map(|k| from_g(g::point_at(&g_line, total * k as f64 / n as f64)))
        .collect()
}

/// Move every point but the first across the path to the weighted
/// centroid of the crack nodes within `radius` of it (normal component
/// only). The normal at a point is that of the chord of `line` from
/// `radius` before to `radius` after it, which averages out the zig-zag of
/// the node chain.
fn centre_across(line: &[P2], crack: &[P2], radius: f64) -> Vec<P2> {
    if line.len() < 2 || radius == 0.0 {
        return line.to_vec();
    }
    let hash = CellHash::new(crack, radius);
    let mut out = line.to_vec();
    let g_line = to_g_all(line);
    let mut s = 0.0;
    for k in 1..line.len() {
        s += dist2(line[k - 1], line[k]).sqrt();
        let a = from_g(g::point_at(&g_line, (s - radius).max(0.0)));
        let b = from_g(g::point_at(&g_line, s + radius));
        let t = [b[0] - a[0], b[1] - a[1]];
        let lt = t[0].hypot(t[1]);
        if lt == 0.0 {
            continue;
        }
        let nrm = [-t[1] / lt, t[0] / lt];
        out[k] = mean_shift_across(line[k], nrm, crack, &hash, radius);
    }
    out
}

/// Mean shift along the normal `nrm` with the smooth kernel
/// $w = (1 - d^2/r^2)^2$: move `p` by the weighted mean normal offset of the
/// crack nodes within `r` until the move is below 1e-9 `r`. With `r` at
/// least twice the band's row spacing the kernel density across the band
/// has one maximum, on the centre line of a symmetric band; 100 passes cap
/// the loop (the move shrinks geometrically).
fn mean_shift_across(p: P2, nrm: P2, crack: &[P2], hash: &CellHash, r: f64) -> P2 {
    let mut q = p;
    let r2 = r * r;
    for _ in 0..100 {
        let (mut s, mut w) = (0.0, 0.0);
        hash.for_each_within(crack, q, r, |j| {
            let c = 1.0 - dist2(crack[j], q) / r2;
            let wj = c * c;
            s += wj * ((crack[j][0] - q[0]) * nrm[0] + (crack[j][1] - q[1]) * nrm[1]);
            w += wj;
        });
        if w <= 0.0 {
            break;
        }
        let off = s / w;
        q = [q[0] + off * nrm[0], q[1] + off * nrm[1]];
        if off.abs() < 1e-9 * r {
            break;
        }
    }
    q
}

#[inline]
fn dist2(a: P2, b: P2) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// A uniform cell hash of points for fixed-radius neighbour queries.
struct CellHash {
    h: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

impl CellHash {
    fn new(pts: &[P2], h: f64) -> Self {
        let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (k, p) in pts.iter().enumerate() {
            cells.entry(Self::key(*p, h)).or_default().push(k);
        }
        CellHash { h, cells }
    }

    fn key(p: P2, h: f64) -> (i64, i64) {
        ((p[0] / h).floor() as i64, (p[1] / h).floor() as i64)
    }

    /// Call `f(j)` for every point `j` within `r` (<= the cell size) of `q`,
    /// in increasing cell then insertion order.
    fn for_each_within(&self, pts: &[P2], q: P2, r: f64, mut f: impl FnMut(usize)) {
        let (cx, cy) = Self::key(q, self.h);
        let r2 = (r * (1.0 + 1e-9)).powi(2);
        for gy in cy - 1..=cy + 1 {
            for gx in cx - 1..=cx + 1 {
                if let Some(v) = self.cells.get(&(gx, gy)) {
                    for &j in v {
                        if dist2(pts[j], q) <= r2 {
                            f(j);
                        }
                    }
                }
            }
        }
    }
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
