//! Regular grid over the region: real nodes at cell centres inside the body,
//! fictitious (virtual) nodes outside it within the horizon of its boundary.
//!
//! Node `k` sits at `origin + R(angle) ((i + 1/2) dx, (j + 1/2) dx)` and owns
//! the volume `V = dx^2 t` (seed 002 section 2.1: one integration point per
//! square cell). Real nodes come first (row-major), then the fictitious
//! nodes selected by fictitious-layer displacement conditions, depth
//! `delta` (seed 002 Fig. 1, seed 000 section 2.3). Refinement zones split real
//! cells into children of smaller spacing ([`crate::mixed`]).

use crate::error::PdError;
use crate::geometry::{dist_point_polygon_boundary, point_in_polygon, rotate, P2};
use crate::problem::{BoundaryCondition, Layer, PdProblem};

/// Node positions of a problem.
#[derive(Clone, Debug)]
pub struct Grid {
    /// Reference positions; real nodes `0..n_real`, then fictitious ones.
    pub pos: Vec<P2>,
    /// Number of real nodes.
    pub n_real: usize,
    /// Grid spacing (m).
    pub dx: f64,
    /// Node volume `dx^2 t` (m^3).
    pub volume: f64,
    /// Horizon (m).
    pub delta: f64,
    /// Grid angle (radians): the lattice directions are `R(angle) e_x`,
    /// `R(angle) e_y`.
    pub angle: f64,
    /// Spacing of every node on a mixed grid ([`crate::mixed`]); empty on a uniform
    /// grid (every node has `dx`). `dx`, `volume` and `delta` are then the coarse
    /// cell's.
    pub spacing: Vec<f64>,
}

impl Grid {
    /// Total number of nodes (real + fictitious).
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether the grid has no node.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Whether node spacings differ (refinement zones, [`crate::mixed`]).
    pub fn is_mixed(&self) -> bool {
        !self.spacing.is_empty()
    }

    /// Spacing of node `i` (m).
    #[inline]
    pub fn node_dx(&self, i: usize) -> f64 {
        self.spacing.get(i).copied().unwrap_or(self.dx)
    }

    /// Volume of node `i` (m^3).
    pub fn node_volume(&self, i: usize) -> f64 {
        let r = self.node_dx(i) / self.dx;
        self.volume * r * r
    }
}

/// The cell lattice of a problem: cell `(i, j)` has its centre at `origin + (i + 1/2,
/// j + 1/2) dx` in the grid frame (turned by the grid angle), and the cells `i0..=i1`,
/// `j0..=j1` cover the outline's bounding box padded by a horizon and a cell.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Lattice {
    /// Origin in the grid frame (a cell corner).
    pub origin: P2,
    /// Cell index range along the grid's x axis.
    pub i: (i64, i64),
    /// Cell index range along the grid's y axis.
    pub j: (i64, i64),
    /// Spacing (m).
    pub dx: f64,
    /// Grid angle (radians, counter-clockwise).
    pub angle: f64,
}

impl Lattice {
    /// The lattice of a validated problem.
    pub fn of(p: &PdProblem) -> Lattice {
        let (dx, angle) = (p.dx, p.grid_angle);
        // Grid frame: local = R(-angle) x.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &q in &p.region.outline {
            let q = rotate(q, -angle);
            for d in 0..2 {
                lo[d] = lo[d].min(q[d]);
                hi[d] = hi[d].max(q[d]);
            }
        }
        let origin = match p.grid_origin {
            Some(o) => rotate(o, -angle),
            None => lo,
        };
        let pad = p.horizon() + dx;
        Lattice {
            origin,
            i: (
                ((lo[0] - pad - origin[0]) / dx).floor() as i64,
                ((hi[0] + pad - origin[0]) / dx).ceil() as i64,
            ),
            j: (
                ((lo[1] - pad - origin[1]) / dx).floor() as i64,
                ((hi[1] + pad - origin[1]) / dx).ceil() as i64,
            ),
            dx,
            angle,
        }
    }

    /// Centre of cell `(i, j)` in the global frame.
    pub fn centre(&self, i: i64, j: i64) -> P2 {
        let q = [
            self.origin[0] + (i as f64 + 0.5) * self.dx,
            self.origin[1] + (j as f64 + 0.5) * self.dx,
        ];
        rotate(q, self.angle)
    }

    /// The cell whose centre is nearest to `x` (global frame).
    pub fn cell_of(&self, x: P2) -> (i64, i64) {
        let q = rotate(x, -self.angle);
        (
            ((q[0] - self.origin[0]) / self.dx - 0.5).round() as i64,
            ((q[1] - self.origin[1]) / self.dx - 0.5).round() as i64,
        )
    }
}

/// Build the uniform grid of a validated problem (refinement zones are applied by
/// [`crate::mixed::build_grid`]).
pub fn build_uniform(p: &PdProblem) -> Result<Grid, PdError> {
    let dx = p.dx;
    let delta = p.horizon();
    let angle = p.grid_angle;
    let region = &p.region;
    let lattice = Lattice::of(p);
    let ((i0, i1), (j0, j1)) = (lattice.i, lattice.j);
    let ncells = (i1 - i0 + 1) as f64 * (j1 - j0 + 1) as f64;
    if ncells > 5.0e7 {
        return Err(PdError::invalid(
            "dx",
            format!("dx = {dx:.3e} m gives {ncells:.3e} grid cells over the bounding box; the cap is 5e7"),
        ));
    }
    let fict_sel: Vec<_> = p
        .boundary
        .iter()
        .filter_map(|bc| match bc {
            BoundaryCondition::Displacement {
                on,
                layer: Layer::Fictitious,
                ..
            } => Some(on),
            _ => None,
        })
        .collect();
    let mut real = Vec::new();
    let mut fict = Vec::new();
    for j in j0..=j1 {
        for i in i0..=i1 {
            let x = lattice.centre(i, j);
            if region.contains(x) {
                real.push(x);
            } else if !fict_sel.is_empty() {
                // Distance to the material: to the outline if outside it,
                // otherwise to the boundary of the hole containing x.
                let d = if !point_in_polygon(x, &region.outline) {
                    dist_point_polygon_boundary(x, &region.outline)
                } else {
                    region
                        .holes
                        .iter()
                        .filter(|h| h.contains(x))
                        .map(|h| h.boundary_distance(x))
                        .fold(f64::INFINITY, f64::min)
                };
                if d <= delta * (1.0 + 1e-9) && fict_sel.iter().any(|s| s.contains(x, delta)) {
                    fict.push(x);
                }
            }
        }
    }
    if real.is_empty() {
        return Err(PdError::invalid(
            "region",
            format!(
                "empty region: no grid point of spacing dx = {dx:.3e} m falls inside the outline"
            ),
        ));
    }
    let n_real = real.len();
    real.extend(fict);
    let g = Grid {
        pos: real,
        n_real,
        dx,
        volume: dx * dx * p.thickness,
        delta,
        angle,
        spacing: Vec::new(),
    };
    Ok(g)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::{Region, Selection};

    #[test]
    fn rectangle_with_layers_counts() {
        // 10 x 4 cells, fictitious layer on the left side: depth delta = 3.015 dx
        // holds 3 columns of 4 nodes inside the side's strip.
        let p = PdProblem {
            region: Region::rectangle([0.0, 0.0], [10.0, 4.0]),
            dx: 1.0,
            youngs_modulus: 1.0,
            boundary: vec![BoundaryCondition::Displacement {
                on: Selection::Box {
                    min: [-10.0, 0.0],
                    max: [0.0, 4.0],
                },
                ux: Some(0.0),
                uy: Some(0.0),
                layer: Layer::Fictitious,
            }],
            ..Default::default()
        };
        let g = build_uniform(&p).unwrap();
        assert_eq!(g.n_real, 40);
        assert_eq!(g.len() - g.n_real, 12);
        assert!(g.pos[g.n_real..].iter().all(|q| q[0] < 0.0 && q[0] > -3.1));
    }

    #[test]
    fn rotated_rectangle_keeps_node_count() {
        let a = 0.3;
        let p = PdProblem {
            region: Region::rotated_rectangle([1.0, 2.0], 10.0, 4.0, a),
            dx: 1.0,
            youngs_modulus: 1.0,
            grid_angle: a,
            ..Default::default()
        };
        assert_eq!(build_uniform(&p).unwrap().n_real, 40);
    }
}
