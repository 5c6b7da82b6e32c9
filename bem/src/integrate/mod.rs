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

pub mod moments;
pub mod quadrature;
pub mod tensors;

use crate::mesh::Element;
use crate::Material;
use nalgebra::Vector2;

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
    let geo = moments::PairGeometry::new(x, el);
    let mom = moments::element_moments(&geo);
    let zeroth = with_jumps(
        tensors::kernel_integrals(&el.tangent, &el.normal, &m, &mom, kc),
        &mom,
        &m,
        el,
    );
    let first_mom = mom.first_moment(0.5 * (geo.s1 + geo.s2));
    let first =
        tensors::kernel_integrals_selected(&el.tangent, &el.normal, &m, &first_mom, kc, false);
    (zeroth, first)
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
