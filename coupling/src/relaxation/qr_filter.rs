//! Thin QR factorisation with the QR2 column filter of Haelterman et al. (2016), as in
//! preCICE: columns are orthogonalised in the order given (newest first) by modified
//! Gram-Schmidt, repeated once ("twice is enough"), and a column whose part orthogonal
//! to the columns kept before it is below `eps` times its own norm,
//! $\|v_j^\perp\| < \varepsilon \|v_j\|$, is dropped. The kept columns $V_k = Q R$ then
//! have $\kappa(R) \lesssim$ (number of columns) / eps instead of an unbounded one.

use super::dot;

/// $V_k = Q R$ of the kept columns.
#[derive(Debug, Clone, Default)]
pub struct FilteredQr {
    /// Orthonormal columns, one per kept column.
    pub q: Vec<Vec<f64>>,
    /// Upper triangle of R by columns: `r[j][i]` = $R_{ij}$, i <= j.
    pub r: Vec<Vec<f64>>,
    /// Indices (into the input) of the kept columns, in input order.
    pub kept: Vec<usize>,
}

/// QR of `columns` (all of one length) with the QR2 filter `eps` in [0, 1).
pub fn filtered_qr<'a>(columns: impl IntoIterator<Item = &'a [f64]>, eps: f64) -> FilteredQr {
    let mut out = FilteredQr::default();
    for (j, col) in columns.into_iter().enumerate() {
        let size = dot(col, col).sqrt();
        if !(size > 0.0 && size.is_finite()) {
            continue;
        }
        let mut v = col.to_vec();
        let mut coef = vec![0.0; out.q.len() + 1];
        for _ in 0..2 {
            for (i, qi) in out.q.iter().enumerate() {
                let d = dot(&v, qi);
                coef[i] += d;
                v.iter_mut().zip(qi).for_each(|(a, b)| *a -= d * b);
            }
        }
        let rest = dot(&v, &v).sqrt();
        if rest < eps * size || rest == 0.0 {
            continue;
        }
        coef[out.q.len()] = rest;
        v.iter_mut().for_each(|a| *a /= rest);
        out.q.push(v);
        out.r.push(coef);
        out.kept.push(j);
    }
    out
}

impl FilteredQr {
    /// Kept columns.
    pub fn len(&self) -> usize {
        self.q.len()
    }

    /// No column kept.
    pub fn is_empty(&self) -> bool {
        self.q.is_empty()
    }

    /// The least-squares solution c of $\min_c \|V_k c - b\|$ (one entry per kept column).
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let m = self.len();
        let z: Vec<f64> = self.q.iter().map(|qi| dot(qi, b)).collect();
        let mut c = vec![0.0; m];
        for i in (0..m).rev() {
            let s: f64 = (i + 1..m).map(|j| self.r[j][i] * c[j]).sum();
            c[i] = (z[i] - s) / self.r[i][i];
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dependent_columns_are_dropped_and_the_rest_solve_exactly() {
        let a = [1.0, 0.0, 0.0, 1.0];
        let b = [0.0, 1.0, 1.0, 0.0];
        // Nearly a + b: its orthogonal part is 1e-4 of its size.
        let c = [1.0, 1.0, 1.0, 1.0 + 2e-4];
        let d = [0.0, 0.0, 1.0, -1.0];
        let cols: Vec<&[f64]> = vec![&a, &b, &c, &d];
        let qr = filtered_qr(cols.iter().copied(), 1e-3);
        assert_eq!(qr.kept, vec![0, 1, 3]);
        let none = filtered_qr(cols.iter().copied(), 0.0);
        assert_eq!(none.kept, vec![0, 1, 2, 3]);
        // 2a - b + 0.5 d lies in the span of the kept columns: exact coefficients.
        let rhs: Vec<f64> = (0..4).map(|i| 2.0 * a[i] - b[i] + 0.5 * d[i]).collect();
        let x = qr.solve(&rhs);
        assert!((x[0] - 2.0).abs() < 1e-12 && (x[1] + 1.0).abs() < 1e-12);
        assert!((x[2] - 0.5).abs() < 1e-12, "{x:?}");
    }
}
