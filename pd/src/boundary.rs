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
}

/// Resolve the problem's boundary conditions on the grid.
pub fn resolve(p: &PdProblem, grid: &Grid) -> Result<Boundary, PdError> {
    let n = grid.len();
    let delta = grid.delta;
    let mut bd = Boundary {
        fixed: vec![[false; 2]; n],
        base: vec![[0.0; 2]; n],
        body: vec![[0.0; 2]; n],
    };
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
                for i in range {
                    if on.contains(grid.pos[i], delta) {
                        count += 1;
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
            }
            BoundaryCondition::Force { on, force } => {
                let sel: Vec<usize> = (0..grid.n_real)
                    .filter(|&i| on.contains(grid.pos[i], delta))
                    .collect();
                spread(&mut bd, &sel, *force, grid.volume, k)?;
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
                    grid.volume,
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
                traction::spread(grid, edge, *traction, p.thickness, k_decay, &mut bd.body, k)?;
            }
        }
    }
    Ok(bd)
}

fn spread(
    bd: &mut Boundary,
    sel: &[usize],
    force: P2,
    volume: f64,
    k: usize,
) -> Result<(), PdError> {
    if sel.is_empty() {
        return Err(PdError::invalid(
            format!("boundary[{k}]"),
            "the loaded boundary layer holds no real node",
        ));
    }
    let v = sel.len() as f64 * volume;
    for &i in sel {
        bd.body[i][0] += force[0] / v;
        bd.body[i][1] += force[1] / v;
    }
    Ok(())
}
