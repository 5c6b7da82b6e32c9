//! Growth criterion of BEM-only growth: maximum circumferential stress (MCS, Erdogan &
//! Sih 1963) for the direction and the equivalent stress intensity factor, compared with
//! the Griffith toughness K_c.
//!
//! Near a tip, $\sqrt{2\pi r}\,\sigma_{\theta\theta} = \cos\frac{\theta}{2}
//! \left[K_I \cos^2\frac{\theta}{2} - \frac32 K_{II}\sin\theta\right]$. Its maximum over
//! $\theta$ is at the kink angle
//! $\theta_c = 2\arctan\left[(K_I - \sqrt{K_I^2 + 8K_{II}^2})/(4K_{II})\right]$
//! (REFERENCES.md, counter-clockwise from the crack line), and the crack grows when the
//! value there reaches the mode-I toughness:
//! $$K_{eq} = K_I\cos^3\frac{\theta_c}{2} - \frac32 K_{II}\cos\frac{\theta_c}{2}\sin\theta_c
//!   \ge K_c = \sqrt{E' G_c}.$$
//! Checks (unit tests below): $K_{II} = 0$ gives $K_{eq} = K_I$, $\theta_c = 0$; pure mode II
//! gives $\theta_c = -70.53°$ and $K_{eq} = \frac{2}{\sqrt3} K_{II}$, i.e. the classical MCS
//! ratio $K_{IIc}/K_{Ic} = \sqrt3/2$; $K_I = K_{II}$ gives $\theta_c = -53.13°$ and
//! $K_{eq} = 4K_I/\sqrt5$ (cos(θ/2) = 2/√5, sin θ = -4/5). A closed crack ($K_I < 0$,
//! $K_{II} = 0$) gives $K_{eq} < 0$ and never grows.

/// SIFs of one tip at unit load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipSif {
    /// Index into the tips of the crack front (`Front::tips`).
    pub tip: usize,
    /// K_I at load factor 1 (Pa sqrt(m)).
    pub k1: f64,
    /// K_II at load factor 1.
    pub k2: f64,
    /// Kink angle (radians, counter-clockwise from the crack line).
    pub theta: f64,
    /// Equivalent K at load factor 1.
    pub k_eq: f64,
}

/// Kink angle (radians, counter-clockwise from the crack line) by maximum circumferential
/// stress; 0 when `k2` vanishes against `k1`.
pub fn kink_angle(k1: f64, k2: f64) -> f64 {
    pdbem_bem::post::kink_angle(k1, k2)
}

/// Equivalent mode-I stress intensity factor by maximum circumferential stress at the
/// kink angle `theta` (radians): K_I cos^3(theta/2) - 3/2 K_II cos(theta/2) sin(theta).
pub fn equivalent_k(k1: f64, k2: f64, theta: f64) -> f64 {
    let c = (0.5 * theta).cos();
    k1 * c * c * c - 1.5 * k2 * c * theta.sin()
}

/// Kink angle (radians) and equivalent K (Pa sqrt(m)) of a tip.
pub fn mcs(k1: f64, k2: f64) -> (f64, f64) {
    let theta = kink_angle(k1, k2);
    (theta, equivalent_k(k1, k2, theta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pure_mode_one_is_straight_and_unchanged() {
        let (t, k) = mcs(2.0, 0.0);
        assert_eq!(t, 0.0);
        assert!((k - 2.0).abs() < 1e-15);
    }

    #[test]
    fn pure_mode_two_gives_the_classical_ratio() {
        let (t, k) = mcs(0.0, 1.0);
        assert!((t.to_degrees() + 70.528_779).abs() < 1e-5);
        // K_IIc / K_Ic = sqrt(3)/2 by MCS.
        assert!((k - 2.0 / 3f64.sqrt()).abs() < 1e-12, "{k}");
    }

    #[test]
    fn equal_modes_kink_by_53_degrees_and_the_maximum_is_at_the_kink() {
        let (t, k) = mcs(1.0, 1.0);
        assert!((t.to_degrees() + 53.130_102).abs() < 1e-5);
        // The hoop stress is largest at the kink: neighbouring angles give less.
        for d in [-0.01, 0.01] {
            assert!(equivalent_k(1.0, 1.0, t + d) < k);
        }
        // cos(theta/2) = 2/sqrt 5, sin(theta) = -4/5: K_eq = 4/sqrt 5.
        assert!((k - 4.0 / 5f64.sqrt()).abs() < 1e-9, "{k}");
    }

    #[test]
    fn negative_mode_two_kinks_the_other_way() {
        let (t, k) = mcs(1.0, -1.0);
        assert!((t.to_degrees() - 53.130_102).abs() < 1e-5);
        assert!((k - mcs(1.0, 1.0).1).abs() < 1e-12);
    }

    #[test]
    fn closed_crack_does_not_grow() {
        assert!(mcs(-1.0, 0.0).1 < 0.0);
    }
}
