//! Crack tip and branching measures of a running dynamic crack.
//!
//! **The crack band** is the set of real nodes with damage above $\varphi_c/2$ (0.2 for
//! the default $\varphi_c = 0.4$, seed 004's) connected to the tip of the first
//! pre-crack: a flood fill over such nodes within a horizon of each other, started from
//! those within the horizon of the pre-crack's tip. The half threshold keeps the band
//! continuous: a straight cut between two node rows leaves the nodes beside it at
//! $\varphi \approx 0.3$, below $\varphi_c$, and a crack crossing the lattice obliquely
//! leaves isolated nodes past $\varphi_c$ with nodes just below it between them. Damage
//! elsewhere (seed 004's "fake damage" at the loaded surfaces in case 2) joins the band
//! only where it touches it.
//!
//! **Frame.** $d$ is the unit direction of the last segment of the first pre-crack (it
//! points to the tip the crack grows from), $n$ its normal, $x_0$ that tip; every node
//! gets $s = (x - x_0)\cdot d$ and $q = (x - x_0)\cdot n$.
//!
//! **Tip**: the band node with $\varphi > \varphi_c$ and the largest $s$, among those
//! with $s > -\delta$ (the damaged nodes at the pre-crack's mouth do not count); none
//! before the crack starts. It **reaches the far boundary** when its $s$ is within
//! $2\Delta x$ of the largest $s$ of the real nodes.
//!
//! **Branching** (two separate damaged bands): the band nodes ahead of the pre-crack tip
//! ($s > 0$) are binned into columns of width $\Delta x$ along $s$; a column is *split*
//! when its nodes, sorted by $q$, fall into two or more runs separated by a gap wider
//! than $2.5\,\Delta x$ (at least two undamaged node rows between the bands). The crack
//! has branched once split columns span at least $\delta$ along $s$ with no single-band
//! column between them (a separation that persists over a horizon, not a hole in a wide
//! band); the branch point is the first split column of that stretch. The bands must be
//! apart by their own width plus two rows, so the detector reports a branch somewhat
//! after the fork itself (a few horizons of crack growth).

use crate::bonds::Bonds;
use crate::geometry::{dist_point_polyline, P2};
use crate::model::PdModel;

/// The measures of one state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CrackState {
    /// The tip (m), if any node is cracked.
    pub tip: Option<P2>,
    /// Where the crack branched (m), if it has.
    pub branch: Option<P2>,
    /// Whether the tip reached the far boundary.
    pub at_boundary: bool,
}

/// Precomputed frame and pre-crack neighbourhood of a model (module docs).
#[derive(Clone, Debug)]
pub struct CrackTracker {
    origin: P2,
    d: P2,
    near_crack: Vec<bool>,
    threshold: f64,
    s_max: f64,
    dx: f64,
    delta: f64,
}

impl CrackTracker {
    /// The tracker of `model`'s real nodes with the pre-cracks `cracks` (none: no crack
    /// measures) and the damage `threshold`.
    pub fn new(model: &PdModel, cracks: &[Vec<P2>], threshold: f64) -> Self {
        let g = model.grid();
        Self::for_points(&g.pos[..g.n_real], cracks, threshold, g.dx, g.delta)
    }

    /// The tracker of particles at `pos` (a refined body: `dx` and `delta` of the base
    /// grid set the column width, the boundary margin and the pre-crack tip radius).
    pub fn for_points(pos: &[P2], cracks: &[Vec<P2>], threshold: f64, dx: f64, delta: f64) -> Self {
        let (origin, d) = match cracks.first() {
            Some(c) if c.len() >= 2 => {
                let (a, b) = (c[c.len() - 2], c[c.len() - 1]);
                let l = (b[0] - a[0]).hypot(b[1] - a[1]).max(f64::MIN_POSITIVE);
                (b, [(b[0] - a[0]) / l, (b[1] - a[1]) / l])
            }
            _ => ([0.0; 2], [1.0, 0.0]),
        };
        let near_crack = pos
            .iter()
            .map(|&x| {
                cracks.first().is_some_and(|c| {
                    c.last()
                        .is_some_and(|&t| (x[0] - t[0]).hypot(x[1] - t[1]) <= delta)
                })
            })
            .collect();
        let s_max = pos
            .iter()
            .map(|x| (x[0] - origin[0]) * d[0] + (x[1] - origin[1]) * d[1])
            .fold(f64::NEG_INFINITY, f64::max);
        CrackTracker {
            origin,
            d,
            near_crack,
            threshold,
            s_max,
            dx,
            delta,
        }
    }

    fn frame(&self, x: P2) -> (f64, f64) {
        let r = [x[0] - self.origin[0], x[1] - self.origin[1]];
        (
            r[0] * self.d[0] + r[1] * self.d[1],
            -r[0] * self.d[1] + r[1] * self.d[0],
        )
    }

    /// The crack band (module docs) and the damage of every node.
    pub fn crack_band(&self, model: &PdModel) -> (Vec<usize>, Vec<f64>) {
        let phi = model.damage();
        (self.band(&phi, model.bonds()), phi)
    }

    /// The crack band of nodes with damage `phi`, connected through `b`'s families.
    fn band(&self, phi: &[f64], b: &Bonds) -> Vec<usize> {
        let n = self.near_crack.len();
        let cracked: Vec<bool> = (0..n).map(|i| phi[i] > 0.5 * self.threshold).collect();
        let mut seen: Vec<bool> = (0..n).map(|i| cracked[i] && self.near_crack[i]).collect();
        let mut stack: Vec<usize> = (0..n).filter(|&i| seen[i]).collect();
        let mut out = stack.clone();
        while let Some(i) = stack.pop() {
            for k in b.row(i) {
                let j = b.nbr[k] as usize;
                if j < n && !seen[j] && cracked[j] {
                    seen[j] = true;
                    stack.push(j);
                    out.push(j);
                }
            }
        }
        out
    }

    /// Tip, branch point and boundary arrival of the current state of `model`.
    pub fn measure(&self, model: &PdModel) -> CrackState {
        let phi = model.damage();
        self.measure_points(model.positions(), &phi, model.bonds())
    }

    /// Tip, branch point and boundary arrival of particles at `pos` with damage `phi`
    /// and families `bonds` (the points of [`CrackTracker::for_points`]).
    pub fn measure_points(&self, pos: &[P2], phi: &[f64], bonds: &Bonds) -> CrackState {
        let nodes = self.band(phi, bonds);
        let mut st = CrackState::default();
        let tip = nodes
            .iter()
            .filter(|&&i| phi[i] > self.threshold)
            .map(|&i| (self.frame(pos[i]).0, i))
            .filter(|&(s, _)| s > -self.delta)
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let Some((s_tip, i_tip)) = tip else {
            return st;
        };
        st.tip = Some(pos[i_tip]);
        st.at_boundary = s_tip >= self.s_max - 2.0 * self.dx;
        st.branch = self.branch_point(&nodes, pos);
        st
    }

    fn branch_point(&self, nodes: &[usize], pos: &[P2]) -> Option<P2> {
        let mut cols: Vec<(i64, f64)> = nodes
            .iter()
            .map(|&i| self.frame(pos[i]))
            .filter(|&(s, _)| s > 0.0)
            .map(|(s, q)| ((s / self.dx).round() as i64, q))
            .collect();
        cols.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let mut start: Option<i64> = None;
        let mut k = 0;
        while k < cols.len() {
            let c = cols[k].0;
            let mut bands = 1;
            let mut m = k + 1;
            while m < cols.len() && cols[m].0 == c {
                if cols[m].1 - cols[m - 1].1 > 2.5 * self.dx {
                    bands += 1;
                }
                m += 1;
            }
            if bands >= 2 {
                let s0 = *start.get_or_insert(c);
                if (c - s0) as f64 * self.dx >= self.delta * (1.0 - 1e-9) {
                    let s = s0 as f64 * self.dx;
                    return Some([
                        self.origin[0] + s * self.d[0],
                        self.origin[1] + s * self.d[1],
                    ]);
                }
            } else {
                start = None;
            }
            k = m;
        }
        None
    }
}

/// Damage past which a point by a loaded edge counts in [`damaged_near_edges`] (the crack
/// tip's threshold of [`CrackTracker`]'s users).
pub const EDGE_DAMAGE: f64 = 0.4;

/// Points at `pos` whose damage `phi` passes [`EDGE_DAMAGE`] within `band` of one of the
/// polylines `edges`: the damage a loaded edge takes that is no part of the crack (seed
/// 004 section 4.2's "fake damage" of a coarse grid).
pub fn damaged_near_edges(pos: &[P2], phi: &[f64], edges: &[&[P2]], band: f64) -> usize {
    pos.iter()
        .zip(phi)
        .filter(|(x, &d)| {
            d > EDGE_DAMAGE && edges.iter().any(|e| dist_point_polyline(**x, e) < band)
        })
        .count()
}

/// Damage past which a point counts in [`branch_exits`].
pub const EXIT_DAMAGE: f64 = 0.3;

/// Where the two branches of a crack along `mid_y` leave a plate through its right edge
/// (m): the damage-weighted mean height of the points within `width` of the right-most
/// point whose damage passes [`EXIT_DAMAGE`], below and above `mid_y` (`None` for a side
/// without such points). Seed 004 section 4.2's branching plate: the heights compare the
/// patterns of two discretisations (the fine grid's 3.9 / 36.1 mm against the coarse
/// grid's 7.0 / 33.0 mm in case 1, `docs/seed004.md`).
pub fn branch_exits(pos: &[P2], phi: &[f64], mid_y: f64, width: f64) -> [Option<f64>; 2] {
    let right = pos.iter().fold(f64::MIN, |a, p| a.max(p[0]));
    let side = |lower: bool| {
        let (mut w, mut wy) = (0.0, 0.0);
        for (p, &d) in pos.iter().zip(phi) {
            if p[0] > right - width && d > EXIT_DAMAGE && (p[1] < mid_y) == lower {
                w += d;
                wy += d * p[1];
            }
        }
        (w > 0.0).then(|| wy / w)
    };
    [side(true), side(false)]
}
