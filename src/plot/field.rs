//! Scatter-field plot: points coloured by a value (viridis) with a colour
//! bar, equal aspect; optional boundary loops drawn over the points.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::style::{viridis, CAPTION_SIZE, FONT, LABEL_SIZE};
use super::ticks::{Ticked, Ticks};
use super::{equal_aspect, msg, span, Figure};
use plotters::coord::types::RangedCoordf64;

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
        let mut pts: Vec<(f64, f64)> = self.points.clone();
        pts.extend(self.loops.iter().flatten().copied());
        let (xs, ys) = (span(pts.iter().map(|p| p.0)), span(pts.iter().map(|p| p.1)));
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
                .caption(&self.title, (FONT, CAPTION_SIZE))
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
        for l in &self.loops {
            let mut p = l.clone();
            if let Some(f) = l.first() {
                p.push(*f);
            }
            chart
                .draw_series(std::iter::once(PathElement::new(p, BLACK.stroke_width(1))))
                .map_err(msg)?;
        }
        Ok(())
    }
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
