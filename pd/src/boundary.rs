//! Boundary conditions resolved onto nodes.
//!
//! - Prescribed displacement per component on fictitious nodes (a layer of
//!   depth `delta` outside the region, seed 000 section 2.3, seed 002 Fig. 1)
//!   or on real nodes; the prescribed DOFs are removed from the unknowns.
//! - Loads as body force density in a boundary layer of real nodes
//!   (seed 000 section 2.3: $b = P/(s\,\Delta x)$, i.e. total force over the
//!   layer's volume). A traction $t$ on an edge of length $L$ becomes the
//!   total force $t L h$ ($h$ the thickness), spread over the layer.
//!
//! - Or, with [`PdProblem::traction`] = [`TractionLoad::TransferFunction`],
//!   tractions through seed 001's transfer functions ([`crate::traction`]).
//!
//! Every base value is multiplied by the model's load factor.

use crate::error::PdError;
use crate::geometry::{dist_point_polyline, polyline_length, P2};
use crate::grid::Grid;
use crate::problem::{BoundaryCondition, Layer, PdProblem};
use crate::traction::{self, TractionLoad};

/// Boundary data per node.
#[derive(Clone, Debug)]
pub struct Boundary {
    /// Prescribed components.
    pub fixed: Vec<[bool; 2]>,
    /// Prescribed displacement at load factor 1 (m).
    pub base: Vec<P2>,
    /// Body force density at load factor 1 (N/m^3).
    pub body: Vec<P2>,
    /// The nodes of every boundary condition, in the problem's order
    /// ([`crate::reaction`]).
    pub groups: Vec<BcGroup>,
}

/// The nodes one boundary condition acts on.
#[derive(Clone, Debug, Default)]
pub struct BcGroup {
    /// Prescribed components (a displacement condition), or none (a load).
    pub fixed: [bool; 2],
    /// Selected nodes; load layers may overlap.
    pub nodes: Vec<usize>,
    /// Per node of `nodes`, the components whose reaction this condition carries: those
    /// it prescribes that no earlier condition prescribed (so that no reaction is
    /// counted twice). Empty for a load.
    pub claimed: Vec<[bool; 2]>,
    /// Mean body force density of the load over `nodes` at load factor 1 (N/m^3, per
    /// reference volume on a mixed grid), so that the load's resultant is its node count
    /// times this times the grid's node volume; zero for a displacement condition.
    pub body: P2,
}

/// Resolve the problem's boundary conditions on the grid.
pub fn resolve(p: &PdProblem, grid: &Grid) -> Result<Boundary, PdError> {
    let n = grid.len();
    let delta = grid.delta;
    let mut bd = Boundary {
        fixed: vec![[false; 2]; n],
        base: vec![[0.0; 2]; n],
        body: vec![[0.0; 2]; n],
        groups: Vec::with_capacity(p.boundary.len()),
    };
    let mut held = vec![[false; 2]; n];
    let transfer = p.traction == TractionLoad::TransferFunction;
    // Seed 001 Eq. 17, shared by every loaded edge.
    let k_decay = traction::decay_k(traction::region_area(p), traction::loaded_length(p), delta);
    for (k, bc) in p.boundary.iter().enumerate() {
        match bc {
            BoundaryCondition::Displacement { on, ux, uy, layer } => {
                let range = match layer {
                    Layer::Fictitious => grid.n_real..n,
                    Layer::Real => 0..grid.n_real,
                };
                let mut count = 0;
                let mut group = BcGroup {
                    fixed: [ux.is_some(), uy.is_some()],
                    ..Default::default()
                };
                for i in range {
                    if on.contains(grid.pos[i], delta) {
                        count += 1;
                        let mut claim = [false; 2];
                        for c in 0..2 {
                            claim[c] = group.fixed[c] && !held[i][c];
                            held[i][c] |= claim[c];
                        }
                        group.nodes.push(i);
                        group.claimed.push(claim);
                        for (c, v) in [ux, uy].iter().enumerate() {
                            if let Some(v) = v {
                                bd.fixed[i][c] = true;
                                bd.base[i][c] = *v;
                            }
                        }
                    }
                }
                if count == 0 {
                    return Err(PdError::invalid(
                        format!("boundary[{k}].on"),
                        format!("the selection holds no {layer:?} node (horizon {delta:.3e} m)"),
                    ));
                }
                bd.groups.push(group);
            }
            BoundaryCondition::Force { on, force } => {
                let sel: Vec<usize> = (0..grid.n_real)
                    .filter(|&i| on.contains(grid.pos[i], delta))
                    .collect();
                spread(&mut bd, &sel, *force, grid, k)?;
            }
            BoundaryCondition::Traction {
                edge,
                traction,
                depth,
            } if !transfer => {
                let d = depth.unwrap_or(grid.dx) * (1.0 + 1e-9);
                let sel: Vec<usize> = (0..grid.n_real)
                    .filter(|&i| dist_point_polyline(grid.pos[i], edge) <= d)
                    .collect();
                let scale = polyline_length(edge) * p.thickness;
                spread(
                    &mut bd,
                    &sel,
                    [traction[0] * scale, traction[1] * scale],
                    grid,
                    k,
                )?;
            }
            BoundaryCondition::Traction {
                edge,
                traction,
                depth,
            } => {
                if depth.is_some() {
                    return Err(PdError::invalid(
                        format!("boundary[{k}].depth"),
                        "a layer depth applies to the body-force layer only: the transfer functions spread the traction over the horizon",
                    ));
                }
                let before = bd.body.clone();
                traction::spread(grid, edge, *traction, p.thickness, k_decay, &mut bd.body, k)?;
                bd.groups.push(transfer_group(&before, &bd.body));
            }
        }
    }
    Ok(bd)
}

/// Spreads the load `force` (N) over the real nodes `sel` in proportion to their volumes
/// (all equal on a uniform grid; a child of a refinement zone, [`crate::mixed`], carries a
/// quarter of its parent's share per level, so a layer crossing a zone is loaded
/// uniformly). `bd.body` holds densities per reference volume `grid.volume`, as every
/// per-node force of a mixed model does.
fn spread(
    bd: &mut Boundary,
    sel: &[usize],
    force: P2,
    grid: &Grid,
    k: usize,
) -> Result<(), PdError> {
    if sel.is_empty() {
        return Err(PdError::invalid(
            format!("boundary[{k}]"),
            "the loaded boundary layer holds no real node",
        ));
    }
    let weight = |i: usize| {
        let r = grid.node_dx(i) / grid.dx;
        r * r
    };
    let total: f64 = sel.iter().map(|&i| weight(i)).sum();
    let v = total * grid.volume;
    let b = [force[0] / v, force[1] / v];
    for &i in sel {
        let w = weight(i);
        bd.body[i][0] += b[0] * w;
        bd.body[i][1] += b[1] * w;
    }
    let mean = sel.len() as f64 * grid.volume;
    bd.groups.push(BcGroup {
        fixed: [false; 2],
        nodes: sel.to_vec(),
        claimed: Vec::new(),
        body: [force[0] / mean, force[1] / mean],
    });
    Ok(())
}

/// The group of a transfer-function traction: the nodes whose body force it changed
/// and their mean added body force density (the spread itself varies with depth).
fn transfer_group(before: &[P2], after: &[P2]) -> BcGroup {
    let nodes: Vec<usize> = (0..after.len())
        .filter(|&i| after[i] != before[i])
        .collect();
    let mut mean = [0.0; 2];
    let n = nodes.len().max(1) as f64;
    for &i in &nodes {
        mean[0] += (after[i][0] - before[i][0]) / n;
        mean[1] += (after[i][1] - before[i][1]) / n;
    }
    BcGroup {
        fixed: [false; 2],
        nodes,
        claimed: Vec::new(),
        body: mean,
    }
}
