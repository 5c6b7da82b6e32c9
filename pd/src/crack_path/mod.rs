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
//! - [`trace_crack_spaced`]: on plain arrays with one spacing per node (a
//!   mixed grid).
//! - [`trace_crack_finest`] ([`trace_crack_finest_in`] on plain arrays): a lower
//!   threshold for the nodes of the finest spacing (a crack held at the end of a
//!   refined growth window's fine cells).
//!
//! They return a [`CrackPath`]; [`PathParams`] sets the threshold and the
//! lengths, all in units of the grid spacing `dx`. On a mixed grid
//! ([`crate::mixed`]) every length is taken at the spacing of the nodes it is
//! measured from (a link at the larger of its two nodes'), so a crack in the
//! fine cells of a refinement zone is traced at their spacing: taken at the
//! coarse spacing, the link would bridge an intact ligament of two fine cells
//! and the centring would average over four fine rows.
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
//! - `tests`: the tracker's unit tests.
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
use search::{chain_to_tip, crack_nodes, shortest_paths, tip_beyond, Spacing};
use smooth::{centre_across, point_at_length, polyline_length, resample};

/// Parameters of the tip tracker. Lengths are multiples of the grid spacing (of each
/// node's own spacing on a mixed grid).
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
/// current damage). See the module docs for the algorithm; on a mixed grid the lengths
/// of `params` are taken at each node's own spacing ([`trace_crack_spaced`]).
pub fn trace_crack(model: &PdModel, entry: P2, params: &PathParams) -> Result<CrackPath, PdError> {
    let (n, phi, spacing) = real_nodes(model);
    trace(
        &model.positions()[..n],
        &phi[..n],
        spacing,
        entry,
        None,
        params,
    )
}

/// The number of real nodes of `model`, the damage of its nodes and their spacing.
fn real_nodes(model: &PdModel) -> (usize, Vec<f64>, Spacing<'_>) {
    let n = model.n_real();
    let grid = model.grid();
    let spacing = if grid.is_mixed() {
        Spacing::PerNode(&grid.spacing[..n])
    } else {
        Spacing::Uniform(grid.dx)
    };
    (n, model.damage(), spacing)
}

/// [`trace_crack_in`] on nodes of different spacings `spacing` (m, one per node; a mixed
/// grid, [`crate::mixed`]). Every length of `params` is taken at the spacing of the nodes
/// it is measured from: a candidate seeds the path within `entry_radius` of its own
/// spacing of the entry, two candidates link within `link` times the larger of their
/// spacings (so the band of a crack that runs from coarse into fine cells stays
/// connected), the path is resampled every `spacing` of the finest connected node, and a
/// point is centred across the band within `smoothing` times the spacing of the
/// connected node nearest to it. With one spacing for every node this is
/// [`trace_crack_in`], bit for bit.
pub fn trace_crack_spaced(
    positions: &[P2],
    damage: &[f64],
    spacing: &[f64],
    entry: P2,
    params: &PathParams,
) -> Result<CrackPath, PdError> {
    trace(
        positions,
        damage,
        Spacing::PerNode(spacing),
        entry,
        None,
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
    trace(positions, damage, Spacing::Uniform(dx), entry, None, params)
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
    let c = crack_nodes(positions, damage, Spacing::Uniform(dx), params, None)?;
    let (cand, pts) = (c.idx, c.pts);
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
    trace(
        positions,
        damage,
        Spacing::Uniform(dx),
        entry,
        Some(previous_tip),
        params,
    )
}

/// [`trace_crack`] with the nodes of the finest spacing of a mixed grid counted as crack
/// nodes from the damage `finest_threshold` ([`trace_crack_finest_in`]).
pub fn trace_crack_finest(
    model: &PdModel,
    entry: P2,
    params: &PathParams,
    finest_threshold: f64,
) -> Result<CrackPath, PdError> {
    let (n, phi, spacing) = real_nodes(model);
    let c = crack_nodes(
        &model.positions()[..n],
        &phi[..n],
        spacing,
        params,
        Some(finest_threshold),
    )?;
    path_of(c, entry, None, params)
}

/// [`trace_crack_spaced`] with the nodes of the finest spacing counted as crack nodes
/// from the damage `finest_threshold`, the others from `params.threshold`. On a refined
/// grid whose coarse cells cannot break (a refined growth window), a crack that reached
/// the end of the fine cells with a damage under the threshold (a fresh crack between
/// two node columns) is followed to them, while the damage that spreads into the coarse
/// cells along the size jump is not taken for the crack. With one spacing for every node
/// every node is of the finest spacing: the trace at `finest_threshold`.
pub fn trace_crack_finest_in(
    positions: &[P2],
    damage: &[f64],
    spacing: &[f64],
    entry: P2,
    params: &PathParams,
    finest_threshold: f64,
) -> Result<CrackPath, PdError> {
    let c = crack_nodes(
        positions,
        damage,
        Spacing::PerNode(spacing),
        params,
        Some(finest_threshold),
    )?;
    path_of(c, entry, None, params)
}

fn trace(
    positions: &[P2],
    damage: &[f64],
    spacing: Spacing,
    entry: P2,
    previous_tip: Option<P2>,
    params: &PathParams,
) -> Result<CrackPath, PdError> {
    let c = crack_nodes(positions, damage, spacing, params, None)?;
    path_of(c, entry, previous_tip, params)
}

/// Steps 2-6 of the module docs on the candidates `c`.
fn path_of(
    c: search::Candidates,
    entry: P2,
    previous_tip: Option<P2>,
    params: &PathParams,
) -> Result<CrackPath, PdError> {
    let hash = CellHash::new(&c.pts, params.link * c.h_max);
    let Some(mut search) = shortest_paths(&c, &hash, entry, params) else {
        return Ok(CrackPath {
            points: vec![entry],
            ..Default::default()
        });
    };
    if let Some(p) = previous_tip {
        search.tip = tip_beyond(&c, &hash, &search, p, params.link, BEYOND_DX);
    }
    let chain = chain_to_tip(&c.pts, &search, entry);
    let h_min = search
        .reached
        .iter()
        .map(|&k| c.h[k])
        .fold(c.h_max, f64::min);
    let raw = resample(&chain, params.spacing * h_min);
    let connected: Vec<P2> = search.reached.iter().map(|&k| c.pts[k]).collect();
    let h_connected: Vec<f64> = search.reached.iter().map(|&k| c.h[k]).collect();
    let points = centre_across(&raw, &connected, &h_connected, params.smoothing);
    let length = polyline_length(&points);
    let cand = &c.idx;
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
mod tests;
