//! The report of `bench trade`: `report.md` (one table per case, every run against the
//! case's finest run) and the plots of path deviation and of failure-load error against
//! wall time (log-log; the reference run itself, at deviation 0, cannot be drawn on a log
//! axis and is named in the legend instead; the failure-load error on a linear axis, where
//! an error of 0 shows).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;

use super::{CaseTrade, TradeReport, TradeRun, MEASURE};
use crate::plot::ticks::human;
use crate::plot::{Series, SeriesStyle, XyPlot};
use crate::scene::PlotFormat;

/// Column heads of the per-case table, in order.
pub const COLUMNS: [&str; 15] = [
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
    "below the first overstrain (m)",
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
        let first = why.split(';').next().unwrap_or(why);
        return format!("ended early: {first}");
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
        match r.before_overstrain {
            Some([d, c, load]) => format!(
                "{} over {} m (loads below {})",
                human(d, 3),
                human(c, 3),
                human(load, 4)
            ),
            None => "-".into(),
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
         its initial position. The runs go on past the first BEM overstrain (where a run \
         ends by default); the last column compares the paths below the first \
         overstrain load of the run and the reference, for every run that got there.\n",
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

/// One marker series per case: `value` of every run that has one except the reference.
/// Runs of one case with the same value within 1 % (the same path, or one a marker apart
/// on the log axis: the tolerance and relaxation runs at n = 20 often are) share one
/// label, in order of wall time, at the fastest of them.
fn series_of(r: &TradeReport, value: impl Fn(&TradeRun) -> Option<f64>) -> XyPlot {
    let mut plot = XyPlot::error_vs_time("", "", Vec::new());
    for c in &r.cases {
        let mut pts: Vec<(f64, f64, &str)> = c
            .runs
            .iter()
            .filter(|x| x.label != c.reference)
            .filter_map(|x| Some((x.wall_time_s, value(x)?, x.label.as_str())))
            .collect();
        pts.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
        let mut groups: Vec<((f64, f64), Vec<&str>)> = Vec::new();
        for &(t, v, label) in &pts {
            let same =
                |g: &((f64, f64), Vec<&str>)| (g.0 .1 - v).abs() <= 1e-2 * v.abs().max(1e-12);
            match groups.iter_mut().find(|g| same(g)) {
                Some(g) => g.1.push(label),
                None => groups.push(((t, v), vec![label])),
            }
        }
        plot.point_labels
            .extend(groups.into_iter().map(|(p, l)| (p, l.join(", "))));
        plot.series.push(Series::new(
            format!("{} (reference {})", short(&c.case), c.reference),
            pts.iter().map(|p| (p.0, p.1)).collect(),
            SeriesStyle::Markers,
        ));
    }
    plot
}

/// Path deviation (m) against wall time (s): over the whole paths, or for a case none of
/// whose runs has that (its reference ended early), below the first overstrain load
/// ([`TradeRun::before_overstrain`], said in the legend).
pub fn deviation_plot(r: &TradeReport) -> XyPlot {
    let whole = |c: &CaseTrade| c.runs.iter().any(|x| x.deviation_m.is_some());
    let mut p = series_of(r, |x| x.deviation_m.or(x.before_overstrain.map(|b| b[0])));
    for (c, s) in r.cases.iter().zip(p.series.iter_mut()) {
        let load = c
            .runs
            .iter()
            .find_map(|x| x.before_overstrain.map(|b| b[2]));
        if let (false, Some(load)) = (whole(c), load) {
            s.label = format!("{}, below load {}", s.label, human(load, 4));
        }
    }
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
    // Linear: an error of 0 (the failure in the reference's load step) is a result too.
    p.log_y = false;
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
    let drop_empty = |mut p: XyPlot| {
        p.series.retain(|s| !s.points.is_empty());
        p
    };
    let d = drop_empty(deviation_plot(r));
    if has(&d) {
        crate::plot::save(&d, &out.join("trade_deviation"), &formats)?;
    }
    let f = drop_empty(failure_load_plot(r));
    if has(&f) {
        crate::plot::save(&f, &out.join("trade_failure_load"), &formats)?;
    }
    Ok(())
}
