//! Break points of loop edges and crack faces: uniform sizes with the mouth and tip
//! refinements of [`subdivide`], or the local size field of [`super::size_field`]
//! marched along each segment (crack segments from their tips, so tip zones are exactly
//! uniform). Each walker counts without storing, so [`super::MeshBuilder::count`] can
//! refuse a mesh of 1e12 elements before anything is allocated.

use super::size_field::{march, SizeField};
use super::spec::{CrackSpec, MAX_ELEMENTS};
use super::{subdivide, V2};
use crate::BemError;

/// True when `count` elements (a ratio that may be NaN or infinite) fit in `left`.
pub(super) fn fits(count: f64, left: usize) -> bool {
    count.partial_cmp(&(left as f64)).is_some_and(|o| o.is_le())
}

pub(super) fn too_many(name: &str, limit: usize) -> BemError {
    BemError::Mesh(format!(
        "'{name}' would need more than {limit} elements (an element size that is not positive or far too small)"
    ))
}

/// Elements of one loop edge, split at crack mouths (the gap interval left out) and
/// refined towards each mouth to the crack's element size; `None` past [`MAX_ELEMENTS`].
pub(super) fn edge_pieces(
    a: V2,
    b: V2,
    size: f64,
    cuts: &[(f64, f64, f64)],
    field: Option<&SizeField>,
) -> Option<Vec<(V2, V2)>> {
    let mut out = Vec::new();
    edge_breaks(a, b, size, cuts, field, MAX_ELEMENTS, |p, q| {
        out.push((p, q))
    })?;
    Some(out)
}

/// Walks the elements of one loop edge (as [`edge_pieces`]), calling `push` with each;
/// returns their count, `None` past `limit`.
pub(super) fn edge_breaks(
    a: V2,
    b: V2,
    size: f64,
    cuts: &[(f64, f64, f64)],
    field: Option<&SizeField>,
    limit: usize,
    mut push: impl FnMut(V2, V2),
) -> Option<usize> {
    let len = (b - a).norm();
    let mut cuts = cuts.to_vec();
    cuts.sort_by(|x, y| x.0.total_cmp(&y.0));
    // Intervals to mesh: [start, end] with the refinement size at each end (if a mouth).
    let mut spans: Vec<(f64, f64, Option<f64>, Option<f64>)> = Vec::new();
    let mut t0 = 0.0;
    let mut h0 = None;
    for &(lo, hi, hc) in &cuts {
        spans.push((t0, lo.max(t0), h0, Some(hc)));
        t0 = hi.min(1.0);
        h0 = Some(hc);
    }
    spans.push((t0, 1.0, h0, None));
    let mut count = 0usize;
    for (s, e, hs, he) in spans {
        let l = (e - s) * len;
        if l <= 1e-12 * len {
            continue;
        }
        let (p0, p1) = (a + (b - a) * s, a + (b - a) * e);
        let left = limit.saturating_sub(count);
        let n = match field {
            Some(f) => {
                let mut prev: Option<V2> = None;
                march(p0, p1, size, f, left, |t| {
                    let p = p0 + (p1 - p0) * (t / l);
                    if let Some(q) = prev {
                        push(q, p);
                    }
                    prev = Some(p);
                })?
            }
            None => {
                if !fits(l / size, left) {
                    return None;
                }
                let pts = span_points(l, size, hs, he);
                for w in pts.windows(2) {
                    push(p0 + (p1 - p0) * (w[0] / l), p0 + (p1 - p0) * (w[1] / l));
                }
                pts.len() - 1
            }
        };
        count += n;
    }
    Some(count)
}

/// Break points of a span refined towards a mouth at its start and/or end.
pub(super) fn span_points(l: f64, size: f64, hs: Option<f64>, he: Option<f64>) -> Vec<f64> {
    let refine = |h: Option<f64>| h.filter(|h| *h < size).map(|h| (h, 3.0 * h));
    match (refine(hs), refine(he)) {
        (None, None) => subdivide(l, size, None, false),
        (Some(r), None) => subdivide(l, size, Some(r), false),
        (None, Some(r)) => subdivide(l, size, Some(r), true),
        (Some(r1), Some(r2)) => {
            let mut a = subdivide(0.5 * l, size, Some(r1), false);
            let b = subdivide(0.5 * l, size, Some(r2), true);
            a.pop();
            a.extend(b.iter().map(|x| x + 0.5 * l));
            a
        }
    }
}

/// Break points along the crack polyline: (point, arc length, segment) of every element
/// end, vertices included once; `None` past `limit` elements.
pub(super) fn crack_stations(
    c: &CrackSpec,
    on: [bool; 2],
    field: Option<&SizeField>,
    limit: usize,
) -> Option<Vec<(V2, f64, usize)>> {
    let nseg = c.points.len() - 1;
    let mut out = Vec::new();
    let mut s0 = 0.0;
    for k in 0..nseg {
        let (a, b) = (c.points[k], c.points[k + 1]);
        let len = (b - a).norm();
        let tip_end = k == nseg - 1 && !on[1];
        let tip_start = k == 0 && !on[0];
        let left = limit.saturating_sub(out.len());
        let pts = match field {
            Some(f) => segment_breaks_field(a, b, c.element_size, f, (tip_start, tip_end), left)?,
            None => {
                if !fits(len / c.element_size, left) {
                    return None;
                }
                segment_breaks_uniform(c, len, (tip_start, tip_end))
            }
        };
        for (i, t) in pts.iter().enumerate() {
            if k > 0 && i == 0 {
                continue;
            }
            out.push((a + (b - a) * (t / len), s0 + t, k));
        }
        s0 += len;
    }
    (out.len() <= limit.saturating_add(1)).then_some(out)
}

/// Break parameters of one crack segment with the uniform sizes and tip refinement of
/// [`subdivide`].
pub(super) fn segment_breaks_uniform(c: &CrackSpec, len: f64, tips: (bool, bool)) -> Vec<f64> {
    let tip = c.tip.map(|t| (t.size, t.radius));
    match tips {
        (true, true) => {
            let mut p = subdivide(0.5 * len, c.element_size, tip, false);
            let q = subdivide(0.5 * len, c.element_size, tip, true);
            p.pop();
            p.extend(q.iter().map(|x| x + 0.5 * len));
            p
        }
        (true, false) => subdivide(len, c.element_size, tip, false),
        (false, true) => subdivide(len, c.element_size, tip, true),
        (false, false) => subdivide(len, c.element_size, None, false),
    }
}

/// Break parameters of one crack segment by the size field, marched from each tip so the
/// tip zones are exactly uniform ([`super::size_field`]).
pub(super) fn segment_breaks_field(
    a: V2,
    b: V2,
    cap: f64,
    f: &SizeField,
    tips: (bool, bool),
    limit: usize,
) -> Option<Vec<f64>> {
    let len = (b - a).norm();
    let forward = |p: V2, q: V2, limit: usize| -> Option<Vec<f64>> {
        let mut v = Vec::new();
        march(p, q, cap, f, limit, |t| v.push(t))?;
        Some(v)
    };
    Some(match tips {
        (true, true) => {
            let mid = 0.5 * (a + b);
            let mut p = forward(a, mid, limit)?;
            let q = forward(b, mid, limit)?;
            p.pop();
            p.extend(q.iter().rev().map(|t| len - t));
            p
        }
        (false, true) => {
            let q = forward(b, a, limit)?;
            q.iter().rev().map(|t| len - t).collect()
        }
        _ => forward(a, b, limit)?,
    })
}
