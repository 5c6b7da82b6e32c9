//! The crack nodes and in-crack shortest paths of the tracker (module docs of
//! [`crate::crack_path`], steps 1-4): candidates, Dijkstra over the candidate graph from
//! the entry, the chain back from the tip, the tip beyond a previous tip. Lengths given in
//! spacings are taken at each candidate's own spacing ([`Spacing`]); a link between two
//! candidates uses the larger of their two.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::cell_hash::dist2;
use super::cell_hash::CellHash;
use super::PathParams;
use crate::error::PdError;
use crate::geometry::P2;

/// The farthest reached candidate beyond the previous tip `p` (module docs,
/// step 4): $d_e(q) + d_q(n) \le d_e(n) + $ `slack`, with $q$ the reached
/// candidate nearest `p` and $d_q$ the in-crack distance from it; `link` and `slack` in
/// spacings ($q$'s for the slack). $q$ itself always qualifies.
pub(super) fn tip_beyond(
    c: &Candidates,
    hash: &CellHash,
    s: &Search,
    p: P2,
    link: f64,
    slack: f64,
) -> usize {
    let pts = &c.pts;
    let q = *s
        .reached
        .iter()
        .min_by(|&&a, &&b| {
            dist2(pts[a], p)
                .total_cmp(&dist2(pts[b], p))
                .then(a.cmp(&b))
        })
        .expect("a search reaches its seeds");
    let dq = dijkstra(c, hash, &[(q, 0.0)], link).dist;
    let slack = slack * c.h[q];
    let mut tip = q;
    for &n in &s.reached {
        let beyond = s.dist[q] + dq[n] <= s.dist[n] + slack;
        if beyond && (s.dist[n], std::cmp::Reverse(n)) > (s.dist[tip], std::cmp::Reverse(tip)) {
            tip = n;
        }
    }
    tip
}

/// Node spacing of a traced field: one `dx` for a uniform grid, or one per node (a mixed
/// grid, [`crate::mixed`]).
#[derive(Clone, Copy, Debug)]
pub(super) enum Spacing<'a> {
    Uniform(f64),
    PerNode(&'a [f64]),
}

impl Spacing<'_> {
    fn at(&self, i: usize) -> f64 {
        match self {
            Spacing::Uniform(dx) => *dx,
            Spacing::PerNode(h) => h[i],
        }
    }
}

/// The candidates of a trace: node indices, positions and spacings, and the largest
/// spacing among them (the cell size of the neighbour queries).
pub(super) struct Candidates {
    pub(super) idx: Vec<usize>,
    pub(super) pts: Vec<P2>,
    pub(super) h: Vec<f64>,
    pub(super) h_max: f64,
}

/// The candidates (step 1 of the module docs): indices, positions and spacings of the
/// nodes with damage above the threshold (`params.threshold`, or `finest` for the nodes
/// of the finest spacing of a mixed grid), after checking the inputs.
pub(super) fn crack_nodes(
    positions: &[P2],
    damage: &[f64],
    spacing: Spacing,
    params: &PathParams,
    finest: Option<f64>,
) -> Result<Candidates, PdError> {
    params.validate()?;
    if let Some(t) = finest {
        PathParams {
            threshold: t,
            ..*params
        }
        .validate()?;
    }
    if damage.len() != positions.len() {
        return Err(PdError::LengthMismatch {
            what: "damage",
            expected: positions.len(),
            got: damage.len(),
        });
    }
    let bad_dx = |dx: f64| PdError::invalid("dx", format!("grid spacing {dx} m must be positive"));
    match spacing {
        Spacing::Uniform(dx) if !(dx > 0.0 && dx.is_finite()) => return Err(bad_dx(dx)),
        Spacing::PerNode(h) => {
            if h.len() != positions.len() {
                return Err(PdError::LengthMismatch {
                    what: "spacing",
                    expected: positions.len(),
                    got: h.len(),
                });
            }
            if let Some(&dx) = h.iter().find(|&&v| !(v > 0.0 && v.is_finite())) {
                return Err(bad_dx(dx));
            }
        }
        Spacing::Uniform(_) => {}
    }
    // The finest spacing, where `finest` applies (none to find without it).
    let h_min = finest.map_or(0.0, |_| {
        (0..positions.len())
            .map(|i| spacing.at(i))
            .fold(f64::INFINITY, f64::min)
    });
    let threshold = |i: usize| match finest {
        Some(t) if spacing.at(i) <= h_min * (1.0 + 1e-9) => t,
        _ => params.threshold,
    };
    let idx: Vec<usize> = (0..positions.len())
        .filter(|&i| damage[i] > threshold(i))
        .collect();
    let pts = idx.iter().map(|&i| positions[i]).collect();
    let h: Vec<f64> = idx.iter().map(|&i| spacing.at(i)).collect();
    let h_max = match spacing {
        Spacing::Uniform(dx) => dx,
        Spacing::PerNode(_) => h.iter().copied().fold(f64::MIN_POSITIVE, f64::max),
    };
    Ok(Candidates { idx, pts, h, h_max })
}

/// Result of the Dijkstra search over the candidate graph.
pub(super) struct Search {
    /// Predecessor of each reached candidate (`usize::MAX` for a seed).
    pub(super) pred: Vec<usize>,
    /// In-crack distance of each candidate from the entry (infinite if not
    /// reached).
    pub(super) dist: Vec<f64>,
    /// Candidates reached from the seeds, in order of distance.
    pub(super) reached: Vec<usize>,
    /// The reached candidate farthest along the crack.
    pub(super) tip: usize,
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
pub(super) fn shortest_paths(
    c: &Candidates,
    hash: &CellHash,
    entry: P2,
    params: &PathParams,
) -> Option<Search> {
    let seeds: Vec<(usize, f64)> = c
        .pts
        .iter()
        .enumerate()
        .map(|(k, p)| (k, dist2(*p, entry).sqrt()))
        .filter(|&(k, d)| d <= params.entry_radius * c.h[k])
        .collect();
    if seeds.is_empty() {
        return None;
    }
    let s = dijkstra(c, hash, &seeds, params.link);
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

/// Dijkstra over the candidates linked within `link` spacings (the larger of the two
/// candidates') from `seeds` (candidate, starting distance); `tip` is left at the first
/// seed settled.
fn dijkstra(c: &Candidates, hash: &CellHash, seeds: &[(usize, f64)], link: f64) -> Search {
    let pts = &c.pts;
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
        hash.for_each_within(pts, pts[k], link * c.h_max, |j| {
            if !within(pts[k], pts[j], link * c.h[k].max(c.h[j])) {
                return;
            }
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

/// Whether `a` and `b` are at most `r` apart, with the tolerance of
/// [`CellHash::for_each_within`] (on a uniform grid every candidate the hash returns
/// passes).
fn within(a: P2, b: P2, r: f64) -> bool {
    dist2(a, b) <= (r * (1.0 + 1e-9)).powi(2)
}

/// The entry followed by the node positions from the seed to the tip.
pub(super) fn chain_to_tip(pts: &[P2], s: &Search, entry: P2) -> Vec<P2> {
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
