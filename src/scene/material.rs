//! `material`: elastic constants, plane idealisation, thickness and fracture data.

use serde::{Deserialize, Serialize};

pub use pdbem_bem::analytic::PlaneKind as Plane;

/// Default out-of-plane thickness: 1 m (results per unit thickness).
pub(crate) fn default_thickness() -> f64 {
    1.0
}

/// Isotropic linear-elastic material.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E (Pa). Required; must be > 0.
    #[serde(rename = "E")]
    pub e: f64,
    /// Poisson ratio nu (-). Required; must lie in (-1, 0.5).
    pub nu: f64,
    /// `Stress` (thin plate) or `Strain`. Required.
    pub plane: Plane,
    /// Out-of-plane thickness (m). Default 1 m (results per unit thickness).
    #[serde(default = "default_thickness")]
    pub thickness: f64,
    /// Fracture data; absent = no fracture data (BEM runs need none).
    #[serde(default)]
    pub fracture: Option<Fracture>,
    /// Mass density rho (kg/m^3), > 0. Required by explicit dynamics
    /// (`pd.solver: Explicit`) only; absent otherwise.
    #[serde(default)]
    pub density: Option<f64>,
}

/// Fracture properties. Any subset may be given; `K_c` defaults to
/// sqrt(E' G_c) when only `g_c` is given.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fracture {
    /// Critical energy release rate G_c (J/m^2), >= 0. Default: absent.
    #[serde(default)]
    pub g_c: Option<f64>,
    /// Fracture toughness K_c (Pa sqrt(m)), > 0. Default: sqrt(E' G_c) if `g_c` is given.
    #[serde(default)]
    pub k_c: Option<f64>,
    /// PMB critical bond stretch s0 (-), > 0. Default: from G_c (REFERENCES.md)
    /// when the PD section asks for it.
    #[serde(default)]
    pub s0: Option<f64>,
}

impl Material {
    /// Effective modulus E' (Pa): E in plane stress, E/(1-nu^2) in plane strain.
    pub fn e_prime(&self) -> f64 {
        pdbem_bem::analytic::e_prime(self.e, self.nu, self.plane)
    }

    /// Shear modulus mu = E / (2 (1 + nu)) (Pa).
    pub fn shear_modulus(&self) -> f64 {
        pdbem_bem::analytic::shear_modulus(self.e, self.nu)
    }

    /// Fracture toughness K_c (Pa sqrt(m)): given, or sqrt(E' G_c), or `None`.
    pub fn k_c(&self) -> Option<f64> {
        let f = self.fracture.as_ref()?;
        f.k_c.or_else(|| {
            f.g_c
                .map(|g| pdbem_bem::analytic::griffith_k_c(g, self.e_prime()))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toughness_from_gc_uses_the_plane_modulus() {
        let m = Material {
            e: 30e9,
            nu: 0.25,
            plane: Plane::Strain,
            thickness: 1.0,
            fracture: Some(Fracture {
                g_c: Some(110.0),
                ..Default::default()
            }),
            density: None,
        };
        let kc = m.k_c().expect("k_c");
        assert!((kc - (30e9 / (1.0 - 0.0625) * 110.0f64).sqrt()).abs() < 1e-6 * kc);
    }
}
