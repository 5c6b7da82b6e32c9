//! Body geometry plot: outline and holes (closed loops), cracks, optional mesh
//! nodes, load arrows and supports, PD window outlines (dashed), tip markers with their
//! names pushed off the crack, and extra labelled polylines (crack paths), equal
//! aspect, axes in metres.

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
    /// Unit direction out of the crack at each tip (same order as `tips`); the tip's
    /// label is placed beside the crack, on its upward normal. Empty: labels above.
    pub tip_directions: Vec<(f64, f64)>,
    /// Load and prescribed-displacement arrows.
    pub arrows: Vec<Arrow>,
    /// Support markers (points held at zero displacement).
    pub supports: Vec<(f64, f64)>,
    /// PD window outlines (closed, drawn dashed).
    pub windows: Vec<Vec<(f64, f64)>>,
}

/// What an arrow shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArrowKind {
    /// A traction (its direction; all arrows have one length).
    Traction,
    /// A prescribed non-zero displacement.
    Displacement,
}

/// An arrow from `from` to `to` (m), head at `to`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arrow {
    /// Tail (m).
    pub from: (f64, f64),
    /// Head (m).
    pub to: (f64, f64),
    /// Traction or displacement.
    pub kind: ArrowKind,
}

const LOAD: RGBColor = RGBColor(0, 114, 178);
const DISPLACEMENT: RGBColor = RGBColor(0, 158, 115);
const SUPPORT: RGBColor = RGBColor(90, 90, 90);
const WINDOW: RGBColor = RGBColor(213, 94, 0);

const SIZE: (u32, u32) = (1000, 800);

impl GeometryPlot {
    fn all_points(&self) -> Vec<(f64, f64)> {
        let mut p: Vec<(f64, f64)> = self.loops.iter().flatten().copied().collect();
        p.extend(self.cracks.iter().flat_map(|c| c.1.iter().copied()));
        p.extend(self.nodes.iter().copied());
        p.extend(self.tips.iter().map(|t| t.1));
        p.extend(self.extra.iter().flat_map(|s| s.points.iter().copied()));
        p.extend(self.arrows.iter().flat_map(|a| [a.from, a.to]));
        p.extend(self.supports.iter().copied());
        p.retain(|q| q.0.is_finite() && q.1.is_finite());
        // Head room for the legend (upper right) above the drawing.
        let (lo, hi) = (
            super::span(p.iter().map(|q| q.1)),
            super::span(p.iter().map(|q| q.0)),
        );
        let size = (lo.1 - lo.0).max(hi.1 - hi.0);
        if !p.is_empty() && size.is_finite() {
            p.push((hi.1, lo.1 + 0.22 * size));
        }
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
            SeriesLabelPosition::UpperRight,
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
        self.draw_windows(chart, labels)?;
        self.draw_arrows(chart, labels)?;
        self.draw_supports(chart, labels)?;
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
                self.draw_tip_labels(chart)?;
            }
        }
        Ok(())
    }
}

impl GeometryPlot {
    fn draw_windows<DB: DrawingBackend>(
        &self,
        chart: &mut MapChart<'_, DB>,
        labels: bool,
    ) -> Result<(), String> {
        let pts = self.all_points();
        let (xs, ys) = (
            super::span(pts.iter().map(|p| p.0)),
            super::span(pts.iter().map(|p| p.1)),
        );
        let dash = (xs.1 - xs.0).max(ys.1 - ys.0) / 80.0;
        for (i, w) in self.windows.iter().enumerate() {
            let mut ring = w.clone();
            if let Some(f) = w.first() {
                ring.push(*f);
            }
            let a = chart
                .draw_series(
                    dashed(&ring, dash)
                        .into_iter()
                        .map(|seg| PathElement::new(seg, WINDOW.stroke_width(2))),
                )
                .map_err(msg)?;
            if labels && i == 0 {
                a.label("PD window").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 8, y)], WINDOW.stroke_width(2))
                });
            }
        }
        Ok(())
    }

    fn draw_arrows<DB: DrawingBackend>(
        &self,
        chart: &mut MapChart<'_, DB>,
        labels: bool,
    ) -> Result<(), String> {
        for (kind, color, name) in [
            (ArrowKind::Traction, LOAD, "load (traction direction)"),
            (
                ArrowKind::Displacement,
                DISPLACEMENT,
                "prescribed displacement",
            ),
        ] {
            let mine: Vec<&Arrow> = self.arrows.iter().filter(|a| a.kind == kind).collect();
            if mine.is_empty() {
                continue;
            }
            let a = chart
                .draw_series(
                    mine.iter()
                        .flat_map(|a| arrow_paths(a))
                        .map(|p| PathElement::new(p, color.stroke_width(2))),
                )
                .map_err(msg)?;
            if labels {
                a.label(name).legend(move |(x, y)| {
                    PathElement::new(
                        vec![
                            (x, y),
                            (x + 20, y),
                            (x + 14, y - 4),
                            (x + 20, y),
                            (x + 14, y + 4),
                        ],
                        color.stroke_width(2),
                    )
                });
            }
        }
        Ok(())
    }

    fn draw_supports<DB: DrawingBackend>(
        &self,
        chart: &mut MapChart<'_, DB>,
        labels: bool,
    ) -> Result<(), String> {
        if self.supports.is_empty() {
            return Ok(());
        }
        let a = chart
            .draw_series(self.supports.iter().map(|p| {
                EmptyElement::at(*p) + Rectangle::new([(-5, -5), (5, 5)], SUPPORT.filled())
            }))
            .map_err(msg)?;
        if labels {
            a.label("support (u_x or u_y = 0)").legend(|(x, y)| {
                Rectangle::new([(x + 5, y - 5), (x + 15, y + 5)], SUPPORT.filled())
            });
        }
        Ok(())
    }

    /// Tip names beside their tips, on the side of the crack's upward (or right) normal.
    fn draw_tip_labels<DB: DrawingBackend>(
        &self,
        chart: &mut MapChart<'_, DB>,
    ) -> Result<(), String> {
        use plotters::style::text_anchor::{HPos, Pos, VPos};
        for (i, (name, p)) in self.tips.iter().enumerate() {
            // Beside the crack, not along it (two tips facing each other across a gap
            // would put their names on top of each other): along the normal that points
            // up, or right for a vertical crack.
            let t = self.tip_directions.get(i).copied().unwrap_or((1.0, 0.0));
            let mut d = (-t.1, t.0);
            if d.1 < -1e-9 || (d.1.abs() <= 1e-9 && d.0 < 0.0) {
                d = (-d.0, -d.1);
            }
            let h = if d.0 > 0.3 {
                HPos::Left
            } else if d.0 < -0.3 {
                HPos::Right
            } else {
                HPos::Center
            };
            let v = if d.1 > 0.3 {
                VPos::Bottom
            } else if d.1 < -0.3 {
                VPos::Top
            } else {
                VPos::Center
            };
            let style = TextStyle::from((FONT, LABEL_SIZE - 4).into_font()).pos(Pos::new(h, v));
            let off = (12.0 * d.0, -12.0 * d.1);
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at(*p)
                        + Text::new(name.clone(), (off.0 as i32, off.1 as i32), style),
                ))
                .map_err(msg)?;
        }
        Ok(())
    }
}

/// The shaft and the two head strokes of an arrow (head 25 % of its length, 25 degrees).
fn arrow_paths(a: &Arrow) -> Vec<Vec<(f64, f64)>> {
    let (dx, dy) = (a.to.0 - a.from.0, a.to.1 - a.from.1);
    let (c, s) = (25f64.to_radians().cos(), 25f64.to_radians().sin());
    let head = |sign: f64| {
        let (hx, hy) = (-0.25 * dx, -0.25 * dy);
        (
            a.to.0 + c * hx - sign * s * hy,
            a.to.1 + sign * s * hx + c * hy,
        )
    };
    vec![vec![a.from, a.to], vec![head(1.0), a.to, head(-1.0)]]
}

/// A polyline cut into dashes about `dash` long (every other piece drawn, at least two
/// dashes per side).
fn dashed(pts: &[(f64, f64)], dash: f64) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        let n = ((len / (2.0 * dash.max(1e-300))).round() as usize).clamp(2, 40);
        for k in (0..2 * n).step_by(2) {
            let t0 = k as f64 / (2 * n) as f64;
            let t1 = (k + 1) as f64 / (2 * n) as f64;
            let at = |t: f64| (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
            out.push(vec![at(t0), at(t1)]);
        }
    }
    out
}
