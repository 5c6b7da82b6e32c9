//! Placing a window (the rules of issue 4): parameter checks, inside the body, not over
//! a hole, two horizons of real nodes per side, the outline touched only along whole
//! sides (a turned window only where an outline edge runs along its side); the kinds of
//! its sides.

use super::{Body, SideKind, Window, WindowSpec};
use crate::error::CouplingError;
use pdbem_geometry::{point_in_polygon, polygon_distance};

impl Window {
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
