//! The report of `bench trade`: `report.md` (one table per case, every run against the
//! case's finest run) and the plots of path deviation and of failure-load error against
//! wall time (log-log; the reference run itself, at deviation 0, cannot be drawn on a log
//! axis and is named in the caption instead).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;

use super::{TradeReport, TradeRun, MEASURE};
use crate::plot::ticks::human;
use crate::plot::{Series, SeriesStyle, XyPlot};
use crate::scene::PlotFormat;

/// Column heads of the per-case table, in order.
pub const COLUMNS: [&str; 14] = [
    "run",
    "side (m)",
    "n",
    "dx (m)",
    "relaxation",
    "psi",
    "wall (s)",
    "iterations",
    "relocations",
    "end",
    "failure load",
    "load error",
    "reach (m)",
    "path deviation (m)",
];

fn opt(v: Option<f64>, sig: usize) -> String {
    v.map(|x| human(x, sig)).unwrap_or_else(|| "-".into())
}

/// How a run ended, in a few words.
pub fn end_state(r: &TradeRun) -> String {
    if let Some(e) = &r.error {
        return format!("error: {e}");
    }
    if let Some(why) = &r.failure_reason {
        return format!("ended early: {why}");
    }
    if r.failure {
        "failure".into()
    } else {
        format!("no failure up to load {}", opt(r.end_load, 4))
    }
}

fn row(r: &TradeRun) -> String {
    let cells = [
        r.label.clone(),
        human(r.side, 3),
        r.n.to_string(),
        human(r.dx, 3),
        r.relaxation.clone(),
        human(r.psi, 2),
        human(r.wall_time_s, 3),
        r.coupling_iterations.to_string(),
        r.relocations.to_string(),
        end_state(r),
        opt(r.failure_load, 4),
        r.failure_load_err
            .map(|e| format!("{:+.2} %", 100.0 * e))
            .unwrap_or_else(|| "-".into()),
        human(r.reach_m, 3),
        match (r.deviation_m, r.common_reach_m) {
            (Some(d), Some(c)) => format!("{} over {} m", human(d, 3), human(c, 3)),
            _ => "-".into(),
        },
    ];
    format!("| {} |", cells.join(" | "))
}

/// `report.md`: the measure, then one table per case.
pub fn markdown(r: &TradeReport) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "# Speed against accuracy of PD-BEM growth{}\n",
        if r.quick { " (quick)" } else { "" }
    );
    let _ = writeln!(
        t,
        "{} threads. Path deviation: {MEASURE}. Load error: (F - F_ref) / F_ref of the \
         failure load. Both against the case's finest run. Reach: how far the tip got from \
         its initial position.\n",
        r.threads
    );
    for c in &r.cases {
        let _ = writeln!(t, "## {} (reference: {})\n", c.case, c.reference);
        let _ = writeln!(t, "| {} |", COLUMNS.join(" | "));
        let _ = writeln!(t, "|{}", "---|".repeat(COLUMNS.len()));
        for run in &c.runs {
            let _ = writeln!(t, "{}", row(run));
        }
        let _ = writeln!(t);
    }
    t
}

/// Short case name for legends (`growth_tension_edge` -> `tension`).
fn short(case: &str) -> &str {
    case.trim_start_matches("growth_")
        .split('_')
        .next()
        .unwrap_or(case)
}

/// One marker series per case and series of variants, `value` of every run that has one.
fn series_of(r: &TradeReport, value: impl Fn(&TradeRun) -> Option<f64>) -> XyPlot {
    let mut plot = XyPlot::error_vs_time("", "", Vec::new());
    for c in &r.cases {
        let mut names: Vec<&str> = Vec::new();
        for run in &c.runs {
            if !names.contains(&run.series.as_str()) {
                names.push(&run.series);
            }
        }
        for name in names {
            let pts: Vec<(f64, f64)> = c
                .runs
                .iter()
                .filter(|x| x.series == name && x.label != c.reference)
                .filter_map(|x| Some((x.wall_time_s, value(x)?)))
                .collect();
            plot.series.push(Series::new(
                format!("{}: {name}", short(&c.case)),
                pts,
                SeriesStyle::Markers,
            ));
        }
        for run in c.runs.iter().filter(|x| x.label != c.reference) {
            if let Some(v) = value(run) {
                plot.point_labels
                    .push(((run.wall_time_s, v), run.label.clone()));
            }
        }
    }
    plot
}

/// Path deviation (m) against wall time (s).
pub fn deviation_plot(r: &TradeReport) -> XyPlot {
    let mut p = series_of(r, |x| x.deviation_m);
    p.title = format!(
        "PD-BEM path deviation from the finest run ({})",
        reference_names(r)
    );
    p.y_label = "path deviation (m)".into();
    p.x_label = "wall time (s)".into();
    p
}

/// |failure-load error| (%) against wall time (s).
pub fn failure_load_plot(r: &TradeReport) -> XyPlot {
    let mut p = series_of(r, |x| x.failure_load_err.map(|e| 100.0 * e.abs()));
    p.title = format!(
        "PD-BEM |failure-load error| against the finest run ({})",
        reference_names(r)
    );
    p.y_label = "|failure-load error| (%)".into();
    p.x_label = "wall time (s)".into();
    p
}

fn reference_names(r: &TradeReport) -> String {
    r.cases
        .iter()
        .map(|c| format!("{} {}", short(&c.case), c.reference))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Writes `trade_deviation` and, when any run has a non-zero failure-load error,
/// `trade_failure_load` (PNG and SVG).
pub fn plots(r: &TradeReport, out: &Path) -> Result<()> {
    let formats = [PlotFormat::Png, PlotFormat::Svg];
    let has = |p: &XyPlot| {
        p.series
            .iter()
            .any(|s| s.points.iter().any(|q| q.0 > 0.0 && q.1 > 0.0))
    };
    let d = deviation_plot(r);
    if has(&d) {
        crate::plot::save(&d, &out.join("trade_deviation"), &formats)?;
    }
    let f = failure_load_plot(r);
    if has(&f) {
        crate::plot::save(&f, &out.join("trade_failure_load"), &formats)?;
    }
    Ok(())
}
