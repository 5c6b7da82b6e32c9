//! `pdbem sweep`: run a scene for every combination of `--vary FIELD=v1,v2,...`
//! values (a grid when several are given), one CSV row per run, and plots of K
//! against the first parameter (with the analytic curve where the scene has a
//! reference) and of error against wall time.
//!
//! Each run writes its own folder `<out>/run_<k>/` all-or-nothing; a failed or
//! invalid combination becomes a row with an `error` and the sweep goes on. A
//! path that does not exist in the scene stops the sweep before any run.
//! Outputs: `<out>/sweep.csv`, `<out>/sweep_k.{png,svg}`, `<out>/sweep_error_time.{png,svg}`.

use std::path::Path;

use anyhow::Context;
use serde_json::Value;

use crate::output::csv::{num, opt};
use crate::output::{CsvTable, OutputWriter};
use crate::plot::{Series, SeriesStyle, XyPlot};
use crate::runner::reference::tip_references;
use crate::runner::summary::RunSummary;
use crate::runner::{report, run_scene};
use crate::scene::path::{parse_value, with_overrides};
use crate::scene::{Scene, SceneError};

/// One `--vary FIELD=v1,v2,...`.
#[derive(Debug, Clone, PartialEq)]
pub struct Vary {
    /// Dotted path into the scene.
    pub path: String,
    /// Values as typed.
    pub raw: Vec<String>,
    /// Values parsed (JSON / RON tuple / bare string).
    pub values: Vec<Value>,
}

/// Parses `FIELD=v1,v2,...` (commas inside `()` or `[]` do not split).
pub fn parse_vary(text: &str) -> Result<Vary, String> {
    let (path, list) = text
        .split_once('=')
        .ok_or_else(|| format!("--vary {text}: expected FIELD=v1,v2,..."))?;
    let path = path.trim().to_string();
    if path.is_empty() {
        return Err(format!("--vary {text}: the field path is empty"));
    }
    let raw = split_top_level(list);
    if raw.iter().any(|v| v.is_empty()) {
        return Err(format!("--vary {text}: empty value in the list"));
    }
    let values = raw.iter().map(|v| parse_value(v)).collect();
    Ok(Vary { path, raw, values })
}

/// Splits on commas outside brackets and parentheses.
fn split_top_level(list: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut depth = 0i32;
    let mut cur = String::new();
    for ch in list.chars() {
        match ch {
            '(' | '[' => depth += 1,
            ')' | ']' => depth -= 1,
            ',' if depth == 0 => {
                out.push(cur.trim().to_string());
                cur.clear();
                continue;
            }
            _ => {}
        }
        cur.push(ch);
    }
    out.push(cur.trim().to_string());
    out
}

/// Every combination (first parameter varies slowest), as value indices.
pub fn grid(varies: &[Vary]) -> Vec<Vec<usize>> {
    let mut combos: Vec<Vec<usize>> = vec![Vec::new()];
    for v in varies {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                (0..v.values.len()).map(move |i| {
                    let mut c = c.clone();
                    c.push(i);
                    c
                })
            })
            .collect();
    }
    combos
}

/// Overrides of one combination.
fn overrides(varies: &[Vary], combo: &[usize]) -> Vec<(String, Value)> {
    varies
        .iter()
        .zip(combo)
        .map(|(v, i)| (v.path.clone(), v.values[*i].clone()))
        .collect()
}

/// One row of the sweep.
#[derive(Debug, Clone)]
pub struct SweepRow {
    /// Values as typed, one per `--vary`.
    pub params: Vec<String>,
    /// The run's summary when it succeeded.
    pub summary: Option<RunSummary>,
    /// Why the run failed.
    pub error: Option<String>,
}

/// Runs the sweep; returns the rows (also written to `<out>/sweep.csv`).
pub fn run_sweep(
    scene: &Scene,
    varies: &[Vary],
    out_dir: &Path,
    quiet: bool,
) -> anyhow::Result<Vec<SweepRow>> {
    if varies.is_empty() {
        anyhow::bail!("sweep needs at least one --vary FIELD=v1,v2,...");
    }
    check_paths(scene, varies)?;
    let combos = grid(varies);
    let writer = OutputWriter::create_run(out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let bar = crate::runner::context::progress_bar(combos.len() as u64, quiet);
    let mut rows = Vec::new();
    for (k, combo) in combos.iter().enumerate() {
        let params: Vec<String> = varies
            .iter()
            .zip(combo)
            .map(|(v, i)| v.raw[*i].clone())
            .collect();
        let run_dir = out_dir.join(format!("run_{k:03}"));
        let result = with_overrides(scene, &overrides(varies, combo))
            .map_err(anyhow::Error::from)
            .and_then(|s| run_scene(&s, &run_dir, true));
        rows.push(match result {
            Ok(s) => SweepRow {
                params,
                summary: Some(s),
                error: None,
            },
            Err(e) => SweepRow {
                params,
                summary: None,
                error: Some(format!("{e:#}")),
            },
        });
        bar.inc(1);
    }
    bar.finish_and_clear();
    writer.write_csv("sweep.csv", &table(varies, &rows))?;
    write_plots(scene, varies, &rows, &writer)?;
    writer.commit()?;
    Ok(rows)
}

/// Paths must exist in the scene (values may still be invalid per combination).
fn check_paths(scene: &Scene, varies: &[Vary]) -> anyhow::Result<()> {
    for v in varies {
        if v.values.is_empty() {
            anyhow::bail!("--vary {}: no values", v.path);
        }
        let mut json = scene.to_json();
        if let Err(reason) = crate::scene::path::set_path(&mut json, &v.path, v.values[0].clone()) {
            return Err(SceneError::Path {
                file: scene.file_label(),
                path: v.path.clone(),
                reason,
            }
            .into());
        }
    }
    Ok(())
}

/// Tip and crack names over all successful rows, in order of appearance.
fn names(rows: &[SweepRow]) -> (Vec<String>, Vec<String>) {
    let mut tips: Vec<String> = Vec::new();
    let mut cracks: Vec<String> = Vec::new();
    for s in rows.iter().filter_map(|r| r.summary.as_ref()) {
        for t in &s.tips {
            if !tips.contains(&t.name) {
                tips.push(t.name.clone());
            }
        }
        for c in &s.cracks {
            if !cracks.contains(&c.name) {
                cracks.push(c.name.clone());
            }
        }
    }
    (tips, cracks)
}

/// `sweep.csv`: parameters, status, wall time, elements, per-tip K and
/// errors, per-crack CMOD and error, error message.
pub fn table(varies: &[Vary], rows: &[SweepRow]) -> CsvTable {
    let (tips, cracks) = names(rows);
    let mut header: Vec<String> = vec!["run".into()];
    header.extend(varies.iter().map(|v| v.path.clone()));
    header.extend(["status", "wall_time_s", "elements"].map(String::from));
    for t in &tips {
        header.extend(
            ["k1", "k2", "kink_deg", "k1_err", "k2_err", "kink_err_deg"]
                .map(|c| format!("{t}.{c}")),
        );
    }
    for c in &cracks {
        header.extend(["cmod", "cmod_err"].map(|k| format!("{c}.{k}")));
    }
    header.push("error".into());
    let mut t = CsvTable::new(&header);
    for (k, r) in rows.iter().enumerate() {
        let mut row = vec![k.to_string()];
        row.extend(r.params.iter().cloned());
        match &r.summary {
            Some(s) => {
                row.extend([
                    "ok".to_string(),
                    num(s.wall_time_s),
                    s.elements.map(|e| e.to_string()).unwrap_or_default(),
                ]);
                for name in &tips {
                    let tip = s.tips.iter().find(|x| &x.name == name);
                    row.push(tip.map(|x| num(x.k1)).unwrap_or_default());
                    row.push(tip.map(|x| num(x.k2)).unwrap_or_default());
                    row.push(tip.map(|x| num(x.kink_deg)).unwrap_or_default());
                    row.push(opt(tip.and_then(|x| x.k1_err)));
                    row.push(opt(tip.and_then(|x| x.k2_err)));
                    row.push(opt(tip.and_then(|x| x.kink_err_deg)));
                }
                for name in &cracks {
                    let c = s.cracks.iter().find(|x| &x.name == name);
                    row.push(opt(c.and_then(|x| x.cmod)));
                    row.push(opt(c.and_then(|x| x.cmod_err)));
                }
                row.push(String::new());
            }
            None => {
                row.extend(["failed".to_string(), String::new(), String::new()]);
                row.extend(std::iter::repeat_n(
                    String::new(),
                    6 * tips.len() + 2 * cracks.len(),
                ));
                row.push(r.error.clone().unwrap_or_default().replace('\n', " | "));
            }
        }
        t.push(row);
    }
    t
}

/// x value of a row for plots: the first parameter as a number, else the row index.
fn x_of(raw: &str, k: usize) -> f64 {
    parse_value(raw).as_f64().unwrap_or(k as f64)
}

fn write_plots(
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
    report::save_plot(w, "sweep_k", &k_plot, formats, &mut dummy)?;
    let e_plot = error_against_time(rows);
    if e_plot.series.iter().any(|s| !s.points.is_empty()) {
        report::save_plot(w, "sweep_error_time", &e_plot, formats, &mut dummy)?;
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
                let e = s.tips.iter().find(|t| &t.name == name)?.k1_err?;
                Some((s.wall_time_s, e.abs()))
            })
            .collect();
        series.push(Series::new(
            format!("{name} |K_I error|"),
            pts,
            SeriesStyle::Markers,
        ));
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
            let e = s.tips.first()?.k1_err?;
            Some(((s.wall_time_s, e.abs()), r.params.join(", ")))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vary_splits_outside_brackets() {
        let v = parse_vary("cracks.0.start=(1,2),(3, 4)").expect("parses");
        assert_eq!(v.raw, vec!["(1,2)", "(3, 4)"]);
        assert_eq!(v.values[1], serde_json::json!([3, 4]));
        assert!(parse_vary("novalue").is_err());
        assert!(parse_vary("a=1,,2").is_err());
    }

    #[test]
    fn grid_is_cartesian() {
        let a = parse_vary("a=1,2").expect("parses");
        let b = parse_vary("b=1,2,3").expect("parses");
        let g = grid(&[a, b]);
        assert_eq!(g.len(), 6);
        assert_eq!(g[0], vec![0, 0]);
        assert_eq!(g[5], vec![1, 2]);
    }
}
