//! Ray casts: the distance `s > 0` along a ray `o + s d` to a segment, a closed polygon
//! or a circle.

use crate::P2;

/// Crossing `s > 0` of the ray `o + s d` with the segment from `a` to `b`: None when
/// parallel (`|d x e| <= 1e-14 |e|`), behind or at the origin (`s <= 1e-12 |e|`), or
/// beyond the ends (parameter outside `[-1e-12, 1 + 1e-12]`). `d` need not be a unit
/// vector; `s` is then in units of `|d|`.
pub fn ray_segment(o: &P2, d: &P2, a: &P2, b: &P2) -> Option<f64> {
    let cross = |p: P2, q: P2| p.x * q.y - p.y * q.x;
    let e = b - a;
    let den = cross(*d, e);
    if den.abs() <= 1e-14 * e.norm() {
        return None;
    }
    let w = a - o;
    let s = cross(w, e) / den;
    let u = cross(w, *d) / den;
    let tol = 1e-12;
    (s > tol * e.norm() && (-tol..=1.0 + tol).contains(&u)).then_some(s)
}

/// Nearest crossing `s > 0` of the ray `o + s d` with a closed polygon ([`ray_segment`]
/// per edge).
pub fn ray_polygon(o: &P2, d: &P2, poly: &[P2]) -> Option<f64> {
    let n = poly.len();
    (0..n)
        .filter_map(|i| ray_segment(o, d, &poly[i], &poly[(i + 1) % n]))
        .min_by(f64::total_cmp)
}

/// Entry `s > 0` of the ray `o + s d` (`d` a unit vector) into the circle of `center`
/// and `radius`, exact: the smaller root of `|o + s d - c|^2 = r^2`. None when the ray
/// misses, or when that root is not positive (the origin inside or the circle behind).
pub fn ray_circle(o: &P2, d: &P2, center: &P2, radius: f64) -> Option<f64> {
    // |o + s d - c|^2 = r^2: s^2 + 2 b s + c0 = 0.
    let w = o - center;
    let b = w.dot(d);
    let c0 = w.norm_squared() - radius * radius;
    let disc = b * b - c0;
    if disc < 0.0 {
        return None;
    }
    let s = -b - disc.sqrt();
    (s > 0.0).then_some(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> [P2; 4] {
        [
            P2::new(0.0, 0.0),
            P2::new(10.0, 0.0),
            P2::new(10.0, 10.0),
            P2::new(0.0, 10.0),
        ]
    }

    #[test]
    fn ray_hits_and_misses_a_segment() {
        let o = P2::new(0.0, 0.0);
        let d = P2::new(1.0, 0.0);
        let (a, b) = (P2::new(2.0, -1.0), P2::new(2.0, 1.0));
        assert_eq!(ray_segment(&o, &d, &a, &b), Some(2.0));
        // Behind the origin.
        assert_eq!(ray_segment(&o, &-d, &a, &b), None);
        // Parallel.
        assert!(ray_segment(&o, &d, &P2::new(0.0, 1.0), &P2::new(2.0, 1.0)).is_none());
        // Beyond the end of the segment.
        assert!(ray_segment(&o, &d, &P2::new(2.0, 1.0), &P2::new(2.0, 3.0)).is_none());
    }

    #[test]
    fn ray_hits_and_misses_a_polygon() {
        let sq = square();
        let c = P2::new(5.0, 5.0);
        assert_eq!(ray_polygon(&c, &P2::new(1.0, 0.0), &sq), Some(5.0));
        assert_eq!(ray_polygon(&c, &P2::new(0.0, -1.0), &sq), Some(5.0));
        // From outside: the nearest edge.
        let o = P2::new(-5.0, 5.0);
        assert_eq!(ray_polygon(&o, &P2::new(1.0, 0.0), &sq), Some(5.0));
        assert_eq!(ray_polygon(&o, &P2::new(-1.0, 0.0), &sq), None);
    }

    #[test]
    fn ray_hits_and_misses_a_circle() {
        let o = P2::new(0.0, 0.0);
        let d = P2::new(1.0, 0.0);
        let c = P2::new(5.0, 0.0);
        assert!((ray_circle(&o, &d, &c, 1.0).unwrap() - 4.0).abs() < 1e-12);
        assert_eq!(ray_circle(&o, &-d, &c, 1.0), None);
        assert_eq!(ray_circle(&o, &P2::new(0.0, 1.0), &c, 1.0), None);
        // Origin inside the circle: no entry ahead.
        assert_eq!(ray_circle(&c, &d, &c, 1.0), None);
    }
}
