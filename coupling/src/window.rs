//! Window geometry (DESIGN.md "Coupling", seed 002 section 2.3 and Fig. 5).
//!
//! A window is a rectangle of `nx x ny` real PD nodes of spacing `dx` (side
//! $L_w = n\,dx$), centred at `center` and rotated by `angle`. Corners run counter-clockwise
//! from the local lower-left one; side `k` runs from corner `k` to corner `k + 1`
//! (0 bottom, 1 right, 2 top, 3 left in the window frame). A side lying on the outer
//! boundary of the body is [`SideKind::Outer`] and takes the scene's boundary conditions;
//! every other side is an [`SideKind::Interface`] with the BEM body.
//!
//! [`Window::place`] checks the rules of issue 4: inside the body, not over a hole, at
//! least two horizons of real nodes per side, and a rotated window may not touch the
//! outline. [`Window::hole_loop`] gives the BEM hole whose elements match the PD node rows
//! (one element of length dx per boundary node); [`cut_outline`] removes a window touching
//! the outline from the BEM outline instead.

use pdbem_bem::mesh::LoopSpec;
use pdbem_bem::V2;
use pdbem_geometry::{point_in_polygon, point_segment_projection, polygon_distance};

use crate::error::CouplingError;

/// Relative tolerance of geometric tests (times the window size).
const GEOM_TOL: f64 = 1e-9;

/// Kind of a window side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SideKind {
    /// Coupled with the BEM body.
    Interface,
    /// On the outer boundary: the scene's boundary conditions apply.
    Outer,
}

/// Where a window goes and how fine it is.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowSpec {
    /// Centre (m).
    pub center: V2,
    /// Rotation (radians, counter-clockwise).
    pub angle: f64,
    /// Node spacing dx (m), > 0.
    pub dx: f64,
    /// Real nodes along the local x axis.
    pub nx: usize,
    /// Real nodes along the local y axis.
    pub ny: usize,
    /// Horizon factor m (delta = m dx); seed 002 uses 3.015.
    pub horizon_factor: f64,
}

/// The body the windows live in: counter-clockwise outline and holes (any orientation).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Body {
    /// Outer boundary, counter-clockwise (m).
    pub outline: Vec<V2>,
    /// Hole polygons (m).
    pub holes: Vec<Vec<V2>>,
}

/// A validated window.
#[derive(Debug, Clone, PartialEq)]
pub struct Window {
    /// Its specification.
    pub spec: WindowSpec,
    /// Kind of each side (bottom, right, top, left in the window frame).
    pub sides: [SideKind; 4],
}

impl Window {
    /// Horizon delta = m dx (m).
    pub fn delta(&self) -> f64 {
        self.spec.horizon_factor * self.spec.dx
    }

    /// Side lengths (local x, local y) (m).
    pub fn size(&self) -> (f64, f64) {
        (
            self.spec.nx as f64 * self.spec.dx,
            self.spec.ny as f64 * self.spec.dx,
        )
    }

    /// Unit axes of the window frame.
    pub fn axes(&self) -> (V2, V2) {
        let (s, c) = self.spec.angle.sin_cos();
        (V2::new(c, s), V2::new(-s, c))
    }

    /// Local coordinates (from the lower-left corner, along the axes) of a point.
    pub fn to_local(&self, p: V2) -> V2 {
        let (e1, e2) = self.axes();
        let d = p - self.corners()[0];
        V2::new(d.dot(&e1), d.dot(&e2))
    }

    /// Corners, counter-clockwise from the local lower-left one.
    pub fn corners(&self) -> [V2; 4] {
        let (e1, e2) = self.axes();
        let (w, h) = self.size();
        let c = self.spec.center;
        let (a, b) = (0.5 * w * e1, 0.5 * h * e2);
        [c - a - b, c + a - b, c + a + b, c - a + b]
    }

    /// End points of side `k`.
    pub fn side(&self, k: usize) -> (V2, V2) {
        let c = self.corners();
        (c[k], c[(k + 1) % 4])
    }

    /// Whether `p` lies in the closed rectangle grown by `grow` on every side.
    pub fn contains(&self, p: V2, grow: f64) -> bool {
        let q = self.to_local(p);
        let (w, h) = self.size();
        q.x >= -grow && q.x <= w + grow && q.y >= -grow && q.y <= h + grow
    }

    /// Absolute tolerance of geometric tests (m).
    pub fn tol(&self) -> f64 {
        let (w, h) = self.size();
        GEOM_TOL * w.max(h)
    }

    /// Whether the rotation is a multiple of 90 degrees.
    pub fn axis_aligned(&self) -> bool {
        let q = self.spec.angle / std::f64::consts::FRAC_PI_2;
        (q - q.round()).abs() < 1e-9
    }

    /// Checks the window against the body and classifies its sides (issue 4 rules).
    pub fn place(index: usize, spec: WindowSpec, body: &Body) -> Result<Window, CouplingError> {
        check_spec(index, &spec)?;
        let mut w = Window {
            spec,
            sides: [SideKind::Interface; 4],
        };
        w.check_node_count(index)?;
        let tol = w.tol();
        for c in w.corners() {
            if !point_in_polygon(&c, &body.outline) && polygon_distance(&c, &body.outline) > tol {
                return Err(CouplingError::OutsideBody {
                    window: index,
                    corner: c,
                });
            }
        }
        let n = body.outline.len();
        for i in 0..n {
            let (a, b) = (body.outline[i], body.outline[(i + 1) % n]);
            if w.segment_enters(a, b) {
                return Err(CouplingError::CrossesBoundary {
                    window: index,
                    rotated: !w.axis_aligned(),
                });
            }
        }
        // A hole must also stay clear of the horizon layer of virtual nodes around the
        // window (depth delta): virtual nodes inside a hole would take the BEM field at
        // points outside the body, and the PD solve then sees a meaningless boundary
        // state (seed 002 section 3.2.4 case, measured: a window 0.3 mm from the hole
        // with its 0.6 mm layer reaching into it, coupling residual stuck near 0.7 and
        // the window's Newton solves stalling at a relative residual of 6e-3).
        let layer = w.delta();
        for (h, hole) in body.holes.iter().enumerate() {
            let m = hole.len();
            let inside = hole.iter().any(|p| w.contains(*p, layer + tol))
                || point_in_polygon(&w.spec.center, hole)
                || (0..m).any(|i| w.segment_enters_by(hole[i], hole[(i + 1) % m], layer));
            if inside {
                return Err(CouplingError::OverHole {
                    window: index,
                    hole: h,
                });
            }
        }
        for k in 0..4 {
            let (a, b) = w.side(k);
            let on = [a, 0.5 * (a + b), b]
                .iter()
                .all(|p| polygon_distance(p, &body.outline) <= tol);
            if on {
                w.sides[k] = SideKind::Outer;
            }
        }
        if w.sides.contains(&SideKind::Outer) && !w.axis_aligned() {
            return Err(CouplingError::CrossesBoundary {
                window: index,
                rotated: true,
            });
        }
        if !w.sides.contains(&SideKind::Interface) {
            return Err(CouplingError::InvalidWindow {
                window: index,
                message: "the window covers the whole body; nothing is left for BEM".into(),
            });
        }
        Ok(w)
    }

    fn check_node_count(&self, index: usize) -> Result<(), CouplingError> {
        let m = self.spec.horizon_factor;
        let nodes = self.spec.nx.min(self.spec.ny);
        if (nodes as f64) < 2.0 * m {
            return Err(CouplingError::TooFewNodes {
                window: index,
                nodes,
                width: nodes as f64 * self.spec.dx,
                min: 2.0 * self.delta(),
                needed: (2.0 * m).ceil() as usize,
            });
        }
        Ok(())
    }

    /// Whether segment `ab` passes through the open interior of the window.
    fn segment_enters(&self, a: V2, b: V2) -> bool {
        self.segment_enters_by(a, b, 0.0)
    }

    /// Whether segment `ab` passes through the open interior of the window grown by
    /// `grow` on every side.
    fn segment_enters_by(&self, a: V2, b: V2, grow: f64) -> bool {
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

fn check_spec(index: usize, s: &WindowSpec) -> Result<(), CouplingError> {
    let bad = |message: String| CouplingError::InvalidWindow {
        window: index,
        message,
    };
    if !(s.dx.is_finite() && s.dx > 0.0) {
        return Err(bad(format!("dx = {} must be positive and finite", s.dx)));
    }
    if s.nx == 0 || s.ny == 0 {
        return Err(bad(format!("{} x {} nodes: need at least one", s.nx, s.ny)));
    }
    if !(s.horizon_factor.is_finite() && s.horizon_factor >= 1.0) {
        return Err(bad(format!(
            "horizon factor {} must be at least 1 (3.015 is usual)",
            s.horizon_factor
        )));
    }
    if !(s.angle.is_finite() && s.center.x.is_finite() && s.center.y.is_finite()) {
        return Err(bad("centre and angle must be finite".into()));
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;

    fn square_body(l: f64) -> Body {
        Body {
            outline: vec![
                V2::new(0.0, 0.0),
                V2::new(l, 0.0),
                V2::new(l, l),
                V2::new(0.0, l),
            ],
            holes: vec![],
        }
    }

    fn spec(cx: f64, cy: f64, angle: f64, n: usize) -> WindowSpec {
        WindowSpec {
            center: V2::new(cx, cy),
            angle,
            dx: 0.1,
            nx: n,
            ny: n,
            horizon_factor: 3.015,
        }
    }

    #[test]
    fn interior_window_has_four_interfaces() {
        let w = Window::place(0, spec(5.0, 5.0, 0.3, 20), &square_body(10.0)).unwrap();
        assert_eq!(w.sides, [SideKind::Interface; 4]);
        let c = w.corners();
        assert!(((c[1] - c[0]).norm() - 2.0).abs() < 1e-12);
    }

    #[test]
    fn a_hole_within_the_horizon_layer_is_refused() {
        // Window [4, 6] x [4, 6] m, horizon layer delta = 0.3015 m around it.
        let square = |x0: f64| {
            vec![
                V2::new(x0, 4.8),
                V2::new(x0 + 0.3, 4.8),
                V2::new(x0 + 0.3, 5.2),
                V2::new(x0, 5.2),
            ]
        };
        let mut body = square_body(10.0);
        body.holes.push(square(6.2));
        let near = Window::place(0, spec(5.0, 5.0, 0.0, 20), &body).unwrap_err();
        assert!(
            matches!(near, CouplingError::OverHole { hole: 0, .. }),
            "{near}"
        );
        body.holes[0] = square(6.4);
        assert!(Window::place(0, spec(5.0, 5.0, 0.0, 20), &body).is_ok());
    }

    #[test]
    fn bad_windows_are_refused() {
        let body = square_body(10.0);
        let outside = Window::place(0, spec(9.5, 5.0, 0.0, 20), &body).unwrap_err();
        assert!(
            matches!(outside, CouplingError::OutsideBody { .. }),
            "{outside}"
        );
        let few = Window::place(0, spec(5.0, 5.0, 0.0, 6), &body).unwrap_err();
        assert!(
            matches!(few, CouplingError::TooFewNodes { needed: 7, .. }),
            "{few}"
        );
        // Rotated by 45 degrees with its corner poking through the right edge.
        let rot =
            Window::place(0, spec(8.8, 5.0, std::f64::consts::FRAC_PI_4, 20), &body).unwrap_err();
        assert!(matches!(rot, CouplingError::OutsideBody { .. }), "{rot}");
        let mut holed = body.clone();
        holed.holes.push(vec![
            V2::new(4.0, 4.0),
            V2::new(4.5, 4.0),
            V2::new(4.5, 4.5),
            V2::new(4.0, 4.5),
        ]);
        let over = Window::place(0, spec(5.0, 5.0, 0.0, 20), &holed).unwrap_err();
        assert!(
            matches!(over, CouplingError::OverHole { hole: 0, .. }),
            "{over}"
        );
    }

    #[test]
    fn window_at_the_end_of_a_beam_cuts_the_outline() {
        let body = Body {
            outline: vec![
                V2::new(0.0, 0.0),
                V2::new(1.0, 0.0),
                V2::new(1.0, 0.2),
                V2::new(0.0, 0.2),
            ],
            holes: vec![],
        };
        let s = WindowSpec {
            center: V2::new(0.75, 0.1),
            angle: 0.0,
            dx: 0.01,
            nx: 50,
            ny: 20,
            horizon_factor: 3.015,
        };
        let w = Window::place(0, s, &body).unwrap();
        use SideKind::*;
        assert_eq!(w.sides, [Outer, Outer, Outer, Interface]);
        let groups: Vec<String> = ["bottom", "right", "top", "left"].map(String::from).into();
        let (p, g, _) = cut_outline(0, &w, &body.outline, &groups, &[0.01; 4], "window").unwrap();
        assert_eq!(p.len(), 4);
        assert!((p[0] - V2::new(0.5, 0.2)).norm() < 1e-12, "{p:?}");
        assert_eq!(g, ["top", "left", "bottom", "window"]);
    }

    #[test]
    fn crack_is_split_at_the_window_boundary() {
        let w = Window::place(0, spec(5.0, 5.0, 0.0, 20), &square_body(10.0)).unwrap();
        let pts = [V2::new(5.0, 10.0), V2::new(5.0, 5.0)];
        let s = w.split_crack(0, &pts, 0.2).unwrap().unwrap();
        let bem = s.bem.unwrap();
        assert!((bem[1] - V2::new(5.0, 6.0)).norm() < 1e-12);
        assert!((s.pd[0] - V2::new(5.0, 6.2)).norm() < 1e-12);
        assert!((s.pd[2] - V2::new(5.0, 5.0)).norm() < 1e-12);
    }
}
