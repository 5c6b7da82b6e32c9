//! A PD window loaded by interface tractions through seed 001's transfer functions: the
//! window side of the traction ordering of Algorithm 1
//! ([`crate::iteration::Ordering::TractionToPd`]).
//!
//! The window is the PD problem of [`crate::pd_window::build_problem`] without the
//! fictitious layers of its interface sides ([`crate::pd_window::traction_problem`]):
//! those sides are free surfaces. The traction $p_e = -t_e$ on the window's side of
//! interface element e ($t_e = \sigma n$ the BEM traction, n pointing into the window)
//! enters as the dead body force of seed 001 Eqs. 12, 16, 17 in the discrete form of
//! Eq. 23 with one boundary point per element (its midpoint $x_e$, area $h_e t$):
//! $$b_i = b_i^{outer} + \sum_e \frac{q(|x_e - x_i|)}{\sum_j q(|x_e - x_j|) V_j}\,
//! p_e\, h_e\, t,\qquad q(r) = 1 - \frac{r}{k\delta},$$
//! with $k = \max(1, \lfloor A / (8 S \delta) \rfloor)$, A the window area and S its
//! interface length ([`pdbem_pd::traction`]).
//!
//! Rigid motions: a window without prescribed displacement on its outer sides is a
//! floating body. Its load is made exactly self-equilibrated by removing the resultant
//! force and moment about the node centroid c as a rigid-body load spread over the
//! nodes (inertia relief): $b_i \mathrel{-}= F/(N V) + \alpha\,\hat z \times (x_i - c)$,
//! $\alpha = M / \sum_j |x_j - c|^2 V$. What is removed is the discretisation error of
//! the BEM's equilibrium and of the transfer functions' moment (their force is exact);
//! three pinned components (the real nodes at corners 0 and 2) then fix the gauge
//! without reaction. The gauge does not reach the BEM: the iteration adds the rigid
//! motion that balances the window ([`crate::iteration`]).
//!
//! Interface displacement: at element midpoint $x_e$ (on the window outline, half a
//! spacing outside the outer node row), the linear extrapolation from the two node rows
//! along the inward normal, $u_e = \tfrac32 u_{1} - \tfrac12 u_{2}$ (exact for a uniform
//! strain).

use pdbem_bem::{Mesh, V2};
use pdbem_pd::{BoundaryCondition, PdModel};

use crate::error::CouplingError;
use crate::pd_window::traction_problem;
use crate::setup::WindowModel;

/// One window of the traction ordering.
#[derive(Debug, Clone)]
pub struct TractionWindow {
    /// The PD model with free interface sides (state = last solve).
    pub model: PdModel,
    /// Interface elements (mesh indices), as in the window's [`crate::interface::Interface`].
    pub elements: Vec<usize>,
    /// Per element: the real nodes of the first and second row along its inward normal.
    rows: Vec<(usize, usize)>,
    /// Per element: (real node, body force density per unit traction, 1/m).
    spread: Vec<Vec<(usize, f64)>>,
    /// Body force density of the window's outer conditions at load factor 1 (N/m^3).
    outer: Vec<[f64; 2]>,
    /// Whether no displacement is prescribed on the window (rigid motions free).
    pub floating: bool,
    /// Window centre (m), the moment point of the balance.
    pub centre: V2,
    /// Length scale of the rotation unknown: half the window diagonal (m).
    pub length: f64,
    /// Rigid motion (x, y translation in m, rotation in rad about [`Self::centre`])
    /// added to the PD displacement in the last BEM solve.
    pub motion: [f64; 3],
    /// The interface displacements the BEM took in the last solve (m, per element).
    pub given: Vec<[f64; 2]>,
}

/// Whether window `w` has no prescribed displacement once its interface layers are
/// removed (a floating body under tractions).
pub fn is_floating(w: &WindowModel) -> bool {
    !traction_problem(&w.window, &w.problem, &[])
        .boundary
        .iter()
        .any(|bc| matches!(bc, BoundaryCondition::Displacement { .. }))
}

impl TractionWindow {
    /// Builds the traction window of window model `w` (index `index`) against `mesh`.
    pub fn new(
        index: usize,
        w: &WindowModel,
        mesh: &Mesh,
        thickness: f64,
    ) -> Result<TractionWindow, CouplingError> {
        let floating = is_floating(w);
        let pins = if floating { pins(w) } else { Vec::new() };
        let problem = traction_problem(&w.window, &w.problem, &pins);
        let mut model = PdModel::new(&problem).map_err(|e| CouplingError::pd(index, e))?;
        if model.n_real() != w.model.n_real() {
            return Err(CouplingError::Interface {
                window: index,
                message: format!(
                    "traction window has {} real nodes, the window {}",
                    model.n_real(),
                    w.model.n_real()
                ),
            });
        }
        model.set_load_factor(1.0);
        let elements = w.interface.elements.clone();
        let rows = elements
            .iter()
            .map(|&e| node_rows(index, &model, mesh, e, w.window.spec.dx))
            .collect::<Result<Vec<_>, _>>()?;
        let spread = spread_weights(index, w, &model, mesh, &elements, thickness)?;
        let outer = model.boundary().body.clone();
        let (lx, ly) = w.window.size();
        Ok(TractionWindow {
            model,
            elements,
            rows,
            spread,
            outer,
            floating,
            centre: w.window.spec.center,
            length: 0.5 * lx.hypot(ly),
            motion: [0.0; 3],
            given: vec![[0.0; 2]; w.interface.elements.len()],
        })
    }

    /// Number of interface unknowns (2 per element: the BEM traction).
    pub fn len(&self) -> usize {
        2 * self.elements.len()
    }

    /// Whether the window has no interface element.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// The resultant force (N) and moment about [`Self::centre`] (N m) of the outer
    /// conditions' load at load factor `scale`.
    pub fn outer_resultant(&self, scale: f64) -> ([f64; 2], f64) {
        resultant(&self.model, &self.outer, self.centre, scale)
    }

    /// Sets the body force for BEM tractions `t` (Pa, per element) at load factor
    /// `scale` (the model multiplies its body force by it), balanced when floating.
    pub fn load(&mut self, t: &[f64], scale: f64) -> Result<(), pdbem_pd::PdError> {
        let mut b = self.outer.clone();
        for (k, weights) in self.spread.iter().enumerate() {
            // The window's traction is minus the BEM body's.
            let p = [-t[2 * k] / scale, -t[2 * k + 1] / scale];
            for &(i, w) in weights {
                b[i][0] += w * p[0];
                b[i][1] += w * p[1];
            }
        }
        if self.floating {
            balance(&self.model, &mut b);
        }
        self.model.set_body_forces(&b)
    }

    /// The displacement (m) of rigid motion [`Self::motion`] at `x`.
    pub fn rigid_at(&self, x: V2) -> [f64; 2] {
        let [ax, ay, th] = self.motion;
        let r = x - self.centre;
        [ax - th * r.y, ay + th * r.x]
    }

    /// Interface displacements (m) at the element midpoints, extrapolated from the two
    /// node rows ([x, y] per element).
    pub fn interface_displacements(&self) -> Vec<[f64; 2]> {
        let u = self.model.displacements();
        self.rows
            .iter()
            .map(|&(a, b)| [1.5 * u[a][0] - 0.5 * u[b][0], 1.5 * u[a][1] - 0.5 * u[b][1]])
            .collect()
    }
}

/// The real nodes at corners 0 and 2: both components of the first and the component
/// across the diagonal with the larger lever of the second (global axes).
fn pins(w: &WindowModel) -> Vec<([f64; 2], [Option<f64>; 2])> {
    let c = w.window.corners();
    let pos = &w.model.positions()[..w.model.n_real()];
    let nearest = |p: V2| {
        pos.iter()
            .copied()
            .min_by(|a, b| {
                let d = |q: &[f64; 2]| (q[0] - p.x).hypot(q[1] - p.y);
                d(a).total_cmp(&d(b))
            })
            .unwrap_or([p.x, p.y])
    };
    let (a, b) = (nearest(c[0]), nearest(c[2]));
    let along_x = (b[0] - a[0]).abs() >= (b[1] - a[1]).abs();
    let second = if along_x {
        [None, Some(0.0)]
    } else {
        [Some(0.0), None]
    };
    vec![(a, [Some(0.0), Some(0.0)]), (b, second)]
}

/// The real nodes of rows 1 and 2 along the inward normal of element `e`.
fn node_rows(
    index: usize,
    model: &PdModel,
    mesh: &Mesh,
    e: usize,
    dx: f64,
) -> Result<(usize, usize), CouplingError> {
    let el = &mesh.elements[e];
    let pos = &model.positions()[..model.n_real()];
    let find = |depth: f64| -> Result<usize, CouplingError> {
        let p = el.mid + depth * dx * el.normal;
        let (i, d) = pos
            .iter()
            .enumerate()
            .map(|(i, q)| (i, (q[0] - p.x).hypot(q[1] - p.y)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, f64::INFINITY));
        if d > 0.1 * dx {
            return Err(CouplingError::Interface {
                window: index,
                message: format!(
                    "no real node {depth} dx inside element {e} at ({:.4}, {:.4})",
                    el.mid.x, el.mid.y
                ),
            });
        }
        Ok(i)
    };
    Ok((find(0.5)?, find(1.5)?))
}

/// Per element, the body force density per unit traction of every real node it reaches
/// (seed 001 Eq. 23 through [`pdbem_pd::traction::spread`]).
fn spread_weights(
    index: usize,
    w: &WindowModel,
    model: &PdModel,
    mesh: &Mesh,
    elements: &[usize],
    thickness: f64,
) -> Result<Vec<Vec<(usize, f64)>>, CouplingError> {
    let grid = model.grid();
    let (lx, ly) = w.window.size();
    let s: f64 = elements.iter().map(|&e| mesh.elements[e].h).sum();
    let k = pdbem_pd::traction::decay_k(lx * ly, s, grid.delta);
    let mut body = vec![[0.0; 2]; model.n_nodes()];
    elements
        .iter()
        .map(|&e| {
            let el = &mesh.elements[e];
            body.iter_mut().for_each(|b| *b = [0.0; 2]);
            let edge = [[el.a.x, el.a.y], [el.b.x, el.b.y]];
            pdbem_pd::traction::spread(grid, &edge, [1.0, 0.0], thickness, k, &mut body, e)
                .map_err(|err| CouplingError::pd(index, err))?;
            Ok(body
                .iter()
                .enumerate()
                .filter(|(_, b)| b[0] != 0.0)
                .map(|(i, b)| (i, b[0]))
                .collect())
        })
        .collect()
}

/// Resultant force (N) and moment about `c` (N m) of the body force `b` at load `scale`
/// over the real nodes.
fn resultant(model: &PdModel, b: &[[f64; 2]], c: V2, scale: f64) -> ([f64; 2], f64) {
    let v = model.grid().volume * scale;
    let pos = model.positions();
    let (mut f, mut m) = ([0.0; 2], 0.0);
    for i in 0..model.n_real() {
        f[0] += v * b[i][0];
        f[1] += v * b[i][1];
        m += v * ((pos[i][0] - c.x) * b[i][1] - (pos[i][1] - c.y) * b[i][0]);
    }
    (f, m)
}

/// Removes the resultant force and moment of `b` as a rigid-body load over the real
/// nodes (see the module docs).
fn balance(model: &PdModel, b: &mut [[f64; 2]]) {
    let n = model.n_real();
    let pos = model.positions();
    let c = pos[..n]
        .iter()
        .fold(V2::zeros(), |s, p| s + V2::new(p[0], p[1]))
        / n as f64;
    let (f, m) = resultant(model, b, c, 1.0);
    let v = model.grid().volume;
    let j: f64 = pos[..n]
        .iter()
        .map(|p| ((p[0] - c.x).powi(2) + (p[1] - c.y).powi(2)) * v)
        .sum();
    let (a, alpha) = ([f[0] / (n as f64 * v), f[1] / (n as f64 * v)], m / j);
    for i in 0..n {
        let r = [pos[i][0] - c.x, pos[i][1] - c.y];
        b[i][0] -= a[0] - alpha * r[1];
        b[i][1] -= a[1] + alpha * r[0];
    }
}
