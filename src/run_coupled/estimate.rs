//! Error estimates of a static coupled solve (issue 17): every K and CMOD of a PD-BEM run
//! carries `k1_err_est`, `k2_err_est`, `cmod_err_est`, like a BEM run's.
//!
//! A static coupled scene is linear elastic with its pre-cracks (no bond breaks), so its
//! K and CMOD should be those of linear elastic fracture mechanics. The estimate compares
//! them with an independent, more accurate solution, the BEM alone on the same scene with
//! local-feature meshing and its own estimate e_BEM ([`crate::refine`]), and with the
//! path dependence of the window-tip interaction integral:
//! $$ e(q) = \max\big(|q - q_\text{BEM}| + e_\text{BEM}(q),\; |K(r_1) - K(r_2)|,\;
//!    \epsilon_0 |q|\big), $$
//! with r_1 the contour of the reported K and r_2 the smallest admissible one
//! ([`pdbem_coupling::post::WindowContour`]: 1.1 times the tip-to-corner distance), and
//! the floor $\epsilon_0$ = [`crate::refine::RESOLUTION_FLOOR`]. The first term bounds the
//! true error whenever the BEM estimate bounds the BEM's; it costs one static BEM solve
//! (two levels), about the time of the coupled solve on the seed's SENT plates.

use serde_json::json;
use std::time::Instant;

use super::CoupledOutcome;
use crate::refine::RESOLUTION_FLOOR;
use crate::runner::summary::RunSummary;
use crate::scene::Scene;
use pdbem_coupling::post::WindowContour;

/// The formula, as `summary.json` states it.
pub const METHOD: &str = "max(|q - q_BEM| + e_BEM(q), |K(r1) - K(r2)|, 2e-4 |q|)";

/// The scene without its PD and coupling sections: the BEM-alone reference.
fn bem_alone(scene: &Scene) -> anyhow::Result<Scene> {
    let mut s = scene.clone();
    s.pd = None;
    s.coupling = None;
    s.bem.tolerance = None;
    s.bem.richardson = false;
    s.validate()?;
    Ok(s)
}

/// The contour term of a windowed tip: |K(r1) - K(r2)| for (K_I, K_II), zero for tips
/// outside windows or when the smaller contour does not fit.
fn contour_term(scene: &Scene, out: &CoupledOutcome, name: &str, k: (f64, f64)) -> (f64, f64) {
    let Some(tip) = out.setup.tips.iter().find(|t| t.name == name) else {
        return (0.0, 0.0);
    };
    let d = WindowContour::default();
    let inner = WindowContour {
        radius_factor: d.min_factor,
        ..d
    };
    let boundaries = crate::setup::coupled::contour_boundaries(scene);
    match pdbem_coupling::post::window_tip_sif(
        &out.setup.problem,
        &out.solution,
        tip.window,
        tip.position,
        tip.direction,
        &boundaries,
        &inner,
    ) {
        Ok(s) => ((s.k1 - k.0).abs(), (s.k2 - k.1).abs()),
        Err(_) => (0.0, 0.0),
    }
}

/// Adds the estimates to `summary` (module docs), with `error_estimate` in its extra
/// section; when the BEM-alone reference cannot be solved, a note says so and the
/// estimates stay empty.
pub fn attach(scene: &Scene, out: &CoupledOutcome, summary: &mut RunSummary) {
    let t0 = Instant::now();
    let reference = bem_alone(scene).and_then(|s| crate::run_bem::solve(&s).map(|r| r.0));
    let reference = match reference {
        Ok(r) => r,
        Err(e) => {
            summary.notes.push(format!(
                "no error estimate for the coupled K and CMOD: the BEM-alone reference \
                 failed: {e:#}"
            ));
            return;
        }
    };
    for t in &mut summary.tips {
        let r = reference.tips.iter().find(|r| r.name == t.name);
        let Some((r, r1, r2)) = r.and_then(|r| Some((r, r.k1_err_est?, r.k2_err_est?))) else {
            t.notes.push(format!(
                "tip {}: no error estimate: the BEM-alone reference has no estimate there",
                t.name
            ));
            continue;
        };
        let floor = RESOLUTION_FLOOR * t.k1.hypot(t.k2);
        let (c1, c2) = contour_term(scene, out, &t.name, (t.k1, t.k2));
        let e1 = (t.k1 - r.k1).abs() + r1;
        let e2 = (t.k2 - r.k2).abs() + r2;
        t.k1_err_est = Some(e1.max(c1).max(floor));
        t.k2_err_est = Some(e2.max(c2).max(floor));
    }
    for c in &mut summary.cracks {
        let (Some(v), Some(r)) = (c.cmod, reference.cracks.iter().find(|r| r.name == c.name))
        else {
            continue;
        };
        let (Some(rv), Some(re)) = (r.cmod, r.cmod_err_est) else {
            continue;
        };
        c.cmod_err_est = Some(((v - rv).abs() + re).max(RESOLUTION_FLOOR * v.abs()));
    }
    summary.extra.insert(
        "error_estimate".into(),
        json!({
            "method": METHOD,
            "reference": "BEM alone, local-feature meshing",
            "reference_elements": reference.elements,
            "seconds": t0.elapsed().as_secs_f64(),
        }),
    );
}
