//! Body geometry plot: outline and holes (closed loops), cracks, optional mesh
//! nodes, tip markers and extra labelled polylines (crack paths, windows),
//! equal aspect, axes in metres.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::map::{draw_map, map_ranges, MapChart};
use super::style::{series_color, CRACK, FONT, LABEL_SIZE};
use super::xy::Series;
use super::{msg, Figure};

/// A geometry plot.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GeometryPlot {
    /// Caption.
    pub title: String,
    /// Length unit for the axis labels (e.g. `m`).
    pub unit: String,
    /// Closed loops: outline and holes.
    pub loops: Vec<Vec<(f64, f64)>>,
    /// Cracks `(name, polyline)`.
    pub cracks: Vec<(String, Vec<(f64, f64)>)>,
    /// Mesh nodes / element end points (small dots).
    pub nodes: Vec<(f64, f64)>,
    /// Crack tips `(name, position)`.
    pub tips: Vec<(String, (f64, f64))>,
    /// Extra polylines with legend entries (paths, PD windows).
    pub extra: Vec<Series>,
}

const SIZE: (u32, u32) = (1000, 800);

impl GeometryPlot {
    fn all_points(&self) -> Vec<(f64, f64)> {
        let mut p: Vec<(f64, f64)> = self.loops.iter().flatten().copied().collect();
        p.extend(self.cracks.iter().flat_map(|c| c.1.iter().copied()));
        p.extend(self.nodes.iter().copied());
        p.extend(self.tips.iter().map(|t| t.1));
        p.extend(self.extra.iter().flat_map(|s| s.points.iter().copied()));
        p.retain(|q| q.0.is_finite() && q.1.is_finite());
        p
    }

    fn ranges(&self, labels: bool) -> ((f64, f64), (f64, f64)) {
        map_ranges(self.all_points().into_iter(), SIZE, labels)
    }
}

impl Figure for GeometryPlot {
    fn size(&self) -> (u32, u32) {
        SIZE
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        labels: bool,
    ) -> Result<(), String> {
        draw_map(
            root,
            labels,
            &self.title,
            &self.unit,
            self.ranges(labels),
            |chart| self.draw_body(chart, labels),
        )
    }
}

impl GeometryPlot {
    fn draw_body<DB: DrawingBackend>(
        &self,
        chart: &mut MapChart<'_, DB>,
        labels: bool,
    ) -> Result<(), String> {
        for (i, l) in self.loops.iter().enumerate() {
            let mut pts = l.clone();
            if let Some(first) = l.first() {
                pts.push(*first);
            }
            let a = chart
                .draw_series(std::iter::once(PathElement::new(
                    pts,
                    BLACK.stroke_width(2),
                )))
                .map_err(msg)?;
            if labels && i == 0 {
                a.label("boundary").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2))
                });
            }
        }
        if !self.nodes.is_empty() {
            let a = chart
                .draw_series(
                    self.nodes
                        .iter()
                        .map(|p| Circle::new(*p, 2, RGBColor(110, 110, 110).filled())),
                )
                .map_err(msg)?;
            if labels {
                a.label("nodes")
                    .legend(|(x, y)| Circle::new((x + 10, y), 2, RGBColor(110, 110, 110).filled()));
            }
        }
        for (i, (_, c)) in self.cracks.iter().enumerate() {
            let a = chart
                .draw_series(std::iter::once(PathElement::new(
                    c.clone(),
                    CRACK.stroke_width(3),
                )))
                .map_err(msg)?;
            if labels && i == 0 {
                a.label("crack").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], CRACK.stroke_width(3))
                });
            }
        }
        for (i, s) in self.extra.iter().enumerate() {
            let color = series_color(i);
            let a = chart
                .draw_series(std::iter::once(PathElement::new(
                    s.points.clone(),
                    color.stroke_width(2),
                )))
                .map_err(msg)?;
            if labels {
                a.label(&s.label).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            }
        }
        if !self.tips.is_empty() {
            let a = chart
                .draw_series(
                    self.tips
                        .iter()
                        .map(|(_, p)| TriangleMarker::new(*p, 8, BLUE.filled())),
                )
                .map_err(msg)?;
            if labels {
                a.label("crack tip")
                    .legend(|(x, y)| TriangleMarker::new((x + 10, y), 8, BLUE.filled()));
                chart
                    .draw_series(
                        self.tips.iter().map(|(n, p)| {
                            Text::new(n.clone(), *p, (FONT, LABEL_SIZE - 6).into_font())
                        }),
                    )
                    .map_err(msg)?;
            }
        }
        Ok(())
    }
}
