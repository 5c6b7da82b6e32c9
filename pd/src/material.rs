//! PMB material constants and the bond failure laws.
//!
//! - Micromodulus (seed 002 Eq. 5, seed 000 Eq. 3):
//!   $c = 9E/(\pi t \delta^3)$ plane stress, $c = 48E/(5\pi t\delta^3)$ plane strain.
//! - Critical stretch from the fracture energy (seed 002 Eq. 7, seed 001 Eq. 19):
//!   $s_0 = \sqrt{4\pi G_c/(9E\delta)}$ plane stress, $\sqrt{5\pi G_c/(12E\delta)}$ plane strain.
//! - Degradation (seed 000 Eq. 12):
//!   $T_s = \tfrac12[1-\tanh(\beta(s_m+s_c-2s)/(s_m-s_c))]$ for $s_m<s<s_c$,
//!   1 below $s_m$, 0 from $s_c$ on; its derivative is seed 000's $L_{ij}$ (Eq. 15).

use crate::problem::{Failure, Plane};

/// PMB micromodulus `c` (N/m^6) for the given plane assumption (seed 002 Eq. 5).
pub fn micromodulus(plane: Plane, youngs_modulus: f64, thickness: f64, delta: f64) -> f64 {
    let pi = std::f64::consts::PI;
    match plane {
        Plane::Stress => 9.0 * youngs_modulus / (pi * thickness * delta.powi(3)),
        Plane::Strain => 48.0 * youngs_modulus / (5.0 * pi * thickness * delta.powi(3)),
    }
}

/// Critical stretch from `G_c` (seed 002 Eq. 7).
pub fn critical_stretch(plane: Plane, youngs_modulus: f64, g_c: f64, delta: f64) -> f64 {
    let pi = std::f64::consts::PI;
    match plane {
        Plane::Stress => (4.0 * pi * g_c / (9.0 * youngs_modulus * delta)).sqrt(),
        Plane::Strain => (5.0 * pi * g_c / (12.0 * youngs_modulus * delta)).sqrt(),
    }
}

/// The failure law resolved to numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BondLaw {
    /// No failure: `T = 1`.
    Elastic,
    /// Brittle PMB: force `c s` until `s >= s0`, then broken for ever.
    Brittle {
        /// Critical stretch.
        s0: f64,
    },
    /// Tanh degradation (seed 000 Eq. 12).
    Degrading {
        /// Degradation onset stretch.
        s_m: f64,
        /// Zero-force stretch.
        s_c: f64,
        /// Steepness.
        beta: f64,
    },
}

impl BondLaw {
    /// Resolve a [`Failure`] (computing `s0` from `G_c` if needed).
    pub fn from_failure(f: Failure, plane: Plane, youngs_modulus: f64, delta: f64) -> Self {
        match f {
            Failure::None => BondLaw::Elastic,
            Failure::CriticalStretch { s0 } => BondLaw::Brittle { s0 },
            Failure::FractureEnergy { g_c } => BondLaw::Brittle {
                s0: critical_stretch(plane, youngs_modulus, g_c, delta),
            },
            Failure::Degradation { s_m, s_c, beta } => BondLaw::Degrading { s_m, s_c, beta },
        }
    }

    /// The stretch past which damage grows (`s0` or `s_m`; infinite if elastic).
    /// The switching solver leaves the implicit phase when a bond passes it.
    pub fn damage_onset(&self) -> f64 {
        match *self {
            BondLaw::Elastic => f64::INFINITY,
            BondLaw::Brittle { s0 } => s0,
            BondLaw::Degrading { s_m, .. } => s_m,
        }
    }

    /// Width `s_c - s_m` of the softening range (0 for brittle and elastic
    /// bonds).
    pub fn softening_range(&self) -> f64 {
        match *self {
            BondLaw::Degrading { s_m, s_c, .. } => s_c - s_m,
            _ => 0.0,
        }
    }
}

/// Degradation factor `T_s(s)` and its derivative `dT/ds` (seed 000 Eqs. 12, 15).
#[inline]
pub fn degradation(s: f64, s_m: f64, s_c: f64, beta: f64) -> (f64, f64) {
    if s <= s_m {
        (1.0, 0.0)
    } else if s >= s_c {
        (0.0, 0.0)
    } else {
        let arg = beta * (s_m + s_c - 2.0 * s) / (s_m - s_c);
        let th = arg.tanh();
        (0.5 * (1.0 - th), beta / (s_m - s_c) * (1.0 - th * th))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed001_critical_stretch_is_0_0026() {
        // Seed 001 section 6: E = 30 GPa, G_c = 110 J/m^2, dx = 0.25 mm,
        // delta = 3.015 dx gives s0 = 0.0026 (plane stress, Eq. 19).
        let s0 = critical_stretch(Plane::Stress, 30e9, 110.0, 3.015 * 0.25e-3);
        assert!((s0 - 0.0026).abs() < 0.00005, "s0 = {s0}");
    }

    #[test]
    fn degradation_derivative_matches_finite_difference() {
        let (s_m, s_c, beta) = (0.015, 0.02, 3.0);
        for &s in &[0.016, 0.0175, 0.019] {
            let h = 1e-8;
            let fd = (degradation(s + h, s_m, s_c, beta).0 - degradation(s - h, s_m, s_c, beta).0)
                / (2.0 * h);
            let an = degradation(s, s_m, s_c, beta).1;
            assert!((fd - an).abs() < 1e-5 * an.abs(), "s = {s}: {fd} vs {an}");
            assert!(an < 0.0);
        }
        assert_eq!(degradation(0.01, s_m, s_c, beta).0, 1.0);
        assert_eq!(degradation(0.03, s_m, s_c, beta).0, 0.0);
    }

    #[test]
    fn micromodulus_ratio_plane_strain_over_stress_is_16_15() {
        let a = micromodulus(Plane::Stress, 1.0, 1.0, 1.0);
        let b = micromodulus(Plane::Strain, 1.0, 1.0, 1.0);
        assert!((b / a - 16.0 / 15.0).abs() < 1e-14);
    }
}
