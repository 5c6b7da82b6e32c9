//! Several tips: windows that would overlap are merged into one rectangle covering both
//! (same orientation and spacing, on the lattice of the first), which then holds both
//! tips; if that is impossible the run stops with an error naming the tips.
//!
//! A merged window moves as one ([`crate::growth::Growth::plan`]): each of its tips past
//! the margin gives a moved window, and the new window is the smallest rectangle covering
//! all of them ([`merge_specs`]) and the tips that did not move ([`cover_box`]).

use pdbem_bem::V2;

use crate::error::CouplingError;
use crate::window::{Body, Window, WindowSpec};

/// The smallest rectangle on the lattice of `a` covering windows `a` and `b`; `Err` with
/// the reason when their lattices differ in orientation (other than by a multiple of 90
/// degrees, which maps a square lattice onto itself), spacing or horizon.
pub fn merge_specs(a: &WindowSpec, b: &WindowSpec) -> Result<WindowSpec, String> {
    if !crate::window::quarter_turns_apart(a.angle, b.angle) {
        return Err(format!(
            "orientations differ ({:.3} vs {:.3} degrees)",
            a.angle.to_degrees(),
            b.angle.to_degrees()
        ));
    }
    if (a.dx - b.dx).abs() > 1e-12 * a.dx || a.horizon_factor != b.horizon_factor {
        return Err(format!(
            "spacings differ (dx {} vs {}, m {} vs {})",
            a.dx, b.dx, a.horizon_factor, b.horizon_factor
        ));
    }
    let (s, c) = a.angle.sin_cos();
    let (e1, e2) = (V2::new(c, s), V2::new(-s, c));
    let origin = a.center - 0.5 * a.nx as f64 * a.dx * e1 - 0.5 * a.ny as f64 * a.dx * e2;
    let corners = |w: &WindowSpec| {
        let (hx, hy) = (0.5 * w.nx as f64 * w.dx, 0.5 * w.ny as f64 * w.dx);
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(p, q)| w.center + p * hx * e1 + q * hy * e2)
    };
    let (mut lo, mut hi) = (V2::repeat(f64::INFINITY), V2::repeat(f64::NEG_INFINITY));
    for p in corners(a).iter().chain(corners(b).iter()) {
        let d = p - origin;
        let q = V2::new(d.dot(&e1), d.dot(&e2));
        lo = lo.inf(&q);
        hi = hi.sup(&q);
    }
    let dx = a.dx;
    let snap_lo = |v: f64| (v / dx + 1e-9).floor() * dx;
    let snap_hi = |v: f64| (v / dx - 1e-9).ceil() * dx;
    let (x0, x1, y0, y1) = (snap_lo(lo.x), snap_hi(hi.x), snap_lo(lo.y), snap_hi(hi.y));
    Ok(WindowSpec {
        center: origin + 0.5 * (x0 + x1) * e1 + 0.5 * (y0 + y1) * e2,
        angle: a.angle,
        dx,
        nx: ((x1 - x0) / dx).round() as usize,
        ny: ((y1 - y0) / dx).round() as usize,
        horizon_factor: a.horizon_factor,
    })
}

/// The smallest rectangle on the lattice of `a` covering `a` and the points `pts`.
pub fn cover_points(a: &WindowSpec, pts: &[V2]) -> WindowSpec {
    pts.iter().fold(a.clone(), |acc, &p| {
        let point = WindowSpec {
            center: p,
            nx: 0,
            ny: 0,
            ..acc.clone()
        };
        merge_specs(&acc, &point).expect("same orientation and spacing")
    })
}

/// `a` grown (on its lattice) to cover the square of half-side `r` around `tip`, clipped
/// to window `old`, and the point `entry`: what a tip that did not move needs of the
/// moved window it shares (its crack entry and its trigger distance around the tip, as
/// far as the old window gave it).
pub fn cover_box(a: &WindowSpec, old: &Window, tip: V2, entry: V2, r: f64) -> WindowSpec {
    let (lx, ly) = old.size();
    let (e1, e2) = old.axes();
    let q = old.to_local(tip);
    let (x0, x1) = ((q.x - r).max(0.0), (q.x + r).min(lx));
    let (y0, y1) = ((q.y - r).max(0.0), (q.y + r).min(ly));
    let c0 = old.corners()[0];
    let at = |x: f64, y: f64| c0 + x * e1 + y * e2;
    cover_points(a, &[at(x0, y0), at(x1, y0), at(x1, y1), at(x0, y1), entry])
}

/// Merges overlapping windows until none overlap. `owner[t]` is the window of tip `t`
/// (updated); `names[t]` names the tips in errors. Windows are placed in `body`.
pub fn resolve_overlaps(
    specs: &mut Vec<WindowSpec>,
    owner: &mut [usize],
    names: &[String],
    body: &Body,
) -> Result<usize, CouplingError> {
    let mut merges = 0;
    loop {
        let placed: Vec<Option<Window>> = specs
            .iter()
            .enumerate()
            .map(|(i, s)| Window::place(i, s.clone(), body).ok())
            .collect();
        let pair = (0..specs.len())
            .flat_map(|a| (a + 1..specs.len()).map(move |b| (a, b)))
            .find(|&(a, b)| match (&placed[a], &placed[b]) {
                (Some(wa), Some(wb)) => wa.overlaps(wb),
                _ => false,
            });
        let Some((a, b)) = pair else {
            return Ok(merges);
        };
        let tip_of = |w: usize| {
            owner
                .iter()
                .position(|&o| o == w)
                .map_or_else(|| format!("(window {w})"), |t| names[t].clone())
        };
        let fail = |reason: String| CouplingError::WindowsCannotMerge {
            first: tip_of(a),
            second: tip_of(b),
            reason,
        };
        let merged = merge_specs(&specs[a], &specs[b]).map_err(fail)?;
        Window::place(a, merged.clone(), body).map_err(|e| {
            fail(format!(
                "the merged {} x {} window does not fit: {e}",
                merged.nx, merged.ny
            ))
        })?;
        specs[a] = merged;
        specs.remove(b);
        for o in owner.iter_mut() {
            if *o == b {
                *o = a;
            } else if *o > b {
                *o -= 1;
            }
        }
        merges += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::fixtures::body;

    fn spec(cx: f64, cy: f64, angle: f64) -> WindowSpec {
        WindowSpec {
            center: V2::new(cx, cy),
            angle,
            dx: 0.05,
            nx: 20,
            ny: 20,
            horizon_factor: 3.015,
        }
    }

    #[test]
    fn overlapping_windows_merge_into_one_rectangle() {
        let mut specs = vec![
            spec(5.0, 5.0, 0.0),
            spec(5.7, 5.2, 0.0),
            spec(15.0, 5.0, 0.0),
        ];
        let mut owner = vec![0, 1, 2];
        let names: Vec<String> = ["a", "b", "c"].map(String::from).into();
        let n = resolve_overlaps(&mut specs, &mut owner, &names, &body()).unwrap();
        assert_eq!(n, 1);
        assert_eq!(owner, vec![0, 0, 1]);
        let m = &specs[0];
        // Covers x in [4.5, 6.2] and y in [4.5, 5.7]: 34 x 24 nodes.
        assert_eq!((m.nx, m.ny), (34, 24));
        assert!(
            (m.center - V2::new(5.35, 5.1)).norm() < 1e-9,
            "{:?}",
            m.center
        );
    }

    #[test]
    fn windows_facing_each_other_merge() {
        // Two edge cracks growing towards each other: window axes at 0 and 180 degrees.
        let mut specs = vec![spec(5.0, 5.0, 0.0), spec(5.8, 5.0, std::f64::consts::PI)];
        let mut owner = vec![0, 1];
        let names: Vec<String> = ["west.end", "east.end"].map(String::from).into();
        resolve_overlaps(&mut specs, &mut owner, &names, &body()).unwrap();
        assert_eq!(owner, vec![0, 0]);
        assert_eq!((specs[0].nx, specs[0].ny), (36, 20));
    }

    #[test]
    fn cover_box_is_clipped_to_the_old_window() {
        // Old window [9.5, 10.5] x [4.5, 5.5]; a moved one [10.0, 11.0] x [4.5, 5.5]; a
        // tip at (9.6, 5.0) with a 0.3 m margin clipped at x = 9.5 and entry (9.5, 5.2).
        let old = Window::place(0, spec(10.0, 5.0, 0.0), &body()).unwrap();
        let m = cover_box(
            &spec(10.5, 5.0, 0.0),
            &old,
            V2::new(9.6, 5.0),
            V2::new(9.5, 5.2),
            0.3,
        );
        assert_eq!((m.nx, m.ny), (30, 20));
        assert!(
            (m.center - V2::new(10.25, 5.0)).norm() < 1e-9,
            "{:?}",
            m.center
        );
        // A point outside grows the window on the lattice.
        let p = cover_points(&spec(10.0, 5.0, 0.0), &[V2::new(10.62, 5.0)]);
        assert_eq!((p.nx, p.ny), (23, 20));
    }

    #[test]
    fn differently_oriented_windows_cannot_merge() {
        let mut specs = vec![spec(5.0, 5.0, 0.0), spec(5.5, 5.0, 0.3)];
        let mut owner = vec![0, 1];
        let names: Vec<String> = ["c1.end", "c2.start"].map(String::from).into();
        let e = resolve_overlaps(&mut specs, &mut owner, &names, &body()).unwrap_err();
        let msg = e.to_string();
        assert!(
            msg.contains("c1.end") && msg.contains("c2.start") && msg.contains("orientations"),
            "{msg}"
        );
    }
}
