//! Smoothing of the traced chain (module docs of [`crate::crack_path`]): resampling,
//! centring across the damage band by mean shift, polyline helpers.

use super::cell_hash::{dist2, CellHash};
use crate::geometry::{from_g, to_g_all, P2};
use pdbem_geometry as g;

/// Points every `h` along the polyline, keeping both end points.
pub(super) fn resample(line: &[P2], h: f64) -> Vec<P2> {
    let total = polyline_length(line);
    if line.len() < 2 || total == 0.0 {
        return line[..1].to_vec();
    }
    let n = ((total / h).round() as usize).max(1);
    (0..=n)
        .map(|k| point_at_length(line, total * k as f64 / n as f64))
        .collect()
}

/// Move every point but the first across the path to the weighted
/// centroid of the crack nodes within a radius of it (normal component
/// only): `smoothing` times the spacing `h` of the crack node nearest to the
/// point (one radius when every node has the same spacing). The normal at a
/// point is that of the chord of `line` from one radius before to one after
/// it, which averages out the zig-zag of the node chain.
pub(super) fn centre_across(line: &[P2], crack: &[P2], h: &[f64], smoothing: f64) -> Vec<P2> {
    let Some(h_max) = h.iter().copied().reduce(f64::max) else {
        return line.to_vec();
    };
    if line.len() < 2 || smoothing == 0.0 {
        return line.to_vec();
    }
    let uniform = h.iter().all(|&v| v == h_max);
    let radius_at = |p: P2| {
        if uniform {
            return smoothing * h_max;
        }
        let nearest = (0..crack.len())
            .min_by(|&a, &b| dist2(crack[a], p).total_cmp(&dist2(crack[b], p)))
            .expect("a connected crack has nodes");
        smoothing * h[nearest]
    };
    let hash = CellHash::new(crack, smoothing * h_max);
    let mut out = line.to_vec();
    let mut s = 0.0;
    for k in 1..line.len() {
        s += dist2(line[k - 1], line[k]).sqrt();
        let radius = radius_at(line[k]);
        let a = point_at_length(line, (s - radius).max(0.0));
        let b = point_at_length(line, s + radius);
        let t = [b[0] - a[0], b[1] - a[1]];
        let lt = t[0].hypot(t[1]);
        if lt == 0.0 {
            continue;
        }
        let nrm = [-t[1] / lt, t[0] / lt];
        out[k] = mean_shift_across(line[k], nrm, crack, &hash, radius);
    }
    out
}

/// Mean shift along the normal `nrm` with the smooth kernel
/// $w = (1 - d^2/r^2)^2$: move `p` by the weighted mean normal offset of the
/// crack nodes within `r` until the move is below 1e-9 `r`. With `r` at
/// least twice the band's row spacing the kernel density across the band
/// has one maximum, on the centre line of a symmetric band; 100 passes cap
/// the loop (the move shrinks geometrically).
fn mean_shift_across(p: P2, nrm: P2, crack: &[P2], hash: &CellHash, r: f64) -> P2 {
    let mut q = p;
    let r2 = r * r;
    for _ in 0..100 {
        let (mut s, mut w) = (0.0, 0.0);
        hash.for_each_within(crack, q, r, |j| {
            let c = 1.0 - dist2(crack[j], q) / r2;
            let wj = c * c;
            s += wj * ((crack[j][0] - q[0]) * nrm[0] + (crack[j][1] - q[1]) * nrm[1]);
            w += wj;
        });
        if w <= 0.0 {
            break;
        }
        let off = s / w;
        q = [q[0] + off * nrm[0], q[1] + off * nrm[1]];
        if off.abs() < 1e-9 * r {
            break;
        }
    }
    q
}

/// The point at arc length `s` along the polyline (clamped to its ends).
pub(super) fn point_at_length(line: &[P2], s: f64) -> P2 {
    from_g(g::point_at(&to_g_all(line), s))
}

/// Length of the polyline.
pub(super) fn polyline_length(line: &[P2]) -> f64 {
    g::polyline_length(&to_g_all(line))
}
