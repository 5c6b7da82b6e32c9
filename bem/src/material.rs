//! Isotropic linear elastic material and the constants the Kelvin kernels need.
//!
//! The kernels are written in plane-strain form. Plane stress uses the effective Poisson
//! ratio $\nu' = \nu/(1+\nu)$ with the shear modulus $\mu = E/(2(1+\nu))$ unchanged
//! (DESIGN.md, conventions). With that substitution $E' = 2\mu/(1-\nu_{\rm eff})$ equals
//! $E$ in plane stress and $E/(1-\nu^2)$ in plane strain, and $\kappa = 3 - 4\nu_{\rm eff}$.

use crate::BemError;
use serde::{Deserialize, Serialize};

/// Plane stress or plane strain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Plane {
    /// Thin plate: sigma_zz = 0.
    Stress,
    /// Long body: eps_zz = 0.
    Strain,
}

/// Isotropic elastic material (SI units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub e: f64,
    /// Poisson ratio nu.
    pub nu: f64,
    /// Plane stress or plane strain.
    pub plane: Plane,
}

impl Material {
    /// A checked material: E > 0 and -1 < nu < 0.5.
    pub fn new(e: f64, nu: f64, plane: Plane) -> Result<Self, BemError> {
        if !(e.is_finite() && e > 0.0) {
            return Err(BemError::Material {
                field: "e",
                value: e,
                reason: "Young's modulus must be positive",
            });
        }
        if !(nu > -1.0 && nu < 0.5) {
            return Err(BemError::Material {
                field: "nu",
                value: nu,
                reason: "Poisson ratio must lie in (-1, 0.5)",
            });
        }
        Ok(Self { e, nu, plane })
    }

    /// Shear modulus mu = E / (2 (1 + nu)).
    pub fn mu(&self) -> f64 {
        self.e / (2.0 * (1.0 + self.nu))
    }

    /// Poisson ratio used in the plane-strain kernels.
    pub fn nu_eff(&self) -> f64 {
        match self.plane {
            Plane::Strain => self.nu,
            Plane::Stress => self.nu / (1.0 + self.nu),
        }
    }

    /// E' = E (plane stress) or E / (1 - nu^2) (plane strain).
    pub fn e_prime(&self) -> f64 {
        2.0 * self.mu() / (1.0 - self.nu_eff())
    }

    /// Kolosov constant kappa = 3 - 4 nu_eff.
    pub fn kappa(&self) -> f64 {
        3.0 - 4.0 * self.nu_eff()
    }

    /// Plane-strain form compliance: strain [exx, eyy, exy] from stress [sxx, syy, sxy].
    pub fn strain_from_stress(&self, s: [f64; 3]) -> [f64; 3] {
        let (mu, nu) = (self.mu(), self.nu_eff());
        let tr = s[0] + s[1];
        [
            (s[0] - nu * tr) / (2.0 * mu),
            (s[1] - nu * tr) / (2.0 * mu),
            s[2] / (2.0 * mu),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_stress_effective_constants() {
        let m = Material::new(1e4, 1.0 / 3.0, Plane::Stress).unwrap();
        assert!((m.e_prime() - 1e4).abs() < 1e-9);
        assert!((m.kappa() - (3.0 - 1.0 / 3.0) / (1.0 + 1.0 / 3.0)).abs() < 1e-12);
        let s = Material::new(1e4, 0.25, Plane::Strain).unwrap();
        assert!((s.e_prime() - 1e4 / (1.0 - 0.0625)).abs() < 1e-8);
    }

    #[test]
    fn rejects_bad_constants() {
        assert!(Material::new(-1.0, 0.3, Plane::Stress).is_err());
        assert!(Material::new(1.0, 0.5, Plane::Stress).is_err());
        assert!(Material::new(1.0, -1.0, Plane::Strain).is_err());
    }
}
