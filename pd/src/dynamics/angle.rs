//! The deflection angle of a crack grown from a pre-crack tip (seed 004 section 4.3,
//! Table 8: "the deflecting angle of the crack propagation with respect to the original
//! crack direction").
//!
//! With $x_0$ the tip, $d$ the unit direction of the pre-crack's last segment and $n$ its
//! normal (counter-clockwise), every point $x$ with damage above the threshold, distance
//! $r = |x - x_0|$ in $[r_{min}, r_{max}]$ and $(x - x_0)\cdot d > 0$ (ahead of the tip)
//! has the polar angle $\theta = \operatorname{atan2}((x - x_0)\cdot n, (x - x_0)\cdot d)$
//! in $(-90°, 90°)$. The angles are counted in 2° bins, the counts summed over a 14°
//! window (7 bins), and the angle is the mean $\theta$ of the points within 10° of the
//! centre of the fullest window: the straight band of the grown crack, not a
//! secondary crack or scattered damage that fall in the annulus. $r_{min}$ (a few
//! horizons) skips the damaged process zone at the tip, where the crack starts curved.

use crate::geometry::P2;

/// The deflection angle (degrees, counter-clockwise positive, in (-90, 90)) of the
/// damaged band ahead of `tip` against the pre-crack direction `dir` (module docs);
/// `None` with fewer than 3 damaged points in the annulus.
pub fn deflection_angle(
    points: &[P2],
    damage: &[f64],
    tip: P2,
    dir: P2,
    threshold: f64,
    (r_min, r_max): (f64, f64),
) -> Option<f64> {
    let norm = dir[0].hypot(dir[1]);
    if norm <= 0.0 || !norm.is_finite() {
        return None;
    }
    let d = [dir[0] / norm, dir[1] / norm];
    let angles: Vec<f64> = points
        .iter()
        .zip(damage)
        .filter(|(_, &phi)| phi > threshold)
        .filter_map(|(x, _)| {
            let r = [x[0] - tip[0], x[1] - tip[1]];
            let (s, q) = (r[0] * d[0] + r[1] * d[1], r[1] * d[0] - r[0] * d[1]);
            let len = s.hypot(q);
            (s > 0.0 && len >= r_min && len <= r_max).then(|| q.atan2(s).to_degrees())
        })
        .collect();
    if angles.len() < 3 {
        return None;
    }
    const BINS: usize = 90;
    let bin = |a: f64| (((a + 90.0) / 2.0) as usize).min(BINS - 1);
    let mut counts = [0usize; BINS];
    for &a in &angles {
        counts[bin(a)] += 1;
    }
    let window =
        |c: usize| -> usize { counts[c.saturating_sub(3)..(c + 4).min(BINS)].iter().sum() };
    let best = (0..BINS).max_by_key(|&c| (window(c), std::cmp::Reverse(c)))?;
    let centre = -90.0 + 2.0 * best as f64 + 1.0;
    let near: Vec<f64> = angles
        .iter()
        .copied()
        .filter(|a| (a - centre).abs() <= 10.0)
        .collect();
    Some(near.iter().sum::<f64>() / near.len() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A band of points at 63 degrees from a tip (lattice-like scatter of +-0.5 mm across
    /// it), a pre-crack's damaged faces behind the tip and a blob of stray damage in the
    /// annulus at -20 degrees: the measure gives 63 degrees within 1 degree, and the
    /// mirrored band -63; nothing damaged gives None.
    #[test]
    fn band_angle_ignores_faces_and_stray_damage() {
        let tip = [0.05, 0.125];
        let mut pts = Vec::new();
        let a = 63f64.to_radians();
        for k in 0..80 {
            let r = 0.001 * k as f64;
            let off = 0.0005 * ((k % 3) as f64 - 1.0);
            pts.push([
                tip[0] + r * a.cos() - off * a.sin(),
                tip[1] + r * a.sin() + off * a.cos(),
            ]);
        }
        for k in 0..50 {
            pts.push([0.001 * k as f64, 0.125 + 0.001 * ((k % 2) as f64 - 0.5)]);
        }
        let b = (-20f64).to_radians();
        for k in 0..10 {
            let r = 0.03 + 0.001 * (k % 5) as f64;
            pts.push([
                tip[0] + r * b.cos(),
                tip[1] + r * b.sin() + 0.001 * (k / 5) as f64,
            ]);
        }
        let phi = vec![0.6; pts.len()];
        let ang = deflection_angle(&pts, &phi, tip, [1.0, 0.0], 0.4, (0.012, 0.045)).unwrap();
        assert!((ang - 63.0).abs() < 1.0, "{ang}");
        let mirrored: Vec<P2> = pts.iter().map(|p| [p[0], 2.0 * tip[1] - p[1]]).collect();
        let ang = deflection_angle(&mirrored, &phi, tip, [1.0, 0.0], 0.4, (0.012, 0.045)).unwrap();
        assert!((ang + 63.0).abs() < 1.0, "{ang}");
        let none = vec![0.1; pts.len()];
        assert!(deflection_angle(&pts, &none, tip, [1.0, 0.0], 0.4, (0.012, 0.045)).is_none());
    }
}
