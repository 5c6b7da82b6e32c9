//! The sweep's plots: K against the first parameter (with the reference curve), error
//! (true and estimated) against wall time, and for a sweep over `bem.tolerance` the
//! measured speed/accuracy trade: true error and error estimate against the tolerance
//! asked for, and wall time against it (issue 17).
//!
//! Relative errors here are against |K| = sqrt(K_I^2 + K_II^2) of the run, the measure
//! the tolerance loop uses ([`crate::refine`]); the true error is the run's `k1_err_fem`
//! where the scene's reference has the FEM table (SENT, a/W in [0.1, 0.8]), else its
//! `k1_err` ([`crate::runner::reference`]).

use crate::output::OutputWriter;
use crate::plot::{Series, SeriesStyle, XyPlot};
use crate::refine::SAFETY;
use crate::runner::reference::tip_references;
use crate::runner::report;
use crate::runner::summary::{RunSummary, TipResult};
use crate::scene::path::with_overrides;
use crate::scene::Scene;

use super::{names, x_of, SweepRow, Vary};

/// The dotted path whose sweep gets the tolerance plots.
pub const TOLERANCE_PATH: &str = "bem.tolerance";

/// Writes every plot of the sweep (none when the scene turns plots off).
pub fn write_plots(
    scene: &Scene,
    varies: &[Vary],
    rows: &[SweepRow],
    w: &OutputWriter,
) -> anyhow::Result<()> {
    if !scene.outputs.plots {
        return Ok(());
    }
    let formats = &scene.outputs.formats;
    let mut dummy = RunSummary::default();
    let k_plot = k_against_parameter(scene, &varies[0], rows);
    // Growth runs report no K in their summary: no empty axes.
    if k_plot.series.iter().any(|s| !s.points.is_empty()) {
        report::save_plot(w, "sweep_k", &k_plot, formats, &mut dummy)?;
    }
    let e_plot = error_against_time(rows);
    if e_plot.series.iter().any(|s| !s.points.is_empty()) {
        report::save_plot(w, "sweep_error_time", &e_plot, formats, &mut dummy)?;
    }
    if varies[0].path == TOLERANCE_PATH {
        let (accuracy, cost) = tolerance_plots(&varies[0], rows);
        if accuracy.series.iter().any(|s| !s.points.is_empty()) {
            report::save_plot(w, "sweep_tolerance", &accuracy, formats, &mut dummy)?;
        }
        if cost.series.iter().any(|s| !s.points.is_empty()) {
            report::save_plot(w, "sweep_tolerance_time", &cost, formats, &mut dummy)?;
        }
    }
    Ok(())
}

/// K_I (and K_II where non-zero) of every tip against the first parameter,
/// with the reference evaluated densely along that parameter.
pub fn k_against_parameter(scene: &Scene, v: &Vary, rows: &[SweepRow]) -> XyPlot {
    let (tips, _) = names(rows);
    let x_label = format!("{} {}", v.path, unit_of(&v.path));
    let mut p = XyPlot::new(
        format!("{}: K against {}", scene.name, v.path),
        x_label,
        "K (Pa m^0.5)",
    );
    for name in &tips {
        let pts = |f: &dyn Fn(&crate::runner::summary::TipResult) -> f64| -> Vec<(f64, f64)> {
            rows.iter()
                .enumerate()
                .filter_map(|(k, r)| {
                    let t = r.summary.as_ref()?.tips.iter().find(|t| &t.name == name)?;
                    Some((x_of(&r.params[0], k), f(t)))
                })
                .collect()
        };
        p.series.push(Series::new(
            format!("{name} K_I"),
            pts(&|t| t.k1),
            SeriesStyle::LineMarkers,
        ));
        let k2 = pts(&|t| t.k2);
        if k2.iter().any(|q| q.1.abs() > 1e-12 * q.1.abs().max(1.0)) {
            p.series.push(Series::new(
                format!("{name} K_II"),
                k2,
                SeriesStyle::LineMarkers,
            ));
        }
    }
    p.series.extend(reference_curves(scene, v));
    p
}

/// Unit of a scene field for axis labels, from its last path segment.
pub fn unit_of(path: &str) -> &'static str {
    let last = path.rsplit('.').next().unwrap_or("");
    match last {
        "length" | "element_size" | "width" | "height" | "radius" | "x0" | "y0" | "dx" | "side"
        | "move_distance" | "da" | "thickness" | "faces" | "Gap" => "(m)",
        "angle_deg" | "beta_deg" => "(deg)",
        "sigma" | "E" | "sxx" | "syy" | "sxy" => "(Pa)",
        _ => "(-)",
    }
}

/// Reference K along the first parameter, sampled at 60 points between its
/// smallest and largest numeric value (other parameters at their scene values).
fn reference_curves(scene: &Scene, v: &Vary) -> Vec<Series> {
    let xs: Vec<f64> = v.values.iter().filter_map(|x| x.as_f64()).collect();
    if xs.len() < v.values.len() || xs.is_empty() {
        return Vec::new();
    }
    let (lo, hi) = xs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(*x), b.max(*x))
        });
    let n = if hi > lo { 60 } else { 1 };
    let mut k1: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for i in 0..n {
        let x = if n == 1 {
            lo
        } else {
            lo + (hi - lo) * i as f64 / (n - 1) as f64
        };
        let Ok(s) = with_overrides(scene, &[(v.path.clone(), serde_json::json!(x))]) else {
            continue;
        };
        for (name, r) in tip_references(&s) {
            match k1.iter_mut().find(|(n2, _)| *n2 == name) {
                Some((_, pts)) => pts.push((x, r.k1)),
                None => k1.push((name, vec![(x, r.k1)])),
            }
        }
    }
    k1.into_iter()
        .take(1)
        .map(|(name, pts)| Series::new(format!("{name} K_I reference"), pts, SeriesStyle::Line))
        .collect()
}

/// |relative K_I error| of each tip (and |CMOD error|) against wall time, log-log.
pub fn error_against_time(rows: &[SweepRow]) -> XyPlot {
    let (tips, cracks) = names(rows);
    let mut series = Vec::new();
    for name in &tips {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| {
                let s = r.summary.as_ref()?;
                let t = s.tips.iter().find(|t| &t.name == name)?;
                let e = t.k1_err_fem.or(t.k1_err)?;
                Some((s.wall_time_s, e.abs()))
            })
            .collect();
        series.push(Series::new(
            format!("{name} |K_I error|"),
            pts,
            SeriesStyle::Markers,
        ));
        let est = tip_points(rows, name, |s, t| {
            Some((s.wall_time_s, relative_estimate(t)?))
        });
        if !est.is_empty() {
            series.push(Series::new(
                format!("{name} K estimate"),
                est,
                SeriesStyle::Markers,
            ));
        }
    }
    for name in &cracks {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| {
                let s = r.summary.as_ref()?;
                let e = s.cracks.iter().find(|c| &c.name == name)?.cmod_err?;
                Some((s.wall_time_s, e.abs()))
            })
            .collect();
        series.push(Series::new(
            format!("{name} |CMOD error|"),
            pts,
            SeriesStyle::Markers,
        ));
    }
    let mut p = XyPlot::error_vs_time("error against wall time", "relative error (-)", series);
    p.point_labels = point_labels(rows);
    p
}

/// Each successful run's parameter values at its K_I error point (the first tip's).
fn point_labels(rows: &[SweepRow]) -> Vec<((f64, f64), String)> {
    rows.iter()
        .filter_map(|r| {
            let s = r.summary.as_ref()?;
            let t = s.tips.first()?;
            let e = t.k1_err_fem.or(t.k1_err)?;
            Some(((s.wall_time_s, e.abs()), r.params.join(", ")))
        })
        .collect()
}

/// Points of one tip over the successful rows.
fn tip_points(
    rows: &[SweepRow],
    name: &str,
    f: impl Fn(&RunSummary, &TipResult) -> Option<(f64, f64)>,
) -> Vec<(f64, f64)> {
    rows.iter()
        .filter_map(|r| {
            let s = r.summary.as_ref()?;
            f(s, s.tips.iter().find(|t| t.name == name)?)
        })
        .collect()
}

/// The error estimate of a tip, max(e(K_I), e(K_II)) relative to its |K| (what
/// `bem.tolerance` bounds).
pub fn relative_estimate(t: &TipResult) -> Option<f64> {
    let e = t.k1_err_est?.max(t.k2_err_est.unwrap_or(0.0));
    let k = t.k1.hypot(t.k2);
    (k > 0.0 && e.is_finite()).then_some(e / k)
}

/// Whether a run met its `bem.tolerance` (`error_estimate.reached` of its summary).
fn tolerance_reached(s: &RunSummary) -> bool {
    s.extra
        .get("error_estimate")
        .and_then(|e| e.get("reached"))
        .and_then(|r| r.as_bool())
        .unwrap_or(false)
}

/// For a sweep over `bem.tolerance`: (true error and estimate against the tolerance,
/// with the line error = tolerance; wall time and elements against the tolerance).
pub fn tolerance_plots(v: &Vary, rows: &[SweepRow]) -> (XyPlot, XyPlot) {
    let (tips, _) = names(rows);
    let tol_of = |r: &SweepRow, k: usize| x_of(&r.params[0], k);
    let mut accuracy = XyPlot::new(
        "K error against the tolerance asked for",
        "bem.tolerance (-)",
        "relative error of K (-)",
    );
    accuracy.log_x = true;
    accuracy.log_y = true;
    let mut cost = XyPlot::new(
        "cost of the tolerance",
        "bem.tolerance (-)",
        "wall time (s)",
    );
    cost.log_x = true;
    cost.log_y = true;
    for name in &tips {
        let on_tol = |f: &dyn Fn(&RunSummary, &TipResult) -> Option<f64>| -> Vec<(f64, f64)> {
            rows.iter()
                .enumerate()
                .filter_map(|(k, r)| {
                    let s = r.summary.as_ref()?;
                    let t = s.tips.iter().find(|t| &t.name == name)?;
                    Some((tol_of(r, k), f(s, t)?))
                })
                .collect()
        };
        let truth = on_tol(&|_, t| t.k1_err_fem.or(t.k1_err).map(f64::abs));
        if !truth.is_empty() {
            accuracy.series.push(Series::new(
                format!("{name} true |K_I error|"),
                truth,
                SeriesStyle::LineMarkers,
            ));
        }
        let estimate_if = |want: bool| {
            on_tol(&move |s, t| {
                (tolerance_reached(s) == want)
                    .then(|| relative_estimate(t))
                    .flatten()
            })
        };
        accuracy.series.push(Series::new(
            format!("{name} error estimate"),
            estimate_if(true),
            SeriesStyle::LineMarkers,
        ));
        let missed = estimate_if(false);
        if !missed.is_empty() {
            accuracy.series.push(Series::new(
                format!("{name} estimate, tolerance not reached"),
                missed,
                SeriesStyle::Markers,
            ));
        }
    }
    let tols: Vec<f64> = v.values.iter().filter_map(|x| x.as_f64()).collect();
    if let (Some(lo), Some(hi)) = (
        tols.iter().copied().reduce(f64::min),
        tols.iter().copied().reduce(f64::max),
    ) {
        accuracy.series.push(Series::new(
            "error = tolerance",
            vec![(lo, lo), (hi, hi)],
            SeriesStyle::Line,
        ));
        accuracy.series.push(Series::new(
            format!("estimate = tolerance / {SAFETY}"),
            vec![(lo, lo / SAFETY), (hi, hi / SAFETY)],
            SeriesStyle::Line,
        ));
    }
    let times: Vec<(f64, f64)> = rows
        .iter()
        .enumerate()
        .filter_map(|(k, r)| Some((tol_of(r, k), r.summary.as_ref()?.wall_time_s)))
        .collect();
    cost.series
        .push(Series::new("wall time", times, SeriesStyle::LineMarkers));
    (accuracy, cost)
}
