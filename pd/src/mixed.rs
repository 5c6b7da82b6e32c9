//! Mixed spacing: a regular grid whose cells inside refinement zones are split, with
//! dual-horizon bond-based forces (seed 004 section 2.2, Eq. 13; Ren, Zhang & Rabczuk's
//! DH-PD) so that particles of different sizes interact without ghost forces.
//!
//! **Grid.** A real node whose coarse cell centre lies in a [`RefineZone`] of `levels`
//! `L` is replaced by its `4^L` children at the centres of the sub-cells of side
//! $\Delta_k = \Delta x/2^L$ (as [`crate::refine`] splits a parent into quadrants);
//! a cell a hole or a slanted side cuts is split likewise where its centre falls outside
//! the region, its children inside the region joining the real nodes (so a zone follows a
//! curved edge at its children's spacing); fictitious nodes stay coarse. Node `k` owns $V_k = \Delta_k^2 t$ and the horizon
//! $\delta_k = m\Delta_k$; its family is $H_k = \{j : |x_j - x_k| \le \delta_k\}$.
//!
//! **Bonds.** Every node lies on the lattice of dx/8 (offset dx/2), so bond vectors are
//! exact lattice vectors and rows take the mirror-group order of [`crate::bonds`]: a
//! mirror-symmetric problem stays bitwise symmetric, as on a uniform grid. Every pair with $j \in H_k$ or $k \in H_j$ is stored in both directions;
//! direction $k \to j$ carries the partial volume of $j$'s cell in $k$'s horizon,
//! `vol_factor` $= [j\in H_k]\, v_{kj} V_j / V_{ref}$ (seed 002 Eq. 16 with $j$'s cell
//! side; $V_{ref} = \Delta x^2 t$ the coarse volume), so the damage of seed 002 Eq. 8
//! counts the node's own family with its volumes.
//!
//! **Forces.** With the half-bond energy $\tfrac14 c_k s^2 |\xi| V'_{kj}$ per member of
//! $H_k$ ($c_k$ the PMB micromodulus of $\delta_k$), the force on $k$ is seed 004
//! Eq. 13 for PMB:
//! $$V_k F_k = \sum_{j\in H_k} \tfrac12 c_k V_k V'_{kj}\, s\, e_{kj} +
//!   \sum_{j:\,k\in H_j} \tfrac12 c_j V_j V'_{jk}\, s\, e_{kj},$$
//! a pair model with the symmetric pair stiffness (per reference volume)
//! $$k_{kj} = \tfrac12\big(c_k V_k\, \mathrm{vf}_{kj} G_{kj} + c_j V_j\, \mathrm{vf}_{jk} G_{jk}\big),$$
//! `vf` the `vol_factor` above and $G$ the surface factors. Every per-node force array of
//! a mixed [`crate::PdModel`] (internal and body forces, residuals) is therefore in
//! newtons per reference volume $V_{ref}$: times `grid.volume` it is the node's force in
//! newtons, as on a uniform grid, where $k = c\,v V G$ unchanged. The stiffness being
//! symmetric, the forces balance exactly, are minus the gradient of
//! $\Pi = \sum_{k\to j} \tfrac14 V_{ref} k_{kj} |\xi| s^2$ and the tangent stays
//! symmetric (Cholesky, ADR's bound, unchanged).
//!
//! **Surface correction** (energy method, [`crate::surface`]): each node corrects its own
//! half-bonds, $G_{kj}$ the ellipse of $g_{d,k} = W^{CM}/W^{PD}_{d,k}$ with
//! $W^{PD}_{d,k} = \tfrac14 c_k \sum_{j\in H_k} |\xi| V'_{kj} n_d^4$.
//!
//! **Failure.** The critical stretch scales as $\delta^{-1/2}$ (seed 002 Eq. 7): the
//! law's `s0` is the coarse horizon's, and a pair breaks at `s0 * s_scale` with
//! `s_scale` $= \sqrt{\delta/\delta_o}$, $\delta_o$ the smallest horizon among its owners
//! (the finer half-bond holds the larger energy density). Force passes report the
//! normalised stretch `s / s_scale`, so every comparison with `s0` stays right. The tanh
//! law (seed 000 Eq. 12) acts on the normalised stretch too, $T(s/\sigma)$ with the
//! history $s_{hist}$ normalised, so a pair softens from $\sigma s_m$ to $\sigma s_c$ and
//! its tangent slope is $T'(s/\sigma)/\sigma$ ([`crate::forces::bond_tangent_scaled`]);
//! $T$ depends on $s$ only through $(s - s_m)/(s_c - s_m)$, so this is the law with both
//! stretches scaled by $\sigma$: the energy a pair dissipates scales as the square of
//! its stretches, as for the critical stretch. Transfer-function tractions and explicit dynamics take
//! uniform grids only (validated).
//!
//! **State-based model** ([`crate::state_based`], seed 004 Eqs. 3-8 and 13): every node
//! is calibrated on its own family against the full lattice family of its own spacing
//! (the corrections as on a uniform grid), and its energy coefficients `a_k`,
//! `beta_kj` carry its relative volume $V_k/V_{ref}$, so that
//! $\Pi = V_{ref}\sum_k (a_k\theta_k^2 + \ldots)$ is $\sum_k V_k W_k$; the pair
//! force on $k$ is then each half with its own partial volume,
//! $\mathrm{vf}_{kj}\,\tau_{kj} + \mathrm{vf}_{jk}\,\tau_{jk}$ (zero for a half whose
//! owner's horizon misses the other node), the dual-horizon force of seed 004 Eq. 13.

use crate::bonds::{partial_volume, segment_crosses_hole, Bonds, GROUP_END};
use crate::error::PdError;
use crate::geometry::{rotate, P2};
use crate::grid::{build_uniform, Grid};
use crate::problem::{PdProblem, Plane, Region};

pub use crate::refine_zone::{RefineZone, MAX_LEVELS};

/// The grid of a validated problem: the uniform grid ([`crate::grid`]) with the cells
/// inside the problem's refinement zones split ([`refine_grid`]).
pub fn build_grid(p: &PdProblem) -> Result<Grid, PdError> {
    let mut g = build_uniform(p)?;
    refine_grid(&mut g, p)?;
    Ok(g)
}

/// Split the real nodes of `grid` inside the zones of `p` (see the module docs): the
/// children replace their parent in place; `grid.spacing` gets every node's spacing.
/// Children outside the region (a hole, a slanted side) are dropped. A zone also splits
/// the cells it holds whose centres lie outside the region (by a hole or a slanted side)
/// but not on a fictitious node: their children inside the region join the real nodes,
/// so a zone over a curved edge resolves it at the children's spacing, as the finer
/// uniform grid does, instead of keeping the coarse grid's staircase.
pub fn refine_grid(grid: &mut Grid, p: &PdProblem) -> Result<(), PdError> {
    if p.refine_zones.is_empty() {
        return Ok(());
    }
    let dx = grid.dx;
    let mut pos = Vec::with_capacity(grid.pos.len());
    let mut spacing = Vec::with_capacity(grid.pos.len());
    let mut used = vec![false; p.refine_zones.len()];
    let axes = crate::surface::lattice_axes(grid.angle);
    let level_at = |x: P2, used: &mut [bool]| {
        let mut level = 0;
        for (z, zone) in p.refine_zones.iter().enumerate() {
            if zone.contains(x, axes) {
                used[z] = true;
                level = level.max(zone.levels);
            }
        }
        level
    };
    for &x in &grid.pos[..grid.n_real] {
        match level_at(x, &mut used) {
            0 => {
                pos.push(x);
                spacing.push(dx);
            }
            level => push_children(&mut pos, &mut spacing, x, level, grid, p),
        }
    }
    for (x, level) in edge_cells(grid, p) {
        let before = pos.len();
        push_children(&mut pos, &mut spacing, x, level, grid, p);
        if pos.len() > before {
            level_at(x, &mut used);
        }
    }
    if let Some(z) = used.iter().position(|u| !u) {
        return Err(PdError::invalid(
            format!("refine_zones[{z}]"),
            "the zone holds no grid cell with a point in the body",
        ));
    }
    let n_real = pos.len();
    for &x in &grid.pos[grid.n_real..] {
        pos.push(x);
        spacing.push(dx);
    }
    grid.n_real = n_real;
    grid.pos = pos;
    grid.spacing = spacing;
    Ok(())
}

/// The children of the cell centred at `x`, `4^level` of them at the centres of its
/// sub-cells, those inside the region.
fn push_children(
    pos: &mut Vec<P2>,
    spacing: &mut Vec<f64>,
    x: P2,
    level: u32,
    grid: &Grid,
    p: &PdProblem,
) {
    let dx = grid.dx;
    let n = 1usize << level;
    let h = dx / n as f64;
    for b in 0..n {
        for a in 0..n {
            let o = [
                (a as f64 + 0.5) * h - 0.5 * dx,
                (b as f64 + 0.5) * h - 0.5 * dx,
            ];
            let r = rotate(o, grid.angle);
            let c = [x[0] + r[0], x[1] + r[1]];
            if p.region.contains(c) {
                pos.push(c);
                spacing.push(h);
            }
        }
    }
}

/// The cells a zone splits whose centres lie outside the region and on no fictitious
/// node of `grid` (cut by a hole or a slanted side), with the deepest level of the zones
/// holding them, in lattice order.
fn edge_cells(grid: &Grid, p: &PdProblem) -> Vec<(P2, u32)> {
    use std::collections::{BTreeMap, HashSet};
    let lattice = crate::grid::Lattice::of(p);
    let axes = crate::surface::lattice_axes(grid.angle);
    let fictitious: HashSet<(i64, i64)> = grid.pos[grid.n_real..]
        .iter()
        .map(|&x| lattice.cell_of(x))
        .collect();
    let mut cells: BTreeMap<(i64, i64), u32> = BTreeMap::new();
    for zone in &p.refine_zones {
        let (ci, cj) = lattice.cell_of(zone.centre);
        // Cells whose centres can lie within half_size (plus a cell for the tie band).
        let reach = (zone.half_size / grid.dx).ceil().min(1e7) as i64 + 1;
        let (i0, i1) = (
            ci.saturating_sub(reach).max(lattice.i.0),
            ci.saturating_add(reach).min(lattice.i.1),
        );
        let (j0, j1) = (
            cj.saturating_sub(reach).max(lattice.j.0),
            cj.saturating_add(reach).min(lattice.j.1),
        );
        for j in j0..=j1 {
            for i in i0..=i1 {
                let x = lattice.centre(i, j);
                if !zone.contains(x, axes) || p.region.contains(x) || fictitious.contains(&(i, j)) {
                    continue;
                }
                let level = cells.entry((j, i)).or_insert(0);
                *level = (*level).max(zone.levels);
            }
        }
    }
    cells
        .into_iter()
        .map(|((j, i), level)| (lattice.centre(i, j), level))
        .collect()
}

/// Neighbour rows: `j` with `|x_j - x_k| <= max(delta_k, delta_j)`, not through a hole,
/// sorted by index (cell list of the coarse horizon).
fn pair_rows(grid: &Grid, region: &Region) -> Vec<Vec<u32>> {
    use rayon::prelude::*;
    use std::collections::HashMap;
    let m = grid.delta / grid.dx;
    let cell = grid.delta;
    let key = |p: P2| ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64);
    let mut cells: HashMap<(i64, i64), Vec<u32>> = HashMap::new();
    for (i, &p) in grid.pos.iter().enumerate() {
        cells.entry(key(p)).or_default().push(i as u32);
    }
    (0..grid.len())
        .into_par_iter()
        .map(|k| {
            let xk = grid.pos[k];
            let (cx, cy) = key(xk);
            let dk = m * grid.node_dx(k);
            let mut row = Vec::new();
            for gx in cx - 1..=cx + 1 {
                for gy in cy - 1..=cy + 1 {
                    for &j in cells.get(&(gx, gy)).map_or(&[][..], |v| v.as_slice()) {
                        let xj = grid.pos[j as usize];
                        let r = dk.max(m * grid.node_dx(j as usize)) * (1.0 + 1e-9);
                        let d2 = (xj[0] - xk[0]).powi(2) + (xj[1] - xk[1]).powi(2);
                        if j as usize != k
                            && d2 <= r * r
                            && !region.holes.iter().any(|h| segment_crosses_hole(xk, xj, h))
                        {
                            row.push(j);
                        }
                    }
                }
            }
            row.sort_unstable();
            row
        })
        .collect()
}

/// The dual-horizon bonds of a mixed grid (module docs): `vol_factor` per direction,
/// `s_scale` per pair, `k` left at zero (see [`set_coefficients`]).
pub fn build_bonds(grid: &Grid, region: &Region) -> Bonds {
    let rows = pair_rows(grid, region);
    let m = grid.delta / grid.dx;
    let mut b = Bonds {
        offsets: vec![0],
        ..Default::default()
    };
    for (k, row) in rows.iter().enumerate() {
        let dk = m * grid.node_dx(k);
        let mut row: Vec<(u32, i64, i64)> = row
            .iter()
            .map(|&j| {
                let (a, c) = lattice_offset(grid, k, j as usize);
                (j, a, c)
            })
            .collect();
        row.sort_unstable_by_key(|&(_, a, c)| (c.abs(), a.abs(), c < 0, a < 0));
        for (n, &(j, a, c)) in row.iter().enumerate() {
            let j = j as usize;
            let dj = m * grid.node_dx(j);
            let xi = exact_offset(grid, a, c);
            let l = xi[0].hypot(xi[1]);
            let in_k = l <= dk * (1.0 + 1e-9);
            let in_j = l <= dj * (1.0 + 1e-9);
            let rel = (grid.node_dx(j) / grid.dx).powi(2);
            let vf = if in_k {
                partial_volume(l, dk, grid.node_dx(j)) * rel
            } else {
                0.0
            };
            let owner = match (in_k, in_j) {
                (true, true) => dk.min(dj),
                (true, false) => dk,
                _ => dj,
            };
            let last = match row.get(n + 1) {
                Some(&(_, a2, c2)) => (a2.abs(), c2.abs()) != (a.abs(), c.abs()),
                None => true,
            };
            let slot = (a < 0) as u8 | (((c < 0) as u8) << 1);
            b.nbr.push(j as u32);
            b.xi.push(xi);
            b.inv_len.push(1.0 / l);
            b.vol_factor.push(vf);
            b.s_scale.push((grid.delta / owner).sqrt());
            b.meta.push(slot | if last { GROUP_END } else { 0 });
        }
        b.offsets.push(b.nbr.len());
    }
    b.surface = vec![1.0; b.nbr.len()];
    b.k = vec![0.0; b.nbr.len()];
    b
}

/// Subdivisions of dx of the lattice every node of a mixed grid lies on (offset by dx/2):
/// children of up to [`MAX_LEVELS`] splits sit at odd multiples of dx/8 from their
/// coarse cell's centre.
const SUBDIV: f64 = 8.0;

/// Integer offset of node `j` from node `k` on the lattice of dx / [`SUBDIV`] (grid frame).
fn lattice_offset(grid: &Grid, k: usize, j: usize) -> (i64, i64) {
    let d = [
        grid.pos[j][0] - grid.pos[k][0],
        grid.pos[j][1] - grid.pos[k][1],
    ];
    let l = rotate(d, -grid.angle);
    let h = grid.dx / SUBDIV;
    ((l[0] / h).round() as i64, (l[1] / h).round() as i64)
}

/// The exact bond vector of a lattice offset: mirror images of a bond are exact negatives
/// of each other's components, so row sums in the group order of [`crate::bonds`] keep a
/// mirror-symmetric problem bitwise symmetric, as on a uniform grid.
fn exact_offset(grid: &Grid, a: i64, c: i64) -> P2 {
    let h = grid.dx / SUBDIV;
    let l = [a as f64 * h, c as f64 * h];
    if grid.angle == 0.0 {
        l
    } else {
        rotate(l, grid.angle)
    }
}

/// Reverse of every directed bond.
pub fn reverse(bonds: &Bonds) -> Vec<u32> {
    let n = bonds.offsets.len() - 1;
    let mut rev = vec![0u32; bonds.len()];
    for i in 0..n {
        for b in bonds.row(i) {
            let j = bonds.nbr[b] as usize;
            let r = bonds.row(j);
            let p = bonds.nbr[r.clone()]
                .iter()
                .position(|&x| x as usize == i)
                .expect("bonds are stored in both directions");
            rev[b] = (r.start + p) as u32;
        }
    }
    rev
}

/// `c_k V_k / V_ref` of every node: the PMB micromodulus of the node's horizon (`c` the
/// coarse one) times its relative volume, `c dx / dx_k`.
fn node_weight(grid: &Grid, c: f64) -> Vec<f64> {
    (0..grid.len())
        .map(|k| c * grid.dx / grid.node_dx(k))
        .collect()
}

/// The pair stiffness `k` of every bond (module docs), per reference volume.
pub fn set_coefficients(bonds: &mut Bonds, grid: &Grid, c: f64) {
    let rev = reverse(bonds);
    let w = node_weight(grid, c);
    let vol = grid.volume;
    let n = grid.len();
    for k in 0..n {
        for b in bonds.row(k) {
            let j = bonds.nbr[b] as usize;
            let r = rev[b] as usize;
            let own = w[k] * bonds.vol_factor[b] * bonds.surface[b];
            let dual = w[j] * bonds.vol_factor[r] * bonds.surface[r];
            bonds.k[b] = 0.5 * vol * (own + dual);
        }
    }
}

/// Surface correction of a mixed grid (module docs): `bonds.surface` from each owner's
/// energy-method factors.
pub fn surface_correction(bonds: &mut Bonds, grid: &Grid, c: f64, youngs: f64, plane: Plane) {
    let e_eff = match plane {
        Plane::Stress => 9.0 / 8.0 * youngs,
        Plane::Strain => 6.0 / 5.0 * youngs,
    };
    let w_cm = 0.5 * e_eff;
    let axes = crate::surface::lattice_axes(grid.angle);
    let m = grid.delta / grid.dx;
    for k in 0..grid.len() {
        let ck = micromodulus_scaled(c, grid.delta, m * grid.node_dx(k));
        let mut w = [0.0; 2];
        for b in bonds.row(k) {
            let (nx, ny) = crate::surface::lattice_direction(bonds, b, axes);
            let f = 0.25 * ck * bonds.vol_factor[b] * grid.volume / bonds.inv_len[b];
            w[0] += f * nx.powi(4);
            w[1] += f * ny.powi(4);
        }
        let g = |d: usize| if w[d] > 0.0 { w_cm / w[d] } else { 1.0 };
        let (gx, gy) = (g(0), g(1));
        for b in bonds.row(k) {
            let (nx, ny) = crate::surface::lattice_direction(bonds, b, axes);
            bonds.surface[b] = 1.0 / ((nx / gx).powi(2) + (ny / gy).powi(2)).sqrt();
        }
    }
}

/// The PMB micromodulus of horizon `d` given `c` at horizon `delta` (`c ~ delta^-3`).
fn micromodulus_scaled(c: f64, delta: f64, d: f64) -> f64 {
    c * (delta / d).powi(3)
}
