//! The Kelvin kernels (REFERENCES.md, seed 002 Eqs. 17-20) integrated over a straight
//! element, written in terms of the scalar moments of [`super::moments`].
//!
//! With $R = \xi e + \eta n$ (so $r_i = R_i / r$, $\partial r/\partial n = \eta / r$):
//! $$U_{ij} = C_U[-(3-4\nu)\delta_{ij}\ln r + R_iR_j/r^2]$$
//! $$T_{ij} = -C_T[(1-2\nu)\delta_{ij}\eta/r^2 + 2\eta R_iR_j/r^4 - (1-2\nu)(R_in_j - R_jn_i)/r^2]$$
//! $$D_{kij} = C_T[(1-2\nu)(R_i\delta_{kj} + R_j\delta_{ki} - R_k\delta_{ij})/r^2 + 2R_iR_jR_k/r^4]$$
//! $$S_{kij} = C_S[2\eta((1-2\nu)\delta_{ij}R_k + \nu(R_i\delta_{jk} + R_j\delta_{ik}))/r^4
//! \; - 8\eta R_iR_jR_k/r^6 + 2\nu(n_iR_jR_k + n_jR_iR_k)/r^4 + 2(1-2\nu)n_kR_iR_j/r^4
//! \; + ((1-2\nu)(n_j\delta_{ik} + n_i\delta_{jk}) - (1-4\nu)n_k\delta_{ij})/r^2]$$
//! with $C_U = 1/(8\pi\mu(1-\nu))$, $C_T = 1/(4\pi(1-\nu))$, $C_S = \mu/(2\pi(1-\nu))$,
//! $K_{jk} = D_{kij} m_i$, $H_{jk} = S_{kij} m_i$.

use super::moments::Moments;
use super::KernelConsts;
use nalgebra::Vector2;
use std::f64::consts::PI;

/// A 2x2 block, row-major: `b[row][col]`.
pub type Block = [[f64; 2]; 2];

/// The four integrated kernels of one field point / element pair.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairIntegrals {
    /// $\int U_{ij}$: displacement i at x from traction j on the element.
    pub u: Block,
    /// $\int T_{ij}$ (with the free-term jump on the element itself).
    pub t: Block,
    /// $\int K_{jk}$: traction j at x (normal m) from traction k on the element.
    pub k: Block,
    /// $\int H_{jk}$: traction j at x (normal m) from displacement k on the element.
    pub h: Block,
}

#[inline]
fn delta(i: usize, j: usize) -> f64 {
    if i == j {
        1.0
    } else {
        0.0
    }
}

/// The four kernel integrals from the moments of one pair, evaluated in the element frame
/// (e = (1, 0), n = (0, 1), m = (e.m, n.m)) where every integrated tensor is a combination
/// of e and n, then rotated to global axes: $X = R X_{loc} R^T$, $R = [e\ n]$.
pub fn kernel_integrals(
    e: &Vector2<f64>,
    n: &Vector2<f64>,
    m: &Vector2<f64>,
    mo: &Moments,
    kc: &KernelConsts,
) -> PairIntegrals {
    kernel_integrals_selected(e, n, m, mo, kc, Kernels::ALL)
}

/// Which of the four kernel integrals [`kernel_integrals_selected`] computes; the others
/// stay zero. Each computed one is the same expression as in [`kernel_integrals`], so it
/// equals that one bit for bit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Kernels {
    /// U and K (the single-layer kernels, multiplying tractions).
    pub single: bool,
    /// H (the hypersingular kernel; T is always computed).
    pub h: bool,
}

impl Kernels {
    /// U, T, K and H.
    pub const ALL: Kernels = Kernels {
        single: true,
        h: true,
    };
    /// T and H: the first-moment integrals multiply the reconstructed displacement only.
    pub const DOUBLE_LAYER: Kernels = Kernels {
        single: false,
        h: true,
    };
    /// U and T (K is computed with U): an interior displacement needs no more.
    pub const DISPLACEMENT: Kernels = Kernels {
        single: true,
        h: false,
    };
    /// T alone: the first-moment part of an interior displacement.
    pub const T_ONLY: Kernels = Kernels {
        single: false,
        h: false,
    };
}

/// As [`kernel_integrals`], computing only the kernels `which` selects.
pub fn kernel_integrals_selected(
    e: &Vector2<f64>,
    n: &Vector2<f64>,
    m: &Vector2<f64>,
    mo: &Moments,
    kc: &KernelConsts,
    which: Kernels,
) -> PairIntegrals {
    let (mu, nu) = (kc.mu, kc.nu);
    let cu = 1.0 / (8.0 * PI * mu * (1.0 - nu));
    let ct = 1.0 / (4.0 * PI * (1.0 - nu));
    let cs = mu / (2.0 * PI * (1.0 - nu));
    let a = 1.0 - 2.0 * nu;
    let eta = mo.eta;
    let mm = &mo.m;
    let (em, nm) = (e.dot(m), n.dot(m));
    let ml = [em, nm];
    let (e1, e2, e3) = (eta, eta * eta, eta * eta * eta);
    // Local integrated tensors: V = int R/r^2k, Q = int RR/r^2k, (W.m)_jk = int R_i R_j R_k m_i / r^2k.
    let v = |k: usize| [mm[1][k], e1 * mm[0][k]];
    let q = |k: usize| {
        let (q0, q1, q2) = (mm[2][k], e1 * mm[1][k], e2 * mm[0][k]);
        [[q0, q1], [q1, q2]]
    };
    let wm = |k: usize| {
        let (w0, w1, w2, w3) = (mm[3][k], e1 * mm[2][k], e2 * mm[1][k], e3 * mm[0][k]);
        let (c11, c12, c22) = (w0 * em + w1 * nm, w1 * em + w2 * nm, w2 * em + w3 * nm);
        [[c11, c12], [c12, c22]]
    };
    let (v1, q1, v2, q2) = (v(1), q(1), v(2), q(2));
    let (w2m, w3m) = (wm(2), wm(3));
    let s0 = mm[0][1];
    let v1m = v1[0] * em + v1[1] * nm;
    let v2m = v2[0] * em + v2[1] * nm;
    let q2m = [q2[0][0] * em + q2[1][0] * nm, q2[0][1] * em + q2[1][1] * nm];
    let nloc = [0.0, 1.0];
    let mut lu = [[0.0; 2]; 2];
    let mut lt = [[0.0; 2]; 2];
    let mut lk = [[0.0; 2]; 2];
    let mut lh = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            let d = delta(i, j);
            let (jj, kk) = (i, j);
            if which.single {
                lu[i][j] = cu * (-(3.0 - 4.0 * nu) * d * mo.l + q1[i][j]);
                lk[jj][kk] = ct
                    * (a * (v1m * delta(kk, jj) + v1[jj] * ml[kk] - v1[kk] * ml[jj])
                        + 2.0 * w2m[jj][kk]);
            }
            lt[i][j] = -ct
                * (a * d * eta * s0 + 2.0 * eta * q2[i][j]
                    - a * (v1[i] * nloc[j] - v1[j] * nloc[i]));
            if !which.h {
                continue;
            }
            lh[jj][kk] = cs
                * (2.0
                    * eta
                    * (a * ml[jj] * v2[kk] + nu * (v2m * delta(jj, kk) + v2[jj] * ml[kk]))
                    - 8.0 * eta * w3m[jj][kk]
                    + 2.0 * nu * (nm * q2[jj][kk] + nloc[jj] * q2m[kk])
                    + 2.0 * a * nloc[kk] * q2m[jj]
                    + (a * (nloc[jj] * ml[kk] + nm * delta(jj, kk))
                        - (1.0 - 4.0 * nu) * nloc[kk] * ml[jj])
                        * s0);
        }
    }
    let r = [[e[0], n[0]], [e[1], n[1]]];
    let rot = |x: &Block| -> Block {
        let mut out = [[0.0; 2]; 2];
        for p in 0..2 {
            for q in 0..2 {
                out[p][q] = r[p][0] * (x[0][0] * r[q][0] + x[0][1] * r[q][1])
                    + r[p][1] * (x[1][0] * r[q][0] + x[1][1] * r[q][1]);
            }
        }
        out
    };
    let zero = [[0.0; 2]; 2];
    PairIntegrals {
        u: if which.single { rot(&lu) } else { zero },
        t: rot(&lt),
        k: if which.single { rot(&lk) } else { zero },
        h: if which.h { rot(&lh) } else { zero },
    }
}

#[cfg(test)]
mod reference {
    //! The kernel formulas in global axes, term by term: the oracle for the local-frame version.
    use super::*;

    /// Integrated products of R: V = int R/r^2k, Q = int RR/r^2k, W = int RRR/r^2k.
    struct RTensors {
        v: [f64; 2],
        q: Block,
        w: [[[f64; 2]; 2]; 2],
    }

    fn r_tensors(e: &Vector2<f64>, n: &Vector2<f64>, mo: &Moments, k: usize) -> RTensors {
        let eta = mo.eta;
        let m = &mo.m;
        // c[p][ne]: coefficient of a product of p factors with ne of them n: eta^ne M[p-ne][k].
        let (e1, e2, e3) = (eta, eta * eta, eta * eta * eta);
        let v = [m[1][k], e1 * m[0][k]];
        let q = [m[2][k], e1 * m[1][k], e2 * m[0][k]];
        let w = [m[3][k], e1 * m[2][k], e2 * m[1][k], e3 * m[0][k]];
        let b = [[e[0], n[0]], [e[1], n[1]]];
        let mut out = RTensors {
            v: [0.0; 2],
            q: [[0.0; 2]; 2],
            w: [[[0.0; 2]; 2]; 2],
        };
        for i in 0..2 {
            out.v[i] = v[0] * b[i][0] + v[1] * b[i][1];
            for j in 0..2 {
                out.q[i][j] = q[0] * b[i][0] * b[j][0]
                    + q[1] * (b[i][0] * b[j][1] + b[i][1] * b[j][0])
                    + q[2] * b[i][1] * b[j][1];
                for l in 0..2 {
                    let (ei, ej, el) = (b[i][0], b[j][0], b[l][0]);
                    let (ni, nj, nl) = (b[i][1], b[j][1], b[l][1]);
                    out.w[i][j][l] = w[0] * ei * ej * el
                        + w[1] * (ei * ej * nl + ei * nj * el + ni * ej * el)
                        + w[2] * (ei * nj * nl + ni * ej * nl + ni * nj * el)
                        + w[3] * ni * nj * nl;
                }
            }
        }
        out
    }

    /// The four kernel integrals from the moments of one pair.
    pub fn kernel_integrals_global(
        e: &Vector2<f64>,
        n: &Vector2<f64>,
        m: &Vector2<f64>,
        mo: &Moments,
        kc: &KernelConsts,
    ) -> PairIntegrals {
        let (mu, nu) = (kc.mu, kc.nu);
        let cu = 1.0 / (8.0 * PI * mu * (1.0 - nu));
        let ct = 1.0 / (4.0 * PI * (1.0 - nu));
        let cs = mu / (2.0 * PI * (1.0 - nu));
        let eta = mo.eta;
        let r1 = r_tensors(e, n, mo, 1);
        let r2 = r_tensors(e, n, mo, 2);
        let r3 = r_tensors(e, n, mo, 3);
        let s0 = mo.m[0][1];
        let a = 1.0 - 2.0 * nu;

        let mut out = PairIntegrals::default();
        for i in 0..2 {
            for j in 0..2 {
                out.u[i][j] = cu * (-(3.0 - 4.0 * nu) * delta(i, j) * mo.l + r1.q[i][j]);
                out.t[i][j] = -ct
                    * (a * delta(i, j) * eta * s0 + 2.0 * eta * r2.q[i][j]
                        - a * (r1.v[i] * n[j] - r1.v[j] * n[i]));
            }
        }
        // K_jk = D_kij m_i ; H_jk = S_kij m_i
        for j in 0..2 {
            for k in 0..2 {
                let mut dk = 0.0;
                let mut sk = 0.0;
                for i in 0..2 {
                    let d = ct
                        * (a * (r1.v[i] * delta(k, j) + r1.v[j] * delta(k, i)
                            - r1.v[k] * delta(i, j))
                            + 2.0 * r2.w[i][j][k]);
                    let s = cs
                        * (2.0
                            * eta
                            * (a * delta(i, j) * r2.v[k]
                                + nu * (r2.v[i] * delta(j, k) + r2.v[j] * delta(i, k)))
                            - 8.0 * eta * r3.w[i][j][k]
                            + 2.0 * nu * (n[i] * r2.q[j][k] + n[j] * r2.q[i][k])
                            + 2.0 * a * n[k] * r2.q[i][j]
                            + (a * (n[j] * delta(i, k) + n[i] * delta(j, k))
                                - (1.0 - 4.0 * nu) * n[k] * delta(i, j))
                                * s0);
                    dk += d * m[i];
                    sk += s * m[i];
                }
                out.k[j][k] = dk;
                out.h[j][k] = sk;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::super::moments::{element_moments, PairGeometry};
    use super::*;

    #[test]
    fn local_frame_matches_global_formulas() {
        let kc = KernelConsts {
            mu: 3750.0,
            nu: 0.25,
        };
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for _ in 0..200 {
            let th = 7.0 * rnd();
            let e = Vector2::new(th.cos(), th.sin());
            let n = Vector2::new(e.y, -e.x);
            let phi = 7.0 * rnd();
            let m = Vector2::new(phi.cos(), phi.sin());
            let g = PairGeometry {
                s1: -0.05 + rnd() * 0.3,
                s2: 0.05 + rnd() * 0.3 + 0.1,
                eta: rnd() * 0.4,
                h: 0.1,
            };
            let mo = element_moments(&g);
            let fast = kernel_integrals(&e, &n, &m, &mo, &kc);
            let slow = reference::kernel_integrals_global(&e, &n, &m, &mo, &kc);
            for (x, y) in [
                (fast.u, slow.u),
                (fast.t, slow.t),
                (fast.k, slow.k),
                (fast.h, slow.h),
            ] {
                let scale = y.iter().flatten().fold(1e-30_f64, |s, v| s.max(v.abs()));
                for i in 0..2 {
                    for j in 0..2 {
                        // Both are exact formulas; they differ by round-off in the cancelling
                        // hypersingular terms (measured up to 1.4e-12 relative).
                        assert!((x[i][j] - y[i][j]).abs() <= 1e-9 * scale, "{x:?} vs {y:?}");
                    }
                }
            }
        }
    }
}
