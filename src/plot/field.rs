//! Scatter-field plot: points coloured by a value (viridis) with a colour
//! bar, equal aspect; optional boundary loops drawn over the points.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{viridis, CAPTION_SIZE, CRACK, FONT, LABEL_SIZE};
use super::ticks::{Ticked, Ticks};
use super::{equal_aspect, msg, span, Figure};
use plotters::coord::types::RangedCoordf64;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A polyline (m).
pub type Polyline = Vec<(f64, f64)>;

/// A labelled point (m).
pub type Mark = ((f64, f64), String);

/// A field sampled at points.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScatterField {
    /// Caption.
    pub title: String,
    /// Length unit for the axes (e.g. `m`).
    pub unit: String,
    /// Colour-bar label with unit, e.g. `damage (-)`.
    pub value_label: String,
    /// Point positions.
    pub points: Vec<(f64, f64)>,
    /// One value per point.
    pub values: Vec<f64>,
    /// Colour range; default the finite min..max of `values`.
    pub range: Option<(f64, f64)>,
    /// Boundary loops drawn on top.
    pub loops: Vec<Vec<(f64, f64)>>,
    /// Marker radius in pixels (0 = automatic).
    pub marker_px: u32,
    /// Polylines drawn over the field in the crack colour (crack paths).
    pub paths: Vec<Polyline>,
    /// Labelled marks (crack tips): a ring in the crack colour and its text.
    pub marks: Vec<Mark>,
    /// The region shown, lower-left and upper-right corners (widened to equal aspect);
    /// default: all points and loops. Loops and paths are clipped to it.
    pub view: Option<((f64, f64), (f64, f64))>,
}

const SIZE: (u32, u32) = (1100, 800);
const BAR: u32 = 150;

impl Figure for ScatterField {
    fn size(&self) -> (u32, u32) {
        SIZE
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        labels: bool,
    ) -> Result<(), String> {
        root.fill(&WHITE).map_err(msg)?;
        let (main, bar) = root.split_horizontally(SIZE.0 - BAR);
        let (vmin, vmax) = self
            .range
            .unwrap_or_else(|| span(self.values.iter().copied()));
        self.draw_points(&main, labels, vmin, vmax)?;
        draw_colorbar(&bar, labels, vmin, vmax, &self.value_label)
    }
}

impl ScatterField {
    fn draw_points<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        labels: bool,
        vmin: f64,
        vmax: f64,
    ) -> Result<(), String> {
        let (xs, ys) = match self.view {
            Some((lo, hi)) => ((lo.0, hi.0), (lo.1, hi.1)),
            None => {
                let mut pts: Vec<(f64, f64)> = self.points.clone();
                pts.extend(self.loops.iter().flatten().copied());
                (span(pts.iter().map(|p| p.0)), span(pts.iter().map(|p| p.1)))
            }
        };
        let (w, h) = area.dim_in_pixel();
        let (pw, ph) = if labels {
            (w.saturating_sub(125), h.saturating_sub(140))
        } else {
            (w - 40, h - 40)
        };
        let ((x0, x1), (y0, y1)) = equal_aspect((xs.0, ys.0), (xs.1, ys.1), pw, ph);
        let mut builder = ChartBuilder::on(area);
        builder.margin(20);
        if labels {
            builder
                .caption(&self.title, (FONT, caption_size(&self.title)))
                .x_label_area_size(55)
                .y_label_area_size(85);
        }
        let (xt, yt) = (
            Ticks::linear_if(labels, x0, x1, 9),
            Ticks::linear_if(labels, y0, y1, 9),
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
            mesh.x_desc(format!("x ({})", self.unit))
                .y_desc(format!("y ({})", self.unit))
                .x_label_formatter(&fx)
                .y_label_formatter(&fy)
                .axis_desc_style((FONT, LABEL_SIZE))
                .label_style((FONT, LABEL_SIZE - 4));
        } else {
            mesh.x_labels(0).y_labels(0);
        }
        mesh.disable_mesh().draw().map_err(msg)?;
        let r = if self.marker_px > 0 {
            self.marker_px
        } else {
            auto_marker(self.points.len(), pw, ph)
        };
        let scale = |v: f64| (v - vmin) / (vmax - vmin).max(1e-300);
        chart
            .draw_series(
                self.points
                    .iter()
                    .zip(&self.values)
                    .map(|(p, v)| Circle::new(*p, r, viridis(scale(*v)).filled())),
            )
            .map_err(msg)?;
        let view = ((x0, y0), (x1, y1));
        for l in &self.loops {
            let mut p = l.clone();
            if let Some(f) = l.first() {
                p.push(*f);
            }
            for piece in clip_polyline(&p, view) {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        piece,
                        BLACK.stroke_width(1),
                    )))
                    .map_err(msg)?;
            }
        }
        for l in &self.paths {
            for piece in clip_polyline(l, view) {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        piece,
                        CRACK.stroke_width(3),
                    )))
                    .map_err(msg)?;
            }
        }
        for (p, text) in &self.marks {
            let inside = p.0 >= x0 && p.0 <= x1 && p.1 >= y0 && p.1 <= y1;
            if !inside {
                continue;
            }
            chart
                .draw_series(std::iter::once(Circle::new(*p, 7, CRACK.stroke_width(3))))
                .map_err(msg)?;
            if labels {
                chart
                    .draw_series(std::iter::once(Text::new(
                        text.clone(),
                        *p,
                        (FONT, LABEL_SIZE - 2)
                            .into_font()
                            .color(&CRACK)
                            .pos(Pos::new(HPos::Left, VPos::Bottom)),
                    )))
                    .map_err(msg)?;
            }
        }
        Ok(())
    }
}

/// The pieces of polyline `p` inside the box `view` (Liang-Barsky clipping of each
/// segment; consecutive visible segments join into one piece).
pub fn clip_polyline(p: &[(f64, f64)], view: ((f64, f64), (f64, f64))) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut open = false;
    for w in p.windows(2) {
        match clip_segment(w[0], w[1], view) {
            Some((a, b)) => {
                let joins = open && out.last().and_then(|l| l.last()) == Some(&a);
                if !joins {
                    out.push(vec![a]);
                }
                out.last_mut().expect("a piece").push(b);
                open = b == w[1];
            }
            None => open = false,
        }
    }
    out
}

/// Liang-Barsky: the part of segment a-b inside the box, if any.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    ((x0, y0), (x1, y1)): ((f64, f64), (f64, f64)),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then(|| {
        let at = |t: f64| {
            if t == 0.0 {
                a
            } else if t == 1.0 {
                b
            } else {
                (a.0 + t * dx, a.1 + t * dy)
            }
        };
        (at(t0), at(t1))
    })
}

/// Caption size that keeps `title` inside the figure: [`CAPTION_SIZE`] up to 64
/// characters, smaller in proportion beyond (at least 16 px).
fn caption_size(title: &str) -> u32 {
    let n = title.chars().count().max(1) as u32;
    (CAPTION_SIZE * 64 / n).clamp(16, CAPTION_SIZE)
}

/// Marker radius so that `n` points roughly tile a `w x h` area.
fn auto_marker(n: usize, w: u32, h: u32) -> u32 {
    let per = ((w as f64 * h as f64) / n.max(1) as f64).sqrt();
    ((per * 0.5).round() as u32).clamp(1, 8)
}

fn draw_colorbar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    labels: bool,
    vmin: f64,
    vmax: f64,
    label: &str,
) -> Result<(), String> {
    let mut builder = ChartBuilder::on(area);
    builder.margin_top(70).margin_bottom(75).margin_right(10);
    if labels {
        builder.y_label_area_size(0).right_y_label_area_size(80);
    }
    let yt = Ticks::linear_if(labels, vmin, vmax, 9);
    let mut chart = builder
        .build_cartesian_2d(0.0..1.0, Ticked::<RangedCoordf64>::new(vmin..vmax, &yt))
        .map_err(msg)?;
    let steps = 100;
    chart
        .draw_series((0..steps).map(|k| {
            let a = vmin + (vmax - vmin) * k as f64 / steps as f64;
            let b = vmin + (vmax - vmin) * (k + 1) as f64 / steps as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                viridis(k as f64 / (steps - 1) as f64).filled(),
            )
        }))
        .map_err(msg)?;
    if labels {
        let fy = |v: &f64| yt.label_of(*v);
        chart
            .configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(label)
            .y_label_formatter(&fy)
            .axis_desc_style((FONT, LABEL_SIZE - 2))
            .label_style((FONT, LABEL_SIZE - 6))
            .draw()
            .map_err(msg)?;
    }
    Ok(())
}

#[cfg(test)]
mod clip_tests {
    use super::clip_polyline;

    #[test]
    fn a_polyline_through_the_box_keeps_its_inside_part() {
        let view = ((0.0, 0.0), (1.0, 1.0));
        // In from the left, out at the top, back in from the top, out at the right.
        let p = [
            (-1.0, 0.5),
            (0.5, 0.5),
            (0.5, 2.0),
            (0.8, 2.0),
            (0.8, 0.2),
            (2.0, 0.2),
        ];
        let pieces = clip_polyline(&p, view);
        assert_eq!(
            pieces,
            vec![
                vec![(0.0, 0.5), (0.5, 0.5), (0.5, 1.0)],
                vec![(0.8, 1.0), (0.8, 0.2), (1.0, 0.2)]
            ]
        );
        assert!(clip_polyline(&[(2.0, 2.0), (3.0, 3.0)], view).is_empty());
    }
}
