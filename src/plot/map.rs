//! The frame shared by the map-like figures (body geometry, crack paths): equal aspect,
//! caption, axes in the scene's length unit, a light grid, the content, a legend.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{CAPTION_SIZE, FONT, LABEL_SIZE};
use super::ticks::{Ticked, Ticks};
use super::{equal_aspect, msg, span};

/// Chart of a map figure (metres on both axes).
pub(crate) type MapChart<'a, DB> =
    ChartContext<'a, DB, Cartesian2d<Ticked<RangedCoordf64>, Ticked<RangedCoordf64>>>;

const MARGIN: u32 = 20;
const X_AREA: u32 = 55;
const Y_AREA: u32 = 95;
const CAPTION: u32 = 45;

/// Equal-aspect data ranges covering the finite `points` in a figure of `size` pixels.
pub(crate) fn map_ranges(
    points: impl Iterator<Item = (f64, f64)>,
    size: (u32, u32),
    labels: bool,
) -> ((f64, f64), (f64, f64)) {
    let pts: Vec<(f64, f64)> = points
        .filter(|q| q.0.is_finite() && q.1.is_finite())
        .collect();
    let (xs, ys) = (span(pts.iter().map(|p| p.0)), span(pts.iter().map(|p| p.1)));
    let (w, h) = if labels {
        (
            size.0 - 2 * MARGIN - Y_AREA,
            size.1 - 2 * MARGIN - X_AREA - CAPTION,
        )
    } else {
        (size.0 - 2 * MARGIN, size.1 - 2 * MARGIN)
    };
    equal_aspect((xs.0, ys.0), (xs.1, ys.1), w, h)
}

/// The corner of `ranges` whose box (40 % of the width, 30 % of the height) the
/// polylines `lines` cross least (each segment sampled at 10 points), so a legend there
/// hides as little as possible; upper right on a tie.
pub(crate) fn emptiest_corner(
    ranges: ((f64, f64), (f64, f64)),
    lines: &[Vec<(f64, f64)>],
) -> SeriesLabelPosition {
    let ((x0, x1), (y0, y1)) = ranges;
    let unit = |p: (f64, f64)| ((p.0 - x0) / (x1 - x0), (p.1 - y0) / (y1 - y0));
    let mut pts: Vec<(f64, f64)> = Vec::new();
    for l in lines {
        pts.extend(l.iter().map(|p| unit(*p)));
        for w in l.windows(2) {
            let (a, b) = (unit(w[0]), unit(w[1]));
            pts.extend((1..10).map(|k| {
                let t = k as f64 / 10.0;
                (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))
            }));
        }
    }
    let count = |left: bool, top: bool| {
        pts.iter()
            .filter(|(u, v)| {
                (if left { *u < 0.4 } else { *u > 0.6 }) && (if top { *v > 0.7 } else { *v < 0.3 })
            })
            .count()
    };
    [
        (SeriesLabelPosition::UpperRight, count(false, true)),
        (SeriesLabelPosition::UpperLeft, count(true, true)),
        (SeriesLabelPosition::LowerRight, count(false, false)),
        (SeriesLabelPosition::LowerLeft, count(true, false)),
    ]
    .into_iter()
    .min_by_key(|(_, n)| *n)
    .map_or(SeriesLabelPosition::UpperRight, |(p, _)| p)
}

/// Draws a map figure on `root` over `ranges`: `content` draws the data (and registers
/// its legend entries); the legend goes to the `legend` corner. Without `labels`: no
/// caption, axes text or legend.
pub(crate) fn draw_map<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    labels: bool,
    title: &str,
    unit: &str,
    ranges: ((f64, f64), (f64, f64)),
    legend: SeriesLabelPosition,
    content: impl FnOnce(&mut MapChart<'_, DB>) -> Result<(), String>,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(msg)?;
    let ((x0, x1), (y0, y1)) = ranges;
    let mut builder = ChartBuilder::on(root);
    builder.margin(MARGIN);
    if labels {
        builder
            .caption(title, (FONT, CAPTION_SIZE))
            .x_label_area_size(X_AREA)
            .y_label_area_size(Y_AREA);
    }
    let (xt, yt) = (
        Ticks::linear_if(labels, x0, x1, 11),
        Ticks::linear_if(labels, y0, y1, 11),
    );
    let mut chart = builder
        .build_cartesian_2d(
            Ticked::<RangedCoordf64>::new(x0..x1, &xt),
            Ticked::<RangedCoordf64>::new(y0..y1, &yt),
        )
        .map_err(msg)?;
    let fx = |v: &f64| xt.label_of(*v);
    let fy = |v: &f64| yt.label_of(*v);
    let mut mesh = chart.configure_mesh();
    if labels {
        mesh.x_desc(format!("x ({unit})"))
            .y_desc(format!("y ({unit})"))
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .axis_desc_style((FONT, LABEL_SIZE))
            .label_style((FONT, LABEL_SIZE - 4));
    } else {
        mesh.x_labels(0).y_labels(0);
    }
    mesh.light_line_style(RGBColor(240, 240, 240))
        .draw()
        .map_err(msg)?;
    content(&mut chart)?;
    if labels {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, LABEL_SIZE - 4))
            .position(legend)
            .draw()
            .map_err(msg)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path through the upper right sends the legend elsewhere; nothing in any corner
    /// keeps it at the upper right.
    #[test]
    fn the_legend_avoids_the_crowded_corner() {
        let r = ((0.0, 1.0), (0.0, 1.0));
        assert_eq!(emptiest_corner(r, &[]), SeriesLabelPosition::UpperRight);
        let path = vec![(0.65, 0.8), (0.95, 0.95)];
        let low = vec![(0.1, 0.1), (0.9, 0.1)];
        assert_eq!(
            emptiest_corner(r, &[path, low]),
            SeriesLabelPosition::UpperLeft
        );
    }
}
