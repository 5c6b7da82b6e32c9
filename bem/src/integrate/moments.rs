//! Scalar moments $M_{ak} = \int_{s_1}^{s_2} \xi^a (\xi^2+\eta^2)^{-k} d\xi$ and
//! $L = \int \ln r \, d\xi$ of one field point / element pair, by the cheapest method that
//! is accurate for the pair's geometry (module docs of [`crate::integrate`]).

use super::quadrature::gauss_legendre;
use crate::mesh::Element;
use nalgebra::Vector2;

/// Relative distance |eta| / h below which a pair is treated as coplanar (eta = 0). At this
/// threshold the O(eta/h) error of the limit and the O(eps h/eta) round-off of the closed
/// form are both about 1e-8.
const COPLANAR_TOL: f64 = 1e-8;

/// Where a field point sits relative to an element, in the element's frame.
#[derive(Debug, Clone, Copy)]
pub struct PairGeometry {
    /// Arc coordinate of the element start relative to the projection of x (s1 = -s_x).
    pub s1: f64,
    /// Arc coordinate of the element end relative to the projection of x (s2 = h - s_x).
    pub s2: f64,
    /// Signed offset eta = (y - x) . n, constant along the element.
    pub eta: f64,
    /// Element length.
    pub h: f64,
}

impl PairGeometry {
    /// Geometry of field point `x` relative to `el`.
    pub fn new(x: Vector2<f64>, el: &Element) -> Self {
        let p = x - el.a;
        let sx = p.dot(&el.tangent);
        Self {
            s1: -sx,
            s2: el.h - sx,
            eta: -p.dot(&el.normal),
            h: el.h,
        }
    }

    /// Shortest distance from the field point to the element.
    pub fn distance(&self) -> f64 {
        let along = if self.s1 > 0.0 {
            self.s1
        } else if self.s2 < 0.0 {
            -self.s2
        } else {
            0.0
        };
        along.hypot(self.eta)
    }
}

/// The moments of one pair. `m[a][k]` is $M_{ak}$ (a <= 4, 1 <= k <= 3; a = 4 serves the
/// first-moment integrals of the linear reconstruction).
#[derive(Debug, Clone, Copy, Default)]
pub struct Moments {
    /// $M_{ak}$.
    pub m: [[f64; 4]; 5],
    /// $\int \ln r\, d\xi$.
    pub l: f64,
    /// $\int \xi \ln r\, d\xi$.
    pub l1: f64,
    /// Offset used in the kernel tensors (0 for coplanar pairs).
    pub eta: f64,
    /// The field point lies on the element itself (coplanar, strictly inside): the
    /// integrals are principal values / finite parts and the free-term jumps apply.
    pub on_element: bool,
}

impl Moments {
    /// Moments of the first-moment integrals $\int K(\xi - c)\,d\xi$ about the arc
    /// coordinate `c` (the element midpoint): $M'_{ak} = M_{a+1,k} - c M_{ak}$,
    /// $L' = L_1 - c L$. The free-term jumps sit at $\xi = 0$ and carry the weight $-c$,
    /// which vanishes for collocation at the midpoint, so `on_element` is cleared.
    pub fn first_moment(&self, c: f64) -> Moments {
        let mut out = Moments {
            eta: self.eta,
            l: self.l1 - c * self.l,
            ..Default::default()
        };
        for a in 0..4 {
            for k in 1..4 {
                out.m[a][k] = self.m[a + 1][k] - c * self.m[a][k];
            }
        }
        out
    }
}

/// The order of the plain Gauss rule over the whole element that [`element_moments`]
/// uses for a pair this far from the element (distance / length >= 3), `None` for nearer
/// or coplanar pairs.
pub fn far_gauss_order(g: &PairGeometry) -> Option<usize> {
    if g.eta.abs() <= COPLANAR_TOL * g.h {
        return None;
    }
    let ratio = g.distance() / g.h;
    if ratio >= 10.0 {
        Some(4)
    } else if ratio >= 3.0 {
        Some(8)
    } else {
        None
    }
}

/// Moments by the method the geometry calls for.
pub fn element_moments(g: &PairGeometry) -> Moments {
    if let Some(n) = far_gauss_order(g) {
        return gauss(g, g.s1, g.s2, n);
    }
    if g.eta.abs() <= COPLANAR_TOL * g.h {
        return coplanar(g);
    }
    let over = g.s1 <= 0.0 && g.s2 >= 0.0;
    let near_end = g.s1.abs().min(g.s2.abs());
    if over || g.eta.abs() >= 0.3 * near_end {
        closed_form(g)
    } else {
        subdivided_gauss(g)
    }
}

/// Finite-part integral of xi^p over [s1, s2] (Cauchy principal value for p = -1,
/// Hadamard finite part for p <= -2 when 0 lies inside; ordinary integral otherwise).
fn power_integral(p: i32, s1: f64, s2: f64) -> f64 {
    match p {
        -1 => (s2 / s1).abs().ln(),
        _ => {
            let q = p + 1;
            (s2.powi(q) - s1.powi(q)) / q as f64
        }
    }
}

/// eta = 0: field point on the element's line.
fn coplanar(g: &PairGeometry) -> Moments {
    let mut mo = Moments {
        on_element: g.s1 < 0.0 && g.s2 > 0.0,
        ..Default::default()
    };
    for a in 0..5 {
        for k in 1..4 {
            mo.m[a][k] = power_integral(a as i32 - 2 * k as i32, g.s1, g.s2);
        }
    }
    let f = |s: f64| if s == 0.0 { 0.0 } else { s * s.abs().ln() - s };
    mo.l = f(g.s2) - f(g.s1);
    let f1 = |s: f64| {
        if s == 0.0 {
            0.0
        } else {
            0.5 * s * s * s.abs().ln() - 0.25 * s * s
        }
    };
    mo.l1 = f1(g.s2) - f1(g.s1);
    mo
}

/// Closed form for eta != 0 by the reduction formulas
/// $\int r^{-2k} = \xi/(2(k-1)\eta^2 r^{2k-2}) + (2k-3)/(2(k-1)\eta^2)\int r^{-2k+2}$ and
/// $M_{a,k} = M_{a-2,k-1} - \eta^2 M_{a-2,k}$.
fn closed_form(g: &PairGeometry) -> Moments {
    let (s1, s2, eta) = (g.s1, g.s2, g.eta);
    let e2 = eta * eta;
    let r1 = s1 * s1 + e2;
    let r2 = s2 * s2 + e2;
    // Signed angle subtended by the element, free of cancellation.
    let theta = (eta * (s2 - s1)).atan2(e2 + s1 * s2);
    let mut m = [[0.0; 4]; 5];
    m[0][1] = theta / eta;
    m[1][1] = 0.5 * (r2 / r1).ln();
    m[2][1] = (s2 - s1) - eta * theta;
    m[0][2] = ((s2 / r2 - s1 / r1) + m[0][1]) / (2.0 * e2);
    m[1][2] = -0.5 * (1.0 / r2 - 1.0 / r1);
    m[2][2] = m[0][1] - e2 * m[0][2];
    m[3][2] = m[1][1] - e2 * m[1][2];
    m[0][3] = (s2 / (r2 * r2) - s1 / (r1 * r1)) / (4.0 * e2) + 3.0 * m[0][2] / (4.0 * e2);
    m[1][3] = -0.25 * (1.0 / (r2 * r2) - 1.0 / (r1 * r1));
    m[2][3] = m[0][2] - e2 * m[0][3];
    m[3][3] = m[1][2] - e2 * m[1][3];
    m[3][1] = 0.5 * (s2 * s2 - s1 * s1) - e2 * m[1][1];
    m[4][1] = (s2 * s2 * s2 - s1 * s1 * s1) / 3.0 - e2 * m[2][1];
    m[4][2] = m[2][1] - e2 * m[2][2];
    m[4][3] = m[2][2] - e2 * m[2][3];
    let l = 0.5 * (s2 * r2.ln() - s1 * r1.ln()) - (s2 - s1) + eta * theta;
    let l1 = 0.25 * ((r2 * r2.ln() - s2 * s2) - (r1 * r1.ln() - s1 * s1));
    Moments {
        m,
        l,
        l1,
        eta,
        on_element: false,
    }
}

/// Gauss-Legendre of order n over [a, b] (a sub-range of [s1, s2]), accumulated into `mo`.
fn accumulate_gauss(mo: &mut Moments, eta: f64, a: f64, b: f64, n: usize) {
    let half = 0.5 * (b - a);
    let mid = 0.5 * (a + b);
    let e2 = eta * eta;
    for &(t, w) in gauss_legendre(n) {
        let xi = mid + half * t;
        let wt = w * half;
        let r2 = xi * xi + e2;
        let inv = 1.0 / r2;
        let mut pk = wt;
        for k in 1..4 {
            pk *= inv;
            let mut pa = pk;
            for a in 0..5 {
                mo.m[a][k] += pa;
                pa *= xi;
            }
        }
        let lr = 0.5 * r2.ln();
        mo.l += wt * lr;
        mo.l1 += wt * xi * lr;
    }
}

/// Plain Gauss over the whole element (far pairs).
fn gauss(g: &PairGeometry, a: f64, b: f64, n: usize) -> Moments {
    let mut mo = Moments {
        eta: g.eta,
        ..Default::default()
    };
    accumulate_gauss(&mut mo, g.eta, a, b, n);
    mo
}

/// Gauss on sub-elements whose length never exceeds their distance to the field point:
/// for field points almost on the element's line but beyond its end, where the closed
/// form would cancel catastrophically.
fn subdivided_gauss(g: &PairGeometry) -> Moments {
    let mut mo = Moments {
        eta: g.eta,
        ..Default::default()
    };
    // Work outward from the end nearest to the projection of x.
    let (near, far, sign) = if g.s1 > 0.0 {
        (g.s1, g.s2, 1.0)
    } else {
        (-g.s2, -g.s1, -1.0)
    };
    let mut a = near;
    while a < far {
        let d = a.hypot(g.eta);
        let b = (a + d).min(far);
        let (lo, hi) = if sign > 0.0 { (a, b) } else { (-b, -a) };
        accumulate_gauss(&mut mo, g.eta, lo, hi, 10);
        a = b;
    }
    mo
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reference moments by heavily subdivided Gauss in extended care.
    fn reference(g: &PairGeometry) -> Moments {
        let mut mo = Moments {
            eta: g.eta,
            ..Default::default()
        };
        let n = 4000;
        let d = (g.s2 - g.s1) / n as f64;
        for i in 0..n {
            let a = g.s1 + i as f64 * d;
            accumulate_gauss(&mut mo, g.eta, a, a + d, 16);
        }
        mo
    }

    fn rel(a: f64, b: f64, scale: f64) -> f64 {
        (a - b).abs() / scale.max(b.abs())
    }

    /// Worst scaled error of the moments of `method` against the reference over the pairs
    /// (sx, eta) of an element of length 0.1; also checks L and L1 to `log_tol`.
    fn worst_error(
        method: fn(&PairGeometry) -> Moments,
        pairs: &[(f64, f64)],
        log_tol: f64,
    ) -> f64 {
        let h = 0.1;
        let mut worst: f64 = 0.0;
        for &(sx, eta) in pairs {
            let g = PairGeometry {
                s1: -sx,
                s2: h - sx,
                eta,
                h,
            };
            let (c, r) = (method(&g), reference(&g));
            for a in 0..5 {
                for k in 1..4 {
                    let scale = r.m[0][k].abs() * (h + sx.abs()).powi(a as i32);
                    worst = worst.max(rel(c.m[a][k], r.m[a][k], scale));
                }
            }
            assert!(rel(c.l, r.l, h) < log_tol, "L at sx={sx} eta={eta}");
            assert!(rel(c.l1, r.l1, h * h) < log_tol, "L1 at sx={sx} eta={eta}");
        }
        worst
    }

    #[test]
    fn closed_form_matches_fine_quadrature() {
        let pairs = [
            (0.05, 0.02),
            (0.05, 1e-3),
            (0.0, 0.05),
            (-0.03, 0.01),
            (0.13, 0.04),
            (0.05, -0.3),
        ];
        let e = worst_error(closed_form, &pairs, 1e-10);
        assert!(e < 1e-9, "worst {e}");
    }

    #[test]
    fn dispatch_is_accurate_for_all_regimes() {
        let pairs = [
            (0.5, 0.01),
            (-0.06, 1e-4),
            (0.3, 0.3),
            (2.0, 0.5),
            (0.05, 0.2),
            (0.16, 0.005),
        ];
        let e = worst_error(element_moments, &pairs, 1e-8);
        assert!(e < 2e-8, "worst {e}");
    }
}
