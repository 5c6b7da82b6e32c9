//! The interior displacement contributed by one element far from the field point, summed
//! straight from the Kelvin kernels at the Gauss points instead of through the moments
//! and integrated tensors (which also build the K block and copy four 2x2 blocks per
//! pair). With $R = y - x = \xi e + \eta n$, $r^2 = \xi^2 + \eta^2$ and the element's
//! constant traction $t$, displacement $u$ and tangential derivative $g$ of the linear
//! reconstruction about the midpoint $c$ (REFERENCES.md, seed 002 Eqs. 17-18):
//! $$\Delta u_i = \int U_{ij} t_j\,d\xi - \int T_{ij}\,(u_j + (\xi - c) g_j)\,d\xi,$$
//! $$U_{ij} t_j = C_U[-(3-4\nu) t_i \ln r + R_i (R\cdot t)/r^2],$$
//! $$T_{ij} v_j = -C_T[(1-2\nu)\eta v_i/r^2 + 2\eta R_i (R\cdot v)/r^4 -
//!   (1-2\nu)(R_i (n\cdot v) - n_i (R\cdot v))/r^2].$$
//!
//! The rule is the one [`super::moments::element_moments`] picks for the pair
//! ([`super::moments::far_gauss_order`]), so both paths give the same sum to round-off.

use std::f64::consts::PI;

use nalgebra::Vector2;

use super::moments::{far_gauss_order, PairGeometry};
use super::quadrature::gauss_legendre;
use super::KernelConsts;
use crate::mesh::Element;

/// The element's densities as the interior displacement sees them.
#[derive(Debug, Clone, Copy)]
pub struct Densities {
    /// Traction (constant on the element).
    pub t: [f64; 2],
    /// Displacement at the midpoint.
    pub u: [f64; 2],
    /// Tangential derivative of the reconstructed displacement (zero without one).
    pub g: [f64; 2],
}

/// $\Delta u(x)$ of element `el` by Gauss at the pair's far-field order; `None` when the
/// field point is too near the element for a plain rule (distance < 3 lengths).
pub fn far_displacement(
    x: Vector2<f64>,
    el: &Element,
    kc: &KernelConsts,
    d: &Densities,
) -> Option<[f64; 2]> {
    let geo = PairGeometry::new(x, el);
    let order = far_gauss_order(&geo)?;
    let nu = kc.nu;
    let cu = 1.0 / (8.0 * PI * kc.mu * (1.0 - nu));
    let ct = 1.0 / (4.0 * PI * (1.0 - nu));
    let a = 1.0 - 2.0 * nu;
    let (e, n, eta) = (el.tangent, el.normal, geo.eta);
    let half = 0.5 * (geo.s2 - geo.s1);
    let c = 0.5 * (geo.s1 + geo.s2);
    let t = Vector2::new(d.t[0], d.t[1]);
    let mut out = Vector2::zeros();
    for &(p, w) in gauss_legendre(order) {
        let xi = c + half * p;
        let wt = w * half;
        let r = e * xi + n * eta;
        let r2 = xi * xi + eta * eta;
        let inv = 1.0 / r2;
        let ln_r = 0.5 * r2.ln();
        let v = Vector2::new(d.u[0] + (xi - c) * d.g[0], d.u[1] + (xi - c) * d.g[1]);
        let (rt, rv, nv) = (r.dot(&t), r.dot(&v), n.dot(&v));
        let ut = (t * (-(3.0 - 4.0 * nu) * ln_r) + r * (rt * inv)) * cu;
        let tv = (v * (a * eta * inv) + r * (2.0 * eta * rv * inv * inv)
            - (r * nv - n * rv) * (a * inv))
            * (-ct);
        out += (ut - tv) * wt;
    }
    Some([out.x, out.y])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::integrate_element_linear_displacement;

    /// The same contribution through the moments and the integrated tensors
    /// ([`crate::post::FieldEvaluator`]'s near path).
    fn by_moments(x: Vector2<f64>, el: &Element, kc: &KernelConsts, d: &Densities) -> [f64; 2] {
        let (p, p1) = integrate_element_linear_displacement(x, Vector2::new(1.0, 0.0), el, kc);
        let mut u = [0.0; 2];
        for i in 0..2 {
            for j in 0..2 {
                u[i] += p.u[i][j] * d.t[j] - p.t[i][j] * d.u[j] - p1.t[i][j] * d.g[j];
            }
        }
        u
    }

    #[test]
    fn far_pairs_match_the_moment_path_and_near_ones_are_left_to_it() {
        let kc = KernelConsts { mu: 80e9, nu: 0.3 };
        let el = Element::new(Vector2::new(0.3, -0.2), Vector2::new(0.42, -0.11), 0);
        let d = Densities {
            t: [1.5e6, -0.7e6],
            u: [2e-5, 3e-5],
            g: [-4e-4, 1e-4],
        };
        let mut far_pairs = 0;
        for k in 0..72 {
            let angle = k as f64 * 5.0_f64.to_radians();
            for dist in [0.1, 0.3, 0.46, 0.9, 1.6, 5.0, 40.0] {
                let x = el.mid + Vector2::new(angle.cos(), angle.sin()) * dist;
                let reference = by_moments(x, &el, &kc, &d);
                match far_displacement(x, &el, &kc, &d) {
                    Some(u) => {
                        far_pairs += 1;
                        let scale = reference[0].hypot(reference[1]);
                        let err = (u[0] - reference[0]).hypot(u[1] - reference[1]);
                        assert!(err <= 1e-12 * scale, "x {x:?}: {u:?} vs {reference:?}");
                    }
                    // Nearer than 3 lengths (0.45 here): the moment path's closed forms.
                    None => assert!(
                        PairGeometry::new(x, &el).distance() < 3.0 * el.h,
                        "x {x:?} left to the moments"
                    ),
                }
            }
        }
        assert!(far_pairs >= 72 * 4, "{far_pairs} far pairs");
    }
}
