//! Local element-size field: element sizes that follow the local feature size.
//!
//! A field is the minimum of sources. A source is a point or a polyline $S$ with a size
//! $h_i$, a uniform zone of radius $r_i$ and a grading $g_i$:
//! $$ h(x) = \min_i \; \phi_i(d_i(x)), \qquad
//!    \phi_i(d) = h_i + g_i \max(0, d - r_i), \qquad d_i(x) = \operatorname{dist}(x, S_i), $$
//! capped by the element size of the edge or crack being meshed. Each $\phi_i$ is
//! Lipschitz in $x$ with constant $g_i$, so neighbouring elements differ in size by a
//! ratio of at most about $1 + g_i$ (REFERENCES.md asks for at most 1.2 near crack tips).
//!
//! Break points along a straight segment are placed by marching: from the current point,
//! the step is the largest $h$ with $h \le \phi_i(d_i(x + h))$ for every source, that is,
//! with $d = d_i(x)$ (distance shrinks by at most $h$ over the step)
//! $$ h = h_i \text{ if } d \le r_i + h_i, \qquad
//!    h = \max\!\Big(h_i, \frac{h_i + g_i (d - r_i)}{1 + g_i}\Big) \text{ otherwise.} $$
//! Marched from a crack tip along its own faces this gives exactly uniform elements of
//! size $h_i$ over the zone (the crack-opening fit and the tangential stencil need them
//! uniform, [`super::stencil`]), then a growth of $1 + g_i/(1+g_i)$ per element.

use super::V2;
use pdbem_geometry::point_segment_distance;

/// Where a source sits.
#[derive(Debug, Clone, PartialEq)]
pub enum SourceShape {
    /// A point (a crack tip, a crack mouth).
    Point(V2),
    /// An open polyline (a crack, a hole's boundary as a closed list of points).
    Polyline(Vec<V2>),
}

/// One source of the field.
#[derive(Debug, Clone, PartialEq)]
pub struct SizeSource {
    /// Point or polyline.
    pub shape: SourceShape,
    /// Element size on the source and within `radius` of it (m).
    pub size: f64,
    /// Radius of the uniform zone (m).
    pub radius: f64,
    /// Grading g (size growth per unit distance outside the zone).
    pub grading: f64,
}

impl SizeSource {
    /// A point source with the default grading.
    pub fn point(at: V2, size: f64, radius: f64) -> Self {
        Self {
            shape: SourceShape::Point(at),
            size,
            radius,
            grading: DEFAULT_GRADING,
        }
    }

    /// The same source with grading `g`.
    pub fn graded(mut self, g: f64) -> Self {
        self.grading = g;
        self
    }

    /// The size this source asks for at distance `d`.
    fn size_at(&self, d: f64) -> f64 {
        self.size + self.grading * (d - self.radius).max(0.0)
    }

    /// The largest step from distance `d` that stays below the source (module docs).
    fn step_at(&self, d: f64) -> f64 {
        if d <= self.radius + self.size {
            self.size
        } else {
            let g = self.grading;
            self.size
                .max((self.size + g * (d - self.radius)) / (1.0 + g))
        }
    }

    /// Distance from `x` to the source.
    fn distance(&self, x: V2) -> f64 {
        match &self.shape {
            SourceShape::Point(p) => (x - p).norm(),
            SourceShape::Polyline(pts) => pts
                .windows(2)
                .map(|w| point_segment_distance(&x, &w[0], &w[1]))
                .fold(f64::INFINITY, f64::min),
        }
    }
}

/// Grading of the field: 0.2 gives a growth of 1.2 per element at most.
pub const DEFAULT_GRADING: f64 = 0.2;

/// The element-size field of a mesh.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SizeField {
    /// Sources.
    pub sources: Vec<SizeSource>,
}

impl SizeField {
    /// The target size at `x` (infinite without sources).
    pub fn at(&self, x: V2) -> f64 {
        self.sources
            .iter()
            .map(|s| s.size_at(s.distance(x)))
            .fold(f64::INFINITY, f64::min)
    }

    /// The largest step from `x` that stays below the field over the step (module docs).
    pub fn step(&self, x: V2) -> f64 {
        self.sources
            .iter()
            .map(|s| s.step_at(s.distance(x)))
            .fold(f64::INFINITY, f64::min)
    }

    /// The sources plus `extra`.
    pub fn with(&self, extra: impl IntoIterator<Item = SizeSource>) -> Self {
        let mut f = self.clone();
        f.sources.extend(extra);
        f
    }
}

/// Marching along the segment from `a` to `b` with steps at most `cap` and at most the
/// field's step; calls `push` with every break parameter (arc length from `a`, the first
/// 0 and the last the segment length) and returns the element count, or `None` as soon
/// as the count passes `limit` or a size is not positive (nothing is allocated here:
/// counting a mesh of 1e12 elements stops at the limit). A last sliver under 0.3 of the
/// element before it is shared with that element.
pub fn march(
    a: V2,
    b: V2,
    cap: f64,
    field: &SizeField,
    limit: usize,
    mut push: impl FnMut(f64),
) -> Option<usize> {
    let len = (b - a).norm();
    let dir = (b - a) / len;
    let step_at = |s: f64| cap.min(field.step(a + dir * s));
    push(0.0);
    // The break before `s` is held back one step, so a sliver can move it.
    let (mut s, mut n) = (0.0, 0usize);
    let mut held: Option<(f64, f64)> = None; // (break, size of the element ending there)
    loop {
        let h = step_at(s);
        if h.is_nan() || h <= 0.0 || (h.is_infinite() && len.is_infinite()) {
            return None;
        }
        let remaining = len - s;
        if remaining <= h * (1.0 + 1e-9) {
            match held {
                Some((p, last)) if remaining < 0.3 * last => {
                    push(p - last + 0.5 * (last + remaining));
                }
                Some((p, _)) => push(p),
                None => {}
            }
            push(len);
            return Some(n + 1);
        }
        if let Some((p, _)) = held {
            push(p);
        }
        s += h;
        n += 1;
        if n > limit {
            return None;
        }
        held = Some((s, h));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn collect(a: V2, b: V2, cap: f64, f: &SizeField) -> Vec<f64> {
        let mut v = Vec::new();
        let n = march(a, b, cap, f, 1 << 20, |s| v.push(s)).unwrap();
        assert_eq!(n + 1, v.len());
        assert!(v.windows(2).all(|w| w[1] > w[0]));
        v
    }

    #[test]
    fn without_sources_the_cap_rules() {
        let f = SizeField::default();
        let mut n = 0;
        let count = march(V2::zeros(), V2::new(1.0, 0.0), 0.1, &f, 100, |_| n += 1).unwrap();
        assert_eq!(count, 10);
    }

    #[test]
    fn a_tip_source_gives_a_uniform_zone_then_bounded_growth() {
        let tip = V2::zeros();
        let f = SizeField {
            sources: vec![SizeSource::point(tip, 0.01, 0.2)],
        };
        let pts = collect(tip, V2::new(2.0, 0.0), 0.25, &f);
        let h: Vec<f64> = pts.windows(2).map(|w| w[1] - w[0]).collect();
        // Uniform 0.01 over the zone (20 elements).
        for d in &h[..20] {
            assert!((d - 0.01).abs() < 1e-12, "{d}");
        }
        for w in h.windows(2).take(h.len() - 2) {
            assert!(w[1] / w[0] <= 1.2 + 1e-12, "{} -> {}", w[0], w[1]);
        }
        assert!(h.iter().all(|&d| d <= 0.25 + 1e-12));
        // Every element is below the field at both of its ends.
        for w in pts.windows(2) {
            let size = w[1] - w[0];
            for s in [w[0], w[1]] {
                assert!(size <= f.at(V2::new(s, 0.0)) * (1.0 + 1e-9) + 1e-12);
            }
        }
    }

    #[test]
    fn marching_towards_a_fine_zone_arrives_at_its_size() {
        // The source sits at the far end: elements shrink towards it without overshoot.
        let f = SizeField {
            sources: vec![SizeSource::point(V2::new(1.0, 0.0), 1e-4, 1e-3)],
        };
        let pts = collect(V2::zeros(), V2::new(1.0, 0.0), 0.05, &f);
        for w in pts.windows(2) {
            let size = w[1] - w[0];
            assert!(size <= f.at(V2::new(w[1], 0.0)) * (1.0 + 1e-9) + 1e-12);
        }
        let last = pts[pts.len() - 1] - pts[pts.len() - 2];
        assert!(last < 2e-4, "{last}");
        // Geometric grading: a few hundred elements, not 1e4.
        assert!(pts.len() < 200, "{}", pts.len());
    }

    #[test]
    fn counting_stops_at_the_limit() {
        let f = SizeField::default();
        assert_eq!(
            march(V2::zeros(), V2::new(1.0, 0.0), 1e-9, &f, 1000, |_| ()),
            None
        );
    }
}
