//! Closed-form reference solutions (REFERENCES.md): the LEFM references the BEM is
//! verified against, also used by pdbem as analytic curves in plots and as the error
//! reference of runs and sweeps.
//!
//! - SENT (single edge-cracked strip in tension): [`sent_f_tada`],
//!   [`sent_f_polynomial`], [`sent_f_fem`] (converged FEM table), [`sent_k1`],
//!   [`sent_cmod_v`], [`sent_cmod`];
//! - inclined central crack in an infinite plate: [`inclined_crack_k`];
//! - two equal colinear cracks in an infinite plate: [`colinear_cracks_k1`], with the
//!   complete elliptic integrals [`complete_elliptic`];
//! - kink angle by maximum circumferential stress: [`kink_angle_deg`];
//! - Kirsch hole: [`kirsch_hoop_on_hole`], [`kirsch_hoop`];
//! - uniform tension field: [`uniform_tension_displacement`];
//! - cantilever with shear deformation: [`cantilever_deflection`];
//! - Griffith: [`griffith_k_c`], [`griffith_load`], [`central_crack_width_factor`];
//! - elastic constants: [`e_prime`], [`kappa`], [`shear_modulus`];
//! - PD constants: [`pd_critical_stretch`], [`pd_micromodulus`].
//!
//! All quantities SI: stresses in Pa, lengths in m, K in Pa sqrt(m).

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

/// Plane stress or plane strain (the material's 2-D idealisation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum PlaneKind {
    /// Thin plate: sigma_zz = 0.
    Stress,
    /// Thick body: eps_zz = 0.
    Strain,
}

/// Effective modulus E' = E (plane stress) or E / (1 - nu^2) (plane strain).
pub fn e_prime(e: f64, nu: f64, plane: PlaneKind) -> f64 {
    match plane {
        PlaneKind::Stress => e,
        PlaneKind::Strain => e / (1.0 - nu * nu),
    }
}

/// Kolosov constant kappa = 3 - 4 nu (plane strain) or (3 - nu)/(1 + nu) (plane stress).
pub fn kappa(nu: f64, plane: PlaneKind) -> f64 {
    match plane {
        PlaneKind::Stress => (3.0 - nu) / (1.0 + nu),
        PlaneKind::Strain => 3.0 - 4.0 * nu,
    }
}

/// Shear modulus mu = E / (2 (1 + nu)).
pub fn shear_modulus(e: f64, nu: f64) -> f64 {
    e / (2.0 * (1.0 + nu))
}

/// Tada-Paris-Irwin geometry factor F(a/W) of the SENT specimen (better than
/// 0.5 % for any a/W):
/// F = sqrt(2W/(pi a) tan(pi a/2W)) [0.752 + 2.02 a/W + 0.37 (1 - sin(pi a/2W))^3] / cos(pi a/2W).
pub fn sent_f_tada(a_over_w: f64) -> f64 {
    let x = a_over_w;
    let t = PI * x / 2.0;
    let root = (t.tan() / t).sqrt();
    root * (0.752 + 2.02 * x + 0.37 * (1.0 - t.sin()).powi(3)) / t.cos()
}

/// Polynomial SENT geometry factor, valid for a/W <= 0.6 (`None` beyond):
/// F = 1.12 - 0.231 x + 10.55 x^2 - 21.72 x^3 + 30.39 x^4.
pub fn sent_f_polynomial(a_over_w: f64) -> Option<f64> {
    let x = a_over_w;
    if !(0.0..=0.6).contains(&x) {
        return None;
    }
    Some(1.12 - 0.231 * x + 10.55 * x.powi(2) - 21.72 * x.powi(3) + 30.39 * x.powi(4))
}

/// Converged quadratic-FEM J-integral values of F(a/W) (REFERENCES.md; H/W = 2,
/// 4, 6 identical; rings agreeing to 0.001 %): `(a/W, F)`.
pub const SENT_FEM_TABLE: [(f64, f64); 8] = [
    (0.1, 1.1891),
    (0.2, 1.3672),
    (0.3, 1.6596),
    (0.4, 2.1110),
    (0.5, 2.8239),
    (0.6, 4.0322),
    (0.7, 6.3536),
    (0.8, 11.953),
];

/// SENT geometry factor from the FEM table for 0.1 <= a/W <= 0.8 (`None`
/// outside). Between table points the ratio F_fem / F_tada (smooth, within
/// 0.5 % of 1) is interpolated linearly and multiplied by Tada's F, so the
/// steep growth of F is carried by the closed form.
pub fn sent_f_fem(a_over_w: f64) -> Option<f64> {
    let x = a_over_w;
    let first = SENT_FEM_TABLE[0].0;
    let last = SENT_FEM_TABLE[SENT_FEM_TABLE.len() - 1].0;
    if !(first - 1e-12..=last + 1e-12).contains(&x) {
        return None;
    }
    let ratio = |(xi, fi): (f64, f64)| fi / sent_f_tada(xi);
    let k = SENT_FEM_TABLE
        .windows(2)
        .position(|w| x <= w[1].0 + 1e-12)
        .unwrap_or(SENT_FEM_TABLE.len() - 2);
    let (lo, hi) = (SENT_FEM_TABLE[k], SENT_FEM_TABLE[k + 1]);
    let s = ((x - lo.0) / (hi.0 - lo.0)).clamp(0.0, 1.0);
    let r = ratio(lo) * (1.0 - s) + ratio(hi) * s;
    Some(r * sent_f_tada(x))
}

/// SENT mode-I stress intensity factor K_I = sigma sqrt(pi a) F(a/W), with
/// Tada's F ([`sent_f_tada`]).
pub fn sent_k1(sigma: f64, a: f64, w: f64) -> f64 {
    sigma * (PI * a).sqrt() * sent_f_tada(a / w)
}

/// SENT crack-mouth opening factor V(a/W) = [1.46 + 3.42 (1 - cos(pi a/2W))] / cos^2(pi a/2W).
pub fn sent_cmod_v(a_over_w: f64) -> f64 {
    let c = (PI * a_over_w / 2.0).cos();
    (1.46 + 3.42 * (1.0 - c)) / (c * c)
}

/// SENT crack-mouth opening displacement CMOD = 4 sigma a V(a/W) / E' (m).
pub fn sent_cmod(sigma: f64, a: f64, w: f64, e_prime: f64) -> f64 {
    4.0 * sigma * a / e_prime * sent_cmod_v(a / w)
}

/// K_I, K_II of a central crack of half-length `a` in an infinite plate under
/// uniaxial tension `sigma` at angle `beta_deg` between crack line and load:
/// K_I = sigma sqrt(pi a) sin^2 beta, K_II = sigma sqrt(pi a) sin beta cos beta.
pub fn inclined_crack_k(sigma: f64, a: f64, beta_deg: f64) -> (f64, f64) {
    let b = beta_deg.to_radians();
    let k0 = sigma * (PI * a).sqrt();
    (k0 * b.sin().powi(2), k0 * b.sin() * b.cos())
}

/// Complete elliptic integrals of the first and second kind, `(K(k), E(k))`, of modulus
/// $k = \sqrt{1 - k'^2}$ given by its complement `k_comp` $= k' \in (0, 1]$, by the
/// arithmetic-geometric mean (Abramowitz & Stegun 17.6.3-4): $a_0 = 1$, $b_0 = k'$,
/// $c_0 = k$; $a_{n+1} = (a_n + b_n)/2$, $b_{n+1} = \sqrt{a_n b_n}$,
/// $c_{n+1} = (a_n - b_n)/2$; $K = \pi / (2 a_N)$,
/// $E = K\,(1 - \sum_{n \ge 0} 2^{n-1} c_n^2)$. Quadratic convergence: a handful of
/// steps to machine precision. Taking $k'$ rather than $k$ keeps both accurate as
/// $k \to 1$, where $K \approx \ln(4/k')$. `k_comp = 0` gives `(inf, 1)`.
pub fn complete_elliptic(k_comp: f64) -> (f64, f64) {
    if k_comp <= 0.0 {
        return (f64::INFINITY, 1.0);
    }
    let (mut a, mut b) = (1.0_f64, k_comp);
    // 2^{-1} c_0^2 with c_0^2 = 1 - k'^2 = (1 - k')(1 + k') (no cancellation).
    let mut sum = 0.5 * (1.0 - k_comp) * (1.0 + k_comp);
    let mut weight = 0.5;
    for _ in 0..64 {
        let c = 0.5 * (a - b);
        if c.abs() <= f64::EPSILON * a {
            break;
        }
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
        weight *= 2.0;
        sum += weight * c * c;
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// K_I at the inner tips ($|x| = b$) and the outer tips ($|x| = c$) of two equal colinear
/// cracks $b < |x| < c$ on the x axis of an infinite plate under remote tension `sigma`
/// normal to them (Tada, Paris & Irwin, *The Stress Analysis of Cracks Handbook*, two
/// equal collinear cracks). With $k' = b/c$, $k = \sqrt{1 - k'^2}$ and the complete
/// elliptic integrals $K(k)$, $E(k)$ ([`complete_elliptic`]):
/// $$K_{inner} = \sigma\sqrt{\pi c}\,\sqrt{c/b}\,\frac{E/K - k'^2}{k}, \qquad
///   K_{outer} = \sigma\sqrt{\pi c}\,\frac{1 - E/K}{k}.$$
/// They follow from Westergaard's $Z = \sigma (z^2 - d^2)/\sqrt{(z^2 - b^2)(z^2 - c^2)}$
/// with $d^2 = c^2 E/K$ (each crack's net opening dislocation vanishes,
/// $\int_b^c Z\,dx = 0$) and $K = \lim \sqrt{2\pi r}\,Z$ at each tip. Limits: $b \to 0$,
/// one crack of half-length $c$, $K_{outer} \to \sigma\sqrt{\pi c}\,(1 - 1/\ln(4c/b))$
/// (logarithmically slowly) while $K_{inner} \approx \sigma\sqrt{\pi c}\,\sqrt{c/b} /
/// \ln(4c/b)$ diverges (the ligament $2b$ carries a finite force); $c - b \ll b$, both
/// tips tend to the isolated crack's $\sigma\sqrt{\pi a}$, $a = (c - b)/2$.
/// Returns `(K_inner, K_outer)` in Pa sqrt(m); needs $0 < b < c$.
pub fn colinear_cracks_k1(sigma: f64, b: f64, c: f64) -> (f64, f64) {
    let kp = b / c;
    let k = ((1.0 - kp) * (1.0 + kp)).sqrt();
    let (ek, ee) = complete_elliptic(kp);
    let ratio = ee / ek;
    let k0 = sigma * (PI * c).sqrt();
    (
        k0 * (c / b).sqrt() * (ratio - kp * kp) / k,
        k0 * (1.0 - ratio) / k,
    )
}

/// Kink angle (degrees, from the crack line, counter-clockwise positive) by
/// maximum circumferential stress (Erdogan & Sih):
/// theta = 2 atan[(K_I - sqrt(K_I^2 + 8 K_II^2)) / (4 K_II)], 0 when K_II = 0.
pub fn kink_angle_deg(k1: f64, k2: f64) -> f64 {
    crate::post::kink_angle(k1, k2).to_degrees()
}

/// Kirsch hoop stress on the hole of an infinite plate under remote uniaxial
/// `sigma`: sigma_tt = sigma (1 - 2 cos 2 theta), theta from the load axis.
pub fn kirsch_hoop_on_hole(sigma: f64, theta: f64) -> f64 {
    sigma * (1.0 - 2.0 * (2.0 * theta).cos())
}

/// Kirsch hoop stress at radius `r >= radius` and angle `theta` from the load
/// axis: sigma_tt = sigma/2 (1 + a^2/r^2) - sigma/2 (1 + 3 a^4/r^4) cos 2 theta.
pub fn kirsch_hoop(sigma: f64, radius: f64, r: f64, theta: f64) -> f64 {
    let q = (radius / r).powi(2);
    0.5 * sigma * (1.0 + q) - 0.5 * sigma * (1.0 + 3.0 * q * q) * (2.0 * theta).cos()
}

/// Displacement `(u_x, u_y)` at `(x, y)` (relative to the fixed point) of a
/// body under uniform uniaxial tension `sigma` along x:
/// u_x = sigma x / E', u_y = -nu* sigma y / E' with nu* = nu (plane stress) or
/// nu/(1 - nu) (plane strain).
pub fn uniform_tension_displacement(
    sigma: f64,
    e: f64,
    nu: f64,
    plane: PlaneKind,
    x: f64,
    y: f64,
) -> (f64, f64) {
    let ep = e_prime(e, nu, plane);
    let nu_star = match plane {
        PlaneKind::Stress => nu,
        PlaneKind::Strain => nu / (1.0 - nu),
    };
    (sigma * x / ep, -nu_star * sigma * y / ep)
}

/// Tip-loaded cantilever (length `l`, depth `d`, thickness `t`, tip shear `p`)
/// deflection at `x` from the clamp, Timoshenko beam:
/// v(x) = P x^2 (3L - x) / (6 E I) + P x / (k G A), I = t d^3/12, A = t d,
/// k = 5/6 (rectangular section).
pub fn cantilever_deflection(p: f64, l: f64, d: f64, t: f64, e: f64, nu: f64, x: f64) -> f64 {
    let i = t * d.powi(3) / 12.0;
    let bending = p * x * x * (3.0 * l - x) / (6.0 * e * i);
    let shear = p * x / (5.0 / 6.0 * shear_modulus(e, nu) * t * d);
    bending + shear
}

/// Critical stress intensity factor K_c = sqrt(E' G_c).
pub fn griffith_k_c(g_c: f64, e_prime: f64) -> f64 {
    (e_prime * g_c).sqrt()
}

/// Finite-width factor of a central crack of half-length `a` in a plate of
/// width `w` (Feddersen): F = sqrt(sec(pi a / w)).
pub fn central_crack_width_factor(a: f64, w: f64) -> f64 {
    (1.0 / (PI * a / w).cos()).sqrt()
}

/// Griffith load sigma_c = K_c / (F sqrt(pi a)) for a crack of (half-)length
/// `a` with geometry factor `f`.
pub fn griffith_load(k_c: f64, a: f64, f: f64) -> f64 {
    k_c / (f * (PI * a).sqrt())
}

/// PMB critical stretch from the fracture energy: s0 = sqrt(4 pi G_c / (9 E delta))
/// (plane stress) or sqrt(5 pi G_c / (12 E delta)) (plane strain).
pub fn pd_critical_stretch(g_c: f64, e: f64, delta: f64, plane: PlaneKind) -> f64 {
    match plane {
        PlaneKind::Stress => (4.0 * PI * g_c / (9.0 * e * delta)).sqrt(),
        PlaneKind::Strain => (5.0 * PI * g_c / (12.0 * e * delta)).sqrt(),
    }
}

/// PMB micromodulus c = 9E/(pi t delta^3) (plane stress) or
/// 48E/(5 pi t delta^3) (plane strain).
pub fn pd_micromodulus(e: f64, thickness: f64, delta: f64, plane: PlaneKind) -> f64 {
    let d3 = thickness * delta.powi(3);
    match plane {
        PlaneKind::Stress => 9.0 * e / (PI * d3),
        PlaneKind::Strain => 48.0 * e / (5.0 * PI * d3),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn elliptic_integrals_by_agm() {
        // k = 1/sqrt(2): K = 1.8540746773013719, E = 1.3506438810476755 (A&S table 17.1).
        let (k, e) = complete_elliptic(std::f64::consts::FRAC_1_SQRT_2);
        assert!((k - 1.854_074_677_301_371_9).abs() < 1e-15);
        assert!((e - 1.350_643_881_047_675_5).abs() < 1e-15);
        // k = 0: K = E = pi/2.
        let (k, e) = complete_elliptic(1.0);
        assert!((k - PI / 2.0).abs() < 1e-15 && (e - PI / 2.0).abs() < 1e-15);
        // Legendre's relation E K' + E' K - K K' = pi/2 for k from 1e-4 to 1 - 1e-8.
        for kp in [1e-8_f64, 1e-4, 0.1, 0.3, 0.5, 0.9, 0.99] {
            let k = (1.0 - kp * kp).sqrt();
            let (kk, ek) = complete_elliptic(kp);
            let (kk2, ek2) = complete_elliptic(k);
            let legendre = ek * kk2 + ek2 * kk - kk * kk2;
            assert!((legendre - PI / 2.0).abs() < 1e-13, "k' = {kp}: {legendre}");
        }
        // k -> 1: K = ln(4/k') + (k'^2/4)(ln(4/k') - 1) + O(k'^4 ln k').
        let kp = 1e-4_f64;
        let l = (4.0 / kp).ln();
        let (kk, ek) = complete_elliptic(kp);
        assert!((kk - (l + 0.25 * kp * kp * (l - 1.0))).abs() < 1e-14);
        assert!((ek - (1.0 + 0.5 * kp * kp * (l - 0.5))).abs() < 1e-14);
    }

    #[test]
    fn colinear_cracks_zero_net_opening_by_quadrature() {
        // d^2 = c^2 E/K makes int_b^c Z dx vanish: with x^2 = t(theta) =
        // (b^2 + c^2)/2 + (c^2 - b^2)/2 cos(theta) the condition is
        // int_0^pi (t - d^2) / sqrt(t) dtheta = 0, a smooth periodic integrand
        // (the trapezoidal rule converges exponentially).
        for (b, c) in [(0.2, 1.2), (0.01, 1.0), (0.9, 1.0)] {
            let n = 2000;
            let (mut num, mut den) = (0.0, 0.0);
            for i in 0..=n {
                let th = PI * i as f64 / n as f64;
                let w = if i == 0 || i == n { 0.5 } else { 1.0 };
                let t = 0.5 * (b * b + c * c) + 0.5 * (c * c - b * b) * th.cos();
                num += w * t.sqrt();
                den += w / t.sqrt();
            }
            let (kk, ek) = complete_elliptic(b / c);
            assert!(rel(num / den, c * c * ek / kk) < 1e-12, "b {b} c {c}");
        }
    }

    #[test]
    fn colinear_cracks_limits() {
        let s = 2.0;
        // Far apart relative to their length (c - b = 1e-4 b): each is an isolated crack
        // of half-length a = (c - b)/2; the interaction is of order (a / b)^2.
        let (b, c) = (1.0, 1.0001);
        let iso = s * (PI * 0.5 * (c - b)).sqrt();
        let (ki, ko) = colinear_cracks_k1(s, b, c);
        assert!(rel(ki, iso) < 1e-8 && rel(ko, iso) < 1e-8);
        // Closer, the cracks amplify each other, the inner tips most.
        let (ki, ko) = colinear_cracks_k1(s, 0.2, 1.2);
        let iso = s * (PI * 0.5_f64).sqrt();
        assert!(ki > ko && ko > iso);
        // b -> 0: one crack of half-length c; the outer tip approaches sigma sqrt(pi c)
        // as 1 - 1/ln(4c/b), the inner tip diverges as sqrt(c/b) / ln(4c/b).
        let c = 1.5;
        let k_one = s * (PI * c).sqrt();
        let mut last = 0.0;
        for b in [1e-2_f64, 1e-4, 1e-8, 1e-16, 1e-300] {
            let (ki, ko) = colinear_cracks_k1(s, b * c, c);
            let l = (4.0 / b).ln();
            assert!(ko > last && ko < k_one);
            last = ko;
            if b <= 1e-4 {
                assert!(rel(ko, k_one * (1.0 - 1.0 / l)) < 1e-6, "b {b}");
                assert!(rel(ki, k_one / (b.sqrt() * l)) < 1e-6, "b {b}");
            }
        }
        assert!(rel(last, k_one) < 2e-3);
    }

    #[test]
    fn colinear_cracks_nearly_touching() {
        // Gap 2b = 1e-3 c. With k' = b/c: E/K = [1 + (k'^2/2)(L - 1/2)] /
        // [L + (k'^2/4)(L - 1)] + O(k'^4 L), L = ln(4/k') (A&S 17.3.26, 17.3.36).
        let (s, c) = (1.0_f64, 1.0_f64);
        let b = 5e-4_f64;
        let kp = b / c;
        let l = (4.0 / kp).ln();
        let ratio = (1.0 + 0.5 * kp * kp * (l - 0.5)) / (l + 0.25 * kp * kp * (l - 1.0));
        let k = (1.0 - kp * kp).sqrt();
        let k0 = s * (PI * c).sqrt();
        let (ki, ko) = colinear_cracks_k1(s, b, c);
        assert!(rel(ki, k0 * (c / b).sqrt() * (ratio - kp * kp) / k) < 1e-12);
        assert!(rel(ko, k0 * (1.0 - ratio) / k) < 1e-12);
        // Leading order: the inner tips as a ligament 2b carrying P = pi sigma c E/K,
        // K_inner = P / sqrt(pi b) (Tada: semi-infinite cracks loaded through a
        // ligament); relative corrections O(k'^2 ln k') ~ 2e-6.
        let p = PI * s * c * ratio;
        assert!(rel(ki, p / (PI * b).sqrt()) < 1e-5);
    }

    #[test]
    fn seed002_table3_exact_cmod() {
        // Seed 002 Table 3 "exact": sigma 0.5 Pa, E 1e4 Pa (plane stress), W 10 m.
        for (a, exact) in [(2.0, 7.20e-4), (5.0, 4.92e-3), (8.0, 6.41e-2)] {
            let c = sent_cmod(0.5, a, 10.0, 1e4);
            // Table values are printed to 3 significant figures.
            assert!(rel(c, exact) < 2e-3, "a = {a}: {c} vs {exact}");
        }
    }

    #[test]
    fn tada_agrees_with_fem_table_within_0_6_percent() {
        // REFERENCES.md: Tada is off by up to about 0.5 %; measured worst
        // case +0.555 % at a/W = 0.1, -0.27 % at 0.3, +0.35 % at 0.7.
        for (x, f) in SENT_FEM_TABLE {
            assert!(rel(sent_f_tada(x), f) < 6e-3, "a/W = {x}");
        }
    }

    #[test]
    fn polynomial_agrees_with_fem_up_to_0_6() {
        for (x, f) in SENT_FEM_TABLE.iter().filter(|(x, _)| *x <= 0.6) {
            let p = sent_f_polynomial(*x).expect("in range");
            assert!(rel(p, *f) < 6e-3, "a/W = {x}: {p} vs {f}");
        }
        assert_eq!(sent_f_polynomial(0.7), None);
        assert!((sent_f_polynomial(0.0).expect("in range") - 1.12).abs() < 1e-15);
    }

    #[test]
    fn fem_interpolation_hits_nodes_and_stays_between() {
        for (x, f) in SENT_FEM_TABLE {
            let v = sent_f_fem(x).expect("in range");
            assert!(rel(v, f) < 1e-12, "a/W = {x}");
        }
        let mid = sent_f_fem(0.45).expect("in range");
        assert!(mid > 2.1110 && mid < 2.8239);
        assert!(rel(mid, sent_f_tada(0.45)) < 6e-3);
        assert_eq!(sent_f_fem(0.05), None);
        assert_eq!(sent_f_fem(0.9), None);
    }

    #[test]
    fn sent_k1_shallow_crack_tends_to_1_12() {
        let k = sent_k1(1.0, 1e-4, 1.0);
        assert!(rel(k, 1.122 * (PI * 1e-4).sqrt()) < 2e-3);
    }

    #[test]
    fn kink_angle_erdogan_sih() {
        assert!((kink_angle_deg(1.0, 1.0) + 53.130_102).abs() < 1e-5);
        assert_eq!(kink_angle_deg(1.0, 0.0), 0.0);
        // Pure mode II: theta = -70.53 deg (2 atan(-1/sqrt 2)).
        assert!((kink_angle_deg(0.0, 1.0) + 70.528_779).abs() < 1e-5);
        assert!((kink_angle_deg(1.0, -1.0) - 53.130_102).abs() < 1e-5);
    }

    #[test]
    fn inclined_crack_at_45_has_equal_modes() {
        let (k1, k2) = inclined_crack_k(1.0, 1.0, 45.0);
        assert!(rel(k1, 0.5 * PI.sqrt()) < 1e-14);
        assert!(rel(k2, k1) < 1e-14);
        let (k1, k2) = inclined_crack_k(2.0, 0.5, 90.0);
        assert!(rel(k1, 2.0 * (PI * 0.5).sqrt()) < 1e-14);
        assert!(k2.abs() < 1e-15);
    }

    #[test]
    fn kirsch_peak_is_three_sigma() {
        assert!((kirsch_hoop_on_hole(1.0, PI / 2.0) - 3.0).abs() < 1e-14);
        assert!((kirsch_hoop_on_hole(1.0, 0.0) + 1.0).abs() < 1e-14);
        assert!((kirsch_hoop(1.0, 1.0, 1.0, PI / 2.0) - 3.0).abs() < 1e-14);
        // Far field: the hoop stress at theta = 90 deg tends to sigma.
        assert!((kirsch_hoop(1.0, 1.0, 1e4, PI / 2.0) - 1.0).abs() < 1e-7);
    }

    #[test]
    fn uniform_tension_plane_strain_poisson() {
        let (ux, uy) = uniform_tension_displacement(1.0, 1.0, 0.25, PlaneKind::Strain, 1.0, 1.0);
        let ep = 1.0 / (1.0 - 0.0625);
        assert!(rel(ux, 1.0 / ep) < 1e-14);
        assert!(rel(uy, -(0.25 / 0.75) / ep) < 1e-14);
    }

    #[test]
    fn cantilever_tip_bending_term() {
        // Seed 002 3.1.2 geometry: L 1, D 0.2, E 100 GPa; bending PL^3/(3EI).
        let (p, l, d, e): (f64, f64, f64, f64) = (1e3, 1.0, 0.2, 100e9);
        let i = d.powi(3) / 12.0;
        let v = cantilever_deflection(p, l, d, 1.0, e, 1.0 / 3.0, l);
        let bend = p * l.powi(3) / (3.0 * e * i);
        assert!(v > bend && v < 1.05 * bend);
    }

    #[test]
    fn seed001_griffith_load_about_14_mpa() {
        // 50 mm plate, 10 mm central crack, E 30 GPa, G_c 110 J/m^2.
        let kc = griffith_k_c(110.0, 30e9);
        let f = central_crack_width_factor(0.005, 0.05);
        let s = griffith_load(kc, 0.005, f);
        assert!((s / 1e6 - 14.13).abs() < 0.05, "{s}");
    }

    #[test]
    fn seed001_critical_stretch() {
        // Seed 001 section 6: s0 = 0.0026 for G_c 110, E 30 GPa, delta 3.015 x 0.25 mm.
        let s0 = pd_critical_stretch(110.0, 30e9, 3.015 * 0.25e-3, PlaneKind::Stress);
        assert!((s0 - 0.0026).abs() < 1e-5, "{s0}");
    }

    #[test]
    fn elastic_constants() {
        assert_eq!(e_prime(2.0, 0.5, PlaneKind::Stress), 2.0);
        assert!(rel(e_prime(3.0, 0.5, PlaneKind::Strain), 4.0) < 1e-15);
        assert!(rel(kappa(1.0 / 3.0, PlaneKind::Stress), 2.0) < 1e-15);
        assert!(rel(kappa(0.25, PlaneKind::Strain), 2.0) < 1e-15);
        assert!(rel(shear_modulus(3.0, 0.5), 1.0) < 1e-15);
        let c = pd_micromodulus(1.0, 1.0, 1.0, PlaneKind::Stress);
        assert!(rel(c, 9.0 / PI) < 1e-15);
    }
}
