//! Line/marker plots of series against a parameter, on linear or log axes:
//! K against a/W with the analytic curve, error against element size, error
//! against wall time (log-log).

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{series_color, CAPTION_SIZE, FONT, LABEL_SIZE};
use super::ticks::{Ticked, Ticks};
use super::{msg, span, Figure};
use plotters::coord::combinators::LogCoord;
use plotters::coord::types::RangedCoordf64;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesStyle {
    /// A line (analytic curves).
    Line,
    /// Markers only (computed points).
    Markers,
    /// Line through markers.
    LineMarkers,
}

/// One labelled series of `(x, y)` points.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: SeriesStyle,
}

impl Series {
    /// A series.
    pub fn new(label: impl Into<String>, points: Vec<(f64, f64)>, style: SeriesStyle) -> Series {
        Series {
            label: label.into(),
            points,
            style,
        }
    }
}

/// A value-against-parameter plot.
#[derive(Debug, Clone, PartialEq)]
pub struct XyPlot {
    /// Caption.
    pub title: String,
    /// x axis label with unit, e.g. `a/W (-)`.
    pub x_label: String,
    /// y axis label with unit, e.g. `K_I (Pa m^0.5)`.
    pub y_label: String,
    /// Series, in legend order.
    pub series: Vec<Series>,
    /// Logarithmic x axis (non-positive x are dropped).
    pub log_x: bool,
    /// Logarithmic y axis (non-positive y are dropped).
    pub log_y: bool,
    /// Text next to points (e.g. the parameter value of each run of a sweep).
    pub point_labels: Vec<((f64, f64), String)>,
}

impl XyPlot {
    /// A linear plot.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> XyPlot {
        XyPlot {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            series: Vec::new(),
            log_x: false,
            log_y: false,
            point_labels: Vec::new(),
        }
    }

    /// Error against wall time, log-log: one point per run.
    pub fn error_vs_time(
        title: impl Into<String>,
        error_label: impl Into<String>,
        series: Vec<Series>,
    ) -> XyPlot {
        XyPlot {
            title: title.into(),
            x_label: "wall time (s)".into(),
            y_label: error_label.into(),
            series,
            log_x: true,
            log_y: true,
            point_labels: Vec::new(),
        }
    }

    /// Points usable on these axes (finite, positive on log axes).
    fn usable(&self, p: &(f64, f64)) -> bool {
        p.0.is_finite()
            && p.1.is_finite()
            && (!self.log_x || p.0 > 0.0)
            && (!self.log_y || p.1 > 0.0)
    }

    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let pts: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|p| self.usable(p))
            .collect();
        let pad = |(a, b): (f64, f64), log: bool| {
            if log {
                // Log axes: positive and at least 1/AXIS_LIMIT, so the ends stay finite.
                let floor = 1.0 / super::AXIS_LIMIT;
                let (a, b) = if a > 0.0 {
                    let a = a.max(floor);
                    (a, if b > a { b } else { 10.0 * a })
                } else {
                    (1.0, 10.0)
                };
                (a / 1.5, b * 1.5)
            } else {
                let d = 0.05 * (b - a);
                (a - d, b + d)
            }
        };
        let x = pad(span(pts.iter().map(|p| p.0)), self.log_x);
        let y = pad(span(pts.iter().map(|p| p.1)), self.log_y);
        (x, y)
    }
}

impl Figure for XyPlot {
    fn size(&self) -> (u32, u32) {
        (900, 650)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        labels: bool,
    ) -> Result<(), String> {
        root.fill(&WHITE).map_err(msg)?;
        let ((x0, x1), (y0, y1)) = self.ranges();
        let tick = |lo: f64, hi: f64, log: bool, n: usize| {
            if !labels {
                Ticks::none()
            } else if log {
                Ticks::log(lo, hi)
            } else {
                Ticks::linear(lo, hi, n)
            }
        };
        let (xt, yt) = (tick(x0, x1, self.log_x, 10), tick(y0, y1, self.log_y, 9));
        let axes = (&xt, &yt);
        match (self.log_x, self.log_y) {
            (false, false) => self.draw_on(
                root,
                labels,
                Ticked::<RangedCoordf64>::new(x0..x1, &xt),
                Ticked::<RangedCoordf64>::new(y0..y1, &yt),
                axes,
            ),
            (true, false) => self.draw_on(
                root,
                labels,
                Ticked::<LogCoord<f64>>::new((x0..x1).log_scale(), &xt),
                Ticked::<RangedCoordf64>::new(y0..y1, &yt),
                axes,
            ),
            (false, true) => self.draw_on(
                root,
                labels,
                Ticked::<RangedCoordf64>::new(x0..x1, &xt),
                Ticked::<LogCoord<f64>>::new((y0..y1).log_scale(), &yt),
                axes,
            ),
            (true, true) => self.draw_on(
                root,
                labels,
                Ticked::<LogCoord<f64>>::new((x0..x1).log_scale(), &xt),
                Ticked::<LogCoord<f64>>::new((y0..y1).log_scale(), &yt),
                axes,
            ),
        }
    }
}

impl XyPlot {
    fn draw_on<DB, XR, YR>(
        &self,
        root: &DrawingArea<DB, Shift>,
        labels: bool,
        xr: XR,
        yr: YR,
        (xt, yt): (&Ticks, &Ticks),
    ) -> Result<(), String>
    where
        DB: DrawingBackend,
        XR: AsRangedCoord<Value = f64>,
        YR: AsRangedCoord<Value = f64>,
        XR::CoordDescType: ValueFormatter<f64>,
        YR::CoordDescType: ValueFormatter<f64>,
    {
        let mut builder = ChartBuilder::on(root);
        builder.margin(20);
        if labels {
            builder
                .caption(&self.title, (FONT, CAPTION_SIZE))
                .x_label_area_size(55)
                .y_label_area_size(85);
        }
        let mut chart = builder.build_cartesian_2d(xr, yr).map_err(msg)?;
        let fx = |v: &f64| xt.label_of(*v);
        let fy = |v: &f64| yt.label_of(*v);
        let mut mesh = chart.configure_mesh();
        if labels {
            mesh.x_desc(&self.x_label)
                .y_desc(&self.y_label)
                .x_label_formatter(&fx)
                .y_label_formatter(&fy)
                .axis_desc_style((FONT, LABEL_SIZE))
                .label_style((FONT, LABEL_SIZE - 4));
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(msg)?;
        let mut marker_index = 0;
        for (i, s) in self.series.iter().enumerate() {
            let color = series_color(i);
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| self.usable(p))
                .collect();
            let line = matches!(s.style, SeriesStyle::Line | SeriesStyle::LineMarkers);
            let marks = matches!(s.style, SeriesStyle::Markers | SeriesStyle::LineMarkers);
            if line {
                let a = chart
                    .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                    .map_err(msg)?;
                if labels {
                    a.label(&s.label).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                }
            }
            if marks {
                // Marker series take turns: a ring, a small disc, a triangle, a square, so
                // points at the same place stay visible (K_I = K_II at 45 degrees).
                let shape = marker_index;
                marker_index += 1;
                let ring = color.stroke_width(2);
                let size = |r: i32| marker_size(r, pts.len());
                let a = match shape % 4 {
                    0 => chart.draw_series(pts.iter().map(|p| Circle::new(*p, size(8), ring))),
                    1 => chart
                        .draw_series(pts.iter().map(|p| Circle::new(*p, size(4), color.filled()))),
                    2 => chart.draw_series(
                        pts.iter()
                            .map(|p| TriangleMarker::new(*p, size(7), color.filled())),
                    ),
                    _ => chart.draw_series(pts.iter().map(|p| {
                        let h = size(4);
                        EmptyElement::at(*p) + Rectangle::new([(-h, -h), (h, h)], color.filled())
                    })),
                }
                .map_err(msg)?;
                if labels && !line {
                    let a = a.label(&s.label);
                    match shape % 4 {
                        0 => a.legend(move |(x, y)| Circle::new((x + 10, y), 8, ring)),
                        1 => a.legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled())),
                        2 => a.legend(move |(x, y)| {
                            TriangleMarker::new((x + 10, y), 7, color.filled())
                        }),
                        _ => a.legend(move |(x, y)| {
                            Rectangle::new([(x + 6, y - 4), (x + 14, y + 4)], color.filled())
                        }),
                    };
                }
            }
        }
        if labels {
            let style = (FONT, LABEL_SIZE - 6).into_font();
            chart
                .draw_series(
                    self.point_labels
                        .iter()
                        .filter(|(p, _)| self.usable(p))
                        .map(|(p, t)| {
                            EmptyElement::at(*p) + Text::new(t.clone(), (9, -18), style.clone())
                        }),
                )
                .map_err(msg)?;
        }
        if labels && !self.series.is_empty() {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font((FONT, LABEL_SIZE - 4))
                .position(self.legend_corner())
                .draw()
                .map_err(msg)?;
        }
        Ok(())
    }
}

impl XyPlot {
    /// The corner whose box (40 % of the width, 30 % of the height) holds the fewest
    /// points, so the legend hides as little data as possible; upper left on a tie.
    fn legend_corner(&self) -> SeriesLabelPosition {
        let ((x0, x1), (y0, y1)) = self.ranges();
        let unit = |v: f64, lo: f64, hi: f64, log: bool| {
            if log {
                (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
            } else {
                (v - lo) / (hi - lo)
            }
        };
        let mut pts: Vec<(f64, f64)> = Vec::new();
        for s in &self.series {
            let own: Vec<(f64, f64)> = s
                .points
                .iter()
                .filter(|p| self.usable(p))
                .map(|p| (unit(p.0, x0, x1, self.log_x), unit(p.1, y0, y1, self.log_y)))
                .collect();
            pts.extend(&own);
            // A line crosses the boxes between its points too.
            if s.style != SeriesStyle::Markers {
                for w in own.windows(2) {
                    pts.extend((1..10).map(|k| {
                        let t = k as f64 / 10.0;
                        (
                            w[0].0 + t * (w[1].0 - w[0].0),
                            w[0].1 + t * (w[1].1 - w[0].1),
                        )
                    }));
                }
            }
        }
        let count = |left: bool, top: bool| {
            pts.iter()
                .filter(|(u, v)| {
                    (if left { *u < 0.4 } else { *u > 0.6 })
                        && (if top { *v > 0.7 } else { *v < 0.3 })
                })
                .count()
        };
        [
            (SeriesLabelPosition::UpperLeft, count(true, true)),
            (SeriesLabelPosition::UpperRight, count(false, true)),
            (SeriesLabelPosition::LowerLeft, count(true, false)),
            (SeriesLabelPosition::LowerRight, count(false, false)),
        ]
        .into_iter()
        .min_by_key(|(_, n)| *n)
        .map_or(SeriesLabelPosition::UpperLeft, |(p, _)| p)
    }
}

/// Marker size (pixels) of a series of `n` points: `full` up to 40 points, smaller in
/// proportion to 1/sqrt(n) beyond (at least 2 px), so a dense series (a load ramp of a
/// hundred steps) reads as a curve of small marks, not a smear of rings.
fn marker_size(full: i32, n: usize) -> i32 {
    if n <= 40 {
        return full;
    }
    let k = (40.0 / n as f64).sqrt().max(0.35);
    ((full as f64 * k).round() as i32).max(2)
}
