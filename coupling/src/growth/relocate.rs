//! The geometry iteration of seed 002 (section 2.3.3, Fig. 9, Algorithm 2 steps 7 and 10):
//! where the window goes and how the macro crack is extended.
//!
//! - [`moved_spec`]: the window moves by the move distance along the growth direction.
//!   The move is snapped to the PD lattice (whole multiples of dx along the window axes),
//!   so the nodes the old and new windows share coincide and their state carries over
//!   exactly ([`crate::growth::transfer`]). A window that would leave the body is pushed
//!   back inside (against the outline, where its side becomes an outer side). A window
//!   that would leave a strip of BEM body thinner than [`MIN_STRIP`] times its side
//!   between one of its sides and the outline is moved against the outline, or else
//!   away from it to that width ([`clear_of_strips`]): the thin strip under a window is
//!   a soft Neumann side for the Dirichlet-Neumann iteration, whose interface map then
//!   has many gains far above 1 that IQN-ILS does not resolve (measured on the tension
//!   plate's 2 m window: the coupling stalls at a residual of 1 for strips of 0.27-0.4 m
//!   and converges from 0.45 m, or with the window against the edge). The tip must
//!   end up inside the new window, clear of its trigger distance
//!   ([`crate::growth::tips::margins`]), or the window is centred on the tip. A window
//!   that cannot be placed either way because a hole is in the way gives
//!   [`CouplingError::OverHole`] (the tip then ends at the hole); other failures give
//!   [`CouplingError::Relocation`].
//! - [`turned_to_outline`]: a window turned with its crack whose move would cross the
//!   outline turns to the orientation of the outline edge ahead of its tip (a window lies
//!   against the outline only along whole sides) and then moves as [`moved_spec`] says.
//! - [`extend_crack`]: the macro crack is the old polyline up to the old window entry,
//!   then the smoothed PD path: from the old entry to where the path enters the new window
//!   it becomes BEM crack, split into `elements_per_extension` straight elements per face,
//!   the last one ending on an interface element end of the new window (one interface
//!   element per PD node row: the crack passes between two rows);
//!   the rest of the path (inside the new window, up to one dx short of the tip: the
//!   copied bond states carry the damage at the tip) becomes the new window's pre-crack
//!   (seed 002: "the macro crack grows to reach the farthest macro crack tip").

use pdbem_bem::V2;

use crate::error::CouplingError;
use crate::growth::polyline;
use crate::growth::tips::{margins, near_interface_side};
use crate::window::{Body, Window, WindowSpec};

/// Snaps `v` to whole multiples of `dx` along the window axes `(e1, e2)`.
pub(crate) fn snap(v: V2, e1: V2, e2: V2, dx: f64) -> V2 {
    let a = (v.dot(&e1) / dx).round() * dx;
    let b = (v.dot(&e2) / dx).round() * dx;
    a * e1 + b * e2
}

/// Thinnest strip of BEM body, as a fraction of the window side, left between a window
/// side and the outline parallel to it (module docs). The coupled tension plate with a
/// 2 m window and 0.1 m elements stalls for strips of 0.3 m (20 x 20 nodes), 0.4 m (30 x
/// 30) and 0.35 m (40 x 40) and converges for 0.35, 0.45 and 0.45 m: the stall sets in
/// between 0.15 and 0.225 sides, so a quarter side keeps a margin.
pub const MIN_STRIP: f64 = 0.25;

/// The strips of BEM body thinner than [`MIN_STRIP`] sides that the window `spec` leaves
/// between one of its sides and the outline's bounding box in the window frame: `(width
/// (m), side (m), the side's outward normal)` per thin strip; empty when none is.
pub fn thin_strips(spec: &WindowSpec, outline: &[V2]) -> Vec<(f64, f64, V2)> {
    let (s, c) = spec.angle.sin_cos();
    let mut out = Vec::new();
    for (e, n) in [(V2::new(c, s), spec.nx), (V2::new(-s, c), spec.ny)] {
        let side = n as f64 * spec.dx;
        let (lo, hi) = outline
            .iter()
            .map(|p| p.dot(&e))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        let x = spec.center.dot(&e);
        let tol = 1e-9 * side;
        for (strip, normal) in [(x - 0.5 * side - lo, -e), (hi - x - 0.5 * side, e)] {
            if strip > tol && strip < MIN_STRIP * side {
                out.push((strip, side, normal));
            }
        }
    }
    out
}

/// Where the window `spec` may go instead of leaving a strip thinner than
/// [`MIN_STRIP`] sides between one of its sides and the outline's bounding box in the
/// window frame: first against the outline, then away from it to at least that strip. Empty
/// when no strip is too thin.
fn clear_of_strips(spec: &WindowSpec, body: &Body) -> Vec<WindowSpec> {
    let (s, c) = spec.angle.sin_cos();
    let (e1, e2) = (V2::new(c, s), V2::new(-s, c));
    let mut flush = spec.clone();
    let mut away = spec.clone();
    let mut thin = false;
    for (e, n) in [(e1, spec.nx), (e2, spec.ny)] {
        let side = n as f64 * spec.dx;
        let h = 0.5 * side;
        let (lo, hi) = body
            .outline
            .iter()
            .map(|p| p.dot(&e))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        let x = spec.center.dot(&e);
        let least = MIN_STRIP * side;
        let tol = 1e-9 * side;
        // The move away is whole dx (the lattice of the old window); the flush one cannot be.
        let whole = |v: f64| ((v - tol) / spec.dx).ceil() * spec.dx;
        let (below, above) = (x - h - lo, hi - x - h);
        if below > tol && below < least {
            thin = true;
            flush.center -= below * e;
            away.center += whole(least - below) * e;
        } else if above > tol && above < least {
            thin = true;
            flush.center += above * e;
            away.center -= whole(least - above) * e;
        }
    }
    if thin {
        vec![flush, away]
    } else {
        Vec::new()
    }
}

/// Shifts `spec` (along its axes, by whole dx where possible) so the window lies inside
/// the bounding box of the outline in the window frame.
fn clamp_into(spec: &WindowSpec, body: &Body) -> WindowSpec {
    let (s, c) = spec.angle.sin_cos();
    let (e1, e2) = (V2::new(c, s), V2::new(-s, c));
    let (hx, hy) = (
        0.5 * spec.nx as f64 * spec.dx,
        0.5 * spec.ny as f64 * spec.dx,
    );
    let proj = |e: V2| {
        body.outline
            .iter()
            .map(|p| p.dot(&e))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    };
    let mut out = spec.clone();
    for (e, h) in [(e1, hx), (e2, hy)] {
        let (lo, hi) = proj(e);
        let x = out.center.dot(&e);
        let clamped = x.clamp(lo + h, (hi - h).max(lo + h));
        out.center += (clamped - x) * e;
    }
    out
}

/// The window after one relocation of the window `w` whose tip is at `tip` and grows
/// along unit `dir`; see the module docs.
pub fn moved_spec(
    w: &Window,
    tip: V2,
    dir: V2,
    distance: f64,
    ratio: f64,
    body: &Body,
    tip_name: &str,
) -> Result<WindowSpec, CouplingError> {
    let (e1, e2) = w.axes();
    let dx = w.spec.dx;
    let mut spec = w.spec.clone();
    spec.center += snap(distance * dir, e1, e2, dx);
    spec = clamp_into(&spec, body);
    let fits = |s: &WindowSpec| {
        Window::place(0, s.clone(), body).ok().filter(|nw| {
            nw.contains(tip, -0.5 * dx) && !near_interface_side(nw, tip, margins(nw, ratio).1)
        })
    };
    if fits(&spec).is_none() {
        // Centre on the tip instead (still on the lattice of the old window).
        let mut c = w.spec.clone();
        c.center += snap(tip - w.spec.center, e1, e2, dx);
        spec = clamp_into(&c, body);
    }
    // A candidate back at the old window would re-place it and trigger again at once.
    let moves = |s: &WindowSpec| (s.center - w.spec.center).norm() >= 1e-9 * dx;
    if let Some(clear) = clear_of_strips(&spec, body)
        .into_iter()
        .find(|s| moves(s) && fits(s).is_some())
    {
        spec = clear;
    }
    if (spec.center - w.spec.center).norm() < 1e-9 * dx {
        // Re-placing the same window changes nothing and would trigger again at once.
        let (lx, ly) = w.size();
        let trigger = margins(w, ratio).1;
        return Err(CouplingError::Relocation {
            tip: tip_name.to_string(),
            reason: format!(
                "the window would stay where it is (tip at ({:.4}, {:.4})): its trigger \
                 distance {trigger:.4} m (band + horizon + dx) leaves no room in a window of \
                 {lx:.4} m x {ly:.4} m; use more nodes per side or a larger window",
                tip.x, tip.y
            ),
        });
    }
    match Window::place(0, spec.clone(), body) {
        Ok(_) => Ok(spec),
        Err(
            e @ (CouplingError::OverHole { .. }
            | CouplingError::OutsideBody { .. }
            | CouplingError::CrossesBoundary { .. }),
        ) => Err(e),
        Err(e) => Err(CouplingError::Relocation {
            tip: tip_name.to_string(),
            reason: format!(
                "moved window centred at ({:.4}, {:.4}) is not admissible: {e}",
                spec.center.x, spec.center.y
            ),
        }),
    }
}

/// The outline edge the tip at `tip` growing along unit `dir` heads for: the first edge
/// its ray crosses, else (a ray along an edge, or out through a corner) the edge nearest
/// the tip. Its unit direction.
fn edge_ahead(tip: V2, dir: V2, outline: &[V2]) -> Option<V2> {
    let n = outline.len();
    let edge = |i: usize| (outline[i], outline[(i + 1) % n]);
    let hit = (0..n)
        .filter_map(|i| {
            let (a, b) = edge(i);
            pdbem_geometry::ray_segment(&tip, &dir, &a, &b).map(|s| (s, i))
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, i)| i);
    let i = hit.or_else(|| {
        (0..n).min_by(|&i, &j| {
            let d = |k: usize| {
                let (a, b) = edge(k);
                pdbem_geometry::point_segment_projection(&tip, &a, &b).0
            };
            d(i).total_cmp(&d(j))
        })
    })?;
    let (a, b) = edge(i);
    polyline::unit(a, b)
}

/// The angle nearest `angle` at which a window's sides run along `edge` (unit): the
/// edge's angle plus a whole number of quarter turns, snapped to an exact multiple of
/// 90 degrees when within 1e-12 rad of one (an axis-aligned outline gives an
/// axis-aligned window, [`Window::axis_aligned`]).
fn angle_along(edge: V2, angle: f64) -> f64 {
    use std::f64::consts::FRAC_PI_2;
    let base = edge.y.atan2(edge.x);
    let turned = base + ((angle - base) / FRAC_PI_2).round() * FRAC_PI_2;
    let q = (turned / FRAC_PI_2).round();
    if (turned - q * FRAC_PI_2).abs() <= 1e-12 {
        q * FRAC_PI_2
    } else {
        turned
    }
}

/// The window `w` turned so that its sides run along the outline edge its tip at `tip`,
/// growing along unit `dir`, heads for: for a turned window that cannot move on because it
/// would cross the outline ([`moved_spec`] gave [`CouplingError::CrossesBoundary`] or
/// [`CouplingError::OutsideBody`]), since a window lies against the outline only along
/// whole sides. The turned window then moves as any window does ([`moved_spec`] on its
/// own lattice); no node of it coincides with the old window's, so the state it takes is
/// the old nodes' displacements and the BEM field ([`crate::growth::transfer`]), and its
/// pre-crack runs to the traced tip. `None` when `w` already runs along that edge.
pub fn turned_to_outline(w: &Window, tip: V2, dir: V2, body: &Body) -> Option<Window> {
    let edge = edge_ahead(tip, dir, &body.outline)?;
    let turned = Window {
        spec: WindowSpec {
            angle: angle_along(edge, w.spec.angle),
            ..w.spec.clone()
        },
        sides: w.sides,
    };
    turned.turned_from(w).then_some(turned)
}

/// The point of the boundary of `w` nearest to `p` that is an interface element end
/// (a whole number of dx from the side's start corner), at least one dx from the corners.
pub fn snap_to_element_end(w: &Window, p: V2) -> V2 {
    let dx = w.spec.dx;
    (0..4)
        .map(|k| {
            let (a, b) = w.side(k);
            let len = (b - a).norm();
            let t = (p - a).dot(&(b - a)) / len;
            let t = ((t / dx).round() * dx).clamp(dx, len - dx);
            a + (b - a) * (t / len)
        })
        .min_by(|x, y| (x - p).norm().total_cmp(&(y - p).norm()))
        .expect("four sides")
}

/// When the BEM crack `out` already runs into the new window `w` (the window moved
/// sideways or back over the old entry, so the path gives no extension), the crack is split
/// where it crosses the window boundary, and that crossing must lie on an interface element
/// end like every other crack mouth on a window (one element per node row): the crossing
/// becomes a vertex moved to the nearest element end (at most dx / 2 along the side).
/// Measured on `cases/growth_shear_edge.ron` with 10 x 10 nodes: the crossing fell at
/// x = 9.9474 m on the side y = 5.2 m, whose element ends lie at 8.4 + 0.2 k m.
fn snap_entry_into(out: &mut Vec<V2>, w: &Window) {
    let inside = |p: V2| w.contains(p, -1e-9 * w.spec.dx);
    let Some(k) = out.iter().position(|p| inside(*p)) else {
        return;
    };
    if k == 0 {
        return;
    }
    let (a, b) = (out[k - 1], out[k]);
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if inside(a + (b - a) * mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let c = snap_to_element_end(w, a + (b - a) * hi);
    if (c - out[k]).norm() <= 1e-9 * w.spec.dx {
        return;
    }
    if (c - a).norm() <= 1e-9 * w.spec.dx {
        out[k - 1] = c;
    } else {
        out.insert(k, c);
    }
}

/// The extended macro crack (see the module docs).
///
/// `line_to_tip`: the current crack polyline oriented towards the tip; `old_entry_s`: the
/// arc length of the old window entry along it; `path`: the traced PD path from the old
/// entry to the tip; `new`: the new window; `base_size`: when the BEM part so far was
/// meshed with a uniform element size, that size (its element ends become polyline
/// points, so the mesh of the old part does not change). Returns the new polyline
/// (oriented towards the tip, one BEM element per segment up to the new window) and the
/// BEM elements added per face.
pub fn extend_crack(
    line_to_tip: &[V2],
    old_entry_s: f64,
    path: &[V2],
    new: &Window,
    elements: usize,
    base_size: Option<f64>,
    tip_name: &str,
) -> Result<(Vec<V2>, usize), CouplingError> {
    let dx = new.spec.dx;
    let mut out: Vec<V2> = Vec::new();
    let mut acc = 0.0;
    out.push(line_to_tip[0]);
    for seg in line_to_tip.windows(2) {
        let l = (seg[1] - seg[0]).norm();
        if acc + l >= old_entry_s - 1e-12 * (1.0 + old_entry_s) {
            break;
        }
        acc += l;
        out.push(seg[1]);
    }
    let entry = pdbem_geometry::point_at(line_to_tip, old_entry_s);
    if (entry - *out.last().expect("non-empty")).norm() > 1e-9 * dx {
        out.push(entry);
    }
    if let Some(h) = base_size {
        out = polyline::subdivide(&out, h);
    }
    snap_entry_into(&mut out, new);
    let total = pdbem_geometry::polyline_length(path);
    let s_new = polyline::entry_length(path, new).ok_or_else(|| CouplingError::Relocation {
        tip: tip_name.to_string(),
        reason: format!(
            "the traced path ({total:.4} m from ({:.4}, {:.4})) does not reach the new window",
            entry.x, entry.y
        ),
    })?;
    let mut added = 0;
    if s_new > 0.5 * dx {
        let mut ext = polyline::resample_between(path, 0.0, s_new, elements);
        // The crack must meet the new window's boundary at an element end: one interface
        // element per PD node row, the crack between two rows.
        ext[elements] = snap_to_element_end(new, ext[elements]);
        out.extend_from_slice(&ext[1..]);
        added = elements;
    }
    // The pre-crack stops one dx short of the traced tip: the bond states copied from the
    // old window carry the damage there, and a cut through the tip node would lengthen
    // the crack by a node.
    let end = (total - dx).max(s_new + dx).min(total);
    let inside = polyline::resample_spacing(path, s_new, end, dx);
    out.extend_from_slice(&inside[1..]);
    if total - s_new < dx {
        return Err(CouplingError::Relocation {
            tip: tip_name.to_string(),
            reason: format!(
                "only {:.4} m of the path lies in the new window (dx = {dx:.4} m); raise the move distance or the window size",
                total - s_new
            ),
        });
    }
    Ok((out, added))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::fixtures::{body, window};

    #[test]
    fn window_moves_on_the_lattice_and_stays_in_the_body() {
        let w = window(10.0, 8.0);
        // Growth slightly off vertical: the move is snapped to whole dx.
        let dir = V2::new(0.03, -1.0).normalize();
        let s = moved_spec(&w, V2::new(10.0, 7.56), dir, 0.5, 0.9, &body(), "t").unwrap();
        let d = s.center - w.spec.center;
        assert!((d.x / 0.05 - (d.x / 0.05).round()).abs() < 1e-9);
        assert!((d.y + 0.5).abs() < 1e-12, "moved by {d:?}");
        // Near the bottom edge the window is pushed back against it.
        let w = window(10.0, 0.75);
        let s = moved_spec(
            &w,
            V2::new(10.0, 0.3),
            V2::new(0.0, -1.0),
            0.5,
            0.9,
            &body(),
            "t",
        )
        .unwrap();
        assert!((s.center.y - 0.5).abs() < 1e-12, "{:?}", s.center);
    }

    #[test]
    fn a_window_leaves_no_thin_strip_of_body_below_it() {
        // The 1 m window (trigger distance 0.3 m from its interface sides) moves down
        // from y = 1.1 by 0.5 m to 0.6: its bottom side would lie 0.1 m (0.1 side) above
        // the bottom edge; it goes against the edge instead.
        let w = window(10.0, 1.1);
        let down = V2::new(0.0, -1.0);
        let s = moved_spec(&w, V2::new(10.0, 0.6), down, 0.5, 0.9, &body(), "t").unwrap();
        assert!((s.center.y - 0.5).abs() < 1e-12, "{:?}", s.center);
        // Moved by 0.45 m to 0.65 with the tip at 0.8 m, 0.2 m below the top side of the
        // flush window (inside its trigger band): the window stays a quarter side (0.25
        // m) above the edge instead.
        let s = moved_spec(&w, V2::new(10.0, 0.8), down, 0.45, 0.9, &body(), "t").unwrap();
        assert!((s.center.y - 0.75).abs() < 1e-12, "{:?}", s.center);
        // From a quarter side above the edge (y = 0.75) by 0.1 m to 0.65: the flush window
        // has the tip (0.8) in its trigger band, and a quarter side away is the old window,
        // which would trigger again at once; the window keeps its move (strip 0.15 m).
        let w = window(10.0, 0.75);
        let s = moved_spec(&w, V2::new(10.0, 0.8), down, 0.1, 0.9, &body(), "t").unwrap();
        assert!((s.center.y - 0.65).abs() < 1e-12, "{:?}", s.center);
        // A strip of a quarter side or more is left alone.
        let w = window(10.0, 1.3);
        let s = moved_spec(&w, V2::new(10.0, 0.9), down, 0.5, 0.9, &body(), "t").unwrap();
        assert!((s.center.y - 0.8).abs() < 1e-12, "{:?}", s.center);
    }

    #[test]
    fn a_turned_window_at_the_outline_turns_to_lie_against_it() {
        use crate::window::SideKind;
        // The 1 m window turned by -60 degrees, 0.9 m above the bottom edge, its tip
        // heading down: moved by 0.5 m it would cross the edge.
        let spec = WindowSpec {
            angle: (-60.0_f64).to_radians(),
            ..crate::growth::fixtures::window_spec(V2::new(10.0, 0.9))
        };
        let w = Window::place(0, spec, &body()).unwrap();
        let (tip, down) = (V2::new(10.0, 0.6), V2::new(0.1, -1.0).normalize());
        let e = moved_spec(&w, tip, down, 0.5, 0.9, &body(), "t").unwrap_err();
        assert!(
            matches!(
                e,
                CouplingError::CrossesBoundary { .. } | CouplingError::OutsideBody { .. }
            ),
            "{e}"
        );
        let turned = turned_to_outline(&w, tip, down, &body()).expect("turned");
        let s = moved_spec(&turned, tip, down, 0.5, 0.9, &body(), "t").unwrap();
        // The nearest quarter turn along the bottom edge: exactly -90 degrees.
        assert_eq!(s.angle, -std::f64::consts::FRAC_PI_2);
        let placed = Window::place(0, s, &body()).unwrap();
        assert!(placed.axis_aligned());
        assert_eq!(
            placed
                .sides
                .iter()
                .filter(|k| **k == SideKind::Outer)
                .count(),
            1
        );
        assert!(placed.contains(tip, -0.5 * placed.spec.dx));
        assert!(
            (placed
                .corners()
                .iter()
                .map(|c| c.y)
                .fold(f64::INFINITY, f64::min))
            .abs()
                < 1e-12
        );
        // A window already along the edge is not turned.
        let flat = window(10.0, 0.9);
        assert!(turned_to_outline(&flat, tip, down, &body()).is_none());
    }

    #[test]
    fn the_turned_angle_is_the_nearest_quarter_turn_along_the_edge() {
        let deg = |a: f64| a.to_radians();
        let edge = V2::new(deg(30.0).cos(), deg(30.0).sin());
        assert!((angle_along(edge, deg(50.0)) - deg(30.0)).abs() < 1e-12);
        assert!((angle_along(edge, deg(80.0)) - deg(120.0)).abs() < 1e-12);
        assert!((angle_along(edge, deg(-100.0)) - deg(-60.0)).abs() < 1e-12);
        // Axis-aligned edges give exact multiples of 90 degrees.
        assert_eq!(
            angle_along(V2::new(0.0, -1.0), deg(-135.0)),
            -std::f64::consts::PI
        );
        assert_eq!(angle_along(V2::new(1.0, 0.0), deg(10.0)), 0.0);
        // The edge a ray heads for, and the nearest edge for a ray along an edge.
        let out = body().outline;
        let left = edge_ahead(V2::new(1.0, 5.0), V2::new(-1.0, 0.2).normalize(), &out).unwrap();
        assert_eq!(left, V2::new(0.0, -1.0));
        let along = edge_ahead(V2::new(5.0, 0.5), V2::new(1.0, 0.0), &out).unwrap();
        assert_eq!(
            along,
            V2::new(0.0, 1.0),
            "the right edge, which the ray meets"
        );
    }

    #[test]
    fn a_crack_already_in_the_new_window_enters_it_at_an_element_end() {
        // Window [9.5, 10.5] x [7.5, 8.5] (dx = 0.05, element ends at 9.5 + 0.05 k); the
        // crack comes down from (10.02, 10) and ends at (10.01, 8.2), inside the window,
        // crossing its top side y = 8.5 at x = 10.0155 (between element ends).
        let w = window(10.0, 8.0);
        let mut line = vec![V2::new(10.02, 10.0), V2::new(10.01, 8.2)];
        snap_entry_into(&mut line, &w);
        assert_eq!(line.len(), 3, "{line:?}");
        let c = line[1];
        assert!((c.y - 8.5).abs() < 1e-12, "{c:?}");
        assert!((c.x - 10.0).abs() < 1e-12, "{c:?}");
        // A crack that stops outside is left alone.
        let mut outside = vec![V2::new(10.02, 10.0), V2::new(10.01, 8.7)];
        snap_entry_into(&mut outside, &w);
        assert_eq!(outside.len(), 2);
    }

    #[test]
    fn a_window_that_cannot_move_is_an_error() {
        // 10 x 10 nodes of dx = 0.2 m: the trigger distance 0.2 + 0.603 + 0.2 m exceeds
        // half the side, so the window centred on the tip triggers again at once.
        let spec = WindowSpec {
            center: V2::new(10.0, 5.0),
            angle: 0.0,
            dx: 0.2,
            nx: 10,
            ny: 10,
            horizon_factor: 3.015,
        };
        let w = Window::place(0, spec, &body()).unwrap();
        let e = moved_spec(
            &w,
            V2::new(10.0, 5.0),
            V2::new(1.0, 0.0),
            0.0,
            0.9,
            &body(),
            "t",
        )
        .unwrap_err();
        assert!(e.to_string().contains("would stay where it is"), "{e}");
    }

    #[test]
    fn crack_is_extended_by_the_set_number_of_elements() {
        // Crack from the top edge to (10, 8); window [9.5, 10.5] x [7.5, 8.5], entry at
        // y = 8.5; the PD path runs from the entry straight down to y = 7.55.
        let line = vec![V2::new(10.0, 10.0), V2::new(10.0, 8.0)];
        let path: Vec<V2> = (0..=19)
            .map(|k| V2::new(10.0, 8.5 - 0.05 * k as f64))
            .collect();
        let new = window(10.0, 7.5);
        let (pts, added) = extend_crack(&line, 1.5, &path, &new, 5, None, "t").unwrap();
        assert_eq!(added, 5);
        assert!((pts[0] - V2::new(10.0, 10.0)).norm() < 1e-12);
        assert!((pts[1] - V2::new(10.0, 8.5)).norm() < 1e-12);
        // Extension points every 0.1 m down to the boundary at 8.0.
        assert!((pts[6] - V2::new(10.0, 8.0)).norm() < 1e-12, "{pts:?}");
        // The pre-crack ends one dx (0.05 m) short of the traced tip at 7.55.
        assert!(
            (pts.last().unwrap() - V2::new(10.0, 7.6)).norm() < 1e-12,
            "{pts:?}"
        );
        assert!(pts.iter().all(|p| (p.x - 10.0).abs() < 1e-12));
        // With the old part meshed at 0.05 m its 1.5 m become 30 segments.
        let (pts, _) = extend_crack(&line, 1.5, &path, &new, 5, Some(0.05), "t").unwrap();
        assert!((pts[30] - V2::new(10.0, 8.5)).norm() < 1e-12, "{pts:?}");
        assert!((pts[31] - V2::new(10.0, 8.4)).norm() < 1e-12);
        // A path meeting the boundary between two element ends is moved to the nearer.
        let bent: Vec<V2> = path.iter().map(|p| V2::new(p.x + 0.02, p.y)).collect();
        let (pts, _) = extend_crack(&line, 1.5, &bent, &new, 5, None, "t").unwrap();
        assert!((pts[6] - V2::new(10.0, 8.0)).norm() < 1e-12, "{pts:?}");
    }
}
