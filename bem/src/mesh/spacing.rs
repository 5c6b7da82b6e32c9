//! One-dimensional element spacing along a segment: uniform, or uniform fine elements near a
//! crack tip followed by a mild geometric transition (ratio <= 1.2) to the far size.
//! REFERENCES.md warns that grading *at* the tip biases crack-opening SIFs, so the elements
//! within the refinement radius are kept uniform.

/// Break points (arc parameters in [0, length], increasing, including both ends) for a
/// segment of `length` with far element size `h`, optionally refined to `tip.0` within
/// `tip.1` of the end (`at_end`) or the start.
pub fn subdivide(length: f64, h: f64, tip: Option<(f64, f64)>, at_end: bool) -> Vec<f64> {
    let uniform = |len: f64, size: f64| -> Vec<f64> {
        let n = ((len / size).round() as usize).max(1);
        (0..=n).map(|i| len * i as f64 / n as f64).collect()
    };
    let Some((ht, radius)) = tip.filter(|(ht, r)| *ht < h && *r > 0.0) else {
        return uniform(length, h);
    };
    // Measured from the tip: uniform ht up to the radius, then growth 1.2 until h.
    let mut from_tip = Vec::new();
    let r = radius.min(length);
    let n_fine = ((r / ht).round() as usize).max(1);
    for i in 0..=n_fine {
        from_tip.push(r * i as f64 / n_fine as f64);
    }
    let mut s = r;
    let mut size = r / n_fine as f64;
    while s < length - 1e-12 * length {
        size = (size * 1.2).min(h);
        let remaining = length - s;
        if remaining < 1.5 * size {
            s = length;
        } else {
            s += size;
        }
        from_tip.push(s);
    }
    let mut pts: Vec<f64> = if at_end {
        from_tip.iter().rev().map(|d| length - d).collect()
    } else {
        from_tip
    };
    pts[0] = 0.0;
    let last = pts.len() - 1;
    pts[last] = length;
    pts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_spacing() {
        let p = subdivide(1.0, 0.1, None, false);
        assert_eq!(p.len(), 11);
        assert!((p[5] - 0.5).abs() < 1e-14);
    }

    #[test]
    fn tip_refinement_is_uniform_near_the_tip() {
        let p = subdivide(2.0, 0.2, Some((0.02, 0.3)), true);
        let n = p.len();
        let last: Vec<f64> = p[n - 10..].windows(2).map(|w| w[1] - w[0]).collect();
        for d in &last {
            assert!((d - 0.02).abs() < 1e-12);
        }
        for w in p.windows(2) {
            assert!(w[1] > w[0]);
            assert!(w[1] - w[0] <= 0.2 * 1.5 + 1e-12);
        }
    }
}
