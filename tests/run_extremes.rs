//! Runs at the extremes (issue 17): a run over the memory budget fails before anything
//! is built, a run whose results are not finite fails naming the field and leaves no
//! output, `--max-memory` takes suffixes, and plots of huge, tiny or non-finite values
//! are drawn in bounded time (a range reaching infinity made the tick search of the
//! plotting library loop forever on `reference: SentTada(sigma: 1e308)`).

use std::sync::mpsc;
use std::time::Duration;

use pdbem::plot::xy::{Series, SeriesStyle, XyPlot};
use pdbem::runner::report::sent_curves;
use pdbem::scene::{PlotFormat, Scene};

fn temp(name: &str) -> std::path::PathBuf {
    std::env::temp_dir().join(format!("pdbem-run-extremes-{}-{name}", std::process::id()))
}

fn plate_src(width: f64, height: f64, traction: &str, extra: &str) -> String {
    format!(
        r#"(name: "x", material: (E: 1e4, nu: 0.3, plane: Stress),
        body: (outline: Rectangle(x0: 0, y0: 0, width: {width}, height: {height})),
        cracks: [(name: "c", start: ({}, {height}), angle_deg: -90, length: {})],
        boundary: [(on: "left", x: Traction(-{traction})), (on: "right", x: Traction({traction}))],
        outputs: (plots: false), {extra})"#,
        0.5 * width,
        0.5 * height
    )
}

fn plate(width: f64, height: f64, traction: &str, extra: &str) -> Scene {
    Scene::from_ron_str(&plate_src(width, height, traction, extra), "cases/x.ron")
        .expect("valid scene")
}

#[test]
fn a_run_over_the_budget_fails_before_building() {
    // A 1000:1 strip at element size 0.01: about 2e5 elements, 1.2 TiB (at the default
    // sizes the local-feature mesh needs about 3000).
    let scene = plate(1000.0, 1.0, "1", "bem: (element_size: 0.01)");
    let out = temp("budget");
    pdbem::setup::estimate::set_budget(1 << 30);
    let start = std::time::Instant::now();
    let err = pdbem::runner::run_scene(&scene, &out, true).expect_err("over budget");
    pdbem::setup::estimate::set_budget(0);
    let msg = format!("{err:#}");
    assert!(
        msg.contains("cases/x.ron: bem.element_size = 0.01 gives about"),
        "{msg}"
    );
    assert!(msg.contains("> budget 1.000 GiB"), "{msg}");
    assert!(
        start.elapsed().as_secs_f64() < 5.0,
        "the refusal took {:?}",
        start.elapsed()
    );
    assert!(!out.exists(), "{} left behind", out.display());
}

#[test]
fn non_finite_results_are_an_error_and_leave_no_output() {
    // A load of 1e308 Pa strains the body by 1e304: `pdbem check` refuses it
    // (src/scene/validate/strain.rs). The run's own guard is the net behind that rule:
    // the scene is run unchecked here.
    let src = plate_src(20.0, 10.0, "1e308", "bem: (element_size: 0.5)");
    let refused = Scene::from_ron_str(&src, "cases/x.ron").expect_err("refused by check");
    assert!(
        refused
            .to_string()
            .contains("boundary.0.x = -1e308: the loads strain the body"),
        "{refused}"
    );
    let mut scene = Scene::parse(&src, std::path::Path::new("cases/x.ron")).expect("parses");
    scene.normalise();
    let out = temp("nonfinite");
    let err = pdbem::runner::run_scene(&scene, &out, true).expect_err("non-finite K");
    let msg = format!("{err:#}");
    assert!(
        msg.contains("cases/x.ron: the run gave a non-finite result, tips.0.k1"),
        "{msg}"
    );
    assert!(!out.exists(), "{} left behind", out.display());
    // The same plate at a sane load runs.
    let ok = plate(20.0, 10.0, "1", "bem: (element_size: 0.5)");
    let out = temp("finite");
    let s = pdbem::runner::run_scene(&ok, &out, true).expect("runs");
    assert!(s.non_finite().is_none() && s.tips[0].k1 > 0.0);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn max_memory_takes_suffixes_on_check_run_and_sweep() {
    use clap::Parser;
    use pdbem::cli::{Cli, Command};
    let parse = |args: &[&str]| Cli::try_parse_from(args).map(|c| c.command);
    match parse(&["pdbem", "check", "a.ron", "--max-memory", "4G"]) {
        Ok(Command::Check { max_memory, .. }) => assert_eq!(max_memory, Some(4 << 30)),
        other => panic!("{other:?}"),
    }
    match parse(&["pdbem", "run", "a.ron", "--max-memory", "512M"]) {
        Ok(Command::Run { max_memory, .. }) => assert_eq!(max_memory, Some(512 << 20)),
        other => panic!("{other:?}"),
    }
    match parse(&[
        "pdbem",
        "sweep",
        "a.ron",
        "--vary",
        "bem.element_size=1",
        "--max-memory",
        "1T",
    ]) {
        Ok(Command::Sweep { max_memory, .. }) => assert_eq!(max_memory, Some(1 << 40)),
        other => panic!("{other:?}"),
    }
    let err = parse(&["pdbem", "check", "a.ron", "--max-memory", "lots"]).expect_err("bad size");
    assert!(
        err.to_string().contains("give a byte count like 4G"),
        "{err}"
    );
}

fn draws_in_time(name: &'static str, fig: XyPlot) {
    let dir = temp("plots");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let stem = dir.join(name);
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let r = pdbem::plot::save(&fig, &stem, &[PlotFormat::Svg, PlotFormat::Png]);
        let _ = tx.send(r.map(|s| s.files.len()).map_err(|e| e.to_string()));
    });
    match rx.recv_timeout(Duration::from_secs(60)) {
        Ok(Ok(n)) => {
            assert_eq!(n, 2, "{name}");
            for ext in ["svg", "png"] {
                let _ = std::fs::remove_file(dir.join(name).with_extension(ext));
            }
        }
        Ok(Err(e)) => panic!("{name}: {e}"),
        Err(_) => panic!("{name}: plotting did not finish in 60 s"),
    }
}

#[test]
fn sent_curves_of_huge_and_tiny_stresses_are_drawn() {
    for (name, sigma) in [
        ("s308", 1e308),
        ("s300", 1e300),
        ("s-308", -1e308),
        ("sub", 5e-324),
    ] {
        draws_in_time(name, sent_curves(sigma, 10.0));
    }
}

#[test]
fn series_with_non_finite_and_degenerate_values_are_drawn() {
    let mut p = XyPlot::new("t", "x", "y");
    p.series.push(Series::new(
        "s",
        vec![
            (0.0, f64::INFINITY),
            (1.0, f64::NAN),
            (-1e308, 1e308),
            (1e308, -1e308),
        ],
        SeriesStyle::LineMarkers,
    ));
    draws_in_time("mixed", p);
    let mut p = XyPlot::new("t", "x", "y");
    p.series.push(Series::new(
        "s",
        vec![(1.0, 5e-324), (1.0, 5e-324)],
        SeriesStyle::Markers,
    ));
    draws_in_time("degenerate", p);
    let mut p = XyPlot::new("t", "x", "y");
    p.log_x = true;
    p.log_y = true;
    p.series.push(Series::new(
        "s",
        vec![(5e-324, 1e308), (1e308, 5e-324), (1e-300, 1e-300)],
        SeriesStyle::LineMarkers,
    ));
    draws_in_time("log", p);
}
