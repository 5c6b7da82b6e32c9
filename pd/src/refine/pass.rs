//! The refined body's force pass with bond breaking and its stable time step (module
//! docs of [`super::dynamics`]; seed 004 Eq. 13 forces, the Gershgorin bound of
//! [`crate::dynamics`]).

use rayon::prelude::*;

use super::Body;
use crate::forces::RowPtr;
use crate::geometry::P2;
use crate::state_based::dual_horizon::DualHorizon;

/// Particles per parallel task of the force pass.
const PAR_MIN_PARTICLES: usize = 512;

/// The Gershgorin stable step $\min_k\sqrt{4\rho V_k/R_k}$ of `body` (module docs) over
/// the particles with a free component (s); infinite when none moves.
///
/// $R_k$ bounds the absolute row sums of the linearised stiffness
/// ([`super::linear::apply`]): every bond's deviatoric bar $c_b\,n n^T$,
/// $c_b = V_k\beta_b V'_b/|\xi_b|$, adds $2c_b|n_p|(|n_x| + |n_y|)$ to the rows of both
/// ends, and every particle's dilatation term $2a_kV_k\,g_k g_k^T$ ($\theta_k = g_k\cdot v$)
/// adds $2|a_k|V_k|g_{k,ip}|\,\|g_k\|_1$ to row $(i, p)$.
pub fn critical_time_step(body: &Body, density: f64) -> f64 {
    let dh = &body.dh;
    let bonds = &dh.bonds;
    let n = body.len();
    let mut r = vec![[0.0f64; 2]; n];
    for k in 0..n {
        let vk = dh.volume[k];
        let mut gk = [0.0; 2];
        let mut l1 = 0.0;
        for b in bonds.row(k).filter(|&b| dh.intact[b] != 0) {
            let j = bonds.nbr[b] as usize;
            let il = bonds.inv_len[b];
            let nb = [bonds.xi[b][0] * il, bonds.xi[b][1] * il];
            let c = vk * dh.beta[b].abs() * bonds.vol_factor[b] * il;
            let spread = nb[0].abs() + nb[1].abs();
            let w = dh.omega[b] * bonds.vol_factor[b] * il;
            for p in 0..2 {
                let dev = 2.0 * c * nb[p].abs() * spread;
                r[k][p] += dev;
                r[j][p] += dev;
                gk[p] -= w * nb[p];
            }
            l1 += w.abs() * spread;
        }
        l1 += gk[0].abs() + gk[1].abs();
        let f = 2.0 * dh.a[k].abs() * vk * l1;
        for p in 0..2 {
            r[k][p] += f * gk[p].abs();
        }
        for b in bonds.row(k).filter(|&b| dh.intact[b] != 0) {
            let j = bonds.nbr[b] as usize;
            let il = bonds.inv_len[b];
            let w = (dh.omega[b] * bonds.vol_factor[b] * il).abs();
            for p in 0..2 {
                r[j][p] += f * w * (bonds.xi[b][p] * il).abs();
            }
        }
    }
    (0..n)
        .filter(|&k| !(body.fixed[k][0] && body.fixed[k][1]))
        .map(|k| r[k][0].max(r[k][1]))
        .zip(&dh.volume)
        .filter(|(rk, _)| *rk > 0.0)
        .map(|(rk, v)| (4.0 * density * v / rk).sqrt())
        .fold(f64::INFINITY, f64::min)
}

/// Reusable per-bond buffers of [`forces_breaking_into`] (no allocation per step).
#[derive(Clone, Debug, Default)]
pub struct PassBuffers {
    /// Stretch of every directed bond.
    stretch: Vec<f64>,
    /// Deformed bond vector, then the force of the bond on its owner (N).
    fb: Vec<P2>,
    /// Per particle, kept and total volume of its horizon (the first part of Eq. 14).
    horizon: Vec<[f64; 2]>,
}

/// The refinement criteria's inputs at the state of a pass ([`forces_measuring_into`]):
/// each particle's damage (seed 004 Eq. 14, as [`Body::damage_of`]) and accumulated
/// strains (Eq. 17, as [`Body::accumulated_strain_of`]), to the last bit.
#[derive(Clone, Debug, Default)]
pub struct Measures {
    /// Damage of every particle.
    pub damage: Vec<f64>,
    /// Accumulated strains `(eps_xx, eps_yy)` of every particle.
    pub strain: Vec<P2>,
}

/// Forces (N) of seed 004 Eq. 13 at `u` after breaking every intact bond whose stretch
/// passes its owner's critical stretch `sc` (`None`: no breaking); returns the forces and
/// the directed bonds broken. Equals [`DualHorizon::forces`] of the updated flags.
pub fn forces_breaking(dh: &mut DualHorizon, u: &[P2], sc: Option<&[f64]>) -> (Vec<P2>, usize) {
    let mut f = Vec::new();
    let broken = forces_breaking_into(dh, u, sc, &mut PassBuffers::default(), &mut f);
    (f, broken)
}

/// [`forces_breaking`] into `f` with the buffers `buf`, in two sweeps over the particles.
///
/// Sweep 1, particle $k$ alone (its own row of directed bonds): the stretch of each
/// bond, the breaking against $s_c(\delta_k)$, the dilatation $\theta_k$, then the force
/// of each bond on its owner, $\tau_b V_k V'_b\,y_b/|y_b|$. Sweep 2: the force on $n$ is
/// its own bonds' sum minus the sum over the bonds of its dual horizon (Eq. 13).
pub fn forces_breaking_into(
    dh: &mut DualHorizon,
    u: &[P2],
    sc: Option<&[f64]>,
    buf: &mut PassBuffers,
    f: &mut Vec<P2>,
) -> usize {
    pass::<false>(dh, u, sc, buf, f, &mut Measures::default())
}

/// [`forces_breaking_into`] that also measures the criteria's inputs after the breaking
/// into `m`: the horizon's sums of Eqs. 14 and 17 in sweep 1, the dual horizon's share
/// of Eq. 14 in sweep 2 (the refinement checks then cost no pass of their own).
pub fn forces_measuring_into(
    dh: &mut DualHorizon,
    u: &[P2],
    sc: Option<&[f64]>,
    buf: &mut PassBuffers,
    f: &mut Vec<P2>,
    m: &mut Measures,
) -> usize {
    pass::<true>(dh, u, sc, buf, f, m)
}

/// Eq. 17 from a particle's bond sums: `num[c] / den[c]`, 0 where `den` is 0.
pub(super) fn strain_of(num: P2, den: P2) -> P2 {
    std::array::from_fn(|c| if den[c] > 0.0 { num[c] / den[c] } else { 0.0 })
}

/// The force pass, measuring ([`forces_measuring_into`]) when `MEASURE`.
fn pass<const MEASURE: bool>(
    dh: &mut DualHorizon,
    u: &[P2],
    sc: Option<&[f64]>,
    buf: &mut PassBuffers,
    f: &mut Vec<P2>,
    m: &mut Measures,
) -> usize {
    let nb = dh.bonds.len();
    let n = dh.pos.len();
    buf.stretch.resize(nb, 0.0);
    buf.fb.resize(nb, [0.0; 2]);
    if MEASURE {
        buf.horizon.resize(n, [0.0; 2]);
        m.strain.resize(n, [0.0; 2]);
        m.damage.resize(n, 0.0);
    }
    let intact = RowPtr(dh.intact.as_mut_ptr());
    let stretch = RowPtr(buf.stretch.as_mut_ptr());
    let fb = RowPtr(buf.fb.as_mut_ptr());
    let dh = &*dh;
    let bonds = &dh.bonds;
    let vol = &dh.volume;
    let sweep = |k: usize, out: Option<(&mut [f64; 2], &mut P2)>| -> usize {
        let (ip, sp, fp) = (&intact, &stretch, &fb);
        let row = bonds.row(k);
        // SAFETY: particle k touches only the slots of its own row of bonds, and rows
        // are disjoint.
        let (flags, s, yb) = unsafe {
            (
                std::slice::from_raw_parts_mut(ip.0.add(row.start), row.len()),
                std::slice::from_raw_parts_mut(sp.0.add(row.start), row.len()),
                std::slice::from_raw_parts_mut(fp.0.add(row.start), row.len()),
            )
        };
        let limit = sc.map_or(f64::INFINITY, |sc| sc[k]);
        let mut broken = 0;
        let mut theta = 0.0;
        // Eq. 14 (kept, all) over the horizon and Eq. 17's sums, as `Body` forms them.
        let (mut kept, mut all) = (0.0, 0.0);
        let (mut num, mut den) = ([0.0; 2], [0.0; 2]);
        for (i, b) in row.clone().enumerate() {
            let j = bonds.nbr[b] as usize;
            let y = [
                bonds.xi[b][0] + u[j][0] - u[k][0],
                bonds.xi[b][1] + u[j][1] - u[k][1],
            ];
            let sb = (y[0] * y[0] + y[1] * y[1]).sqrt() * bonds.inv_len[b] - 1.0;
            if flags[i] != 0 && sb > limit {
                flags[i] = 0;
                broken += 1;
            }
            theta += f64::from(flags[i]) * dh.omega[b] * sb * bonds.vol_factor[b];
            s[i] = sb;
            yb[i] = y;
            if MEASURE {
                let v = vol[j];
                all += v;
                kept += f64::from(flags[i]) * v;
                if flags[i] != 0 {
                    let xi = bonds.xi[b];
                    let w = v * bonds.inv_len[b] * bonds.inv_len[b];
                    for c in 0..2 {
                        num[c] += w * (u[j][c] - u[k][c]) * xi[c];
                        den[c] += w * xi[c] * xi[c];
                    }
                }
            }
        }
        for (i, b) in row.enumerate() {
            let l = (1.0 + s[i]) / bonds.inv_len[b];
            let tau = f64::from(flags[i])
                * (2.0 * dh.a[k] * dh.omega[b] * theta * bonds.inv_len[b] + dh.beta[b] * s[i]);
            let c = tau * dh.volume[k] * bonds.vol_factor[b] / l;
            yb[i] = [c * yb[i][0], c * yb[i][1]];
        }
        if let Some((h, e)) = out {
            *h = [kept, all];
            *e = strain_of(num, den);
        }
        broken
    };
    let broken: usize = if MEASURE {
        buf.horizon
            .par_iter_mut()
            .zip(m.strain.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_MIN_PARTICLES)
            .map(|(k, (h, e))| sweep(k, Some((h, e))))
            .sum()
    } else {
        (0..n)
            .into_par_iter()
            .with_min_len(PAR_MIN_PARTICLES)
            .map(|k| sweep(k, None))
            .sum()
    };
    let fb = &buf.fb;
    let gather = |n: usize| -> P2 {
        let mut s = [0.0; 2];
        for b in bonds.row(n) {
            s[0] += fb[b][0];
            s[1] += fb[b][1];
        }
        for &b in &dh.dual[dh.dual_offsets[n]..dh.dual_offsets[n + 1]] {
            s[0] -= fb[b as usize][0];
            s[1] -= fb[b as usize][1];
        }
        s
    };
    f.resize(n, [0.0; 2]);
    if MEASURE {
        let horizon = &buf.horizon;
        f.par_iter_mut()
            .zip(m.damage.par_iter_mut())
            .enumerate()
            .with_min_len(PAR_MIN_PARTICLES)
            .for_each(|(n, (fn_, phi))| {
                *fn_ = gather(n);
                let [mut kept, mut all] = horizon[n];
                let duals = dh.dual_offsets[n]..dh.dual_offsets[n + 1];
                for (&b, &o) in dh.dual[duals.clone()].iter().zip(&dh.dual_owner[duals]) {
                    let v = vol[o as usize];
                    all += v;
                    kept += f64::from(dh.intact[b as usize]) * v;
                }
                *phi = if all > 0.0 { 1.0 - kept / all } else { 0.0 };
            });
    } else {
        f.par_iter_mut()
            .enumerate()
            .with_min_len(PAR_MIN_PARTICLES)
            .for_each(|(n, fn_)| *fn_ = gather(n));
    }
    broken
}
