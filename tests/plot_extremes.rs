//! Plots at the extremes (issue 17): reference curves with huge, tiny or non-finite
//! values are drawn in bounded time (a range reaching infinity made the tick search of
//! the plotting library loop forever on `reference: SentTada(sigma: 1e308)`).

use std::sync::mpsc;
use std::time::Duration;

use pdbem::plot::xy::{Series, SeriesStyle, XyPlot};
use pdbem::runner::report::sent_curves;
use pdbem::scene::PlotFormat;

fn draws_in_time(name: &'static str, fig: XyPlot) {
    let dir = std::env::temp_dir().join(format!("pdbem-plot-extremes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let stem = dir.join(name);
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let r = pdbem::plot::save(&fig, &stem, &[PlotFormat::Svg, PlotFormat::Png]);
        let _ = tx.send(r.map(|s| s.files.len()).map_err(|e| e.to_string()));
    });
    match rx.recv_timeout(Duration::from_secs(60)) {
        Ok(Ok(n)) => assert_eq!(n, 2, "{name}"),
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
