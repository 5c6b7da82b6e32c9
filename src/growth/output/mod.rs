//! Output layer of growth runs: every mode hands its [`GrowthHistory`] to [`finish`], which
//! writes the tables, the machine-readable records and the plots into the run's staging
//! folder (committed all-or-nothing by the runner) and returns the [`RunSummary`]
//! (`mode: "growth"`) whose fields `summary.json` carries. File list: docs/outputs.md.
//!
//! - tables: `path_<tip>.csv` (`x,y,step,load`), `steps.csv`;
//! - records: `growth.json` (the history, what `pdbem plot-paths` reads), `geometry.json`
//!   (outline, holes and initial cracks), `growth_log.jsonl` (completed here for solvers
//!   that did not log while running, see [`super::log`]);
//! - plots: `paths` (crack paths over the outline with the window outlines), `load_cmod`,
//!   `load_extension`, and one `snapshot_<label>_step<NNN>` per field snapshot.

use anyhow::{Context, Result};
use serde_json::{json, Value};

use super::log::GrowthLog;
use super::{FieldSnapshot, GrowthHistory, TipPath};
use crate::geometry::P2;
use crate::output::csv::{num, opt, CsvTable};
use crate::plot::field::{Mark, Polyline};
use crate::plot::{PathGroup, PathsPlot, ScatterField, Series, SeriesStyle, XyPlot};
use crate::runner::context::RunContext;
use crate::runner::report::{save_plot, save_plots};
use crate::runner::summary::RunSummary;
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// File of the serialised history.
pub const HISTORY_FILE: &str = "growth.json";
/// File of the body geometry.
pub const GEOMETRY_FILE: &str = "geometry.json";

/// Writes every output of a growth run and returns its summary.
pub fn finish(scene: &Scene, ctx: &RunContext, history: &GrowthHistory) -> Result<RunSummary> {
    let w = &ctx.writer;
    let mut summary = growth_summary(scene, history);
    complete_log(ctx, history, &summary)?;
    w.write_json(HISTORY_FILE, history)
        .with_context(|| format!("writing {HISTORY_FILE}"))?;
    w.write_json(GEOMETRY_FILE, &geometry_json(scene))
        .with_context(|| format!("writing {GEOMETRY_FILE}"))?;
    if scene.outputs.csv {
        for p in &history.paths {
            let name = path_file(&p.name);
            w.write_csv(&name, &path_table(p))
                .with_context(|| format!("writing {name}"))?;
        }
        w.write_csv("steps.csv", &steps_table(history))
            .context("writing steps.csv")?;
        w.write_csv("sif_path.csv", &super::sif_record::sif_table(history))
            .context("writing sif_path.csv")?;
    }
    if scene.outputs.plots {
        write_plots(scene, ctx, history, &mut summary)?;
    }
    if scene.outputs.vtk {
        super::vtk::write(ctx, history)?;
    }
    Ok(summary)
}

/// `path_<tip>.csv` for a tip name.
pub fn path_file(tip: &str) -> String {
    format!("path_{tip}.csv")
}

/// The summary of a growth run: `mode: "growth"` and the growth fields of docs/outputs.md.
pub fn growth_summary(scene: &Scene, h: &GrowthHistory) -> RunSummary {
    let mut extra = serde_json::Map::new();
    extra.insert("growth_mode".into(), json!(h.mode));
    extra.insert("relocations".into(), json!(h.relocations.len()));
    extra.insert("failure".into(), json!(h.failure));
    extra.insert("failure_load".into(), json!(h.failure_load));
    extra.insert("complete".into(), json!(h.failure_reason.is_none()));
    extra.insert("failure_reason".into(), json!(h.failure_reason));
    extra.insert("end_state".into(), json!(h.end_state()));
    extra.insert("initiation_load".into(), json!(h.initiation_load));
    extra.insert("steps".into(), json!(h.steps.len()));
    extra.insert("final_load".into(), json!(h.steps.last().map(|s| s.load)));
    extra.insert("tips_final".into(), Value::Array(final_tips(h)));
    let times: Vec<f64> = h.steps.iter().map(|s| s.wall_time_s).collect();
    extra.insert(
        "step_wall_time_s".into(),
        json!({"total": times.iter().fold(0.0, |a, t| a + t),
               "max": times.iter().copied().fold(0.0, f64::max)}),
    );
    let rebuild = h.relocations.iter().fold(0.0, |a, r| a + r.rebuild_s);
    extra.insert("relocation_rebuild_s".into(), json!(rebuild));
    if h.mode == "pd-bem" {
        extra.insert("bem_overstrain".into(), json!(h.overstrain));
        extra.insert("window_stray_damage".into(), json!(h.stray_damage));
    }
    let mut notes = h.notes.clone();
    notes.extend(first_step_bounds(h));
    RunSummary {
        scene: scene.name.clone(),
        mode: "growth".into(),
        notes,
        extra,
        ..Default::default()
    }
}

/// Notes for an initiation or failure load that is the first step's: the crack grew (or
/// the body failed) at the first load it was given, so that load is only an upper bound.
pub fn first_step_bounds(h: &GrowthHistory) -> Vec<String> {
    let Some(first) = h.steps.first().map(|s| s.load) else {
        return Vec::new();
    };
    let at_first = |f: Option<f64>| f.is_some_and(|f| f <= first);
    let mut what = Vec::new();
    if at_first(h.initiation_load) {
        what.push("the crack grew");
    }
    if h.failure && at_first(h.failure_load) {
        what.push("the body failed");
    }
    if what.is_empty() {
        return Vec::new();
    }
    vec![format!(
        "{} in the first load step (load factor {first}): {} only an upper bound, the true \
         value lies below it; start the ramp lower (load.initial)",
        what.join(" and "),
        if what.len() == 2 {
            "the initiation and failure loads are each"
        } else if what[0] == "the crack grew" {
            "the initiation load is"
        } else {
            "the failure load is"
        }
    )]
}

/// `tips_final`: name, last position, length grown and why each tip stopped.
fn final_tips(h: &GrowthHistory) -> Vec<Value> {
    h.paths
        .iter()
        .map(|p| {
            let last = p.points.last();
            json!({
                "name": p.name,
                "position": last.map(|q| [q.x, q.y]),
                "extension": extension(p),
                "ended": p.ended,
            })
        })
        .collect()
}

/// Arc length of a tip path (m).
pub fn extension(p: &TipPath) -> f64 {
    p.points
        .windows(2)
        .map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y))
        .sum()
}

/// Adds the history's events to the log when the solver did not write one, then the
/// closing `end` event.
fn complete_log(ctx: &RunContext, h: &GrowthHistory, s: &RunSummary) -> Result<()> {
    let logged = GrowthLog::exists(ctx);
    let log = GrowthLog::open(ctx)?;
    if !logged {
        log.event("start", json!({"mode": h.mode, "replayed": true}))?;
        log.replay(h)?;
    }
    log.event("end", Value::Object(s.extra.clone()))
}

/// `path_<tip>.csv`: one row per path point.
pub fn path_table(p: &TipPath) -> CsvTable {
    let mut t = CsvTable::new(&["x", "y", "step", "load"]);
    for q in &p.points {
        t.push(vec![num(q.x), num(q.y), q.step.to_string(), num(q.load)]);
    }
    t
}

/// `steps.csv`: one row per load step; tip positions as `<tip>.x`, `<tip>.y` columns.
pub fn steps_table(h: &GrowthHistory) -> CsvTable {
    let mut header: Vec<String> = [
        "step",
        "load",
        "cmod",
        "coupling_iterations",
        "coupling_residual",
        "broken_bonds",
        "wall_time_s",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for p in &h.paths {
        header.push(format!("{}.x", p.name));
        header.push(format!("{}.y", p.name));
    }
    let mut t = CsvTable::new(&header);
    for s in &h.steps {
        let mut row = vec![
            s.step.to_string(),
            num(s.load),
            opt(s.cmod),
            s.coupling_iterations.to_string(),
            opt(s.coupling_residual),
            s.broken_bonds.to_string(),
            num(s.wall_time_s),
        ];
        for k in 0..h.paths.len() {
            let p = s.tips.get(k);
            row.push(p.map(|q| num(q[0])).unwrap_or_default());
            row.push(p.map(|q| num(q[1])).unwrap_or_default());
        }
        t.push(row);
    }
    t
}

/// `geometry.json`: `{unit, outline, holes, cracks: [{name, points}]}` (m).
pub fn geometry_json(scene: &Scene) -> Value {
    let geo = SceneGeometry::of(scene);
    let pts = |v: &[P2]| v.iter().map(|p| [p.x, p.y]).collect::<Vec<_>>();
    json!({
        "unit": "m",
        "outline": geo.outline.as_ref().map(|o| pts(&o.points)),
        "holes": geo.holes.iter().map(|(_, h)| pts(&h.polygon())).collect::<Vec<_>>(),
        "cracks": geo.cracks.iter()
            .map(|c| json!({"name": c.name, "points": pts(&c.points)}))
            .collect::<Vec<_>>(),
    })
}

fn xy(v: &[P2]) -> Vec<(f64, f64)> {
    v.iter().map(|p| (p.x, p.y)).collect()
}

/// Outline and hole loops of the scene.
fn body_loops(geo: &SceneGeometry) -> Vec<Vec<(f64, f64)>> {
    let mut loops = Vec::new();
    if let Some(o) = &geo.outline {
        loops.push(xy(&o.points));
    }
    loops.extend(geo.holes.iter().map(|(_, h)| xy(&h.polygon())));
    loops
}

/// Tip path as plot points.
fn path_line(p: &TipPath) -> Vec<(f64, f64)> {
    p.points.iter().map(|q| (q.x, q.y)).collect()
}

/// The crack-path figure of one run.
pub fn paths_plot(scene: &Scene, h: &GrowthHistory) -> PathsPlot {
    let geo = SceneGeometry::of(scene);
    let groups = h
        .paths
        .iter()
        .map(|p| PathGroup {
            label: format!("{} ({})", p.name, h.mode),
            lines: vec![path_line(p)],
        })
        .collect();
    PathsPlot {
        title: format!("{}: crack paths ({})", scene.name, h.mode),
        unit: "m".into(),
        loops: body_loops(&geo),
        cracks: geo.cracks.iter().map(|c| xy(&c.points)).collect(),
        windows: h
            .windows
            .iter()
            .map(|w| w.corners.iter().map(|c| (c[0], c[1])).collect())
            .collect(),
        groups,
        marks: h
            .overstrain
            .iter()
            .map(|o| {
                let label = format!("BEM strain at the PD onset (load {})", o.load);
                (label, (o.position[0], o.position[1]))
            })
            .collect(),
    }
}

/// Load factor against CMOD (`None` when no step has a CMOD): from the unloaded body (a
/// linear elastic body opens nothing at load 0) through every step with a CMOD, and the
/// structural failure load as a horizontal line (its step has no CMOD: the body came
/// apart).
fn load_cmod_plot(scene: &Scene, h: &GrowthHistory) -> Option<XyPlot> {
    let steps: Vec<(f64, f64)> = h
        .steps
        .iter()
        .filter_map(|s| s.cmod.map(|c| (c, s.load)))
        .collect();
    if steps.is_empty() {
        return None;
    }
    let mut p = XyPlot::new(
        format!("{}: load against CMOD ({})", scene.name, h.mode),
        "CMOD (m)",
        "load factor (-)",
    );
    let mut pts = vec![(0.0, 0.0)];
    pts.extend(steps);
    let right = pts.iter().map(|q| q.0).fold(0.0, f64::max);
    p.series
        .push(Series::new(h.mode.clone(), pts, SeriesStyle::LineMarkers));
    if let Some(f) = h.failure_load.filter(|_| h.failure) {
        p.series.push(Series::new(
            format!("structural failure (load {f})"),
            vec![(0.0, f), (right, f)],
            SeriesStyle::Line,
        ));
    }
    Some(p)
}

/// Load factor against the length grown at each tip.
fn load_extension_plot(scene: &Scene, h: &GrowthHistory) -> XyPlot {
    let mut p = XyPlot::new(
        format!("{}: crack extension ({})", scene.name, h.mode),
        "crack extension (m)",
        "load factor (-)",
    );
    for path in &h.paths {
        let mut len = 0.0;
        let mut pts = Vec::with_capacity(path.points.len());
        for (i, q) in path.points.iter().enumerate() {
            if i > 0 {
                let a = &path.points[i - 1];
                len += (q.x - a.x).hypot(q.y - a.y);
            }
            pts.push((len, q.load));
        }
        p.series.push(Series::new(
            path.name.clone(),
            pts,
            SeriesStyle::LineMarkers,
        ));
    }
    p
}

/// A field snapshot as a scatter plot in the body frame: damage in [0, 1], other fields
/// scaled by a power of 1000 so the colour bar reads well; the body outline and holes,
/// the crack paths so far ([`path_so_far`]) and the tips on top. A window snapshot
/// (`*window*` labels) shows its window and a margin of a tenth of its size around it
/// (the window is small against the body), with the outline where it passes.
fn snapshot_plot(scene: &Scene, h: &GrowthHistory, s: &FieldSnapshot) -> ScatterField {
    let damage = s.label.starts_with("damage");
    let loops = body_loops(&SceneGeometry::of(scene));
    let view = s
        .label
        .contains("window")
        .then(|| window_view(&s.points))
        .flatten();
    let (paths, marks) = path_so_far(h, s);
    let (label, range, scale) = if damage {
        ("damage phi (-)".to_string(), Some((0.0, 1.0)), 1.0)
    } else {
        let (exp, scale) = engineering_scale(s.values.iter().copied());
        let unit = if exp == 0 {
            "m".to_string()
        } else {
            format!("1e{exp} m")
        };
        let name = if s.label.starts_with("displacement") {
            "|u|"
        } else {
            s.label.as_str()
        };
        (format!("{name} ({unit})"), None, scale)
    };
    ScatterField {
        title: format!(
            "{}: {}{} ({})",
            scene.name,
            snapshot_title(s),
            if collapse_field(h, s) {
                " at structural failure (the collapse)"
            } else {
                ""
            },
            h.mode
        ),
        unit: "m".into(),
        value_label: label,
        points: s.points.iter().map(|p| (p[0], p[1])).collect(),
        values: s.values.iter().map(|v| v * scale).collect(),
        range,
        loops,
        marker_px: 0,
        groups: s.groups.clone(),
        paths,
        marks,
        view,
    }
}

/// The box around a window's nodes with a margin of a tenth of its larger side.
fn window_view(points: &[[f64; 2]]) -> Option<((f64, f64), (f64, f64))> {
    let first = points.first()?;
    let (mut lo, mut hi) = ((first[0], first[1]), (first[0], first[1]));
    for p in points {
        lo = (lo.0.min(p[0]), lo.1.min(p[1]));
        hi = (hi.0.max(p[0]), hi.1.max(p[1]));
    }
    let m = 0.1 * (hi.0 - lo.0).max(hi.1 - lo.1);
    Some(((lo.0 - m, lo.1 - m), (hi.0 + m, hi.1 + m)))
}

/// The crack paths as far as they had grown when `s` was taken, and the tips then, named.
/// A snapshot taken at the end of load step k shows the points reached by step k; one
/// taken before a window relocation in step k carries the tip that triggered it
/// ([`FieldSnapshot::tips`]): each such tip ends the path whose points come nearest to
/// it, cut at that nearest point, and every other path shows its points before step k.
pub fn path_so_far(h: &GrowthHistory, s: &FieldSnapshot) -> (Vec<Polyline>, Vec<Mark>) {
    let (mut paths, mut marks) = (Vec::new(), Vec::new());
    let nearest = |p: &TipPath, t: [f64; 2]| {
        p.points
            .iter()
            .enumerate()
            .map(|(i, q)| (i, (q.x - t[0]).hypot(q.y - t[1])))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    };
    for p in &h.paths {
        let tip = s
            .tips
            .iter()
            .filter_map(|t| nearest(p, *t).map(|(i, d)| (i, d, *t)))
            .filter(|(_, d, t)| {
                // This path's tip, not another's: no other path comes nearer.
                h.paths
                    .iter()
                    .all(|o| nearest(o, *t).is_none_or(|(_, od)| od >= *d))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let mut pts: Vec<(f64, f64)> = match tip {
            Some((i, _, _)) => p.points[..=i].iter().map(|q| (q.x, q.y)).collect(),
            None if s.tips.is_empty() => p
                .points
                .iter()
                .filter(|q| q.step <= s.step)
                .map(|q| (q.x, q.y))
                .collect(),
            None => p
                .points
                .iter()
                .filter(|q| q.step < s.step)
                .map(|q| (q.x, q.y))
                .collect(),
        };
        if let Some((_, _, t)) = tip {
            pts.push((t[0], t[1]));
        }
        if let Some(last) = pts.last() {
            marks.push((*last, format!(" {}", p.name)));
        }
        if pts.len() > 1 {
            paths.push(pts);
        }
    }
    (paths, marks)
}

/// Whether `s` is a displacement field of the step at which the body came apart: the
/// collapse (the tension plate's right half turned about the last PD bonds by metres),
/// not an equilibrium of the body in one piece.
fn collapse_field(h: &GrowthHistory, s: &FieldSnapshot) -> bool {
    h.failure
        && s.label.starts_with("displacement")
        && h.steps.last().is_some_and(|l| l.step == s.step)
}

/// What a snapshot shows, in words, with the 0-based load step of the file names and the
/// CSVs: `damage_window0_step001_reloc007` is "damage in PD window 0, load step 1, before
/// window relocation 7" (the state that made the window move for the 7th time).
fn snapshot_title(s: &FieldSnapshot) -> String {
    let (mut field, mut window, mut reloc, mut step) = (Vec::new(), None, None, s.step);
    for part in s.label.split('_') {
        if let Some(w) = part.strip_prefix("window") {
            window = Some(w.to_string());
        } else if let Some(k) = part.strip_prefix("step").and_then(|k| k.parse().ok()) {
            step = k;
        } else if let Some(r) = part
            .strip_prefix("reloc")
            .and_then(|r| r.parse::<usize>().ok())
        {
            reloc = Some(r);
        } else if part == "displacement" {
            field.push("|u|".to_string());
        } else {
            field.push(part.to_string());
        }
    }
    let mut text = field.join(" ");
    if let Some(w) = window {
        text.push_str(&format!(" in PD window {w}"));
    }
    text.push_str(&format!(", load step {step}"));
    if let Some(r) = reloc {
        text.push_str(&format!(", before window relocation {r}"));
    }
    text
}

/// Exponent (a multiple of 3) and factor 10^-exponent that bring the largest magnitude of
/// `values` into [1, 1000).
fn engineering_scale(values: impl Iterator<Item = f64>) -> (i32, f64) {
    let max = values
        .filter(|v| v.is_finite())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    if max == 0.0 {
        return (0, 1.0);
    }
    let exp = 3 * (max.log10() / 3.0).floor() as i32;
    (exp, 10f64.powi(-exp))
}

fn write_plots(
    scene: &Scene,
    ctx: &RunContext,
    h: &GrowthHistory,
    summary: &mut RunSummary,
) -> Result<()> {
    let (w, formats) = (&ctx.writer, &scene.outputs.formats);
    save_plot(w, "paths", &paths_plot(scene, h), formats, summary)?;
    if let Some(p) = load_cmod_plot(scene, h) {
        save_plot(w, "load_cmod", &p, formats, summary)?;
    }
    if let Some(p) = super::sif_record::sif_plot(scene, h) {
        save_plot(w, "sif_path", &p, formats, summary)?;
    }
    save_plot(
        w,
        "load_extension",
        &load_extension_plot(scene, h),
        formats,
        summary,
    )?;
    // A step can be asked for twice (initiation or the last step in
    // `growth.snapshot_steps`): the first of a name is plotted.
    let mut seen = std::collections::HashSet::new();
    let snapshots: Vec<_> = h
        .snapshots
        .iter()
        .filter_map(|s| {
            let stem = super::vtk::snapshot_stem(s);
            seen.insert(stem.clone())
                .then(|| (stem, snapshot_plot(scene, h, s)))
        })
        .collect();
    save_plots(w, &snapshots, formats, summary)
}

#[cfg(test)]
mod tests;
