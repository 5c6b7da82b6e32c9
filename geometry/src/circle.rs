//! Circles as polygons.

use crate::P2;

/// Points of a circle split into `n` straight edges, clockwise when
/// `clockwise` (holes) and counter-clockwise otherwise, starting at angle 0.
pub fn circle_polygon(center: &P2, radius: f64, n: usize, clockwise: bool) -> Vec<P2> {
    let sign = if clockwise { -1.0 } else { 1.0 };
    (0..n)
        .map(|k| {
            let t = sign * 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            center + P2::new(t.cos(), t.sin()) * radius
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{is_ccw, signed_area};

    #[test]
    fn circle_orientation_and_area() {
        let c = circle_polygon(&P2::new(1.0, 2.0), 1.0, 256, true);
        assert!(!is_ccw(&c));
        let area = -signed_area(&c);
        assert!((area - std::f64::consts::PI).abs() < 1e-3);
        let c = circle_polygon(&P2::new(1.0, 2.0), 2.0, 4, false);
        assert!(is_ccw(&c));
        assert!((c[0] - P2::new(3.0, 2.0)).norm() < 1e-15);
        assert!((c[1] - P2::new(1.0, 4.0)).norm() < 1e-15);
    }
}
