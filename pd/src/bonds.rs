//! Bond families in CSR order, partial-volume weights and pre-crack cutting.
//!
//! Neighbours of node `i` are all `j != i` with `|x_j - x_i| <= delta`, found
//! with a cell list of cell size `delta`, sorted by index, and stored once per
//! direction (`i -> j` in row `i`, `j -> i` in row `j`) so forces are gathered
//! per node without atomics. The partial-volume factor (seed 002 Eq. 16) is
//! $v_j = 1$ for $|\xi| \le \delta - \Delta x/2$ and
//! $v_j = (\delta + \Delta x/2 - |\xi|)/\Delta x$ beyond. Bonds whose segment
//! passes through a hole are dropped; bonds crossing a pre-crack polyline are
//! kept but marked broken, so the damage of Eq. 8 sees them.
//!
//! Exact mirror symmetry: the reference bond vector is the lattice vector
//! $\xi = R(\theta)\,(a\,\Delta x, b\,\Delta x)$ with integer $a, b$ (not
//! the difference of two rounded positions), and each row is ordered by
//! the key $(|b|, |a|, \operatorname{sign} b, \operatorname{sign} a)$. Bonds
//! with the same $(|a|, |b|)$ form a group of at most four mirror images;
//! [`Bonds::meta`] holds each bond's slot in its group (bit 0: $a<0$, bit
//! 1: $b<0$) and marks the group's last bond (bit 2). Sums over a row are
//! taken group by group as $((t_0+t_1)+(t_2+t_3))$ ([`group_sum`]), so the
//! sum at a node and at its mirror image about a lattice line are bitwise
//! mirror images (IEEE addition is commutative and negation is exact). On
//! a mirror-symmetric body and load the discrete solution then stays
//! exactly symmetric instead of drifting off through round-off.

use rayon::prelude::*;

use crate::geometry::{dist_point_segment, segment_crosses_crack, segment_crosses_polyline, P2};
use crate::grid::Grid;
use crate::problem::{Hole, Region};

/// Static bond data (CSR, one entry per direction).
#[derive(Clone, Debug, Default)]
pub struct Bonds {
    /// Row offsets, length `n + 1`.
    pub offsets: Vec<usize>,
    /// Neighbour node of each bond.
    pub nbr: Vec<u32>,
    /// Reference bond vector `x_j - x_i`.
    pub xi: Vec<P2>,
    /// `1 / |xi|`.
    pub inv_len: Vec<f64>,
    /// Partial-volume factor `v_j` (seed 002 Eq. 16).
    pub vol_factor: Vec<f64>,
    /// Surface-correction factor `G_ij` (1 without correction).
    pub surface: Vec<f64>,
    /// Force coefficient `c v_j V_j G_ij` (N/m^3 per unit stretch).
    pub k: Vec<f64>,
    /// Mirror-group data of each bond: slot (bits 0-1) and end of group
    /// (bit 2), see the module docs.
    pub meta: Vec<u8>,
    /// Mixed spacing ([`crate::mixed`]): the factor of the law's critical stretch for
    /// each bond; empty on a uniform grid (factor 1).
    pub s_scale: Vec<f64>,
}

/// Bit of [`Bonds::meta`] marking the last bond of a mirror group.
pub const GROUP_END: u8 = 4;

/// Sum `f(b)` over the bonds `range` of one row, group by group in the
/// mirror-symmetric order of the module docs.
#[inline]
pub fn group_sum(meta: &[u8], range: std::ops::Range<usize>, mut f: impl FnMut(usize) -> P2) -> P2 {
    let mut g = [[0.0f64; 2]; 4];
    let mut tot = [0.0f64; 2];
    for b in range {
        let m = meta[b];
        let v = f(b);
        let s = (m & 3) as usize;
        g[s][0] += v[0];
        g[s][1] += v[1];
        if m & GROUP_END != 0 {
            for c in 0..2 {
                tot[c] += (g[0][c] + g[1][c]) + (g[2][c] + g[3][c]);
            }
            g = [[0.0; 2]; 4];
        }
    }
    tot
}

impl Bonds {
    /// Number of directed bonds.
    pub fn len(&self) -> usize {
        self.nbr.len()
    }

    /// Whether there is no bond.
    pub fn is_empty(&self) -> bool {
        self.nbr.is_empty()
    }

    /// Bond index range of node `i`.
    #[inline]
    pub fn row(&self, i: usize) -> std::ops::Range<usize> {
        self.offsets[i]..self.offsets[i + 1]
    }

    /// Recompute `k = c v V G`.
    pub fn set_coefficients(&mut self, c: f64, volume: f64) {
        let (v, g) = (&self.vol_factor, &self.surface);
        self.k
            .par_iter_mut()
            .enumerate()
            .for_each(|(b, k)| *k = c * v[b] * volume * g[b]);
    }
}

/// Whether the segment from `a` to `b` passes through the hole `h` (a bond across it is
/// not made).
pub(crate) fn segment_crosses_hole(a: P2, b: P2, h: &Hole) -> bool {
    match h {
        Hole::Circle { centre, radius } => dist_point_segment(*centre, a, b) < *radius,
        Hole::Polygon { points } => {
            let mut closed = points.clone();
            closed.push(points[0]);
            segment_crosses_polyline(a, b, &closed)
                || h.contains([0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])])
        }
    }
}

/// Find all bonds of the grid (cell list), drop those through holes.
pub fn build_bonds(grid: &Grid, region: &Region) -> Bonds {
    let n = grid.len();
    let delta = grid.delta;
    let dx = grid.dx;
    let r2 = (delta * (1.0 + 1e-9)).powi(2);
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in &grid.pos {
        for d in 0..2 {
            lo[d] = lo[d].min(q[d]);
            hi[d] = hi[d].max(q[d]);
        }
    }
    let h = delta;
    let nx = (((hi[0] - lo[0]) / h).floor() as usize) + 1;
    let ny = (((hi[1] - lo[1]) / h).floor() as usize) + 1;
    let cell_of = |q: P2| {
        let cx = (((q[0] - lo[0]) / h) as usize).min(nx - 1);
        let cy = (((q[1] - lo[1]) / h) as usize).min(ny - 1);
        (cx, cy)
    };
    // Counting sort of nodes into cells.
    let mut start = vec![0usize; nx * ny + 1];
    for q in &grid.pos {
        let (cx, cy) = cell_of(*q);
        start[cy * nx + cx + 1] += 1;
    }
    for c in 0..nx * ny {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut cell_nodes = vec![0u32; n];
    for (i, q) in grid.pos.iter().enumerate() {
        let (cx, cy) = cell_of(*q);
        let c = cy * nx + cx;
        cell_nodes[fill[c]] = i as u32;
        fill[c] += 1;
    }
    let holes = &region.holes;
    let rows: Vec<Vec<u32>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let xi = grid.pos[i];
            let (cx, cy) = cell_of(xi);
            let mut row = Vec::with_capacity(32);
            for gy in cy.saturating_sub(1)..=(cy + 1).min(ny - 1) {
                for gx in cx.saturating_sub(1)..=(cx + 1).min(nx - 1) {
                    let c = gy * nx + gx;
                    for &j in &cell_nodes[start[c]..start[c + 1]] {
                        if j as usize == i {
                            continue;
                        }
                        let xj = grid.pos[j as usize];
                        let d2 = (xj[0] - xi[0]).powi(2) + (xj[1] - xi[1]).powi(2);
                        if d2 <= r2 && !holes.iter().any(|h| segment_crosses_hole(xi, xj, h)) {
                            row.push(j);
                        }
                    }
                }
            }
            row.sort_unstable();
            row
        })
        .collect();
    // Integer lattice offsets, the exact bond vectors and the group order.
    let (sa, ca) = grid.angle.sin_cos();
    let lattice = |v: P2| -> (i32, i32) {
        let l = if grid.angle == 0.0 {
            v
        } else {
            [ca * v[0] + sa * v[1], -sa * v[0] + ca * v[1]]
        };
        ((l[0] / dx).round() as i32, (l[1] / dx).round() as i32)
    };
    let exact = |a: i32, b: i32| -> P2 {
        let l = [a as f64 * dx, b as f64 * dx];
        if grid.angle == 0.0 {
            l
        } else {
            [ca * l[0] - sa * l[1], sa * l[0] + ca * l[1]]
        }
    };
    let rows: Vec<Vec<(u32, i32, i32)>> = rows
        .into_par_iter()
        .enumerate()
        .map(|(i, r)| {
            let xi = grid.pos[i];
            let mut v: Vec<(u32, i32, i32)> = r
                .into_iter()
                .map(|j| {
                    let xj = grid.pos[j as usize];
                    let (a, b) = lattice([xj[0] - xi[0], xj[1] - xi[1]]);
                    (j, a, b)
                })
                .collect();
            v.sort_unstable_by_key(|&(_, a, b)| (b.abs(), a.abs(), b < 0, a < 0));
            v
        })
        .collect();
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0);
    for r in &rows {
        offsets.push(offsets.last().unwrap() + r.len());
    }
    let nb = *offsets.last().unwrap();
    let mut b = Bonds {
        offsets,
        nbr: Vec::with_capacity(nb),
        xi: Vec::with_capacity(nb),
        inv_len: Vec::with_capacity(nb),
        vol_factor: Vec::with_capacity(nb),
        surface: vec![1.0; nb],
        k: vec![0.0; nb],
        meta: Vec::with_capacity(nb),
        s_scale: Vec::new(),
    };
    for r in &rows {
        for (m, &(j, a, bb)) in r.iter().enumerate() {
            let v = exact(a, bb);
            let len = v[0].hypot(v[1]);
            b.nbr.push(j);
            b.xi.push(v);
            b.inv_len.push(1.0 / len);
            b.vol_factor.push(partial_volume(len, delta, dx));
            let last = match r.get(m + 1) {
                Some(&(_, a2, b2)) => (a2.abs(), b2.abs()) != (a.abs(), bb.abs()),
                None => true,
            };
            let slot = (a < 0) as u8 | (((bb < 0) as u8) << 1);
            b.meta.push(slot | if last { GROUP_END } else { 0 });
        }
    }
    b
}

/// Partial-volume factor of seed 002 Eq. 16.
#[inline]
pub fn partial_volume(len: f64, delta: f64, dx: f64) -> f64 {
    if len <= delta - 0.5 * dx {
        1.0
    } else {
        ((delta + 0.5 * dx - len) / dx).clamp(0.0, 1.0)
    }
}

/// Mark bonds crossing any crack polyline as broken (`intact[b] = 0`); the crack ends
/// are open ([`segment_crosses_crack`] with a tolerance of 1e-6 dx).
/// Returns the number of directed bonds cut.
pub fn cut_cracks(grid: &Grid, bonds: &Bonds, cracks: &[Vec<P2>], intact: &mut [u8]) -> usize {
    if cracks.is_empty() {
        return 0;
    }
    let pos = &grid.pos;
    // Bounding boxes of the cracks, padded by nothing: a bond crossing a crack
    // has both its end points within delta of it.
    let boxes: Vec<(P2, P2)> = cracks
        .iter()
        .map(|c| {
            let mut lo = [f64::INFINITY; 2];
            let mut hi = [f64::NEG_INFINITY; 2];
            for p in c {
                for d in 0..2 {
                    lo[d] = lo[d].min(p[d]);
                    hi[d] = hi[d].max(p[d]);
                }
            }
            (lo, hi)
        })
        .collect();
    let delta = grid.delta;
    let end_tol = 1e-6 * grid.dx;
    let mut count = 0;
    for i in 0..grid.len() {
        let a = pos[i];
        for bnd in bonds.row(i) {
            let bpt = pos[bonds.nbr[bnd] as usize];
            for (c, line) in cracks.iter().enumerate() {
                let (lo, hi) = boxes[c];
                if a[0] < lo[0] - delta
                    || a[0] > hi[0] + delta
                    || a[1] < lo[1] - delta
                    || a[1] > hi[1] + delta
                {
                    continue;
                }
                if segment_crosses_crack(a, bpt, line, end_tol) {
                    if intact[bnd] != 0 {
                        count += 1;
                    }
                    intact[bnd] = 0;
                    break;
                }
            }
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::build_uniform;
    use crate::problem::PdProblem;

    fn square(n: usize) -> (Grid, Bonds) {
        let p = PdProblem {
            region: Region::rectangle([0.0, 0.0], [n as f64, n as f64]),
            dx: 1.0,
            youngs_modulus: 1.0,
            ..Default::default()
        };
        let g = build_uniform(&p).unwrap();
        let b = build_bonds(&g, &p.region);
        (g, b)
    }

    #[test]
    fn interior_family_has_28_members_and_rows_are_symmetric() {
        // m = 3.015: the 2-D family is the 28 grid points with |xi| <= 3 dx
        // (seed 000 section 2.2: N_m = 28 in 2-D).
        let (g, b) = square(11);
        let centre = 5 * 11 + 5;
        assert_eq!(b.row(centre).len(), 28);
        for i in 0..g.len() {
            for bnd in b.row(i) {
                let j = b.nbr[bnd] as usize;
                assert!(b.row(j).any(|k| b.nbr[k] as usize == i));
            }
        }
    }

    #[test]
    fn partial_volume_matches_eq16() {
        assert_eq!(partial_volume(2.0, 3.015, 1.0), 1.0);
        assert!((partial_volume(3.0, 3.015, 1.0) - 0.515).abs() < 1e-12);
    }

    #[test]
    fn crack_cuts_bonds_across_it_only() {
        let (g, b) = square(10);
        let mut intact = vec![1u8; b.len()];
        let n = cut_cracks(&g, &b, &[vec![[0.0, 5.0], [10.0, 5.0]]], &mut intact);
        assert!(n > 0);
        for i in 0..g.len() {
            for bnd in b.row(i) {
                let j = b.nbr[bnd] as usize;
                let crosses = (g.pos[i][1] - 5.0) * (g.pos[j][1] - 5.0) < 0.0;
                assert_eq!(intact[bnd] == 0, crosses);
            }
        }
    }
}
