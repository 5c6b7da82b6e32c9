//! Plausibility review of a run's results (issue 17): a result is either right within
//! the error it reports or comes with a note that says why not. [`review`] runs on every
//! summary before the reference values are added, and:
//!
//! 1. moves the tips' own notes ([`TipResult::notes`]) into `notes`;
//! 2. (a crack-opening fit with too few stations for a K is not reviewed here: it is
//!    refused before the run, [`crate::setup::fit_stations`]);
//! 3. notes crack faces that overlap: the linear solution has no contact, so
//!    $K_I < 0$ or CMOD $< 0$ is not physical ([`OVERLAP_TOLERANCE`]);
//! 4. notes tips where the crack-opening fit and the interaction integral disagree,
//!    $\sqrt{(K_I^{cod} - K_I^{J})^2 + (K_{II}^{cod} - K_{II}^{J})^2} >
//!    \epsilon\,K_{eq}$ with $K_{eq} = \max(\sqrt{K_I^2 + K_{II}^2})$ over the two
//!    estimates and $\epsilon$ = [`COD_J_DISAGREEMENT`];
//! 5. notes a BEM condition estimate above [`CONDITION_LIMIT`], and cracks whose flank
//!    runs along a thin ligament the BEM does not resolve
//!    ([`crate::setup::thin_ligament`]), tips close to another boundary
//!    ([`crate::setup::close_tips`]) and holes nearer another loop than the elements at
//!    the gap ([`crate::setup::close_holes`]), and a stand-alone PD body with cracks or
//!    holes only a few horizons across ([`crate::setup::horizon_scale`]), and a static
//!    solution that opens a crack by more than [`LARGE_OPENING`] of its length or moves a
//!    held body's boundary by more than [`LARGE_DISPLACEMENT`] of its size;
//! 6. sets every tip's energy release rate $G = (K_I^2 + K_{II}^2) / E'$ from its
//!    reported K and notes a tip whose contour J-integral (computed from the solved
//!    field alone) differs from it by more than [`J_G_DISAGREEMENT`] of G: in linear
//!    elastic fracture mechanics $J = G$ on any contour around the tip;
//! 7. puts the scene's own notes first ([`Scene::notes`]: fields no solver reads, e.g.
//!    a Poisson ratio the bond-based PD model cannot take), so `summary.json` keeps them
//!    and not only the terminal.

use super::summary::{RunSummary, TipResult};
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// Largest relative disagreement between the crack-opening and the interaction-integral
/// SIFs (as a fraction of K_eq) that passes without a note. Measured on every BEM-only
/// case of `cases/` and on the static BEM solve of every coupled and growth case (their
/// windows and growth removed): at most 0.57 % (`growth_colinear_edge_cracks`; SENT
/// cases 0.007 to 0.03 %, inclined cracks 0.04 to 0.5 %). The same scenes with elements
/// twice as long reach 4.6 to 5.3 % on the central and inclined cracks, where the
/// interaction integral has moved by up to 4 % from its fine value: 2 % separates the two.
pub const COD_J_DISAGREEMENT: f64 = 0.02;

/// Largest relative difference |J - G| / G between the contour J-integral and the energy
/// release rate of the reported K that passes without a note. G is quadratic in K, so the
/// 2 % of [`COD_J_DISAGREEMENT`] between two K estimates is about 4 % in G. Measured on
/// the BEM-only cases of `cases/`: at most 0.57 % (`sent_bem_a8`).
pub const J_G_DISAGREEMENT: f64 = 0.04;

/// Largest 1-norm condition estimate of the scaled BEM system that passes without a
/// note. Measured on every case of `cases/` solved by the BEM alone: 11 (Kirsch hole) to
/// 4.9e6 (`sent_bem_a8`, 1844 elements), growing about as N^1.7 with the element count N;
/// a wrong-signed hypersingular weight shows as a jump of two to three orders
/// (REFERENCES.md). At 1e10 rounding can cost 2e-6 of the solution (cond times the
/// machine epsilon): far above every sound case and still harmless in itself, so a note
/// means something is nearly singular.
pub const CONDITION_LIMIT: f64 = 1e10;

/// K_I or CMOD below minus this fraction of its scale (K_eq of the tip; for CMOD,
/// K_eq sqrt(crack length) / E' over the crack's tips) counts as overlapping faces.
/// Symmetric pure-shear meshes give K_I and CMOD of 1e-14 of their scale; any physical
/// overlap is far larger.
pub const OVERLAP_TOLERANCE: f64 = 1e-6;

/// A static BEM or coupled solution whose CMOD exceeds this fraction of its crack's
/// length (faces turned by about a tenth of a radian) gets a note: the linear,
/// small-displacement solution no longer describes such a body. An edge crack at 2
/// degrees to its edge (a flap 3 m long and at most 0.1 m thick on a 20 m x 10 m plate
/// pulled by 1 Pa, E = 1e4 Pa) read a CMOD of 138 m with an estimate of 147 m and no
/// note; the shipped static cases reach 0.008 (`sent_bem_a8`).
pub const LARGE_OPENING: f64 = 0.1;

/// The same for the mean displacement of a boundary group of a body held by displacement
/// conditions, as a fraction of the body's size (a mean strain of 1 %).
pub const LARGE_DISPLACEMENT: f64 = 1e-2;

/// Adds the plausibility notes of `summary` (see the module docs).
pub fn review(scene: &Scene, summary: &mut RunSummary) {
    let mut notes = Vec::new();
    for t in &mut summary.tips {
        notes.append(&mut t.notes);
    }
    notes.extend(summary.tips.iter().filter_map(tip_overlap));
    notes.extend(crack_overlap(scene, summary));
    notes.extend(
        summary
            .tips
            .iter()
            .filter(|t| !one_face_loaded(scene, &t.name))
            .filter_map(disagreement),
    );
    notes.extend(condition(summary));
    notes.extend(thin_ligaments(scene));
    notes.extend(close_tips(scene));
    notes.extend(close_holes(scene));
    notes.extend(outline_necks(scene));
    notes.extend(crate::setup::horizon_scale::note(scene));
    notes.extend(large_displacements(scene, summary));
    let e_prime = scene.material.e_prime();
    for t in &mut summary.tips {
        t.g = Some(pdbem_coupling::growth::history::energy_release(
            t.k1, t.k2, e_prime,
        ));
    }
    notes.extend(summary.tips.iter().filter_map(j_against_g));
    summary.notes.extend(notes);
    let scene_notes = scene.notes.iter().map(|n| format!("scene: {n}"));
    summary.notes.splice(0..0, scene_notes);
}

/// The notes of cracks along a thin ligament, in every mode whose K and CMOD come from
/// the BEM ([`crate::setup::thin_ligament`]).
pub fn thin_ligaments(scene: &Scene) -> Vec<String> {
    if matches!(super::mode::mode_of(scene), super::mode::Mode::Pd) {
        return Vec::new();
    }
    let ligaments = crate::setup::thin_ligament::of_scene(scene);
    crate::setup::thin_ligament::grouped_notes(scene, &ligaments)
}

/// The notes of tips within [`crate::setup::close_tips::CLOSE_FEATURE_RATIO`] of the body's
/// size of another boundary, in every mode whose K comes from the BEM.
pub fn close_tips(scene: &Scene) -> Vec<String> {
    if matches!(super::mode::mode_of(scene), super::mode::Mode::Pd) {
        return Vec::new();
    }
    crate::setup::close_tips::close_tip_notes(scene)
}

/// The notes of holes nearer the outline or another hole than the elements at the gap
/// ([`crate::setup::close_holes`]), in every mode whose fields come from the BEM.
pub fn close_holes(scene: &Scene) -> Vec<String> {
    if matches!(super::mode::mode_of(scene), super::mode::Mode::Pd) {
        return Vec::new();
    }
    let gaps = crate::setup::close_holes::unresolved(scene);
    gaps.iter()
        .map(|g| crate::setup::close_holes::note(scene, g))
        .collect()
}

/// The notes of necks of a boundary loop narrower than the elements there
/// ([`crate::setup::outline_necks`]), in every mode whose fields come from the BEM.
pub fn outline_necks(scene: &Scene) -> Vec<String> {
    if matches!(super::mode::mode_of(scene), super::mode::Mode::Pd) {
        return Vec::new();
    }
    crate::setup::outline_necks::unresolved(scene)
        .iter()
        .map(crate::setup::outline_necks::note)
        .collect()
}

/// K_eq = sqrt(K_I^2 + K_II^2).
fn k_eq(k1: f64, k2: f64) -> f64 {
    k1.hypot(k2)
}

/// The note of a tip with K_I < 0.
fn tip_overlap(t: &TipResult) -> Option<String> {
    // The scale is the larger of the two extractions' K_eq: a K_I of round-off size
    // (-1e-15 next to an integral of 1) is not an overlap.
    let j = k_eq(t.k1_j.unwrap_or(0.0), t.k2_j.unwrap_or(0.0));
    let scale = k_eq(t.k1, t.k2).max(if j.is_finite() { j } else { 0.0 });
    (t.k1 < -OVERLAP_TOLERANCE * scale).then(|| {
        format!(
            "tip {}: K_I = {:.6e} Pa m^0.5 < 0: crack faces overlap: the linear solution has \
             no contact; K_I < 0 is not a physical SIF (the faces would close and carry load)",
            t.name, t.k1
        )
    })
}

/// The notes of cracks with a negative CMOD.
fn crack_overlap(scene: &Scene, summary: &RunSummary) -> Vec<String> {
    let geo = SceneGeometry::of(scene);
    let e_prime = pdbem_bem::analytic::e_prime(
        scene.material.e,
        scene.material.nu,
        match scene.material.plane {
            crate::scene::Plane::Stress => pdbem_bem::analytic::PlaneKind::Stress,
            crate::scene::Plane::Strain => pdbem_bem::analytic::PlaneKind::Strain,
        },
    );
    let mut out = Vec::new();
    for c in &summary.cracks {
        let Some(cmod) = c.cmod.filter(|v| *v < 0.0) else {
            continue;
        };
        let length = geo
            .cracks
            .iter()
            .find(|g| g.name == c.name)
            .map_or(0.0, |g| crate::geometry::polyline_length(&g.points));
        let k = summary
            .tips
            .iter()
            .filter(|t| t.name.rsplit_once('.').is_some_and(|(n, _)| n == c.name))
            .map(|t| k_eq(t.k1, t.k2))
            .fold(0.0, f64::max);
        let scale = k * length.sqrt() / e_prime;
        if cmod < -OVERLAP_TOLERANCE * scale {
            out.push(format!(
                "crack {}: CMOD = {cmod:.6e} m < 0: crack faces overlap: the linear solution \
                 has no contact, a negative opening is not physical",
                c.name
            ));
        }
    }
    out
}

/// The notes of CMODs over [`LARGE_OPENING`] of their crack's length and boundary
/// displacements over [`LARGE_DISPLACEMENT`] of the body's size, in static BEM and
/// coupled runs (a growth run's last geometry may be cut through, which its verdict says).
fn large_displacements(scene: &Scene, summary: &RunSummary) -> Vec<String> {
    use super::mode::{mode_of, Mode};
    if !matches!(mode_of(scene), Mode::Bem | Mode::Coupled) {
        return Vec::new();
    }
    let geo = SceneGeometry::of(scene);
    let text = |what: String, v: f64, of: &str, scale: f64, limit: f64| {
        format!(
            "{what} is {v:.4e} m, {:.2e} of {of} {scale:.4e} m (a note over {limit:.0e}): the \
             linear, small-displacement solution no longer describes the body there (a thin \
             flap bent far, a load too large for E, or a body held too little); its K and CMOD \
             are those of linear theory only",
            v / scale
        )
    };
    let mut out = Vec::new();
    for c in &summary.cracks {
        let (Some(cmod), Some(g)) = (c.cmod, geo.cracks.iter().find(|g| g.name == c.name)) else {
            continue;
        };
        let length = crate::geometry::polyline_length(&g.points);
        if cmod.abs() > LARGE_OPENING * length {
            let what = format!("crack {}: CMOD", c.name);
            out.push(text(what, cmod.abs(), "its length", length, LARGE_OPENING));
        }
    }
    let size = crate::setup::sizing::geometry_extent(&geo);
    let limit = LARGE_DISPLACEMENT * size;
    // A body held by tractions alone moves by the rigid motion the solver fixed: only
    // a body held by displacement conditions has group displacements to judge.
    let held = scene.boundary.iter().any(|b| {
        [b.x, b.y]
            .iter()
            .any(|c| matches!(c, crate::scene::Component::Displacement(_)))
    });
    let groups = summary
        .extra
        .get("load_displacement")
        .and_then(|l| l["groups"].as_array())
        .filter(|_| held);
    for g in groups.into_iter().flatten() {
        let u = &g["displacement"];
        let (ux, uy) = (u[0].as_f64().unwrap_or(0.0), u[1].as_f64().unwrap_or(0.0));
        if ux.hypot(uy) > limit {
            let name = g["group"].as_str().unwrap_or("?");
            let what = format!("boundary group '{name}': its displacement");
            out.push(text(
                what,
                ux.hypot(uy),
                "the body's size",
                size,
                LARGE_DISPLACEMENT,
            ));
        }
    }
    out
}

/// The note of a tip whose contour J differs from G of its K by more than
/// [`J_G_DISAGREEMENT`] of G.
fn j_against_g(t: &TipResult) -> Option<String> {
    let (j, g) = (t.j?, t.g?);
    let diff = (j - g).abs();
    (diff > J_G_DISAGREEMENT * g.abs()).then(|| {
        format!(
            "tip {}: the contour J-integral ({j:.6e} J/m^2) and G = (K_I^2 + K_II^2) / E' of \
             the reported K ({g:.6e} J/m^2) differ by {:.2} % of G, more than {:.0} %: the \
             contour field is not resolved (refine the crack mesh or move the contour, \
             bem.j_contour, off other boundaries), or the contour holds damage besides the \
             tip's crack (a PD window that broke bonds, which a note names)",
            t.name,
            100.0 * diff / g.abs().max(f64::MIN_POSITIVE),
            100.0 * J_G_DISAGREEMENT
        )
    })
}

/// The note of a tip whose two SIF estimates disagree by more than
/// [`COD_J_DISAGREEMENT`] of K_eq.
fn disagreement(t: &TipResult) -> Option<String> {
    let (k1c, k2c, k1j, k2j) = (t.k1_cod?, t.k2_cod?, t.k1_j?, t.k2_j?);
    let scale = k_eq(k1c, k2c).max(k_eq(k1j, k2j));
    let diff = (k1c - k1j).hypot(k2c - k2j);
    (diff > COD_J_DISAGREEMENT * scale).then(|| {
        format!(
            "tip {}: the crack-opening fit (K_I {k1c:.6e}, K_II {k2c:.6e}) and the interaction \
             integral (K_I {k1j:.6e}, K_II {k2j:.6e} Pa m^0.5) differ by {:.2} % of K_eq, more \
             than {:.0} %: the SIF is not resolved; refine the crack mesh or move the contour \
             (bem.j_contour) off other boundaries",
            t.name,
            100.0 * diff / scale,
            100.0 * COD_J_DISAGREEMENT
        )
    })
}

/// Whether the crack of tip `tip` (`<crack>.end` / `.start`) has a condition on one of
/// its faces alone: its K is the interaction integral's and the tip's own note says why
/// the fit differs ([`crate::run_bem::level::tip_result`]).
fn one_face_loaded(scene: &Scene, tip: &str) -> bool {
    let crack = tip.rsplit_once('.').map_or(tip, |(c, _)| c);
    crate::setup::bem::loaded_on_one_face(scene, crack)
}

/// The note of a condition estimate above [`CONDITION_LIMIT`].
fn condition(summary: &RunSummary) -> Option<String> {
    let c = summary.extra.get("condition_estimate")?.as_f64()?;
    (c > CONDITION_LIMIT).then(|| {
        format!(
            "BEM condition estimate {c:.3e} exceeds {CONDITION_LIMIT:.0e}: the system is \
             nearly singular (rounding may cost {:.1e} of the solution); look for elements \
             much smaller than their neighbours, nearly touching boundaries or a support that \
             barely holds the body",
            c * f64::EPSILON
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tip(k1c: f64, k1j: f64) -> TipResult {
        TipResult {
            name: "c.end".into(),
            k1: k1c,
            k1_cod: Some(k1c),
            k2_cod: Some(0.0),
            k1_j: Some(k1j),
            k2_j: Some(0.0),
            ..Default::default()
        }
    }

    #[test]
    fn disagreement_notes_only_above_the_threshold() {
        assert!(disagreement(&tip(1.0, 1.0 + 0.5 * COD_J_DISAGREEMENT)).is_none());
        let n = disagreement(&tip(1.0, 1.0 + 2.0 * COD_J_DISAGREEMENT)).unwrap();
        assert!(n.contains("c.end") && n.contains("1.000000e0") && n.contains("1.040000e0"));
        assert!(n.contains("refine the crack mesh"));
    }

    #[test]
    fn negative_k1_is_an_overlap() {
        assert!(tip_overlap(&tip(1.0, 1.0)).is_none());
        assert!(tip_overlap(&tip(-1e-15, 1.0)).is_none());
        let n = tip_overlap(&tip(-2.0, -2.0)).unwrap();
        assert!(n.contains("c.end") && n.contains("-2.000000e0") && n.contains("overlap"));
    }

    #[test]
    fn a_large_condition_estimate_is_noted() {
        let mut s = RunSummary::default();
        s.extra
            .insert("condition_estimate".into(), serde_json::json!(1e6));
        assert!(condition(&s).is_none());
        s.extra.insert(
            "condition_estimate".into(),
            serde_json::json!(10.0 * CONDITION_LIMIT),
        );
        assert!(condition(&s).unwrap().contains("1.000e11"));
    }
}
