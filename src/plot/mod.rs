//! Report plots with plotters, as PNG and SVG: plain data in, files out.
//!
//! - [`geometry::GeometryPlot`]: outline, holes, cracks, optional mesh nodes,
//!   tip markers and extra polylines (paths, windows); equal aspect.
//! - [`xy::XyPlot`]: value against a parameter with analytic curves (e.g. K
//!   against a/W), or error against wall time on log-log axes.
//! - [`field::ScatterField`]: nodes coloured by a value (PD damage,
//!   displacement) with a colour bar; equal aspect.
//! - [`paths::PathsPlot`]: crack paths of growth runs over the body outline, with
//!   PD window outlines; one colour per run or mode.
//!
//! - [`ticks`]: the one tick placement and label formatter every axis and colour bar
//!   uses (no `0.30000000000000004`, no `0.0` for 5e-6, at least three ticks on log
//!   axes).
//!
//! [`save`] writes a [`Figure`] in the requested formats. If drawing text
//! fails (no usable font), the figure is drawn again without text and
//! [`SavedPlot::degraded`] is set; plotters panics are caught and returned as
//! errors. Plot code never panics on bad data: empty or non-finite data give
//! an empty frame.

pub mod field;
pub mod geometry;
mod map;
pub mod paths;
pub mod style;
pub mod ticks;
pub mod xy;

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::scene::PlotFormat;

pub use field::ScatterField;
pub use geometry::GeometryPlot;
pub use paths::{PathGroup, PathsPlot};
pub use xy::{Series, SeriesStyle, XyPlot};

/// A plot that can draw itself on any plotters backend.
pub trait Figure {
    /// Image size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws on `root`; without `labels` no text at all is drawn.
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        labels: bool,
    ) -> Result<(), String>;
}

/// Plot failure.
#[derive(Debug, thiserror::Error)]
#[error("plot {file}: {message}")]
pub struct PlotError {
    /// File being written.
    pub file: PathBuf,
    /// What went wrong.
    pub message: String,
}

/// Files written by [`save`].
#[derive(Debug, Clone, Default)]
pub struct SavedPlot {
    /// Written files.
    pub files: Vec<PathBuf>,
    /// True when text could not be drawn and the plot was written without it.
    pub degraded: bool,
}

/// Writes `fig` to `<stem>.png` and/or `<stem>.svg`.
pub fn save<F: Figure>(
    fig: &F,
    stem: &Path,
    formats: &[PlotFormat],
) -> Result<SavedPlot, PlotError> {
    let mut saved = SavedPlot::default();
    for f in formats {
        let ext = match f {
            PlotFormat::Png => "png",
            PlotFormat::Svg => "svg",
        };
        let file = stem.with_extension(ext);
        let first = render(fig, &file, *f, true);
        if let Err(first_err) = first {
            render(fig, &file, *f, false).map_err(|e| PlotError {
                file: file.clone(),
                message: format!("{first_err}; without text: {e}"),
            })?;
            saved.degraded = true;
        }
        saved.files.push(file);
    }
    Ok(saved)
}

/// Renders one file, catching plotters panics.
fn render<F: Figure>(fig: &F, file: &Path, format: PlotFormat, labels: bool) -> Result<(), String> {
    let size = fig.size();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| match format {
        PlotFormat::Png => {
            let root = BitMapBackend::new(file, size).into_drawing_area();
            fig.draw(&root, labels)?;
            root.present().map_err(|e| e.to_string())
        }
        PlotFormat::Svg => {
            let root = SVGBackend::new(file, size).into_drawing_area();
            fig.draw(&root, labels)?;
            root.present().map_err(|e| e.to_string())
        }
    }));
    match result {
        Ok(r) => r,
        Err(_) => Err("the plotting library panicked".into()),
    }
}

/// Converts any displayable error to a message.
pub(crate) fn msg<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// Largest magnitude an axis may reach: beyond it values are clamped, so that ranges,
/// their padding and the tick computation of the plotting library stay finite (a range
/// reaching infinity made the tick search loop forever).
pub(crate) const AXIS_LIMIT: f64 = 1e150;

/// Finite `(min, max)` of values (clamped to [`AXIS_LIMIT`]), widened when empty or
/// degenerate.
pub(crate) fn span(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values
        .filter(|v| v.is_finite())
        .map(|v| v.clamp(-AXIS_LIMIT, AXIS_LIMIT))
    {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo <= 1e-300_f64.max(1e-12 * hi.abs().max(lo.abs())) {
        let d = if lo == 0.0 { 1.0 } else { 0.05 * lo.abs() };
        return (lo - d, hi + d);
    }
    (lo, hi)
}

/// Ranges for an equal-aspect plot of the box `lo..hi` in a plot area of
/// `w x h` pixels, with a 5 % margin.
pub(crate) fn equal_aspect(
    lo: (f64, f64),
    hi: (f64, f64),
    w: u32,
    h: u32,
) -> ((f64, f64), (f64, f64)) {
    let c = |v: f64| {
        if v.is_finite() {
            v.clamp(-AXIS_LIMIT, AXIS_LIMIT)
        } else {
            0.0
        }
    };
    let (lo, hi) = ((c(lo.0), c(lo.1)), (c(hi.0), c(hi.1)));
    let (mut dx, mut dy) = ((hi.0 - lo.0).max(0.0), (hi.1 - lo.1).max(0.0));
    if dx == 0.0 && dy == 0.0 {
        dx = 1.0;
        dy = 1.0;
    }
    let (cx, cy) = (0.5 * (lo.0 + hi.0), 0.5 * (lo.1 + hi.1));
    let aspect = w.max(1) as f64 / h.max(1) as f64;
    let (mut dx, mut dy) = (dx * 1.1, dy * 1.1);
    if dx / dy.max(1e-300) > aspect {
        dy = dx / aspect;
    } else {
        dx = dy * aspect;
    }
    (
        (cx - dx / 2.0, cx + dx / 2.0),
        (cy - dy / 2.0, cy + dy / 2.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_aspect_matches_pixels() {
        let ((x0, x1), (y0, y1)) = equal_aspect((0.0, 0.0), (20.0, 10.0), 800, 800);
        assert!(((x1 - x0) - (y1 - y0)).abs() < 1e-12);
        assert!(x0 < 0.0 && x1 > 20.0);
    }

    #[test]
    fn span_of_degenerate_data() {
        assert_eq!(span([].into_iter()), (0.0, 1.0));
        let (a, b) = span([2.0, 2.0].into_iter());
        assert!(a < 2.0 && b > 2.0);
        assert_eq!(span([f64::NAN, 1.0, 3.0].into_iter()), (1.0, 3.0));
        let (a, b) = span([0.0, 1.7e308].into_iter());
        assert!(a == 0.0 && b == AXIS_LIMIT);
        let ((x0, x1), (y0, y1)) = equal_aspect((-1e308, 0.0), (1e308, f64::INFINITY), 800, 600);
        assert!([x0, x1, y0, y1].iter().all(|v| v.is_finite()) && x1 > x0 && y1 > y0);
    }
}
