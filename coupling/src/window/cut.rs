//! What a window cuts out of the BEM body: the hole loop, the crack split between BEM and
//! PD, the outline cut of a window on the outline; segment tests and window overlap.

use pdbem_bem::mesh::LoopSpec;
use pdbem_bem::V2;

use super::{SideKind, Window};
use crate::error::CouplingError;
use pdbem_geometry::point_segment_projection;

impl Window {
    /// Whether segment `ab` passes through the open interior of the window.
    pub(super) fn segment_enters(&self, a: V2, b: V2) -> bool {
        self.segment_enters_by(a, b, 0.0)
    }

    /// Whether segment `ab` passes through the open interior of the window grown by
    /// `grow` on every side.
    pub(super) fn segment_enters_by(&self, a: V2, b: V2, grow: f64) -> bool {
        let (w, h) = self.size();
        let tol = self.tol() - grow;
        let (p, q) = (self.to_local(a), self.to_local(b));
        // Liang-Barsky clipping against the rectangle shrunk by tol (grown by `grow`).
        let d = q - p;
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        for (den, num) in [
            (-d.x, p.x - tol),
            (d.x, w - tol - p.x),
            (-d.y, p.y - tol),
            (d.y, h - tol - p.y),
        ] {
            if den == 0.0 {
                if num < 0.0 {
                    return false;
                }
            } else {
                let t = num / den;
                if den < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
        t1 - t0 > 1e-12
    }

    /// Whether two windows overlap, horizon layers included.
    pub fn overlaps(&self, other: &Window) -> bool {
        let g = self.delta() + other.delta();
        other.corners().iter().any(|c| self.contains(*c, g))
            || self.corners().iter().any(|c| other.contains(*c, g))
            || (0..4).any(|k| {
                let (a, b) = other.side(k);
                self.segment_enters(a, b)
            })
    }

    /// The BEM hole of an interior window: corners clockwise, elements of length dx in
    /// group `group` (one per boundary node row).
    pub fn hole_loop(&self, group: &str) -> LoopSpec {
        let c = self.corners();
        LoopSpec {
            points: vec![c[0], c[3], c[2], c[1]],
            edge_groups: vec![group.to_string(); 4],
            edge_sizes: vec![self.spec.dx; 4],
            is_hole: true,
        }
    }

    /// Splits crack polyline `pts` between BEM and this window: the part outside
    /// (None when the crack lies wholly inside) and the PD pre-crack inside, extended by
    /// `extend` (m) beyond the window boundary so that bonds from virtual to real nodes
    /// across the crack are cut too. Only cracks with one end (a tip) inside are handled.
    pub fn split_crack(
        &self,
        crack: usize,
        pts: &[V2],
        extend: f64,
    ) -> Result<Option<CrackSplit>, CouplingError> {
        let tol = self.tol();
        let inside: Vec<bool> = pts.iter().map(|p| self.contains(*p, -tol)).collect();
        if !inside.iter().any(|b| *b) {
            return Ok(None);
        }
        let (last_in, first_in) = (*inside.last().unwrap(), inside[0]);
        if first_in && last_in {
            return Ok(Some(CrackSplit {
                bem: None,
                pd: pts.to_vec(),
                tip_at_end: true,
            }));
        }
        // Orient from outside to the tip inside.
        let mut line = pts.to_vec();
        if first_in {
            line.reverse();
        }
        let k = line
            .iter()
            .position(|p| self.contains(*p, -tol))
            .expect("a point is inside");
        if line[k..].iter().any(|p| !self.contains(*p, tol)) {
            return Err(CouplingError::Crack {
                crack,
                message: "the crack leaves the window again; a window must hold one crack tip"
                    .into(),
            });
        }
        let entry = self.boundary_crossing(line[k - 1], line[k]);
        let dir = (line[k] - line[k - 1]).normalize();
        let mut bem: Vec<V2> = line[..k].to_vec();
        if (entry - line[k - 1]).norm() > tol {
            // (A crack polyline may already have a vertex on the boundary.)
            bem.push(entry);
        }
        if bem.len() < 2 {
            return Err(CouplingError::Crack {
                crack,
                message: format!(
                    "the window holds the whole crack, whose end ({:.4}, {:.4}) lies on the \
                     window's side: no part of it is left to the BEM body. Use a smaller \
                     window (coupling.side), so that the crack enters it from the BEM body",
                    line[0].x, line[0].y
                ),
            });
        }
        let mut pd = vec![entry - extend * dir, entry];
        pd.extend_from_slice(&line[k..]);
        if first_in {
            bem.reverse();
            pd.reverse();
        }
        Ok(Some(CrackSplit {
            bem: Some(bem),
            pd,
            tip_at_end: !first_in,
        }))
    }

    /// Entry and exit points of segment ab through the open window (None if it misses).
    pub fn chord(&self, a: V2, b: V2) -> Option<(V2, V2)> {
        let (w, h) = self.size();
        let (p, q) = (self.to_local(a), self.to_local(b));
        let d = q - p;
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        for (den, num) in [(-d.x, p.x), (d.x, w - p.x), (-d.y, p.y), (d.y, h - p.y)] {
            if den == 0.0 {
                if num < 0.0 {
                    return None;
                }
            } else if den < 0.0 {
                t0 = t0.max(num / den);
            } else {
                t1 = t1.min(num / den);
            }
        }
        (t1 - t0 > 1e-9).then(|| (a + t0 * (b - a), a + t1 * (b - a)))
    }

    /// Point where segment a (outside) -> b (inside) crosses the window boundary.
    pub fn boundary_crossing(&self, a: V2, b: V2) -> V2 {
        let (w, h) = self.size();
        let (p, q) = (self.to_local(a), self.to_local(b));
        let d = q - p;
        let mut t_in = 0.0_f64;
        for (den, num) in [(-d.x, p.x), (d.x, w - p.x), (-d.y, p.y), (d.y, h - p.y)] {
            if den < 0.0 {
                t_in = t_in.max(num / den);
            }
        }
        a + t_in.clamp(0.0, 1.0) * (b - a)
    }
}

/// A crack split between BEM and a window.
#[derive(Debug, Clone, PartialEq)]
pub struct CrackSplit {
    /// The part meshed by BEM (ends on the window boundary), None if wholly inside.
    pub bem: Option<Vec<V2>>,
    /// The PD pre-crack (starts outside the window by the extension).
    pub pd: Vec<V2>,
    /// Whether the tip is the last point of the original polyline.
    pub tip_at_end: bool,
}

/// An outline as (points, edge groups, edge sizes).
pub type OutlineParts = (Vec<V2>, Vec<String>, Vec<f64>);

/// Removes windows that touch the outer boundary from the BEM outline.
///
/// `points`/`groups`/`sizes` describe the outline (counter-clockwise, edge i from point i
/// to i + 1). The outline portion along the window's outer sides is replaced by its
/// interface sides, traversed clockwise around the window (the BEM body lies outside),
/// in group `group` with element size dx. The window must touch the outline along one
/// contiguous chain of sides.
pub fn cut_outline(
    index: usize,
    w: &Window,
    points: &[V2],
    groups: &[String],
    sizes: &[f64],
    group: &str,
) -> Result<OutlineParts, CouplingError> {
    let tol = w.tol();
    let corners = w.corners();
    // 1. Insert the window corners that lie inside outline edges.
    let (mut p, mut g, mut s) = (Vec::new(), Vec::new(), Vec::new());
    let n = points.len();
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        p.push(a);
        g.push(groups[i].clone());
        s.push(sizes[i]);
        let mut inner: Vec<(f64, V2)> = corners
            .iter()
            .filter_map(|c| {
                let (d, t) = point_segment_projection(c, &a, &b);
                (d <= tol && t > 1e-12 && t < 1.0 - 1e-12).then_some((t, *c))
            })
            .collect();
        inner.sort_by(|x, y| x.0.total_cmp(&y.0));
        for (_, c) in inner {
            p.push(c);
            g.push(groups[i].clone());
            s.push(sizes[i]);
        }
    }
    // 2. Edges along the window boundary.
    let m = p.len();
    let on_window = |i: usize| {
        let mid = 0.5 * (p[i] + p[(i + 1) % m]);
        w.contains(mid, tol) && !w.contains(mid, -tol)
    };
    let along: Vec<bool> = (0..m).map(on_window).collect();
    let starts: Vec<usize> = (0..m)
        .filter(|&i| along[i] && !along[(i + m - 1) % m])
        .collect();
    if starts.len() != 1 {
        return Err(CouplingError::InvalidWindow {
            window: index,
            message: format!(
                "the window touches the outline along {} separate pieces; only one is supported",
                starts.len()
            ),
        });
    }
    let i_in = starts[0];
    let mut i_out = i_in;
    while along[i_out % m] {
        i_out += 1;
    }
    let i_out = i_out % m;
    let corner_of = |q: V2| corners.iter().position(|c| (c - q).norm() <= 10.0 * tol);
    let (Some(c_in), Some(c_out)) = (corner_of(p[i_in]), corner_of(p[i_out])) else {
        return Err(CouplingError::InvalidWindow {
            window: index,
            message: "the window touches the outline but not with whole sides".into(),
        });
    };
    // 3. Rebuild: outline from i_out around to i_in, then clockwise around the window.
    let (mut q, mut qg, mut qs) = (Vec::new(), Vec::new(), Vec::new());
    let mut i = i_out;
    while i != i_in {
        q.push(p[i]);
        qg.push(g[i].clone());
        qs.push(s[i]);
        i = (i + 1) % m;
    }
    let mut c = c_in;
    while c != c_out {
        // Clockwise: corner c -> c - 1, along side c - 1.
        let side = (c + 3) % 4;
        if w.sides[side] != SideKind::Interface {
            return Err(CouplingError::InvalidWindow {
                window: index,
                message: format!("side {side} should be an interface but lies on the outline"),
            });
        }
        q.push(corners[c]);
        qg.push(group.to_string());
        qs.push(w.spec.dx);
        c = side;
    }
    Ok((q, qg, qs))
}
