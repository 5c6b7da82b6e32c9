//! Integrals of the Kelvin kernels over one straight constant element.
//!
//! Entry point: [`integrate_element`], which returns the four 2x2 blocks
//! $\hat U_{ij}, \hat T_{ij}, \hat K_{jk}, \hat H_{jk}$ (seed 002 Eqs. 17-20, REFERENCES.md)
//! for a field point $x$ with normal $m$ and one element with tangent $e$, normal $n$.
//!
//! Along the element $r = y - x = \xi e + \eta n$ with $\eta = (y - x)\cdot n$ constant, so
//! every kernel is a sum of $\xi^a \eta^b / r^{2k}$ terms. The kernel formulas are therefore
//! written once ([`tensors`]) in terms of eleven scalar moments
//! $M_{ak} = \int \xi^a r^{-2k} d\xi$ and $L = \int \ln r\, d\xi$; what differs between
//! far, near and singular pairs is only how the moments are obtained ([`moments`]):
//! - far pairs: Gauss-Legendre with an order chosen from distance / length;
//! - near pairs: closed form (atan / log recurrences), exact for any gap;
//! - near-collinear pairs off the element: Gauss on a geometrically subdivided element;
//! - coplanar pairs (self element, coincident opposite crack face, collinear neighbours):
//!   $\eta = 0$ with Cauchy principal values and Hadamard finite parts, plus the free-term
//!   jumps $-\tfrac12 \operatorname{sign}(m\cdot n) I$ in $\hat T$ and $+\tfrac12 I$ in $\hat K$.
//!
//! The convention of the jumps: $\hat T$ and $\hat K$ are the limits as $x$ approaches the
//! element from the body side, so the boundary equations read
//! $u(x) + \sum \hat T u = \sum \hat U t$ and $t(x) = \sum \hat K t - \sum \hat H u$.

pub mod far;
pub mod moments;
pub mod quadrature;
pub mod tensors;

use crate::mesh::Element;
use crate::Material;
use nalgebra::Vector2;
use tensors::Kernels;

pub use tensors::PairIntegrals;

/// Kernel constants of a material (plane-strain form with the effective Poisson ratio).
#[derive(Debug, Clone, Copy)]
pub struct KernelConsts {
    /// Shear modulus (Pa).
    pub mu: f64,
    /// Effective Poisson ratio.
    pub nu: f64,
}

impl From<&Material> for KernelConsts {
    fn from(m: &Material) -> Self {
        Self {
            mu: m.mu(),
            nu: m.nu_eff(),
        }
    }
}

/// Integrals of U, T, K, H over `el` for the field point `x` with unit normal `m`.
pub fn integrate_element(
    x: Vector2<f64>,
    m: Vector2<f64>,
    el: &Element,
    kc: &KernelConsts,
) -> PairIntegrals {
    let geo = moments::PairGeometry::new(x, el);
    let mom = moments::element_moments(&geo);
    with_jumps(
        tensors::kernel_integrals(&el.tangent, &el.normal, &m, &mom, kc),
        &mom,
        &m,
        el,
    )
}

/// The integrals of [`integrate_element`] and the first-moment integrals
/// $\int K\,(s - s_{mid})\,ds$ about the element midpoint, which multiply the tangential
/// derivative of a linearly reconstructed density (see [`crate::mesh::stencil`]); only
/// their T and H blocks are computed (the traction is not reconstructed).
pub fn integrate_element_linear(
    x: Vector2<f64>,
    m: Vector2<f64>,
    el: &Element,
    kc: &KernelConsts,
) -> (PairIntegrals, PairIntegrals) {
    linear_selected(x, m, el, kc, Kernels::ALL, Kernels::DOUBLE_LAYER)
}

/// [`integrate_element_linear`] restricted to what an interior displacement
/// $u(x) = \sum \hat U t - \sum \hat T u - \sum \hat T_1 u'$ uses: U, T (and K) of the
/// element, T of its first moment; the H blocks stay zero. The computed blocks equal
/// those of [`integrate_element_linear`] bit for bit (same expressions), at about half
/// the cost of the kernel tensors.
pub fn integrate_element_linear_displacement(
    x: Vector2<f64>,
    m: Vector2<f64>,
    el: &Element,
    kc: &KernelConsts,
) -> (PairIntegrals, PairIntegrals) {
    linear_selected(x, m, el, kc, Kernels::DISPLACEMENT, Kernels::T_ONLY)
}

/// Zeroth- and first-moment integrals with the kernels `zeroth` and `first` selected.
fn linear_selected(
    x: Vector2<f64>,
    m: Vector2<f64>,
    el: &Element,
    kc: &KernelConsts,
    zeroth: Kernels,
    first: Kernels,
) -> (PairIntegrals, PairIntegrals) {
    let geo = moments::PairGeometry::new(x, el);
    let mom = moments::element_moments(&geo);
    let z = with_jumps(
        tensors::kernel_integrals_selected(&el.tangent, &el.normal, &m, &mom, kc, zeroth),
        &mom,
        &m,
        el,
    );
    let first_mom = mom.first_moment(0.5 * (geo.s1 + geo.s2));
    let f = tensors::kernel_integrals_selected(&el.tangent, &el.normal, &m, &first_mom, kc, first);
    (z, f)
}

fn with_jumps(
    mut out: PairIntegrals,
    mom: &moments::Moments,
    m: &Vector2<f64>,
    el: &Element,
) -> PairIntegrals {
    if mom.on_element {
        let s = if m.dot(&el.normal) > 0.0 { 1.0 } else { -1.0 };
        for i in 0..2 {
            out.t[i][i] -= 0.5 * s;
            out.k[i][i] += 0.5;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Element;

    /// The displacement selection computes the blocks it keeps with the full set's
    /// expressions: equal bit for bit, far, near and on the element; H stays zero.
    #[test]
    fn displacement_selection_equals_the_full_integrals() {
        let kc = KernelConsts {
            mu: 3750.0,
            nu: 0.25,
        };
        let el = Element::new(Vector2::new(0.3, -0.2), Vector2::new(0.42, -0.11), 0);
        let m = Vector2::new(0.6, 0.8);
        for x in [
            Vector2::new(3.0, 1.0),
            Vector2::new(0.37, -0.13),
            Vector2::new(0.36, -0.1549),
            el.mid,
        ] {
            let (z, f) = integrate_element_linear(x, m, &el, &kc);
            let (zd, fd) = integrate_element_linear_displacement(x, m, &el, &kc);
            assert_eq!((zd.u, zd.t, zd.k), (z.u, z.t, z.k), "x = {x:?}");
            assert_eq!(fd.t, f.t, "x = {x:?}");
            assert_eq!((zd.h, fd.h), ([[0.0; 2]; 2], [[0.0; 2]; 2]));
            assert!(z.h.iter().flatten().any(|v| *v != 0.0), "x = {x:?}");
        }
    }
}
