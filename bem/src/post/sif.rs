//! Stress intensity factors, J, kink angle and crack-mouth opening.
//!
//! **Crack-opening SIF** (REFERENCES.md): with the jump $\Delta u$ (upper minus lower face) at
//! distance r behind the tip in the tip frame (s ahead, n = left normal),
//! $K^{app}(r) = \frac{\mu}{\kappa+1}\sqrt{2\pi/r}\,\Delta u$. On constant elements
//! $K^{app} \approx K(1 + 0.13 h/r)$, so $r K^{app}(r) = d_0 + K r + d_2 r^2 + d_3 r^3$ is
//! fitted by least squares over $r < 0.3 L$ ($L$ = crack length, half length for interior
//! cracks, or the ligament ahead of the tip if shorter). The fit needs
//! [`MIN_FIT_STATIONS`] crack-face stations in that range to mean K: with fewer it has
//! fewer terms than the opening's shape (see the constant's docs), and its error no
//! longer shrinks with h, so no two-level estimate can see it.
//!
//! **Interaction integral**: on a circle of radius $\rho$ around the tip (tip frame),
//! $M = \oint [\sigma_{ij}\varepsilon^{aux}_{ij} n_1 - \sigma_{ij} u^{aux}_{i,1} n_j - \sigma^{aux}_{ij} u_{i,1} n_j]\,ds$
//! with the Williams fields of unit $K^{aux}$, and
//! $K = E' M / 2$. $J = \oint (W n_1 - \sigma_{ij} u_{i,1} n_j) ds = (K_I^2 + K_{II}^2)/E'$.
//! Tractions on the crack faces inside the contour add a face integral to both
//! ([`super::face_traction`]).
//!
//! **Kink angle** (Erdogan & Sih): $\theta = 2\arctan[(K_I - \sqrt{K_I^2 + 8K_{II}^2})/(4K_{II})]$,
//! from the crack line, positive counter-clockwise.

use super::williams::williams;
use super::FieldEvaluator;
use crate::integrate::quadrature::gauss_legendre;
use crate::mesh::{Crack, Mesh, V2};
use crate::{BemError, Material, Solution};
use serde::Serialize;
use std::f64::consts::PI;

/// Results at one crack tip.
#[derive(Debug, Clone, Serialize)]
pub struct TipResult {
    /// Crack index in the mesh.
    pub crack: usize,
    /// Tip at the end (true) or the start (false) of the crack polyline.
    pub at_end: bool,
    /// Tip position.
    pub position: [f64; 2],
    /// Unit direction ahead of the tip.
    pub direction: [f64; 2],
    /// K_I from the crack-opening fit (Pa m^0.5).
    pub k1_cod: f64,
    /// K_II from the crack-opening fit.
    pub k2_cod: f64,
    /// Number of stations in the fit.
    pub cod_points: usize,
    /// K_I from the interaction integral.
    pub k1_m: f64,
    /// K_II from the interaction integral.
    pub k2_m: f64,
    /// J integral (N/m).
    pub j: f64,
    /// Radius of the integration contour (m).
    pub contour_radius: f64,
    /// Kink angle from the interaction-integral SIFs (degrees).
    pub kink_deg: f64,
}

/// Options of the tip analysis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SifOptions {
    /// Fit range as a fraction of L (REFERENCES.md: 0.3).
    pub fit_fraction: f64,
    /// Contour radius as a fraction of L.
    pub contour_fraction: f64,
    /// Gauss points on the contour.
    pub contour_points: usize,
}

impl Default for SifOptions {
    fn default() -> Self {
        Self {
            fit_fraction: 0.3,
            contour_fraction: 0.3,
            contour_points: 64,
        }
    }
}

/// Kink angle (radians) by maximum circumferential stress.
pub fn kink_angle(k1: f64, k2: f64) -> f64 {
    if k2 == 0.0 || (k2 / k1.abs().max(1e-300)).abs() < 1e-14 {
        return 0.0;
    }
    // Scaled to the larger of the two: K of 1e155 Pa m^0.5 squared overflows.
    let m = k1.abs().max(k2.abs());
    let (k1, k2) = (k1 / m, k2 / m);
    2.0 * ((k1 - (k1 * k1 + 8.0 * k2 * k2).sqrt()) / (4.0 * k2)).atan()
}

fn jump(sol: &Solution, c: &Crack, i: usize) -> V2 {
    let (u, l) = (sol.u[c.upper[i]], sol.u[c.lower[i]]);
    V2::new(u[0] - l[0], u[1] - l[1])
}

/// Direction of the polyline segment holding station i (unit, along the polyline).
fn station_direction(mesh: &Mesh, c: &Crack, i: usize) -> V2 {
    mesh.elements[c.upper[i]].tangent
}

/// Crack-mouth opening displacement (opening component, quadratic extrapolation of the
/// first three stations to the mouth). None for cracks without a mouth.
pub fn cmod(mesh: &Mesh, sol: &Solution, crack: usize) -> Option<f64> {
    let c = &mesh.cracks[crack];
    c.mouth()?;
    let k = c.stations.len().min(3);
    let pts: Vec<(f64, f64)> = (0..k)
        .map(|i| {
            let d = station_direction(mesh, c, i);
            let nrm = V2::new(-d.y, d.x);
            (c.stations[i], jump(sol, c, i).dot(&nrm))
        })
        .collect();
    Some(lagrange_at_zero(&pts))
}

/// Value at s = 0 of the polynomial through the given points.
fn lagrange_at_zero(p: &[(f64, f64)]) -> f64 {
    let mut v = 0.0;
    for (i, (si, yi)) in p.iter().enumerate() {
        let mut w = 1.0;
        for (j, (sj, _)) in p.iter().enumerate() {
            if i != j {
                w *= (0.0 - sj) / (si - sj);
            }
        }
        v += w * yi;
    }
    v
}

/// Characteristic length L of a tip: the crack length from the mouth (half the length for a
/// crack with two tips), or the distance to the nearest boundary not on this crack if shorter.
pub fn tip_length_scale(mesh: &Mesh, crack: usize, tip: V2) -> f64 {
    let c = &mesh.cracks[crack];
    let len = if c.start_is_tip && c.end_is_tip {
        0.5 * c.length()
    } else {
        c.length()
    };
    let own: Vec<usize> = c.upper.iter().chain(&c.lower).copied().collect();
    let mut lig = f64::INFINITY;
    for (i, e) in mesh.elements.iter().enumerate() {
        if own.contains(&i) {
            continue;
        }
        let d = e.b - e.a;
        let t = ((tip - e.a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
        lig = lig.min((e.a + t * d - tip).norm());
    }
    len.min(lig)
}

/// Fewest crack-face stations within the fit length for the crack-opening fit to be a K.
///
/// The fit takes 1 term for one station, 2 for 2-4, 3 for 5-6 and 4 from 7 ([`cod_sif`]).
/// Below 5 stations its error is that of the model, not of h, and keeps its size as h
/// halves (an estimate from two levels, |K(h) - K(2h)|, cannot see it):
/// one station reads $K^{app}$ at r = h/2, about 26 % high at every h; the linear fit
/// misses the curvature of the opening, $\sqrt{1 - r/2a}$ for a central crack, -7 % at
/// 0.3 a. Measured with uniform crack elements against the converged K, K_I error / its
/// estimate: central crack at 45 degrees, 1 station +23 % / 18 %, 3 stations -7.4 % /
/// 3.3 %, 4 stations -6.7 % / 2.1 %; 5 stations +0.5 % / 9.3 %, 6 stations +0.4 % /
/// 7.8 %; SENT a/W = 0.5, 5 stations +0.03 % / 5.5 %, 8 stations -0.15 % / 7 %.
pub const MIN_FIT_STATIONS: usize = 5;

/// A station this close to the end of the fit length (relative) is inside it: the two
/// tips of a symmetric crack measure their distances from opposite ends of the crack and
/// would otherwise round one such station in and the other out.
const FIT_EDGE: f64 = 1e-9;

/// The crack-face stations of a tip within `fit_length` behind it: (station index,
/// distance r behind the tip), nearest first for the start tip, farthest first for the
/// end tip.
pub fn fit_stations(mesh: &Mesh, crack: usize, at_end: bool, fit_length: f64) -> Vec<(usize, f64)> {
    let c = &mesh.cracks[crack];
    let total = c.length();
    let edge = fit_length * (1.0 + FIT_EDGE);
    (0..c.stations.len())
        .map(|i| {
            let r = if at_end {
                total - c.stations[i]
            } else {
                c.stations[i]
            };
            (i, r)
        })
        .filter(|&(_, r)| r > 0.0 && r < edge)
        .collect()
}

/// The fit length of a tip at `fit_fraction` of its length scale ([`tip_length_scale`])
/// and the number of crack-face stations within it.
pub fn fit_station_count(
    mesh: &Mesh,
    crack: usize,
    at_end: bool,
    fit_fraction: f64,
) -> (f64, usize) {
    let c = &mesh.cracks[crack];
    let tip = if at_end {
        *c.points.last().expect("a crack has points")
    } else {
        c.points[0]
    };
    let fit_length = fit_fraction * tip_length_scale(mesh, crack, tip);
    (
        fit_length,
        fit_stations(mesh, crack, at_end, fit_length).len(),
    )
}

/// K_I, K_II by the least-squares crack-opening fit. Returns (k1, k2, points used).
pub fn cod_sif(
    mesh: &Mesh,
    material: &Material,
    sol: &Solution,
    crack: usize,
    at_end: bool,
    fit_length: f64,
) -> (f64, f64, usize) {
    let c = &mesh.cracks[crack];
    let coef = material.mu() / (material.kappa() + 1.0) * (2.0 * PI).sqrt();
    let mut rows = Vec::new();
    for (i, r) in fit_stations(mesh, crack, at_end, fit_length) {
        let d = station_direction(mesh, c, i);
        let nrm = V2::new(-d.y, d.x);
        let du = jump(sol, c, i);
        // r K_app = coef sqrt(r) du
        rows.push((
            r,
            coef * r.sqrt() * du.dot(&nrm),
            coef * r.sqrt() * du.dot(&d),
        ));
    }
    let npts = rows.len();
    let terms = match npts {
        0 => return (f64::NAN, f64::NAN, 0),
        1 => 1,
        2..=4 => 2,
        5..=6 => 3,
        _ => 4,
    };
    let k1 = fit_slope(&rows, |r| r.1, terms, fit_length);
    let k2 = fit_slope(&rows, |r| r.2, terms, fit_length);
    (k1, k2, npts)
}

/// Least-squares fit of y(r) = d0 + K r + d2 r^2 + d3 r^3 (first `terms` terms; with one
/// term, y = K r); returns K.
fn fit_slope(
    rows: &[(f64, f64, f64)],
    y: impl Fn(&(f64, f64, f64)) -> f64,
    terms: usize,
    scale: f64,
) -> f64 {
    if terms == 1 {
        return y(&rows[0]) / rows[0].0;
    }
    let mut ata = nalgebra::DMatrix::<f64>::zeros(terms, terms);
    let mut atb = nalgebra::DVector::<f64>::zeros(terms);
    for row in rows {
        let x = row.0 / scale;
        let basis: Vec<f64> = (0..terms).map(|p| x.powi(p as i32)).collect();
        for a in 0..terms {
            atb[a] += basis[a] * y(row);
            for b in 0..terms {
                ata[(a, b)] += basis[a] * basis[b];
            }
        }
    }
    match ata.lu().solve(&atb) {
        Some(c) => c[1] / scale,
        None => f64::NAN,
    }
}

/// Integrand of (M_I, M_II, J) per unit arc length at angle `th` of the contour.
fn contour_integrand(ev: &FieldEvaluator, tip: V2, dir: V2, radius: f64, th: f64) -> [f64; 3] {
    let mat = *ev.material();
    let (mu, kappa) = (mat.mu(), mat.kappa());
    let nrm = V2::new(-dir.y, dir.x);
    let to_local = |v: V2| V2::new(v.dot(&dir), v.dot(&nrm));
    let delta = 1e-4 * radius;
    let (sn, cs) = th.sin_cos();
    let x = tip + radius * (cs * dir + sn * nrm);
    let sg = ev.stress(x);
    // Rotate stress into the tip frame.
    let (c1, s1) = (dir.x, dir.y);
    let s11 = sg[0] * c1 * c1 + sg[1] * s1 * s1 + 2.0 * sg[2] * c1 * s1;
    let s22 = sg[0] * s1 * s1 + sg[1] * c1 * c1 - 2.0 * sg[2] * c1 * s1;
    let s12 = (sg[1] - sg[0]) * c1 * s1 + sg[2] * (c1 * c1 - s1 * s1);
    let up = ev.displacement(x + delta * dir);
    let um = ev.displacement(x - delta * dir);
    let du = to_local(V2::new(up[0] - um[0], up[1] - um[1]) / (2.0 * delta));
    let n = [cs, sn];
    let sig = [[s11, s12], [s12, s22]];
    let eps = mat.strain_from_stress([s11, s22, s12]);
    let w_energy = 0.5 * (s11 * eps[0] + s22 * eps[1] + 2.0 * s12 * eps[2]);
    let mut out = [0.0; 3];
    out[2] = w_energy * n[0];
    for i in 0..2 {
        for jj in 0..2 {
            out[2] -= sig[i][jj] * du[i] * n[jj];
        }
    }
    for mode in 1..=2u8 {
        let (_, sa) = williams(mode, radius, th, mu, kappa);
        let ea = mat.strain_from_stress(sa);
        // d u_aux / d x1 by central differences in the tip frame.
        let ua = |dx: f64| {
            let (xx, yy) = (radius * cs + dx, radius * sn);
            williams(mode, xx.hypot(yy), yy.atan2(xx), mu, kappa).0
        };
        let (ap, am) = (ua(delta), ua(-delta));
        let dua = [
            (ap[0] - am[0]) / (2.0 * delta),
            (ap[1] - am[1]) / (2.0 * delta),
        ];
        let siga = [[sa[0], sa[2]], [sa[2], sa[1]]];
        let w12 = s11 * ea[0] + s22 * ea[1] + 2.0 * s12 * ea[2];
        let mut v = w12 * n[0];
        for i in 0..2 {
            for jj in 0..2 {
                v -= (sig[i][jj] * dua[i] + siga[i][jj] * du[i]) * n[jj];
            }
        }
        out[mode as usize - 1] = v;
    }
    out
}

/// Interaction-integral SIFs and J on a circle of `radius` around `tip` (direction `dir`).
///
/// Interior fields of constant elements are polluted within about one element length of
/// the boundary (the element-to-element jumps act as small dislocations), so the contour
/// is integrated by Gauss panels on |θ| ≤ π - θ_c with θ_c = 3 h_tip / ρ, and the two
/// wedges next to the crack faces by the quadratic through three unpolluted samples (the
/// integrand is smooth in θ up to the faces).
///
/// `crack`: the mesh crack the tip belongs to, whose face tractions within the contour
/// add their terms ([`super::face_traction`]); `None` for a contour whose crack faces
/// inside it carry no tractions.
pub fn interaction_integral(
    ev: &FieldEvaluator,
    tip: V2,
    dir: V2,
    radius: f64,
    npts: usize,
    h_tip: f64,
    crack: Option<usize>,
) -> (f64, f64, f64) {
    let ep = ev.material().e_prime();
    let theta_c = (3.0 * h_tip / radius).clamp(0.0, 0.5);
    let f = |th: f64| contour_integrand(ev, tip, dir, radius, th);
    let rule = gauss_legendre(16);
    let panels = npts.div_ceil(16).max(1);
    let (lo, hi) = (-PI + theta_c, PI - theta_c);
    let mut acc = [0.0; 3];
    for p in 0..panels {
        let a = lo + (hi - lo) * p as f64 / panels as f64;
        let b = lo + (hi - lo) * (p + 1) as f64 / panels as f64;
        for &(t, w) in rule {
            let v = f(0.5 * (a + b) + 0.5 * (b - a) * t);
            for k in 0..3 {
                acc[k] += w * 0.5 * (b - a) * radius * v[k];
            }
        }
    }
    if theta_c > 0.0 {
        for side in [-1.0, 1.0] {
            // Samples at distance theta_c, 2 theta_c, 3 theta_c from the face; the quadratic
            // through them (in the distance d from the face) integrated over d in [0, theta_c].
            let s: Vec<[f64; 3]> = (1..=3)
                .map(|k| f(side * (PI - k as f64 * theta_c)))
                .collect();
            // Weights of the quadratic through d = 1, 2, 3 (units of theta_c) integrated on [0, 1].
            let wts = [23.0 / 12.0, -16.0 / 12.0, 5.0 / 12.0];
            for k in 0..3 {
                acc[k] +=
                    radius * theta_c * (wts[0] * s[0][k] + wts[1] * s[1][k] + wts[2] * s[2][k]);
            }
        }
    }
    if let Some(ci) = crack {
        let faces = super::face_traction::face_terms(ev, ci, tip, dir, radius);
        for k in 0..3 {
            acc[k] += faces[k];
        }
    }
    (0.5 * ep * acc[0], 0.5 * ep * acc[1], acc[2])
}

/// Length of the crack-face element nearest to a tip.
fn tip_element_size(mesh: &Mesh, crack: usize, at_end: bool) -> f64 {
    let c = &mesh.cracks[crack];
    let i = if at_end { c.upper.len() - 1 } else { 0 };
    mesh.elements[c.upper[i]].h
}

/// Analyses every tip of the mesh.
pub fn analyze_tips(
    mesh: &Mesh,
    ev: &FieldEvaluator,
    sol: &Solution,
    opts: &SifOptions,
) -> Result<Vec<TipResult>, BemError> {
    let mat = *ev.material();
    let mut out = Vec::new();
    for (ci, at_end, pos, dir) in mesh.tips() {
        let l = tip_length_scale(mesh, ci, pos);
        if l.is_nan() || l <= 0.0 {
            return Err(BemError::Post(format!(
                "crack '{}': tip touches another boundary",
                mesh.cracks[ci].name
            )));
        }
        let (k1c, k2c, np) = cod_sif(mesh, &mat, sol, ci, at_end, opts.fit_fraction * l);
        let radius = opts.contour_fraction * l;
        let h_tip = tip_element_size(mesh, ci, at_end);
        let (k1m, k2m, j) =
            interaction_integral(ev, pos, dir, radius, opts.contour_points, h_tip, Some(ci));
        out.push(TipResult {
            crack: ci,
            at_end,
            position: [pos.x, pos.y],
            direction: [dir.x, dir.y],
            k1_cod: k1c,
            k2_cod: k2c,
            cod_points: np,
            k1_m: k1m,
            k2_m: k2m,
            j,
            contour_radius: radius,
            kink_deg: kink_angle(k1m, k2m).to_degrees(),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kink_angle_matches_erdogan_sih() {
        assert!((kink_angle(1.0, 1.0).to_degrees() + 53.13).abs() < 0.01);
        assert_eq!(kink_angle(1.0, 0.0), 0.0);
        // Pure mode II: -70.53 degrees.
        assert!((kink_angle(0.0, 1.0).to_degrees() + 70.5288).abs() < 1e-3);
        // Scale invariant up to the largest K: squared, 1e155 overflowed to -180 degrees.
        for scale in [1e-200, 1e155, 1e300] {
            let k = kink_angle(scale, scale);
            assert!((k - kink_angle(1.0, 1.0)).abs() < 1e-12, "{scale}: {k}");
        }
    }

    #[test]
    fn lagrange_extrapolation_is_exact_for_quadratics() {
        let f = |s: f64| 2.0 + 3.0 * s - s * s;
        let p: Vec<(f64, f64)> = [0.1, 0.3, 0.5].iter().map(|&s| (s, f(s))).collect();
        assert!((lagrange_at_zero(&p) - 2.0).abs() < 1e-12);
    }
}
