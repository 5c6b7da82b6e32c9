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
//! least two horizons of real nodes per side, and the outline touched only along whole
//! sides (a rotated window where an outline edge runs along its side).
//! [`Window::hole_loop`] gives the BEM hole whose elements match the PD node rows (one
//! element of length dx per boundary node); [`cut_outline`] removes a window touching the
//! outline from the BEM outline instead.
//!
//! Files of the module:
//! - `mod.rs`: [`WindowSpec`], [`Window`], [`Body`], [`SideKind`], the window frame
//!   (corners, sides, containment) and point-segment distances.
//! - `place`: [`Window::place`] and its parameter checks.
//! - `cut`: [`Window::hole_loop`], [`Window::split_crack`], [`cut_outline`], chords and
//!   boundary crossings, segment tests, [`Window::overlaps`].

mod cut;
mod place;

pub use cut::{cut_outline, CrackSplit, OutlineParts};

use pdbem_bem::V2;

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
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
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

    /// Whether this window is turned against `other` by other than whole quarter turns:
    /// their lattices then share no node.
    pub fn turned_from(&self, other: &Window) -> bool {
        !quarter_turns_apart(self.spec.angle, other.spec.angle)
    }

    /// Whether the rotation is a multiple of 90 degrees.
    pub fn axis_aligned(&self) -> bool {
        quarter_turns_apart(self.spec.angle, 0.0)
    }
}

/// Whether angles `a` and `b` (radians) differ by a whole number of quarter turns (to
/// 1e-9 of one): windows at such angles share their lattice directions.
pub fn quarter_turns_apart(a: f64, b: f64) -> bool {
    let q = (a - b) / std::f64::consts::FRAC_PI_2;
    (q - q.round()).abs() <= 1e-9
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::CouplingError;

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
    fn a_turned_window_lies_against_an_outline_edge_along_its_side() {
        // The 10 m square turned by 30 degrees about the origin; a 2 m window turned with
        // it, flush against its bottom edge.
        let a = 30.0_f64.to_radians();
        let (e1, e2) = (V2::new(a.cos(), a.sin()), V2::new(-a.sin(), a.cos()));
        let turned = Body {
            outline: square_body(10.0)
                .outline
                .iter()
                .map(|p| p.x * e1 + p.y * e2)
                .collect(),
            holes: vec![],
        };
        let flush = spec(5.0 * e1.x + 1.0 * e2.x, 5.0 * e1.y + 1.0 * e2.y, a, 20);
        let w = Window::place(0, flush.clone(), &turned).unwrap();
        assert_eq!(
            w.sides,
            [
                SideKind::Outer,
                SideKind::Interface,
                SideKind::Interface,
                SideKind::Interface
            ]
        );
        // Turned against the edge (by 10 degrees more), it reaches across it.
        let across = Window::place(
            0,
            spec(flush.center.x, flush.center.y, a + 0.17, 20),
            &turned,
        )
        .unwrap_err();
        assert!(
            matches!(
                across,
                CouplingError::OutsideBody { .. } | CouplingError::CrossesBoundary { .. }
            ),
            "{across}"
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

    #[test]
    fn a_window_whose_side_holds_the_crack_mouth_is_refused() {
        // 4 m window on the tip (5, 8) of a 2 m edge crack from the top edge: its top side
        // lies on the edge, and the BEM body would keep no part of the crack.
        let w = Window::place(0, spec(5.0, 8.0, 0.0, 40), &square_body(10.0)).unwrap();
        let pts = [V2::new(5.0, 10.0), V2::new(5.0, 8.0)];
        let e = w.split_crack(0, &pts, 0.2).unwrap_err().to_string();
        assert!(e.contains("the window holds the whole crack"), "{e}");
        assert!(e.contains("(5.0000, 10.0000)"), "{e}");
        // A 2 m window leaves the crack's upper half to the BEM body.
        let w = Window::place(0, spec(5.0, 8.0, 0.0, 20), &square_body(10.0)).unwrap();
        let s = w.split_crack(0, &pts, 0.2).unwrap().unwrap();
        assert_eq!(s.bem.map(|b| b.len()), Some(2));
    }
}
