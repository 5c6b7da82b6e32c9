//! Ordinary state-based peridynamics in 2-D (seed 004 section 2.1), plane stress and
//! plane strain, any Poisson ratio in [0, 1/2): below 0 the discrete energy is not
//! positive definite on every grid ([`crate::problem::MIN_STATE_BASED_NU`]).
//!
//! **Model.** Seed 004 Eqs. 3-5 with the 2-D constants of Eqs. 6-8. The strain energy
//! density of node $k$ is (Eq. 4)
//! $$W_k = a_k\,\theta_k^2 + \frac12\sum_{j\in H_k} \beta_{kj}\,T_{kj}\,\frac{e_{kj}^2}{|\xi_{kj}|}\,V'_j,
//!   \qquad \theta_k = \sum_{j\in H_k} \omega_{kj}\,T_{kj}\, s_{kj}\, V'_j \quad\text{(Eq. 5)},$$
//! with $e = |y| - |\xi|$, $s = e/|\xi|$, $V'_j = v_j V$ (partial volume, seed 002
//! Eq. 16) and $T_{kj}$ the bond's failure factor (1 intact, 0 broken, seed 004 Eq. 10;
//! the tanh law of seed 000 Eq. 12 for degrading bonds). The force state (Eq. 3,
//! $t_{kj} = V_j^{-1}\,\partial W_k/\partial|y_{kj}|$) is
//! $$t_{kj} = \tau_{kj}\,\frac{y_j-y_k}{|y_j-y_k|},\qquad
//!   \tau_{kj} = T_{kj}\Big(2a_k\omega_{kj}\,\frac{\theta_k}{|\xi_{kj}|} + \beta_{kj}\, s_{kj}\Big),$$
//! and the force density (Eq. 2) $F_k = \sum_j (\tau_{kj}+\tau_{jk})\,e_{kj}\,V'_j$.
//! In the continuum bulk $\omega = d\delta$, $\beta = 2b\delta$ and $a$ are Eqs. 6-8:
//! $a = (\kappa - 2\mu)/2$, $b = 6\mu/(\pi\delta^4 h)$, $d = 2/(\pi h \delta^3)$.
//! One change from Eq. 5: the factor $\Lambda_{kj} = \cos\angle(\xi, y) = 1 + O(\varepsilon^2)$
//! is taken as 1, so $\theta$ depends on bond lengths only; the forces are then exactly
//! $-\partial/\partial u$ of $\sum_k V W_k$ (for frozen $T$), the tangent is symmetric
//! and the work of the loads equals the strain energy.
//!
//! **Plane stress and plane strain** enter through the 2-D bulk modulus
//! ($\mu = E/(2(1+\nu))$ in both): plane stress $\kappa = E/(2(1-\nu))$, plane strain
//! $\kappa = E/(2(1+\nu)(1-2\nu))$ (Madenci & Oterkus, Peridynamic Theory and Its
//! Applications, 2014, ch. 4; Le, Oterkus & Madenci, 2014), so that
//! $W = \tfrac12\kappa(\mathrm{tr}\,\varepsilon)^2 + \mu\,\varepsilon_{dev}:\varepsilon_{dev}$.
//! For $\nu = 1/3$ in plane stress $a = 0$ and the model is PMB with $c = 2\beta/V$
//! (tested). The critical stretch from $G_c$ is seed 004 Eq. 11 ([`critical_stretch`]).
//!
//! **Discrete calibration.** The constants use the lattice sums of the discrete horizon
//! instead of the continuum integrals (14 % apart for $m = 3.015$): with
//! $S_0 = \sum_j V'_j$ and $S_1 = \sum_j |\xi_j| V'_j$ over a full family,
//! $\omega_{bulk} = 2/S_0$ (exact dilatation $\theta = \mathrm{tr}\,\varepsilon$ for every
//! homogeneous strain: the square lattice's second moments are isotropic) and
//! $\beta_{bulk} = 8\mu/S_1$ (the isotropic part of the fourth moment; the lattice's is
//! anisotropic by $M_{xxxx}/3M_{xxyy} - 1 = -0.68\,\%$ at $m = 3.015$, which leaves the
//! energy density of a homogeneous strain within 0.51 % of the classical one).
//!
//! **Surfaces.** Every node's dilatation is exact for every homogeneous strain whatever
//! its family (the volume/dilatation correction): $\omega_{kj} = n^T B_k n$ with the
//! $2\times2$ tensor $B_k$ solving $\sum_j \omega_{kj}\, n n^T V'_j = I$ over the bonds
//! the pre-cracks left (the scalar $2/S_{0,k}$ where that has no positive solution). The
//! energy coefficients answer for a family: without corrections the node's own, so that
//! $a_k = a\,S_{0,k}/S_0$ and $\beta = \beta_{bulk}$ (force coefficients of the bulk, the
//! energy density the fraction of the horizon present); `surface_correction` adds back
//! what the outline removed and `crack_face_correction` what the pre-cracks removed: then
//! $a_k = a$ and $\beta_{kj} = \sum_p c_{k,p}\, n_x^{4-p} n_y^p$ with the five $c_{k,p}$
//! making the node's fourth moment $\sum_j \beta_{kj}\, n^{\otimes4}|\xi| V'_j$ that of
//! the full lattice family times $\beta_{bulk}$. The node's energy density is then the
//! bulk one for every homogeneous strain (0.51 % from the classical, tested row by row
//! from the edge). The directions $n$ of these fits are taken in the lattice frame (the
//! grid's angle, [`crate::surface::lattice_axes`]), the frame of the full family's
//! moments, so a turned window's constants turn with it. Per-node and per-bond constants
//! keep the energy form, so no correction
//! breaks the symmetry of the tangent; the forces of a node with corrected constants
//! still differ from the bulk's (the PD surface effect on forces, measured by
//! `tests/verification_state_based_uniform_strain.rs`).
//!
//! **Damage.** Bonds break by the laws of [`crate::material::BondLaw`] on their stretch
//! (seed 004 Eq. 10; `FractureEnergy` gives the critical stretch of Eq. 11); a broken or
//! degraded bond leaves both the dilatation and the deviatoric sum ($T_{kj}$).
//!
//! Files: `mod.rs` (constants, calibration, [`StateBased`]), `dispatch.rs` (the
//! [`crate::PdModel`] methods the solvers call for either model), `forces.rs` (the
//! two-pass force gather), `tangent.rs` (the tangent rows, their sparse assembly and the
//! ADR density bound), `dual_horizon.rs` (particles of different sizes, seed 004
//! section 2.2).

mod dispatch;
pub mod dual_horizon;
mod forces;
mod tangent;

pub(crate) use dispatch::for_problem;
pub use forces::{elastic_energy, internal_forces, pair_force};
pub use tangent::{
    assemble, dense_tangent, row_blocks, row_sums, stencil, Families, Part, RowInput, RowScratch,
};

use crate::bonds::{partial_volume, Bonds};
use crate::grid::Grid;
use crate::problem::Plane;

/// 2-D bulk modulus kappa and shear modulus mu (Pa) of the plane idealisation.
pub fn moduli(plane: Plane, youngs_modulus: f64, nu: f64) -> (f64, f64) {
    let mu = youngs_modulus / (2.0 * (1.0 + nu));
    let kappa = match plane {
        Plane::Stress => youngs_modulus / (2.0 * (1.0 - nu)),
        Plane::Strain => youngs_modulus / (2.0 * (1.0 + nu) * (1.0 - 2.0 * nu)),
    };
    (kappa, mu)
}

/// Critical stretch from `G_c` (seed 004 Eq. 11, 2-D):
/// $s_c = \sqrt{G_c / ((6\mu/\pi + \tfrac{16}{9\pi^2}(\kappa - 2\mu))\,\delta)}$.
pub fn critical_stretch(kappa: f64, mu: f64, g_c: f64, delta: f64) -> f64 {
    let pi = std::f64::consts::PI;
    (g_c / ((6.0 * mu / pi + 16.0 / (9.0 * pi * pi) * (kappa - 2.0 * mu)) * delta)).sqrt()
}

/// Lattice sums $(S_0, S_1, X) = (\sum_j V'_j, \sum_j |\xi_j| V'_j,
/// \sum_j n_x^4 |\xi_j| V'_j)$ of a full family on the regular grid of spacing `dx` (node
/// volume `volume`, horizon `delta`), with the neighbour rule and partial volumes of
/// [`crate::bonds`].
pub fn lattice_sums(dx: f64, delta: f64, volume: f64) -> (f64, f64, f64) {
    let r = (delta / dx).ceil() as i64 + 1;
    let cut = delta * (1.0 + 1e-9);
    let (mut s0, mut s1, mut x4) = (0.0, 0.0, 0.0);
    for a in -r..=r {
        for b in -r..=r {
            let l = (a as f64 * dx).hypot(b as f64 * dx);
            if (a, b) == (0, 0) || l > cut {
                continue;
            }
            let v = partial_volume(l, delta, dx) * volume;
            s0 += v;
            s1 += l * v;
            x4 += (a as f64 * dx / l).powi(4) * l * v;
        }
    }
    (s0, s1, x4)
}

/// Which truncations of a node's family the constants make up for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Corrections {
    /// The outline's (free surfaces, holes, grid edges).
    pub surface: bool,
    /// The pre-cracks'.
    pub crack_faces: bool,
}

/// Per-node and per-bond constants and scratch of the state-based model.
#[derive(Clone, Debug)]
pub struct StateBased {
    /// 2-D bulk modulus kappa (Pa).
    pub kappa: f64,
    /// Shear modulus mu (Pa).
    pub mu: f64,
    /// Dilatational coefficient `a_k` of every node (Pa; on a mixed grid times the
    /// node's volume over the reference volume, [`crate::mixed`]).
    pub a: Vec<f64>,
    /// Dilatation weight `omega_b` of every directed bond (1/m^3).
    pub omega: Vec<f64>,
    /// Deviatoric coefficient `beta_b = Q G_b` of every directed bond (Pa/m^3; on a
    /// mixed grid times the owner's relative volume, as `a`).
    pub beta: Vec<f64>,
    /// The reverse of every directed bond (`j -> i` for `i -> j`).
    pub rev: Vec<u32>,
    /// Dilatation of every node at the last force pass.
    pub(crate) theta: Vec<f64>,
    /// Failure factor `T` of every bond at the last force pass.
    pub(crate) tfac: Vec<f64>,
    /// Force density of every directed bond `k -> j` on its owner at the last force
    /// pass, $\tau_{kj} V'_j\, (y_j - y_k)/|y_j - y_k|$ ([`forces`]).
    pub(crate) half: Vec<crate::geometry::P2>,
    /// Current length of every directed bond at the last force pass (scratch of
    /// [`forces`]).
    pub(crate) length: Vec<f64>,
}

/// Moments of a family over the bonds `keep` selects: `s0 = sum V'`, the dilatation
/// moments `m[p] = sum n_x^(4-p) n_y^p V'`, the deviatoric energy moments
/// `f[p] = sum n_x^(4-p) n_y^p |xi| V'` and `h[p] = sum n_x^(8-p) n_y^p |xi| V'`.
#[derive(Clone)]
struct Moments {
    s0: f64,
    m: [f64; 5],
    f: [f64; 5],
    h: [f64; 9],
}

impl Moments {
    /// Every moment times `v` (the volumes scaled).
    fn scaled(&self, v: f64) -> Self {
        Moments {
            s0: self.s0 * v,
            m: self.m.map(|x| x * v),
            f: self.f.map(|x| x * v),
            h: self.h.map(|x| x * v),
        }
    }
}

/// The moments of node `k`'s bonds that `keep` selects, with the bond directions taken in
/// the lattice frame `axes` ([`crate::surface::lattice_axes`]), the frame of the full
/// family's moments ([`bulk_moments`]) they are fitted to.
fn moments(
    bonds: &Bonds,
    k: usize,
    vol: f64,
    axes: (f64, f64),
    keep: impl Fn(usize) -> bool,
) -> Moments {
    let mut mo = Moments {
        s0: 0.0,
        m: [0.0; 5],
        f: [0.0; 5],
        h: [0.0; 9],
    };
    for b in bonds.row(k).filter(|&b| keep(b)) {
        let v = bonds.vol_factor[b] * vol;
        let l = 1.0 / bonds.inv_len[b];
        let (nx, ny) = crate::surface::lattice_direction(bonds, b, axes);
        mo.s0 += v;
        for p in 0..5 {
            let t = nx.powi(4 - p as i32) * ny.powi(p as i32) * v;
            mo.m[p] += t;
            mo.f[p] += t * l;
        }
        for (p, hp) in mo.h.iter_mut().enumerate() {
            *hp += nx.powi(8 - p as i32) * ny.powi(p as i32) * l * v;
        }
    }
    mo
}

/// The [`Moments`] of a full family on the regular grid (the lattice of
/// [`lattice_sums`]).
fn bulk_moments(dx: f64, delta: f64, vol: f64) -> Moments {
    let r = (delta / dx).ceil() as i64 + 1;
    let cut = delta * (1.0 + 1e-9);
    let mut xi = Vec::new();
    for a in -r..=r {
        for b in -r..=r {
            let l = (a as f64 * dx).hypot(b as f64 * dx);
            if (a, b) != (0, 0) && l <= cut {
                xi.push([a as f64 * dx, b as f64 * dx]);
            }
        }
    }
    let n = xi.len();
    let bonds = Bonds {
        offsets: vec![0, n],
        nbr: vec![0; n],
        inv_len: xi.iter().map(|v| 1.0 / v[0].hypot(v[1])).collect(),
        vol_factor: xi
            .iter()
            .map(|v| partial_volume(v[0].hypot(v[1]), delta, dx))
            .collect(),
        xi,
        ..Default::default()
    };
    moments(&bonds, 0, vol, (1.0, 0.0), |_| true)
}

/// Solve the small dense system `a x = r` by Gaussian elimination with partial pivoting;
/// `None` if a pivot falls below `1e-10` of the largest entry.
fn solve<const N: usize>(mut a: [[f64; N]; N], mut r: [f64; N]) -> Option<[f64; N]> {
    let big = a.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    for c in 0..N {
        let p = (c..N).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if a[p][c].abs() <= 1e-10 * big || a[p][c].is_nan() {
            return None;
        }
        a.swap(c, p);
        r.swap(c, p);
        for i in c + 1..N {
            let f = a[i][c] / a[c][c];
            for j in c..N {
                a[i][j] -= f * a[c][j];
            }
            r[i] -= f * r[c];
        }
    }
    let mut x = [0.0; N];
    for c in (0..N).rev() {
        let s: f64 = (c + 1..N).map(|j| a[c][j] * x[j]).sum();
        x[c] = (r[c] - s) / a[c][c];
    }
    Some(x)
}

/// The tensor `B` of the dilatation weights $\omega = n^T B n$ with
/// $\sum_j \omega_j n_j n_j^T V'_j = I$ (exact dilatation for every homogeneous strain),
/// as `[B_xx, B_xy, B_yy]`; `None` if the family does not determine it.
fn dilatation_tensor(m: [f64; 5]) -> Option<[f64; 3]> {
    // Rows: the xx, xy and yy components of sum (B_xx nx^2 + 2 B_xy nx ny + B_yy ny^2) n n^T V'.
    solve(
        [
            [m[0], 2.0 * m[1], m[2]],
            [m[1], 2.0 * m[2], m[3]],
            [m[2], 2.0 * m[3], m[4]],
        ],
        [1.0, 0.0, 1.0],
    )
}

/// Coefficients `c` of the deviatoric weights $\beta = \sum_p c_p n_x^{4-p} n_y^p$ whose
/// fourth moments $\sum_j \beta_j n^{\otimes 4} |\xi| V'_j$ equal `target` (the
/// components `xxxx, xxxy, xxyy, xyyy, yyyy`): the node's deviatoric energy is then the
/// target's for every homogeneous strain. `None` if the family does not determine them.
fn deviatoric_weights(h: [f64; 9], target: [f64; 5]) -> Option<[f64; 5]> {
    let mut a = [[0.0; 5]; 5];
    for (q, row) in a.iter_mut().enumerate() {
        for (p, v) in row.iter_mut().enumerate() {
            *v = h[p + q];
        }
    }
    solve(a, target)
}

impl StateBased {
    /// Constants of every node and bond of `grid` for the moduli `(kappa, mu)`;
    /// `intact` are the bond flags after the pre-cracks were cut.
    pub fn new(
        grid: &Grid,
        bonds: &Bonds,
        intact: &[u8],
        (kappa, mu): (f64, f64),
        corr: Corrections,
    ) -> Self {
        let n = grid.len();
        let vol = grid.volume;
        let a_bulk = 0.5 * (kappa - 2.0 * mu);
        // The full lattice family of a spacing (every spacing of a mixed grid keeps
        // m = delta / dx): its deviatoric coefficient and moments.
        let level = |dx: f64| {
            let (d, v) = if dx == grid.dx {
                (grid.delta, vol)
            } else {
                (grid.delta * dx / grid.dx, vol * (dx / grid.dx).powi(2))
            };
            let (_, s1b, _) = lattice_sums(dx, d, v);
            (8.0 * mu / s1b, bulk_moments(dx, d, v))
        };
        let (q_coarse, bulk_coarse) = level(grid.dx);
        let mut levels = vec![(grid.dx, q_coarse, bulk_coarse)];
        if grid.is_mixed() {
            for &d in &grid.spacing {
                if !levels.iter().any(|l| l.0 == d) {
                    let (q, m) = level(d);
                    levels.push((d, q, m));
                }
            }
        }
        let nb = bonds.len();
        let axes = crate::surface::lattice_axes(grid.angle);
        let (mut a, mut omega, mut beta) = (vec![0.0; n], vec![0.0; nb], vec![q_coarse; nb]);
        for k in 0..n {
            let lv = levels
                .iter()
                .find(|l| l.0 == grid.node_dx(k))
                .unwrap_or(&levels[0]);
            let (q_bulk, bulk) = (lv.1, &lv.2);
            if grid.is_mixed() {
                beta[bonds.row(k)].fill(q_bulk);
            }
            let all = moments(bonds, k, vol, axes, |_| true);
            let kept = moments(bonds, k, vol, axes, |b| intact[b] != 0);
            if kept.s0 <= 0.0 {
                continue;
            }
            // The family the constants answer for: the intact one, plus what the
            // outline's truncation (surface correction) and the pre-cracks (crack-face
            // correction) removed.
            let target = |k: f64, a: f64, b: f64| {
                k + if corr.surface { b - a } else { 0.0 }
                    + if corr.crack_faces { a - k } else { 0.0 }
            };
            a[k] = a_bulk * target(kept.s0, all.s0, bulk.s0) / bulk.s0;
            let scalar = 2.0 / kept.s0;
            let bt = dilatation_tensor(kept.m);
            let dev = if corr.surface || corr.crack_faces {
                let t: [f64; 5] =
                    std::array::from_fn(|p| q_bulk * target(kept.f[p], all.f[p], bulk.f[p]));
                deviatoric_weights(kept.h, t)
            } else {
                None
            };
            let mut w_om = Vec::new();
            let mut w_be = Vec::new();
            for b in bonds.row(k) {
                let (nx, ny) = crate::surface::lattice_direction(bonds, b, axes);
                w_om.push(bt.map_or(scalar, |t| {
                    t[0] * nx * nx + 2.0 * t[1] * nx * ny + t[2] * ny * ny
                }));
                w_be.push(dev.map_or(q_bulk, |c| {
                    (0..5)
                        .map(|p| c[p] * nx.powi(4 - p as i32) * ny.powi(p as i32))
                        .sum()
                }));
            }
            if w_be.iter().all(|&w| w > 0.0) {
                for (b, w) in bonds.row(k).zip(w_be) {
                    beta[b] = w;
                }
            }
            // A family too lopsided for positive weights falls back to the scalar ones.
            let positive = w_om.iter().all(|&w| w > 0.0);
            for (b, w) in bonds.row(k).zip(w_om) {
                omega[b] = if positive { w } else { scalar };
            }
            if grid.is_mixed() {
                // Mixed spacing: the energy coefficients carry the node's volume relative
                // to the reference one (crate::mixed: forces per reference volume).
                let r = grid.node_volume(k) / vol;
                a[k] *= r;
                for w in &mut beta[bonds.row(k)] {
                    *w *= r;
                }
            }
        }
        let mut rev = vec![0u32; nb];
        for i in 0..n {
            for b in bonds.row(i) {
                let j = bonds.nbr[b] as usize;
                let r = bonds
                    .row(j)
                    .find(|&r| bonds.nbr[r] as usize == i)
                    .expect("bonds are stored in both directions");
                rev[b] = r as u32;
            }
        }
        StateBased {
            kappa,
            mu,
            a,
            omega,
            beta,
            rev,
            theta: vec![0.0; n],
            tfac: vec![0.0; nb],
            half: vec![[0.0; 2]; nb],
            length: vec![0.0; nb],
        }
    }

    /// The pair stiffness of the deviatoric part, `(beta_b + beta_rev) V'` per bond (the
    /// `Bonds::k` of the state-based model, read by the estimates that treat bonds as
    /// springs: low-rank secant updates, node detachment).
    pub fn pair_stiffness(&self, bonds: &Bonds, volume: f64) -> Vec<f64> {
        (0..bonds.len())
            .map(|b| {
                let r = self.rev[b] as usize;
                if bonds.s_scale.is_empty() {
                    (self.beta[b] + self.beta[r]) * bonds.vol_factor[b] * volume
                } else {
                    (self.beta[b] * bonds.vol_factor[b] + self.beta[r] * bonds.vol_factor[r])
                        * volume
                }
            })
            .collect()
    }

    /// Dilatation of every node at the last force pass.
    pub fn dilatation(&self) -> &[f64] {
        &self.theta
    }
}

#[cfg(test)]
mod tests;
