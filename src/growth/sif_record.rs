//! The fracture-mechanics record along the path of a growth run (`sif_path.csv`,
//! `sif_path.png/svg`; docs/outputs.md). BEM-only growth fills it while it runs; for the
//! PD modes [`replay_record`] solves the path geometry after the run
//! (`pdbem_coupling::growth::sif_path`, where the choice is explained).

use anyhow::{Context, Result};
use pdbem_bem::analytic::{sent_f_fem, sent_f_tada};
use pdbem_coupling::growth::history::SifRow;
use pdbem_coupling::growth::sif_path::{replay, ReplayParams};

use super::GrowthHistory;
use crate::output::csv::{num, opt, CsvTable};
use crate::plot::{Series, SeriesStyle, XyPlot};
use crate::scene::shapes::SceneGeometry;
use crate::scene::{Reference, Scene};
use crate::setup::growth::{bem_only_body, bem_only_scenario, front, toughness};

/// Default crack advance between rows within a step in the PD modes, as a fraction of the
/// smaller side of the body's bounding box (`growth.sif_spacing`).
pub const DEFAULT_SPACING_FRACTION: f64 = 1.0 / 40.0;

/// K_I varying by more than this factor along the path gets a logarithmic K axis.
pub const LOG_RATIO: f64 = 20.0;

/// Simplification tolerance of a PD path before it is solved, in grid spacings: the
/// traced tip zig-zags by up to half a spacing between neighbouring nodes.
const SMOOTH_DX: f64 = 0.5;

/// The spacing of the record of `scene` (m); 0: none.
pub fn spacing(scene: &Scene) -> f64 {
    let geo = SceneGeometry::of(scene);
    scene
        .growth
        .as_ref()
        .and_then(|g| g.sif_spacing)
        .unwrap_or_else(|| {
            let (lo, hi) = geo.bounds();
            DEFAULT_SPACING_FRACTION * (hi - lo).min()
        })
}

/// Fills `history.sif_path` of a PD-mode run of `scene` by BEM solves of its path
/// geometry, with spacing [`spacing`], the paths smoothed to half a grid spacing and
/// points within a horizon of the outline or a hole left out. Stations that could not be
/// solved as a growth state become notes.
pub fn replay_record(scene: &Scene, history: &mut GrowthHistory) -> Result<()> {
    let sp = spacing(scene);
    let (Some(co), Some(pd)) = (&scene.coupling, &scene.pd) else {
        return Ok(());
    };
    if sp <= 0.0 {
        return Ok(());
    }
    let geo = SceneGeometry::of(scene);
    let body = bem_only_body(scene, &geo)?;
    let scenario = bem_only_scenario(scene);
    let dx = co.dx();
    let params = ReplayParams {
        spacing: sp.max(dx),
        smooth: SMOOTH_DX * dx,
        clear: pd.horizon_factor * dx,
    };
    let (rows, notes) = replay(&body, &scenario, &front(scene), history, &params)
        .with_context(|| format!("{}: sif_path", scene.file_label().display()))?;
    history.sif_path = rows;
    history.notes.extend(notes);
    Ok(())
}

/// `sif_path.csv`: one row per tip and state.
pub fn sif_table(h: &GrowthHistory) -> CsvTable {
    let mut t = CsvTable::new(&[
        "step",
        "load",
        "tip",
        "x",
        "y",
        "crack_length",
        "extension",
        "k1",
        "k2",
        "k_eq",
        "kink_deg",
        "g",
        "cmod",
    ]);
    for r in &h.sif_path {
        t.push(vec![
            r.step.to_string(),
            num(r.load),
            r.tip.clone(),
            num(r.x),
            num(r.y),
            num(r.crack_length),
            num(r.extension),
            num(r.k1),
            num(r.k2),
            num(r.k_eq),
            num(r.kink_deg),
            num(r.g),
            opt(r.cmod),
        ]);
    }
    t
}

/// K against crack length (`None` without rows): K_I and K_II of every tip, K_c when the
/// scene has a toughness, and for a `SentTada` reference the analytic K_I (Tada) at each
/// row's load and crack length, with the FEM table of REFERENCES.md when every row has
/// the same load. K_I of a crack growing to an edge spans decades: the K axis is
/// logarithmic when K_I varies by more than [`LOG_RATIO`], and then shows |K_II|.
pub fn sif_plot(scene: &Scene, h: &GrowthHistory) -> Option<XyPlot> {
    if h.sif_path.is_empty() {
        return None;
    }
    let k1 = h.sif_path.iter().map(|r| r.k1);
    let (lo_k, hi_k) = k1.fold((f64::MAX, f64::MIN), |(a, b), k| (a.min(k), b.max(k)));
    let log = lo_k > 0.0 && hi_k / lo_k > LOG_RATIO;
    let mut p = XyPlot::new(
        format!("{}: K along the path ({})", scene.name, h.mode),
        "crack length (m)",
        "K (Pa m^0.5)",
    );
    p.log_y = log;
    let mut names: Vec<&str> = h.sif_path.iter().map(|r| r.tip.as_str()).collect();
    names.sort_unstable();
    names.dedup();
    for name in names {
        let rows: Vec<&SifRow> = h.sif_path.iter().filter(|r| r.tip == name).collect();
        let pts = |f: &dyn Fn(&SifRow) -> f64| -> Vec<(f64, f64)> {
            rows.iter().map(|r| (r.crack_length, f(r))).collect()
        };
        p.series.push(Series::new(
            format!("K_I {name}"),
            pts(&|r| r.k1),
            SeriesStyle::Markers,
        ));
        let (label, k2) = if log {
            (format!("|K_II| {name}"), pts(&|r| r.k2.abs()))
        } else {
            (format!("K_II {name}"), pts(&|r| r.k2))
        };
        p.series.push(Series::new(label, k2, SeriesStyle::Markers));
    }
    // The references over the computed markers, so that both show.
    if let Some(Reference::SentTada { width, sigma }) = &scene.reference {
        p.series.extend(sent_series(h, *width, *sigma));
    }
    if let Ok((k_c, _)) = toughness(scene) {
        let (lo, hi) = h.sif_path.iter().fold((f64::MAX, f64::MIN), |(a, b), r| {
            (a.min(r.crack_length), b.max(r.crack_length))
        });
        p.series.push(Series::new(
            "K_c",
            vec![(lo, k_c), (hi, k_c)],
            SeriesStyle::Line,
        ));
    }
    Some(p)
}

/// Tada's K_I at each row of the first tip (its load and crack length) and, when all
/// rows share one load, the FEM table points inside the rows' range.
fn sent_series(h: &GrowthHistory, width: f64, sigma: f64) -> Vec<Series> {
    let first = &h.sif_path[0].tip;
    let rows: Vec<&SifRow> = h.sif_path.iter().filter(|r| &r.tip == first).collect();
    let k = |a: f64, load: f64, f: f64| load * sigma * (std::f64::consts::PI * a).sqrt() * f;
    let mut tada: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.crack_length < width)
        .map(|r| {
            let f = sent_f_tada(r.crack_length / width);
            (r.crack_length, k(r.crack_length, r.load, f))
        })
        .collect();
    tada.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = vec![Series::new("K_I Tada (SENT)", tada, SeriesStyle::Line)];
    let load = rows[0].load;
    if rows.iter().all(|r| r.load == load) {
        let (lo, hi) = rows.iter().fold((f64::MAX, f64::MIN), |(a, b), r| {
            (a.min(r.crack_length), b.max(r.crack_length))
        });
        let fem: Vec<(f64, f64)> = (1..=8)
            .map(|i| 0.1 * i as f64 * width)
            .filter(|&a| a >= lo && a <= hi)
            .filter_map(|a| sent_f_fem(a / width).map(|f| (a, k(a, load, f))))
            .collect();
        if !fem.is_empty() {
            out.push(Series::new(
                "K_I FEM table (SENT)",
                fem,
                SeriesStyle::Markers,
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(a: f64, k1: f64, k2: f64) -> SifRow {
        SifRow {
            step: 0,
            load: 2.0,
            tip: "crack.end".into(),
            x: 10.0,
            y: 10.0 - a,
            crack_length: a,
            extension: a - 2.0,
            k1,
            k2,
            k_eq: k1,
            kink_deg: 0.0,
            g: k1 * k1 / 1e3,
            cmod: Some(1e-3 * a),
        }
    }

    #[test]
    fn the_k_plot_carries_the_reference_and_goes_logarithmic_over_decades() {
        let scene = Scene::load(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/cases/growth_tension_edge.ron"
        ))
        .expect("case");
        let mut h = GrowthHistory {
            mode: "bem-only".into(),
            sif_path: vec![row(2.0, 20.0, 0.1), row(5.0, 60.0, -0.1)],
            ..Default::default()
        };
        let p = sif_plot(&scene, &h).expect("plot");
        assert!(!p.log_y);
        let labels: Vec<&str> = p.series.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "K_I crack.end",
                "K_II crack.end",
                "K_I Tada (SENT)",
                "K_I FEM table (SENT)",
                "K_c"
            ]
        );
        // Tada at the rows' load 2 (sigma = 1 Pa per unit load): a = 2 m, F(0.2) = 1.37.
        let tada = &p.series[2].points[0];
        let expect = 2.0 * (std::f64::consts::PI * 2.0).sqrt() * sent_f_tada(0.2);
        assert!((tada.1 - expect).abs() < 1e-12);
        h.sif_path.push(row(9.5, 3000.0, -2.0));
        let p = sif_plot(&scene, &h).expect("plot");
        assert!(p.log_y);
        assert!(p.series[1].points.iter().all(|q| q.1 > 0.0));
        assert_eq!(sif_table(&h).rows.len(), 3);
    }
}
