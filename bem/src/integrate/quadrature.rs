//! Gauss-Legendre rules on [-1, 1], computed once by Newton iteration on the Legendre
//! recurrence (Golub-Welsch accuracy is not needed for the orders used here, n <= 16).

use std::sync::OnceLock;

/// Largest rule order provided.
pub const MAX_ORDER: usize = 16;

/// Nodes and weights of the n-point Gauss-Legendre rule on [-1, 1], 1 <= n <= 16.
pub fn gauss_legendre(n: usize) -> &'static [(f64, f64)] {
    static RULES: OnceLock<Vec<Vec<(f64, f64)>>> = OnceLock::new();
    let rules = RULES.get_or_init(|| (0..=MAX_ORDER).map(rule).collect());
    &rules[n.clamp(1, MAX_ORDER)]
}

fn rule(n: usize) -> Vec<(f64, f64)> {
    if n == 0 {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        // Initial guess (Abramowitz & Stegun 22.16.6), then Newton on P_n.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre(n, x);
            dp = d;
            let dx = p / d;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        let (_, d) = legendre(n, x);
        dp = if d != 0.0 { d } else { dp };
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    out
}

/// P_n(x) and P_n'(x) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
        p0 = p1;
        p1 = p2;
    }
    if n == 0 {
        return (1.0, 0.0);
    }
    let d = n as f64 * (x * p1 - p0) / (x * x - 1.0);
    (p1, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_exactly() {
        for n in 1..=MAX_ORDER {
            let r = gauss_legendre(n);
            for deg in 0..(2 * n) {
                let q: f64 = r.iter().map(|(x, w)| w * x.powi(deg as i32)).sum();
                let exact = if deg % 2 == 1 {
                    0.0
                } else {
                    2.0 / (deg as f64 + 1.0)
                };
                assert!((q - exact).abs() < 1e-13, "n={n} deg={deg} q={q}");
            }
        }
    }
}
