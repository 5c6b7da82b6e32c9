//! A uniform cell hash of points for fixed-radius neighbour queries.

use std::collections::HashMap;

use crate::geometry::P2;

/// A uniform cell hash of points for fixed-radius neighbour queries.
pub(super) struct CellHash {
    h: f64,
    cells: HashMap<(i64, i64), Vec<usize>>,
}

impl CellHash {
    pub(super) fn new(pts: &[P2], h: f64) -> Self {
        let mut cells: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
        for (k, p) in pts.iter().enumerate() {
            cells.entry(Self::key(*p, h)).or_default().push(k);
        }
        CellHash { h, cells }
    }

    fn key(p: P2, h: f64) -> (i64, i64) {
        ((p[0] / h).floor() as i64, (p[1] / h).floor() as i64)
    }

    /// Call `f(j)` for every point `j` within `r` (<= the cell size) of `q`,
    /// in increasing cell then insertion order.
    pub(super) fn for_each_within(&self, pts: &[P2], q: P2, r: f64, mut f: impl FnMut(usize)) {
        let (cx, cy) = Self::key(q, self.h);
        let r2 = (r * (1.0 + 1e-9)).powi(2);
        for gy in cy - 1..=cy + 1 {
            for gx in cx - 1..=cx + 1 {
                if let Some(v) = self.cells.get(&(gx, gy)) {
                    for &j in v {
                        if dist2(pts[j], q) <= r2 {
                            f(j);
                        }
                    }
                }
            }
        }
    }
}

/// Squared distance between two points.
#[inline]
pub(super) fn dist2(a: P2, b: P2) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}
