//! Crack-path plot: body outline and holes, the initial cracks, PD window outlines, and
//! groups of crack paths (one colour and one legend entry per group: a run, or a mode), with
//! a marker at the end of every path; equal aspect, axes in the scene's length unit.

use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::map::{draw_map, emptiest_corner, map_ranges, MapChart};
use super::style::{series_color, CRACK};
use super::{msg, Figure};

/// Paths drawn in one colour with one legend entry.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PathGroup {
    /// Legend text.
    pub label: String,
    /// Polylines (one per tip).
    pub lines: Vec<Vec<(f64, f64)>>,
}

/// A crack-path figure.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PathsPlot {
    /// Caption.
    pub title: String,
    /// Length unit for the axis labels (e.g. `m`).
    pub unit: String,
    /// Closed loops: outline and holes.
    pub loops: Vec<Vec<(f64, f64)>>,
    /// Initial cracks (open polylines).
    pub cracks: Vec<Vec<(f64, f64)>>,
    /// PD window outlines (closed), drawn dashed.
    pub windows: Vec<Vec<(f64, f64)>>,
    /// Path groups, in legend order.
    pub groups: Vec<PathGroup>,
    /// Labelled points, drawn as crosses (e.g. where a PD-BEM body reached the PD
    /// critical stretch).
    pub marks: Vec<(String, (f64, f64))>,
}

const SIZE: (u32, u32) = (1000, 850);
const WINDOW: RGBColor = RGBColor(120, 120, 120);
const MARK: RGBColor = RGBColor(230, 120, 0);

fn closed(l: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut p = l.to_vec();
    if let Some(f) = l.first() {
        p.push(*f);
    }
    p
}

impl PathsPlot {
    fn ranges(&self, labels: bool) -> ((f64, f64), (f64, f64)) {
        let mut pts: Vec<(f64, f64)> = self.loops.iter().flatten().copied().collect();
        pts.extend(self.cracks.iter().flatten().copied());
        pts.extend(self.windows.iter().flatten().copied());
        pts.extend(
            self.groups
                .iter()
                .flat_map(|g| g.lines.iter().flatten().copied()),
        );
        pts.extend(self.marks.iter().map(|m| m.1));
        map_ranges(pts.into_iter(), SIZE, labels)
    }

    fn draw_body<DB: DrawingBackend>(
        &self,
        chart: &mut MapChart<'_, DB>,
        labels: bool,
    ) -> Result<(), String> {
        for (i, l) in self.loops.iter().enumerate() {
            let a = chart
                .draw_series(std::iter::once(PathElement::new(
                    closed(l),
                    BLACK.stroke_width(2),
                )))
                .map_err(msg)?;
            if labels && i == 0 {
                a.label("body").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2))
                });
            }
        }
        for (i, w) in self.windows.iter().enumerate() {
            let a = chart
                .draw_series(std::iter::once(DashedPathElement::new(
                    closed(w),
                    5,
                    4,
                    WINDOW.stroke_width(1),
                )))
                .map_err(msg)?;
            if labels && i == 0 {
                a.label("PD window").legend(|(x, y)| {
                    DashedPathElement::new(vec![(x, y), (x + 20, y)], 5, 4, WINDOW.stroke_width(1))
                });
            }
        }
        for (i, c) in self.cracks.iter().enumerate() {
            let a = chart
                .draw_series(std::iter::once(PathElement::new(
                    c.clone(),
                    CRACK.stroke_width(4),
                )))
                .map_err(msg)?;
            if labels && i == 0 {
                a.label("initial crack").legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], CRACK.stroke_width(4))
                });
            }
        }
        Ok(())
    }

    fn draw_groups<DB: DrawingBackend>(
        &self,
        chart: &mut MapChart<'_, DB>,
        labels: bool,
    ) -> Result<(), String> {
        for (gi, g) in self.groups.iter().enumerate() {
            // Skip black (the body colour) in the palette.
            let color = series_color(if gi >= 6 { gi + 1 } else { gi });
            for (li, line) in g.lines.iter().enumerate() {
                let a = chart
                    .draw_series(std::iter::once(PathElement::new(
                        line.clone(),
                        color.stroke_width(2),
                    )))
                    .map_err(msg)?;
                if labels && li == 0 {
                    a.label(&g.label).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                    });
                }
            }
            chart
                .draw_series(
                    g.lines
                        .iter()
                        .filter_map(|l| l.last())
                        .map(|p| Circle::new(*p, 4, color.filled())),
                )
                .map_err(msg)?;
        }
        Ok(())
    }

    fn draw_marks<DB: DrawingBackend>(
        &self,
        chart: &mut MapChart<'_, DB>,
        labels: bool,
    ) -> Result<(), String> {
        for (label, p) in &self.marks {
            let a = chart
                .draw_series(std::iter::once(Cross::new(*p, 7, MARK.stroke_width(3))))
                .map_err(msg)?;
            if labels {
                a.label(label)
                    .legend(|(x, y)| Cross::new((x + 10, y), 6, MARK.stroke_width(3)));
            }
        }
        Ok(())
    }
}

impl Figure for PathsPlot {
    fn size(&self) -> (u32, u32) {
        SIZE
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        labels: bool,
    ) -> Result<(), String> {
        let ranges = self.ranges(labels);
        let mut lines: Vec<Vec<(f64, f64)>> = self.loops.iter().map(|l| closed(l)).collect();
        lines.extend(self.cracks.iter().cloned());
        lines.extend(self.windows.iter().map(|w| closed(w)));
        lines.extend(self.groups.iter().flat_map(|g| g.lines.iter().cloned()));
        lines.extend(self.marks.iter().map(|m| vec![m.1]));
        draw_map(
            root,
            labels,
            &self.title,
            &self.unit,
            ranges,
            emptiest_corner(ranges, &lines),
            |chart| {
                self.draw_body(chart, labels)?;
                self.draw_groups(chart, labels)?;
                self.draw_marks(chart, labels)
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_png_and_svg_with_an_empty_group() {
        let dir = std::env::temp_dir().join(format!("pdbem-paths-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let p = PathsPlot {
            title: "paths".into(),
            unit: "m".into(),
            loops: vec![vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]],
            cracks: vec![vec![(0.0, 0.5), (0.2, 0.5)]],
            windows: vec![vec![(0.1, 0.4), (0.3, 0.4), (0.3, 0.6), (0.1, 0.6)]],
            groups: vec![
                PathGroup {
                    label: "bem-only".into(),
                    lines: vec![vec![(0.2, 0.5), (0.6, 0.52), (1.0, 0.55)]],
                },
                PathGroup {
                    label: "empty".into(),
                    lines: vec![],
                },
            ],
            marks: vec![("BEM body at s0".into(), (0.5, 0.05))],
        };
        let saved = crate::plot::save(
            &p,
            &dir.join("paths"),
            &[crate::scene::PlotFormat::Png, crate::scene::PlotFormat::Svg],
        )
        .expect("saved");
        assert_eq!(saved.files.len(), 2);
        for f in saved.files {
            assert!(std::fs::metadata(f).expect("file").len() > 1000);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
