//! Tractions on the boundary surface through transfer functions (seed 001
//! sections 2-4), the alternative to the body-force layer of seed 000
//! section 2.3 ([`crate::boundary`]).
//!
//! Seed 001 Eq. 12 adds to the PD equation of motion the term
//! $$\chi \int_{\partial\Omega_p} L(x, x')\, \bar p(x')\, da(x'),$$
//! with the traction transfer function of Eq. 16,
//! $$L(x, x') = \frac{q(|x - x'|)}{\int_\Omega q(|x - x'|)\, dv(x)},$$
//! and the decay of Eq. 17,
//! $$q(r) = 1 - \frac{r}{k\delta}\ (r \le \delta),\quad 0\ (r > \delta),
//! \qquad k = \left[\frac{L W}{8 S \delta}\right].$$
//! Discretised as in Eq. 23, each boundary point $x_m$ of a loaded edge with
//! area $A_m$ (edge length times thickness) gives every real node $i$ within
//! $\delta$ of it the body force density
//! $$b_i \mathrel{+}= \chi\,\frac{q(|x_m - x_i|)}{\sum_j q(|x_m - x_j|)\,V_j}\,\bar p_m A_m.$$
//!
//! Choices (seed 001 fixes them only for its rectangle):
//! - Boundary points: each segment of a loaded edge is split into
//!   $\lceil \ell / \Delta x \rceil$ equal pieces; $x_m$ is a piece's midpoint
//!   and $A_m$ its length times the thickness.
//! - General outlines: $L W$ (the rectangle's area) becomes the area of the
//!   region (outline minus holes), $S$ the total length of the edges with a
//!   non-zero traction; the integer function is the floor, and $k \ge 1$
//!   (for $L W < 8 S \delta$ the floor is 0 and $q$ would change sign).
//! - $\chi = (V - V_B)/V = 1$: there is no boundary layer ($V_B = 0$, seed 001
//!   section 6: "the surface correction and artificial boundary layer ... are
//!   no longer needed"). Then $\sum_i b_i V_i = \sum_m \bar p_m A_m$ exactly:
//!   the applied force is the traction times the edge length and thickness
//!   (Eq. 2, $\int_\Omega L\, dv = 1$).
//!
//! $L$ depends on reference positions only, so the term is a dead load: it
//! enters every solver's residual as $\lambda b$ like the body-force layer,
//! and the tangent does not change.

pub mod study;

use crate::error::PdError;
use crate::geometry::{dist_point_polyline, signed_area, P2};
use crate::grid::Grid;
pub use crate::problem::TractionLoad;
use crate::problem::{BoundaryCondition, Hole, PdProblem};

/// Seed 001 Eq. 17: $k = \max(1, \lfloor A / (8 S \delta) \rfloor)$ with `area`
/// the region's area ($L W$ for the seed's rectangle) and `loaded_length` the
/// total length `S` of the loaded edges.
pub fn decay_k(area: f64, loaded_length: f64, delta: f64) -> f64 {
    (area / (8.0 * loaded_length * delta)).floor().max(1.0)
}

/// Seed 001 Eq. 17: $q(r) = 1 - r/(k\delta)$ for $r \le \delta$, else 0.
pub fn q(r: f64, k: f64, delta: f64) -> f64 {
    if r <= delta {
        1.0 - r / (k * delta)
    } else {
        0.0
    }
}

/// Boundary points of a polyline edge: piece midpoints and piece lengths,
/// each segment split into `ceil(len / dx)` equal pieces.
pub fn boundary_points(edge: &[P2], dx: f64) -> Vec<(P2, f64)> {
    let mut out = Vec::new();
    for w in edge.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        if len == 0.0 {
            continue;
        }
        let n = (len / dx).ceil().max(1.0) as usize;
        for p in 0..n {
            let t = (p as f64 + 0.5) / n as f64;
            out.push((
                [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
                len / n as f64,
            ));
        }
    }
    out
}

/// Area of the region: outline minus holes (m^2).
pub fn region_area(p: &PdProblem) -> f64 {
    let holes: f64 = p
        .region
        .holes
        .iter()
        .map(|h| match h {
            Hole::Circle { radius, .. } => std::f64::consts::PI * radius * radius,
            Hole::Polygon { points } => signed_area(points).abs(),
        })
        .sum();
    signed_area(&p.region.outline) - holes
}

/// Total length `S` of the traction edges with a non-zero traction (m).
pub fn loaded_length(p: &PdProblem) -> f64 {
    p.boundary
        .iter()
        .map(|bc| match bc {
            BoundaryCondition::Traction { edge, traction, .. } if *traction != [0.0, 0.0] => {
                crate::geometry::polyline_length(edge)
            }
            _ => 0.0,
        })
        .sum()
}

/// Add the body force density (N/m^3 at load factor 1) of `traction` (Pa) on
/// `edge` to `body` through the transfer function with decay `k` (seed 001
/// Eq. 23, $\chi = 1$). `k_bc` is the condition's index, for errors.
pub fn spread(
    grid: &Grid,
    edge: &[P2],
    traction: P2,
    thickness: f64,
    k: f64,
    body: &mut [P2],
    k_bc: usize,
) -> Result<(), PdError> {
    let delta = grid.delta;
    let reach = delta * (1.0 + 1e-9);
    // Real nodes within the horizon of the edge: the only ones a boundary point reaches.
    let near: Vec<usize> = (0..grid.n_real)
        .filter(|&i| dist_point_polyline(grid.pos[i], edge) <= reach)
        .collect();
    let mut weights: Vec<(usize, f64)> = Vec::new();
    for (xm, len) in boundary_points(edge, grid.dx) {
        weights.clear();
        let mut norm = 0.0;
        for &i in &near {
            let x = grid.pos[i];
            let r = (x[0] - xm[0]).hypot(x[1] - xm[1]);
            if r <= reach {
                let w = q(r.min(delta), k, delta);
                norm += w * grid.volume;
                weights.push((i, w));
            }
        }
        if norm <= 0.0 {
            return Err(PdError::invalid(
                format!("boundary[{k_bc}].edge"),
                format!(
                    "no real node within the horizon {delta:.3e} m of the boundary point {xm:?}: the traction edge must lie on the region's boundary"
                ),
            ));
        }
        let area = len * thickness;
        for &(i, w) in &weights {
            let s = w / norm * area;
            body[i][0] += s * traction[0];
            body[i][1] += s * traction[1];
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
