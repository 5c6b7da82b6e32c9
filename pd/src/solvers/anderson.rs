//! Anderson mixing of a fixed-point iteration (type II; Walker & Ni 2011,
//! SIAM J. Numer. Anal. 49(4)), used by [`super::secant`].
//!
//! For the iteration $u \leftarrow u + f(u)$ with the last $m$ steps
//! $\Delta U = [s_{k-m}, \dots, s_{k-1}]$ and update differences
//! $\Delta F = [f_{k-m+1} - f_{k-m}, \dots, f_k - f_{k-1}]$, the mixed step is
//! $$s_k = f_k - (\Delta U + \Delta F)\,\gamma,\qquad
//!   \gamma = \arg\min_\gamma \|f_k - \Delta F\,\gamma\|_2 .$$
//! On a linear problem this is GMRES on the preconditioned operator, so it
//! removes the few slow modes of a chord iteration (the soft bending mode
//! of the three-point bend) in as many steps. The least-squares problem is
//! solved by its normal equations ($m \le 4$ columns); a step that is not
//! finite or far longer than $f_k$ (`STEP_GUARD`) is replaced by $f_k$
//! and the history dropped.

/// Longest history kept.
pub const MAX_DEPTH: usize = 4;

/// A mixed step longer than this many times the plain update is discarded.
/// The mixed step estimates the error, which exceeds the update by
/// $1/(1-\rho)$ for a mode contracting by $\rho$ per plain step; 100 allows
/// contractions up to 0.99 (a guard of 10 threw away exactly the steps that
/// remove a 0.9 mode: 224 iterations instead of 5 in the unit test).
const STEP_GUARD: f64 = 100.0;

/// Mixing history over vectors of one length.
pub struct Anderson {
    depth: usize,
    /// Step differences `s_i` (ring), and update differences.
    du: Vec<Vec<f64>>,
    df: Vec<Vec<f64>>,
    /// Columns in use and the next slot.
    len: usize,
    next: usize,
    /// Last update `f` and last step `s`, valid when `have_prev`.
    f_prev: Vec<f64>,
    s_prev: Vec<f64>,
    have_prev: bool,
}

impl Anderson {
    /// History of `depth` (at most [`MAX_DEPTH`]) columns of length `n`;
    /// depth 0 returns every update unchanged.
    pub fn new(n: usize, depth: usize) -> Self {
        let depth = depth.min(MAX_DEPTH);
        Anderson {
            depth,
            du: vec![vec![0.0; n]; depth],
            df: vec![vec![0.0; n]; depth],
            len: 0,
            next: 0,
            f_prev: vec![0.0; n],
            s_prev: vec![0.0; n],
            have_prev: false,
        }
    }

    /// Drop the history (the fixed-point map changed).
    pub fn reset(&mut self) {
        self.len = 0;
        self.next = 0;
        self.have_prev = false;
    }

    /// Turn the update `f` (in place) into the mixed step.
    pub fn mix(&mut self, f: &mut [f64]) {
        if self.depth == 0 {
            return;
        }
        if self.have_prev {
            let k = self.next;
            for (i, (du, df)) in self.du[k].iter_mut().zip(&mut self.df[k]).enumerate() {
                *du = self.s_prev[i];
                *df = f[i] - self.f_prev[i];
            }
            self.next = (k + 1) % self.depth;
            self.len = (self.len + 1).min(self.depth);
        }
        self.f_prev.copy_from_slice(f);
        let gamma = self.least_squares(f);
        let fnorm = dot(f, f).sqrt();
        for (j, g) in gamma.iter().enumerate().take(self.len) {
            for (i, x) in f.iter_mut().enumerate() {
                *x -= g * (self.du[j][i] + self.df[j][i]);
            }
        }
        let snorm = dot(f, f).sqrt();
        if !snorm.is_finite() || snorm > STEP_GUARD * fnorm {
            f.copy_from_slice(&self.f_prev);
            self.reset();
        }
        self.s_prev.copy_from_slice(f);
        self.have_prev = true;
    }

    /// $\gamma$ minimising $\|f - \Delta F \gamma\|$ (zeros if the normal
    /// matrix is singular).
    fn least_squares(&self, f: &[f64]) -> [f64; MAX_DEPTH] {
        let m = self.len;
        let mut a = [[0.0; MAX_DEPTH]; MAX_DEPTH];
        let mut b = [0.0; MAX_DEPTH];
        for p in 0..m {
            b[p] = dot(&self.df[p], f);
            for q in 0..=p {
                a[p][q] = dot(&self.df[p], &self.df[q]);
                a[q][p] = a[p][q];
            }
        }
        solve_spd(&mut a, &mut b, m).unwrap_or([0.0; MAX_DEPTH])
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solve the `m x m` symmetric positive definite system by Cholesky, with a
/// relative floor of 1e-12 on the pivots (`None` below it).
fn solve_spd(
    a: &mut [[f64; MAX_DEPTH]; MAX_DEPTH],
    b: &mut [f64; MAX_DEPTH],
    m: usize,
) -> Option<[f64; MAX_DEPTH]> {
    let scale = (0..m).map(|i| a[i][i]).fold(0.0, f64::max);
    for j in 0..m {
        let mut d = a[j][j];
        for k in 0..j {
            d -= a[j][k] * a[j][k];
        }
        if d <= 1e-12 * scale {
            return None;
        }
        let d = d.sqrt();
        a[j][j] = d;
        for i in j + 1..m {
            let mut v = a[i][j];
            for k in 0..j {
                v -= a[i][k] * a[j][k];
            }
            a[i][j] = v / d;
        }
    }
    for i in 0..m {
        let mut v = b[i];
        for k in 0..i {
            v -= a[i][k] * b[k];
        }
        b[i] = v / a[i][i];
    }
    for i in (0..m).rev() {
        let mut v = b[i];
        for k in i + 1..m {
            v -= a[k][i] * b[k];
        }
        b[i] = v / a[i][i];
    }
    Some(*b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Chord iteration `u <- u + P^-1 (b - A u)` on a 3 x 3 system whose
    /// preconditioner misses one mode badly (contraction 0.9).
    fn run(depth: usize) -> usize {
        let a = [[4.0, 1.0, 0.0], [1.0, 3.0, 0.5], [0.0, 0.5, 2.0]];
        let p_inv = [0.25 * 0.1, 1.0 / 3.0, 0.5];
        let b = [1.0, 2.0, 3.0];
        let mut u = [0.0; 3];
        let mut acc = Anderson::new(3, depth);
        for it in 1..=500 {
            let mut f: Vec<f64> = (0..3)
                .map(|i| p_inv[i] * (b[i] - (0..3).map(|j| a[i][j] * u[j]).sum::<f64>()))
                .collect();
            acc.mix(&mut f);
            for i in 0..3 {
                u[i] += f[i];
            }
            if dot(&f, &f).sqrt() < 1e-12 {
                return it;
            }
        }
        500
    }

    #[test]
    fn mixing_turns_a_slow_chord_iteration_into_a_few_steps() {
        let (plain, mixed) = (run(0), run(3));
        eprintln!("plain {plain} iterations, Anderson(3) {mixed}");
        // Measured: 249 plain, 5 with Anderson(3) (GMRES on 3 unknowns:
        // exact after the third history column).
        assert!(plain > 100 && mixed <= 8, "plain {plain}, mixed {mixed}");
    }
}
