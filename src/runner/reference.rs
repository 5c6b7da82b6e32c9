//! Reference values and errors for a run, from the scene's `reference`
//! section (REFERENCES.md formulas in [`pdbem_bem::analytic`]).
//!
//! Errors: `k1_err = (k1 - k1_ref) / |k1_ref|`, likewise for `k2` and `cmod`;
//! when a reference value is zero (K_II of a mode-I crack) the error is taken
//! relative to |K_ref| = sqrt(k1_ref^2 + k2_ref^2). `kink_err_deg` is the
//! difference in degrees.
//!
//! A reference's `sigma` (and an infinite plate's remote stress) is at load factor 1, as the
//! boundary values are; a static run solves once at the scene's final load factor
//! ([`crate::setup::final_factor`]), so its references are at that factor
//! ([`load_factor`]); a growth run's K record scales them by each step's factor.

use serde_json::json;

use super::summary::{RunSummary, TipResult};
use crate::geometry::{polyline_length, P2};
use crate::scene::shapes::{CrackLine, SceneGeometry};
use crate::scene::{Reference, Scene};
use pdbem_bem::analytic::{inclined_crack_k, kink_angle_deg, sent_cmod, sent_f_fem, sent_k1};

/// Relative error of `value` against `reference`, scaled by `scale` when the
/// reference is (nearly) zero.
pub fn relative_error(value: f64, reference: f64, scale: f64) -> f64 {
    let s = if reference.abs() > 1e-12 * scale.abs() {
        reference.abs()
    } else {
        scale.abs()
    };
    (value - reference) / s.max(1e-300)
}

/// Reference of one tip: `(k1, k2, optional k1 from the FEM table)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipReference {
    /// K_I (Pa sqrt(m)).
    pub k1: f64,
    /// K_II (Pa sqrt(m)).
    pub k2: f64,
    /// K_I from the SENT FEM table, where it applies.
    pub k1_fem: Option<f64>,
}

/// The load factor the references of a static run are at: the scene's final one, at
/// which the static modes solve (a scene with `load: (initial: 2)` and tractions of 0.5 Pa
/// under `SentTada(sigma: 0.5)` read k1_err = +99.6 % against the unscaled table).
pub fn load_factor(scene: &Scene) -> f64 {
    crate::setup::final_factor(scene)
}

/// Reference values of every tip that has one, by tip name, at [`load_factor`].
pub fn tip_references(scene: &Scene) -> Vec<(String, TipReference)> {
    let geo = SceneGeometry::of(scene);
    let Some(crack) = geo.cracks.first() else {
        return Vec::new();
    };
    let f = load_factor(scene);
    match scene.reference {
        Some(Reference::SentTada { width, sigma }) if crack.mouth => {
            let sigma = sigma * f;
            let a = polyline_length(&crack.points);
            let k1 = sent_k1(sigma, a, width);
            let fem = sent_f_fem(a / width).map(|f| sigma * (std::f64::consts::PI * a).sqrt() * f);
            vec![(
                format!("{}.end", crack.name),
                TipReference {
                    k1,
                    k2: 0.0,
                    k1_fem: fem,
                },
            )]
        }
        Some(Reference::InclinedCrackInfinite { sigma, beta_deg }) => {
            // The remote stress, or without beta_deg the uniform stress of the loads.
            let stress = geo.remote.or_else(|| {
                beta_deg
                    .is_none()
                    .then(|| crate::setup::reference_loads::load_stress(scene))
                    .flatten()
            });
            match (stress, beta_deg) {
                (Some(s), _) => inclined_references(crack, Some(s.map(|v| v * f)), 0.0, 0.0),
                (None, Some(b)) => inclined_references(crack, None, sigma * f, b),
                (None, None) => Vec::new(),
            }
        }
        _ => Vec::new(),
    }
}

/// Inclined-crack references: from the stress tensor `remote` (an infinite plate's remote
/// stress, or the loads' uniform stress when `beta_deg` is not given; sign-consistent per
/// tip), else from sigma and beta.
fn inclined_references(
    crack: &CrackLine,
    remote: Option<[f64; 3]>,
    sigma: f64,
    beta_deg: f64,
) -> Vec<(String, TipReference)> {
    let a = 0.5 * polyline_length(&crack.points);
    let n = crack.points.len();
    let ends = [
        (
            format!("{}.start", crack.name),
            crack.points[0] - crack.points[1],
        ),
        (
            format!("{}.end", crack.name),
            crack.points[n - 1] - crack.points[n - 2],
        ),
    ];
    ends.into_iter()
        .map(|(name, dir)| {
            let (k1, k2) = match remote {
                Some(s) => tensor_k(s, dir, a),
                None => inclined_crack_k(sigma, a, beta_deg),
            };
            (
                name,
                TipReference {
                    k1,
                    k2,
                    k1_fem: None,
                },
            )
        })
        .collect()
}

/// K_I = sigma_nn sqrt(pi a), K_II = sigma_tn sqrt(pi a) for a straight crack
/// of half-length `a` in an infinite plate; t = outward tip direction, n = t
/// rotated +90 degrees.
fn tensor_k(s: [f64; 3], dir: P2, a: f64) -> (f64, f64) {
    let t = dir / dir.norm().max(1e-300);
    let n = P2::new(-t.y, t.x);
    let sig = |u: &P2, v: &P2| u.x * (s[0] * v.x + s[2] * v.y) + u.y * (s[2] * v.x + s[1] * v.y);
    let root = (std::f64::consts::PI * a).sqrt();
    (sig(&n, &n) * root, sig(&t, &n) * root)
}

/// Fills reference values and errors into a summary.
pub fn apply(scene: &Scene, summary: &mut RunSummary) {
    for (name, r) in tip_references(scene) {
        if let Some(tip) = summary.tips.iter_mut().find(|t| t.name == name) {
            fill_tip(tip, &r);
        }
    }
    apply_cmod(scene, summary);
    apply_kirsch(scene, summary);
}

fn fill_tip(tip: &mut TipResult, r: &TipReference) {
    let scale = r.k1.hypot(r.k2);
    let kink = kink_angle_deg(r.k1, r.k2);
    tip.k1_ref = Some(r.k1);
    tip.k2_ref = Some(r.k2);
    tip.kink_ref_deg = Some(kink);
    tip.k1_err = Some(relative_error(tip.k1, r.k1, scale));
    tip.k2_err = Some(relative_error(tip.k2, r.k2, scale));
    tip.kink_err_deg = Some(tip.kink_deg - kink);
    tip.k1_ref_fem = r.k1_fem;
    tip.k1_err_fem = r.k1_fem.map(|f| relative_error(tip.k1, f, scale));
}

/// SENT CMOD reference of the first crack at [`load_factor`], `(crack name, cmod)`.
pub fn cmod_reference(scene: &Scene) -> Option<(String, f64)> {
    let Some(Reference::SentTada { width, sigma }) = scene.reference else {
        return None;
    };
    let geo = SceneGeometry::of(scene);
    let crack = geo.cracks.first().filter(|c| c.mouth)?;
    let a = polyline_length(&crack.points);
    Some((
        crack.name.clone(),
        sent_cmod(
            sigma * load_factor(scene),
            a,
            width,
            scene.material.e_prime(),
        ),
    ))
}

fn apply_cmod(scene: &Scene, summary: &mut RunSummary) {
    let Some((name, reference)) = cmod_reference(scene) else {
        return;
    };
    if let Some(c) = summary.cracks.iter_mut().find(|c| c.name == name) {
        c.cmod_ref = Some(reference);
        c.cmod_err = c.cmod.map(|v| relative_error(v, reference, reference));
    }
}

/// Kirsch: `hoop_peak_ref` = 3 sigma (at [`load_factor`]), and `hoop_peak_err` when the
/// solver reported `hoop_peak` (Pa) in `extra`.
fn apply_kirsch(scene: &Scene, summary: &mut RunSummary) {
    let Some(Reference::Kirsch { sigma }) = scene.reference else {
        return;
    };
    let reference = 3.0 * sigma * load_factor(scene);
    summary
        .extra
        .insert("hoop_peak_ref".into(), json!(reference));
    if let Some(v) = summary.extra.get("hoop_peak").and_then(|v| v.as_f64()) {
        summary.extra.insert(
            "hoop_peak_err".into(),
            json!(relative_error(v, reference, reference)),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tensor_k_matches_beta_formula_at_45_degrees() {
        // Uniaxial syy = 1, crack at 45 degrees: beta = 45.
        let (k1, k2) = tensor_k([0.0, 1.0, 0.0], P2::new(1.0, 1.0), 1.0);
        let (r1, r2) = inclined_crack_k(1.0, 1.0, 45.0);
        assert!((k1 - r1).abs() < 1e-12);
        assert!((k2.abs() - r2).abs() < 1e-12);
        // Both tips give the same K_II sign.
        let (_, k2b) = tensor_k([0.0, 1.0, 0.0], P2::new(-1.0, -1.0), 1.0);
        assert!((k2 - k2b).abs() < 1e-12);
    }

    #[test]
    fn relative_error_of_zero_reference_uses_scale() {
        assert!((relative_error(0.01, 0.0, 2.0) - 0.005).abs() < 1e-15);
        assert!((relative_error(1.1, 1.0, 1.0) - 0.1).abs() < 1e-12);
    }
}
