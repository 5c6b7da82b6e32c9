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
    /// The discretisation each point belongs to, for the automatic markers (one entry
    /// per point, e.g. 0 for a BEM interior grid and 1 for the PD windows' nodes):
    /// within a group the markers are either all cell-covering or all separate discs
    /// ([`auto_markers`]). Empty: all points are one group.
    pub groups: Vec<u32>,
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
        let radii: Vec<u32> = if self.marker_px > 0 {
            vec![self.marker_px; self.points.len()]
        } else {
            auto_markers(
                &self.points,
                &self.groups,
                pw as f64 / (x1 - x0).max(1e-300),
            )
        };
        // Coarse points first, so a fine PD window over a coarse BEM grid stays on top.
        let mut order: Vec<usize> = (0..self.points.len()).collect();
        order.sort_by_key(|&i| std::cmp::Reverse(radii[i]));
        let scale = |v: f64| (v - vmin) / (vmax - vmin).max(1e-300);
        chart
            .draw_series(order.iter().map(|&i| {
                let c = viridis(scale(self.values[i])).filled();
                Circle::new(self.points[i], radii[i], c)
            }))
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
                // A white halo (the text drawn at one-pixel offsets) keeps the red label
                // readable on dark markers as on light ones.
                let font = (FONT, LABEL_SIZE - 2).into_font();
                let pos = Pos::new(HPos::Left, VPos::Bottom);
                let halo = font.clone().color(&WHITE).pos(pos);
                for (dx, dy) in HALO_OFFSETS {
                    chart
                        .draw_series(std::iter::once(
                            EmptyElement::at(*p) + Text::new(text.clone(), (dx, dy), halo.clone()),
                        ))
                        .map_err(msg)?;
                }
                chart
                    .draw_series(std::iter::once(
                        EmptyElement::at(*p)
                            + Text::new(text.clone(), (0, 0), font.color(&CRACK).pos(pos)),
                    ))
                    .map_err(msg)?;
            }
        }
        Ok(())
    }
}

/// Pixel offsets of the white halo behind a mark's label.
const HALO_OFFSETS: [(i32, i32); 8] = [
    (-2, 0),
    (2, 0),
    (0, -2),
    (0, 2),
    (-1, -1),
    (1, 1),
    (-1, 1),
    (1, -1),
];

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

/// Marker radius (pixels) of every point from its local spacing: d1, the distance to its
/// nearest neighbour, and d2, to the nearest one off that direction (the other side of a
/// grid cell). Where a discretisation is dense, each disc covers its cell (radius a
/// little over half the cell's diagonal), so a field reads as a field, not as a lattice
/// of white dots; where it is sparse (a PD window of 20 x 20 nodes), each is a separate
/// disc of 0.4 d1 (at most 12 px), so the nodes stay countable. The choice is made once
/// per group (`groups`, one per point; empty: one group): covering when the group's
/// coarsest cell needs at most 14 px, so a refined PD grid draws its children as smaller
/// discs of the same kind as their coarse neighbours, while a fine PD window (its own
/// group) keeps its own size beside a coarse BEM grid. `px_per_unit` is the plot's
/// scale.
fn auto_markers(points: &[(f64, f64)], groups: &[u32], px_per_unit: f64) -> Vec<u32> {
    const COVER_MAX_PX: f64 = 14.0;
    let spacing = local_spacings(points);
    let group = |i: usize| groups.get(i).copied().unwrap_or(0);
    // Half the cell diagonal: a disc of that radius, rounded up, on every node leaves
    // no gap at the cell corners (rounding down left a lattice of white dots).
    let cover = |(d1, d2): (f64, f64)| 0.5 * d1.hypot(d2) * px_per_unit;
    let mut coarsest = std::collections::BTreeMap::<u32, f64>::new();
    for (i, d) in spacing.iter().enumerate() {
        if let Some(d) = d {
            let c = coarsest.entry(group(i)).or_insert(0.0);
            *c = c.max(cover(*d));
        }
    }
    spacing
        .iter()
        .enumerate()
        .map(|(i, d)| match d {
            Some(d) if coarsest[&group(i)] <= COVER_MAX_PX => cover(*d).ceil().max(1.0) as u32,
            Some((d1, _)) => (0.4 * d1 * px_per_unit).min(12.0).round().max(1.0) as u32,
            None => 4,
        })
        .collect()
}

/// Per point, (d1, d2) of [`auto_markers`] (d2 = d1 when every neighbour lies along the
/// first direction; None for a lone point).
fn local_spacings(points: &[(f64, f64)]) -> Vec<Option<(f64, f64)>> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    let first = |k: usize| nearest_in(points, &order, k, |_| true);
    let mut out = vec![None; points.len()];
    for (k, &i) in order.iter().enumerate() {
        let Some((d1, v)) = first(k) else { continue };
        // Off the first direction: more than 45 degrees from it, either way.
        let off = |w: (f64, f64)| (w.0 * v.0 + w.1 * v.1).abs() < 0.7072 * d1 * w.0.hypot(w.1);
        let d2 = nearest_in(points, &order, k, off).map_or(d1, |(d, _)| d);
        out[i] = Some((d1, d2));
    }
    out
}

/// Nearest distinct neighbour of the point `order[k]` among those whose offset passes
/// `keep`: distance and offset. Scans the x-sorted `order` outwards both ways until the
/// x gap alone exceeds the best distance, or after 4096 points each way (the sizes of
/// markers need no more, and points on one line would otherwise cost n^2).
fn nearest_in(
    points: &[(f64, f64)],
    order: &[usize],
    k: usize,
    keep: impl Fn((f64, f64)) -> bool,
) -> Option<(f64, (f64, f64))> {
    let p = points[order[k]];
    let mut best: Option<(f64, (f64, f64))> = None;
    let mut visit = |j: usize| {
        let q = points[order[j]];
        let w = (q.0 - p.0, q.1 - p.1);
        if best.is_some_and(|(d, _)| w.0.abs() > d) {
            return false;
        }
        let d = w.0.hypot(w.1);
        if d > 0.0 && keep(w) && best.is_none_or(|(b, _)| d < b) {
            best = Some((d, w));
        }
        true
    };
    const REACH: usize = 4096;
    for j in k + 1..order.len().min(k + 1 + REACH) {
        if !visit(j) {
            break;
        }
    }
    for j in (k.saturating_sub(REACH)..k).rev() {
        if !visit(j) {
            break;
        }
    }
    best
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

#[cfg(test)]
mod marker_tests {
    use super::{auto_markers, local_spacings};

    /// A rectangular grid: d1 is the short side of its cell, d2 the long one; a lone
    /// point has none; coincident points do not count as neighbours.
    #[test]
    fn local_spacings_of_a_grid_are_its_cell_sides() {
        let mut pts: Vec<(f64, f64)> = Vec::new();
        for i in 0..7 {
            for j in 0..5 {
                pts.push((0.3 * i as f64, 0.1 * j as f64));
            }
        }
        for d in local_spacings(&pts) {
            let (d1, d2) = d.unwrap();
            assert!(
                (d1 - 0.1).abs() < 1e-12 && (d2 - 0.3).abs() < 1e-12,
                "{d1} {d2}"
            );
        }
        assert_eq!(local_spacings(&[(1.0, 2.0)]), vec![None]);
        let d = local_spacings(&[(0.0, 0.0), (0.0, 0.0), (0.0, 2.0)]);
        assert_eq!(d, vec![Some((2.0, 2.0)); 3]);
    }

    /// A dense field covers its cells (radius over half the diagonal); a sparse grid
    /// keeps separate discs; a fine patch keeps its own small size beside a coarse one.
    #[test]
    fn markers_cover_dense_fields_and_separate_sparse_nodes() {
        let grid = |h: f64, x0: f64| {
            let mut v = Vec::new();
            for i in 0..4 {
                for j in 0..4 {
                    v.push((x0 + h * i as f64, h * j as f64));
                }
            }
            v
        };
        // 10 px cells: half the diagonal is 7.07 px; radius 8 covers the corners (7
        // would leave a dot of background at each).
        let dense = auto_markers(&grid(1.0, 0.0), &[], 10.0);
        assert!(dense.iter().all(|&r| r == 8), "{dense:?}");
        // 30 px cells: separate discs of 0.4 * 30 = 12 px.
        let sparse = auto_markers(&grid(1.0, 0.0), &[], 30.0);
        assert!(sparse.iter().all(|&r| r == 12), "{sparse:?}");
        // A fine PD window (group 1) beside a coarse grid (group 0) keeps its own size.
        let mut mixed = grid(1.0, 0.0);
        mixed.extend(grid(0.1, 100.0));
        let groups: Vec<u32> = (0..32).map(|i| u32::from(i >= 16)).collect();
        let r = auto_markers(&mixed, &groups, 10.0);
        assert!(r[..16].iter().all(|&r| r == 8) && r[16..].iter().all(|&r| r == 1));
    }

    /// A sparse grid with one cell split into four children (one group, as a refined PD
    /// grid is plotted): the children are separate discs of half their parents' radius,
    /// not cell-covering blobs that merge at the split cell (what sizing each point on
    /// its own gave: radius 9 px, against 10 px for the coarse nodes).
    #[test]
    fn children_of_a_sparse_grid_are_discs_of_their_own_size() {
        let mut pts: Vec<(f64, f64)> = Vec::new();
        for i in 0..6 {
            for j in 0..6 {
                if (i, j) != (2, 2) {
                    pts.push((2.0 * i as f64, 2.0 * j as f64));
                }
            }
        }
        let coarse = pts.len();
        for (a, b) in [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)] {
            pts.push((4.0 + a, 4.0 + b));
        }
        // 12.5 px per unit: coarse cells 25 px (cover 17.7 px: sparse), children 12.5 px.
        // The coarse nodes next to the children are sized by their distance to them
        // (the four beside it, 1.58 units away: 8 px) and stay larger than the children.
        let r = auto_markers(&pts, &[], 12.5);
        assert!(r[..coarse].iter().all(|&r| r == 10 || r == 8), "{r:?}");
        assert_eq!(r[..coarse].iter().filter(|&&r| r == 10).count(), coarse - 4);
        assert!(r[coarse..].iter().all(|&r| r == 5), "{r:?}");
        let own: Vec<u32> = (0..pts.len() as u32).collect();
        let apart = auto_markers(&pts, &own, 12.5);
        assert!(apart[coarse..].iter().all(|&r| r == 9), "{apart:?}");
    }
}
