//! Tables and plots of a run: `tips.csv`, `cracks.csv`, `geometry.{png,svg}`,
//! `sif.{png,svg}` (SIF against the analytic curve where the scene has a
//! reference) and `summary.json`.

use anyhow::Context;

use super::context::RunContext;
use super::reference::tip_references;
use super::summary::RunSummary;
use crate::geometry::polyline_length;
use crate::output::csv::{num, opt};
use crate::output::{CsvTable, OutputWriter};
use crate::plot::{self, Figure, GeometryPlot, Series, SeriesStyle, XyPlot};
use crate::scene::shapes::SceneGeometry;
use crate::scene::{PlotFormat, Reference, Scene};
use pdbem_bem::analytic::{inclined_crack_k, sent_f_tada, SENT_FEM_TABLE};

/// Writes every output of a run into the staging area (plots first, so their
/// notes reach `summary.json`).
pub fn write_all(scene: &Scene, ctx: &RunContext, summary: &mut RunSummary) -> anyhow::Result<()> {
    let w = &ctx.writer;
    if scene.outputs.plots {
        let formats = &scene.outputs.formats;
        let geo = geometry_plot(scene, Some(summary));
        save_plot(w, "geometry", &geo, formats, summary)?;
        if let Some(p) = sif_plot(scene, summary) {
            save_plot(w, "sif", &p, formats, summary)?;
        }
    }
    if scene.outputs.csv {
        w.write_csv("tips.csv", &tips_table(summary))
            .context("writing tips.csv")?;
        w.write_csv("cracks.csv", &cracks_table(summary))
            .context("writing cracks.csv")?;
    }
    w.write_json("summary.json", summary)
        .context("writing summary.json")?;
    Ok(())
}

/// Saves a figure into the staging area under `stem` and registers its files;
/// a plot drawn without text adds a note.
pub fn save_plot<F: Figure>(
    w: &OutputWriter,
    stem: &str,
    fig: &F,
    formats: &[PlotFormat],
    summary: &mut RunSummary,
) -> anyhow::Result<()> {
    let saved = plot::save(fig, &w.staging_path(stem), formats)?;
    register_plot(w, stem, &saved, summary);
    Ok(())
}

/// [`save_plot`] for many figures: drawn in parallel (a growth run has one damage
/// snapshot per relocation), registered and noted in their order.
pub fn save_plots<F: Figure + Sync>(
    w: &OutputWriter,
    figures: &[(String, F)],
    formats: &[PlotFormat],
    summary: &mut RunSummary,
) -> anyhow::Result<()> {
    use rayon::prelude::*;
    let saved: Vec<_> = figures
        .par_iter()
        .map(|(stem, fig)| plot::save(fig, &w.staging_path(stem), formats))
        .collect();
    for ((stem, _), saved) in figures.iter().zip(saved) {
        register_plot(w, stem, &saved?, summary);
    }
    Ok(())
}

/// Registers the files of a saved plot; a plot drawn without text adds a note.
fn register_plot(w: &OutputWriter, stem: &str, saved: &plot::SavedPlot, summary: &mut RunSummary) {
    for f in &saved.files {
        if let Some(name) = f.file_name().and_then(|n| n.to_str()) {
            w.register(name);
        }
    }
    if saved.degraded {
        summary
            .notes
            .push(format!("{stem}: drawn without text (no usable font)"));
    }
}

/// Geometry plot of a scene, with the run's tips and mesh nodes when given.
pub fn geometry_plot(scene: &Scene, summary: Option<&RunSummary>) -> GeometryPlot {
    let geo = SceneGeometry::of(scene);
    let xy = |p: &crate::geometry::P2| (p.x, p.y);
    let mut loops: Vec<Vec<(f64, f64)>> = Vec::new();
    if let Some(o) = &geo.outline {
        loops.push(o.points.iter().map(xy).collect());
    }
    loops.extend(
        geo.holes
            .iter()
            .map(|(_, h)| h.polygon().iter().map(xy).collect()),
    );
    let tips: Vec<(String, (f64, f64))> = match summary {
        Some(s) if !s.tips.is_empty() => s
            .tips
            .iter()
            .map(|t| (t.name.clone(), (t.position[0], t.position[1])))
            .collect(),
        _ => geo.tips().iter().map(|(n, p)| (n.clone(), xy(p))).collect(),
    };
    let nodes = match summary {
        Some(s) if scene.outputs.show_mesh => s.plot_nodes.clone(),
        _ => Vec::new(),
    };
    let (arrows, supports) = super::marks::boundary_marks(scene);
    let infinite = match geo.remote {
        Some(r) => {
            let parts: Vec<String> = ["sxx", "syy", "sxy"]
                .iter()
                .zip(r)
                .filter(|(_, v)| *v != 0.0)
                .map(|(k, v)| format!("{k} = {} Pa", crate::plot::ticks::human(v, 4)))
                .collect();
            format!(" (infinite plate, remote {})", parts.join(", "))
        }
        None => String::new(),
    };
    GeometryPlot {
        title: format!("{}{infinite}", scene.name),
        unit: "m".into(),
        loops,
        cracks: geo
            .cracks
            .iter()
            .map(|c| (c.name.clone(), c.points.iter().map(xy).collect()))
            .collect(),
        nodes,
        tip_directions: super::marks::tip_directions(scene, &tips),
        tips,
        extra: Vec::new(),
        arrows,
        supports,
        windows: super::marks::window_outlines(scene),
    }
}

/// `tips.csv`: one row per tip.
pub fn tips_table(summary: &RunSummary) -> CsvTable {
    let mut t = CsvTable::new(&[
        "tip",
        "x",
        "y",
        "k1",
        "k2",
        "kink_deg",
        "k1_cod",
        "k2_cod",
        "k1_j",
        "k2_j",
        "j",
        "g",
        "k1_ref",
        "k2_ref",
        "kink_ref_deg",
        "k1_err",
        "k2_err",
        "kink_err_deg",
        "k1_ref_fem",
        "k1_err_fem",
        "k1_err_est",
        "k2_err_est",
    ]);
    for tip in &summary.tips {
        t.push(vec![
            tip.name.clone(),
            num(tip.position[0]),
            num(tip.position[1]),
            num(tip.k1),
            num(tip.k2),
            num(tip.kink_deg),
            opt(tip.k1_cod),
            opt(tip.k2_cod),
            opt(tip.k1_j),
            opt(tip.k2_j),
            opt(tip.j),
            opt(tip.g),
            opt(tip.k1_ref),
            opt(tip.k2_ref),
            opt(tip.kink_ref_deg),
            opt(tip.k1_err),
            opt(tip.k2_err),
            opt(tip.kink_err_deg),
            opt(tip.k1_ref_fem),
            opt(tip.k1_err_fem),
            opt(tip.k1_err_est),
            opt(tip.k2_err_est),
        ]);
    }
    t
}

/// `cracks.csv`: one row per crack.
pub fn cracks_table(summary: &RunSummary) -> CsvTable {
    let mut t = CsvTable::new(&["crack", "cmod", "cmod_ref", "cmod_err"]);
    for c in &summary.cracks {
        t.push(vec![
            c.name.clone(),
            opt(c.cmod),
            opt(c.cmod_ref),
            opt(c.cmod_err),
        ]);
    }
    t
}

/// SIF of this run against the analytic curve: K_I against a/W (SENT: Tada
/// curve and FEM table) or K against beta (inclined crack). `None` without a
/// SIF reference or tips.
pub fn sif_plot(scene: &Scene, summary: &RunSummary) -> Option<XyPlot> {
    let refs = tip_references(scene);
    let (name, _) = refs.first()?;
    let tip = summary.tips.iter().find(|t| &t.name == name)?;
    let f = super::reference::load_factor(scene);
    match scene.reference.clone()? {
        Reference::SentTada { width, sigma } => {
            let a = polyline_length(&SceneGeometry::of(scene).cracks.first()?.points);
            let mut p = sent_curves(sigma * f, width);
            p.title = format!("{}: K_I against a/W", scene.name);
            p.series.push(Series::new(
                format!("pdbem ({})", summary.mode),
                vec![(a / width, tip.k1)],
                SeriesStyle::Markers,
            ));
            Some(p)
        }
        Reference::InclinedCrackInfinite { sigma, beta_deg } => {
            let beta_deg =
                beta_deg.or_else(|| crate::setup::reference_loads::load_beta_deg(scene))?;
            let half = 0.5 * polyline_length(&SceneGeometry::of(scene).cracks.first()?.points);
            let mut p = inclined_curves(sigma * f, half);
            p.title = format!("{}: K against beta", scene.name);
            p.series.push(Series::new(
                "K_I pdbem",
                vec![(beta_deg, tip.k1)],
                SeriesStyle::Markers,
            ));
            p.series.push(Series::new(
                "|K_II| pdbem",
                vec![(beta_deg, tip.k2.abs())],
                SeriesStyle::Markers,
            ));
            Some(p)
        }
        Reference::Kirsch { .. } => None,
    }
}

/// SENT K_I(a/W) curves: Tada's formula (line) and the FEM table (markers).
pub fn sent_curves(sigma: f64, width: f64) -> XyPlot {
    let k = |x: f64, f: f64| sigma * (std::f64::consts::PI * x * width).sqrt() * f;
    let tada: Vec<(f64, f64)> = (1..=85)
        .map(|i| i as f64 / 100.0)
        .map(|x| (x, k(x, sent_f_tada(x))))
        .collect();
    let fem: Vec<(f64, f64)> = SENT_FEM_TABLE
        .iter()
        .map(|(x, f)| (*x, k(*x, *f)))
        .collect();
    let mut p = XyPlot::new("K_I against a/W", "a/W (-)", "K_I (Pa m^0.5)");
    p.series
        .push(Series::new("Tada formula", tada, SeriesStyle::Line));
    p.series.push(Series::new(
        "FEM table (converged, 0.1 <= a/W <= 0.8)",
        fem,
        SeriesStyle::Markers,
    ));
    p
}

/// Inclined-crack K_I and K_II against beta for half-length `a`.
pub fn inclined_curves(sigma: f64, a: f64) -> XyPlot {
    let betas: Vec<f64> = (0..=90).map(|b| b as f64).collect();
    let k1: Vec<(f64, f64)> = betas
        .iter()
        .map(|b| (*b, inclined_crack_k(sigma, a, *b).0))
        .collect();
    let k2: Vec<(f64, f64)> = betas
        .iter()
        .map(|b| (*b, inclined_crack_k(sigma, a, *b).1))
        .collect();
    let mut p = XyPlot::new("K against beta", "beta (deg)", "K (Pa m^0.5)");
    p.series
        .push(Series::new("K_I analytic", k1, SeriesStyle::Line));
    p.series
        .push(Series::new("K_II analytic", k2, SeriesStyle::Line));
    p
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runner::reference;
    use crate::runner::summary::{CrackResult, TipResult};

    const SENT: &str = r#"(
        name: "sent_report_test",
        material: (E: 1e4, nu: 0.3333333333333333, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: 20, height: 10)),
        cracks: [(name: "crack", start: (10, 10), angle_deg: -90, length: 5)],
        boundary: [(on: "left", x: Traction(-0.5)), (on: "right", x: Traction(0.5))],
        reference: SentTada(width: 10, sigma: 0.5),
    )"#;

    #[test]
    fn writes_summary_tables_and_plots_with_reference_errors() {
        let scene = Scene::from_ron_str(SENT, "inline.ron").expect("valid");
        let dir = std::env::temp_dir().join(format!("pdbem-report-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let ctx = RunContext::new(&dir, true).expect("run folder");
        let mut s = RunSummary {
            mode: "bem".into(),
            elements: Some(700),
            tips: vec![TipResult {
                name: "crack.end".into(),
                position: [10.0, 5.0],
                k1: 5.6,
                ..TipResult::default()
            }],
            cracks: vec![CrackResult {
                name: "crack".into(),
                cmod: Some(4.9e-3),
                ..CrackResult::default()
            }],
            ..RunSummary::default()
        };
        reference::apply(&scene, &mut s);
        let err = s.tips[0].k1_err.expect("reference error");
        assert!(err.abs() < 1e-3, "{err}");
        write_all(&scene, &ctx, &mut s).expect("outputs");
        ctx.writer.commit().expect("commit");
        for f in [
            "summary.json",
            "tips.csv",
            "cracks.csv",
            "geometry.png",
            "geometry.svg",
            "sif.png",
            "sif.svg",
        ] {
            assert!(dir.join(f).is_file(), "missing {f}");
        }
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).expect("read"))
                .expect("json");
        assert_eq!(json["mode"], "bem");
        assert!(json["cracks"][0]["cmod_err"].as_f64().is_some());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
