//! Rules of `material`.

use super::Checker;
use crate::scene::Scene;

/// E > 0, nu in (-1, 0.5), thickness > 0, density > 0 if given, fracture data
/// non-negative.
pub fn check(c: &mut Checker, scene: &Scene) {
    let m = &scene.material;
    c.positive("material.E", m.e, "Young's modulus");
    if c.finite("material.nu", m.nu) && !(m.nu > -1.0 && m.nu < 0.5) {
        c.fail("material.nu", m.nu, "Poisson ratio must lie in (-1, 0.5)");
    }
    c.positive("material.thickness", m.thickness, "thickness");
    if let Some(rho) = m.density {
        c.positive("material.density", rho, "mass density");
    }
    let Some(f) = &m.fracture else { return };
    if let Some(g) = f.g_c {
        if c.finite("material.fracture.g_c", g) && g < 0.0 {
            c.fail(
                "material.fracture.g_c",
                g,
                "critical energy release rate G_c must not be negative",
            );
        }
    }
    if let Some(k) = f.k_c {
        c.positive("material.fracture.k_c", k, "fracture toughness K_c");
    }
    if let Some(s) = f.s0 {
        c.positive("material.fracture.s0", s, "critical stretch s0");
    }
}
