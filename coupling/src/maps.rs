//! Interface maps between the BEM solution and the PD windows (seed 002 Eqs. 23-24).
//!
//! **BEM -> PD displacements** ([`DisplacementMap`]), per coupled virtual node:
//! - `Copy` (seed 002 Eq. 23): $u_{i1} = u_{i2} = u_{i3} = u_i^{BEM}$, the value of its
//!   element copied to every layer: zero-order, so a uniform strain $\varepsilon$ reaches
//!   the outer layers with an error $\varepsilon\,d$ at depth d.
//! - `Interior`: the BEM displacement evaluated at the node's own position by the interior
//!   representation (`pdbem_bem::post::FieldEvaluator`), one pass over all elements per node.
//! - `Taylor`: $u(x) = u_e + \partial_s u\,(x - x_e)\cdot s + \partial_n u\,(x - x_e)\cdot n$
//!   from the element's own data: the tangential derivative $\partial_s u$ of the linear
//!   reconstruction and the normal derivative from Hooke's law with the element traction
//!   $t = \sigma n$: $\varepsilon_{nn} = [(1-2\nu)\sigma_{nn}/(2\mu) - \nu\varepsilon_{ss}]/(1-\nu)$,
//!   $\partial_n u_n = \varepsilon_{nn}$, $\partial_n u_s = \sigma_{ns}/\mu - \partial_s u_n$
//!   (plane-strain form with the effective Poisson ratio). Exact for uniform strain,
//!   and costs nothing next to `Interior`.
//!
//! **PD -> BEM tractions** ([`TractionMap`]), per interface element e of length $h_e$:
//! $t_e = -F_e / (h_e\,\text{thickness})$ (seed 002 Eq. 24 per unit length), $F_e$ the
//! force the virtual nodes exert on the real nodes (virtual-virtual bonds excluded):
//! - `Rows`: the forces of the virtual nodes assigned to e (`PdModel::virtual_node_forces`).
//! - `Crossing`: the forces of the bonds whose segment crosses e (the PD flux).
//!
//! The minus sign: $t = \sigma n$ with n the outward normal of the BEM body (pointing into
//! the window) is the force per area the window exerts on the BEM body, the reaction of the
//! force the BEM material (virtual nodes) exerts on the window.

use pdbem_bem::post::{Background, FieldEvaluator};
use pdbem_bem::{Material, Mesh, Solution, V2};
use pdbem_pd::PdModel;

use crate::interface::Interface;

/// How BEM displacements reach the PD virtual nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DisplacementMap {
    /// Element value copied to its row (seed 002 Eq. 23). The default, as in scenes.
    #[default]
    Copy,
    /// BEM interior-point evaluation at each virtual node.
    Interior,
    /// First-order expansion from the element (value, tangential derivative, traction).
    Taylor,
}

/// How PD forces become BEM tractions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TractionMap {
    /// Forces of the virtual nodes of each element's row (seed 002 Eq. 24).
    Rows,
    /// Forces of the bonds crossing each element.
    #[default]
    Crossing,
}

/// BEM data the displacement maps need.
pub struct BemView<'a> {
    /// Mesh.
    pub mesh: &'a Mesh,
    /// Material.
    pub material: &'a Material,
    /// Current solution.
    pub solution: &'a Solution,
    /// Remote field (infinite bodies).
    pub background: Background,
}

/// Virtual-node displacements of every interface from the BEM solution, flattened
/// (x, y per coupled node, interfaces in order).
pub fn bem_to_virtual(map: DisplacementMap, bem: &BemView, ifaces: &[Interface]) -> Vec<f64> {
    match map {
        DisplacementMap::Copy => ifaces
            .iter()
            .flat_map(|f| {
                f.node_element
                    .iter()
                    .flat_map(|&s| bem.solution.u[f.elements[s]])
            })
            .collect(),
        DisplacementMap::Interior => {
            let ev = FieldEvaluator::new(bem.mesh, bem.material, bem.solution, bem.background);
            let pts: Vec<V2> = ifaces.iter().flat_map(|f| f.positions.clone()).collect();
            ev.displacements(&pts).into_iter().flatten().collect()
        }
        DisplacementMap::Taylor => ifaces
            .iter()
            .flat_map(|f| {
                f.positions
                    .iter()
                    .zip(&f.node_element)
                    .flat_map(|(x, &s)| taylor(bem, f.elements[s], *x))
                    .collect::<Vec<f64>>()
            })
            .collect(),
    }
}

/// First-order expansion of the BEM displacement about element `e`'s midpoint.
fn taylor(bem: &BemView, e: usize, x: V2) -> [f64; 2] {
    let el = &bem.mesh.elements[e];
    let sol = bem.solution;
    let u = V2::new(sol.u[e][0], sol.u[e][1]);
    let Some(du) = sol.du.get(e) else {
        return [u.x, u.y];
    };
    let du_s = V2::new(du[0], du[1]);
    let (s, n) = (el.tangent, el.normal);
    let t = V2::new(sol.t[e][0], sol.t[e][1]);
    let (mu, nu) = (bem.material.mu(), bem.material.nu_eff());
    let eps_ss = du_s.dot(&s);
    let eps_nn = ((1.0 - 2.0 * nu) * t.dot(&n) / (2.0 * mu) - nu * eps_ss) / (1.0 - nu);
    let dun_dn = eps_nn;
    let dus_dn = t.dot(&s) / mu - du_s.dot(&n);
    let du_n = dus_dn * s + dun_dn * n;
    let d = x - el.mid;
    let v = u + d.dot(&s) * du_s + d.dot(&n) * du_n;
    [v.x, v.y]
}

/// Interface tractions (Pa) of one window from its PD state: one [tx, ty] per element
/// of `iface.elements`.
pub fn pd_to_tractions(
    map: TractionMap,
    model: &PdModel,
    iface: &Interface,
    mesh: &Mesh,
    thickness: f64,
) -> Vec<[f64; 2]> {
    let mut f = vec![[0.0; 2]; iface.elements.len()];
    match map {
        TractionMap::Rows => {
            let fv = model.virtual_node_forces();
            for (k, &s) in iface.coupled.iter().zip(&iface.node_element) {
                f[s][0] += fv[*k][0];
                f[s][1] += fv[*k][1];
            }
        }
        TractionMap::Crossing => crossing_forces(model, iface, &mut f),
    }
    f.iter()
        .zip(&iface.elements)
        .map(|(fe, &e)| {
            let h = mesh.elements[e].h * thickness;
            [-fe[0] / h, -fe[1] / h]
        })
        .collect()
}

/// Sums, per element, the force each crossing bond's virtual node exerts on its real node.
fn crossing_forces(model: &PdModel, iface: &Interface, f: &mut [[f64; 2]]) {
    let intact = model.bond_intact();
    let v = model.grid().volume;
    let force = |i: usize, b: usize| -> Option<[f64; 2]> {
        if intact[b] == 0 {
            return None;
        }
        // Force on j from i: minus the force density on i from the pair (PMB bond or
        // state-based t_ij - t_ji), times its volume.
        let g = model.pair_force(i, b);
        Some([-v * g[0], -v * g[1]])
    };
    for &(i, b, slot, share) in &iface.crossings {
        if let Some(g) = force(i, b) {
            f[slot][0] += share * g[0];
            f[slot][1] += share * g[1];
        }
    }
}
