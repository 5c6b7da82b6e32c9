//! Unit tests of the state-based constants: the energy density of every node under a
//! homogeneous strain against the classical one, bulk and near the surface.

use super::*;
use crate::geometry::P2;
use crate::problem::{PdMaterial, PdProblem, Region};
use crate::PdModel;

/// A deterministic sequence uniform in [-1, 1) from `seed` (a 64-bit LCG).
fn uniform_in_pm1(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Classical energy density of a homogeneous strain `[exx, eyy, gxy/2]` (2-D moduli).
fn w_cm(kappa: f64, mu: f64, e: [f64; 3]) -> f64 {
    let tr = e[0] + e[1];
    let dev2 = (e[0] - 0.5 * tr).powi(2) + (e[1] - 0.5 * tr).powi(2) + 2.0 * e[2] * e[2];
    0.5 * kappa * tr * tr + mu * dev2
}

/// Energy density of node `k` of `m` under the homogeneous strain `e`.
fn w_pd(m: &PdModel, k: usize, e: [f64; 3]) -> f64 {
    let sb = m.state_based().unwrap();
    let b = m.bonds();
    let vol = m.grid().volume;
    let (mut th, mut dev) = (0.0, 0.0);
    for q in b.row(k) {
        let l = 1.0 / b.inv_len[q];
        let (nx, ny) = (b.xi[q][0] / l, b.xi[q][1] / l);
        let s = e[0] * nx * nx + e[1] * ny * ny + 2.0 * e[2] * nx * ny;
        let v = b.vol_factor[q] * vol;
        th += sb.omega[q] * s * v;
        dev += sb.beta[q] * s * s * l * v;
    }
    sb.a[k] * th * th + 0.5 * dev
}

pub(crate) fn plate(nu: f64, plane: Plane, surface: bool) -> PdModel {
    PdModel::new(&PdProblem {
        region: Region::rectangle([0.0, 0.0], [16.0, 16.0]),
        dx: 1.0,
        youngs_modulus: 1.0,
        plane,
        material: PdMaterial::StateBased { poisson_ratio: nu },
        surface_correction: surface,
        ..Default::default()
    })
    .unwrap()
}

/// Largest |W_PD / W_CM - 1| over the strain modes, per row of the column x = 8.5
/// (row 0 on the edge).
fn row_errors(m: &PdModel) -> Vec<f64> {
    let sb = m.state_based().unwrap();
    let modes = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0],
        [1.0, -0.3, 0.0],
        [1.0, -0.3, 0.5],
    ];
    (0..8)
        .map(|row| {
            let k = row * 16 + 8;
            modes
                .iter()
                .map(|&e| (w_pd(m, k, e) / w_cm(sb.kappa, sb.mu, e) - 1.0).abs())
                .fold(0.0, f64::max)
        })
        .collect()
}

#[test]
fn homogeneous_strain_energy_density_bulk_and_surface() {
    for plane in [Plane::Stress, Plane::Strain] {
        for nu in [0.2, 0.3, 1.0 / 3.0] {
            let corr = row_errors(&plate(nu, plane, true));
            let plain = row_errors(&plate(nu, plane, false));
            eprintln!("{plane:?} nu {nu:.3}: corrected rows 0..8 {corr:.4?}");
            eprintln!("{plane:?} nu {nu:.3}: plain     rows 0..8 {plain:.4?}");
            // Measured: 0.51 % at every row with the correction (the lattice's
            // fourth-moment anisotropy, Q calibrated on its isotropic part); without it
            // the same 0.51 % from row 3 on (full families) and 35-52 % on the edge rows.
            assert!(corr.iter().all(|&e| e < 0.006), "corrected {corr:?}");
            assert!(plain[3..].iter().all(|&e| e < 0.006), "bulk {plain:?}");
            assert!(plain[0] > 0.3 && plain[1] > 0.3, "edge {plain:?}");
        }
    }
}

#[test]
fn lattice_anisotropy_is_below_one_percent() {
    // M_xxxx / (3 M_xxyy) - 1 of the m = 3.015 family with partial volumes: -0.68 %.
    let m = bulk_moments(1.0, 3.015, 1.0);
    let r = m.f[0] / (3.0 * m.f[2]) - 1.0;
    assert!((r + 0.0068).abs() < 0.0005, "{r}");
}

#[test]
fn nu_one_third_plane_stress_is_the_pmb_model() {
    // a = 0 and a uniform beta: the state-based forces are the PMB forces scaled by
    // 2 Q_bulk / c, for any displacement field and bond state (brittle law: bonds past s0
    // break in both models in the same pass).
    let problem = |material| PdProblem {
        region: Region::rectangle([0.0, 0.0], [12.0, 10.0]),
        dx: 1.0,
        youngs_modulus: 3.0,
        material,
        cracks: vec![vec![[3.0, 5.2], [7.5, 5.2]]],
        failure: crate::problem::Failure::CriticalStretch { s0: 0.02 },
        ..Default::default()
    };
    let mut osb = PdModel::new(&problem(PdMaterial::StateBased {
        poisson_ratio: 1.0 / 3.0,
    }))
    .unwrap();
    let mut pmb = PdModel::new(&problem(PdMaterial::Pmb)).unwrap();
    let mut rnd = uniform_in_pm1(11);
    let u: Vec<P2> = osb
        .positions()
        .iter()
        .map(|x| [0.01 * x[0] + 0.02 * rnd(), 0.004 * x[1] + 0.02 * rnd()])
        .collect();
    for m in [&mut osb, &mut pmb] {
        m.set_displacements(&u).unwrap();
        m.commit_history();
    }
    assert_eq!(osb.bond_intact(), pmb.bond_intact());
    assert!(osb.broken_bonds() > 0);
    let (s1b, vol) = (lattice_sums(1.0, 3.015, 1.0).1, 1.0);
    let q = 8.0 * osb.state_based().unwrap().mu / s1b;
    let ratio = 2.0 * q / pmb.micromodulus() / vol;
    let (fo, fp) = (osb.internal_forces(), pmb.internal_forces());
    let scale = fp.iter().map(|f| f[0].hypot(f[1])).fold(0.0, f64::max);
    let err = fo
        .iter()
        .zip(&fp)
        .map(|(a, b)| (a[0] - ratio * b[0]).hypot(a[1] - ratio * b[1]))
        .fold(0.0, f64::max);
    // Measured: 7e-15 of the largest force (round-off); ratio 2Q/c = 1.1598 (the
    // lattice calibration, 14 % stiffer than the continuum micromodulus).
    eprintln!("ratio {ratio}, err {:e}", err / scale);
    assert!(err < 1e-12 * scale, "{err:e} vs {scale:e}");
    assert!((ratio - 1.16).abs() < 0.01, "{ratio}");
}

#[test]
fn critical_stretch_at_nu_one_third_is_the_pmb_one() {
    // Seed 004 Eq. 11 at kappa = 2 mu (nu = 1/3, plane stress) is seed 002 Eq. 7.
    let (kappa, mu) = moduli(Plane::Stress, 30e9, 1.0 / 3.0);
    let s = critical_stretch(kappa, mu, 110.0, 7.5e-4);
    let p = crate::material::critical_stretch(Plane::Stress, 30e9, 110.0, 7.5e-4);
    assert!((s / p - 1.0).abs() < 1e-12, "{s} vs {p}");
}

#[test]
fn the_force_pass_is_the_sum_of_pair_forces_and_conserves_momentum() {
    // The pass forms each bond's half force on its owner and gathers h_kj - h_jk
    // (forces.rs); the model docs' F_k = sum_j (tau_kj + tau_jk) e_kj V'_j is
    // `pair_force` bond by bond. Uniform and mixed spacing (each half with its own
    // partial volume), degrading bonds (T between 0 and 1, on the normalised stretch on
    // mixed spacing), broken and cut bonds.
    use crate::problem::Failure;
    use crate::refine_zone::RefineZone;
    for zones in [
        Vec::new(),
        vec![RefineZone {
            centre: [6.0, 5.0],
            half_size: 2.0,
            levels: 1,
        }],
    ] {
        let mut m = PdModel::new(&PdProblem {
            region: Region::rectangle([0.0, 0.0], [12.0, 10.0]),
            dx: 1.0,
            youngs_modulus: 3.0,
            material: PdMaterial::StateBased { poisson_ratio: 0.2 },
            plane: Plane::Strain,
            cracks: vec![vec![[0.0, 5.2], [5.5, 5.2]]],
            failure: Failure::Degradation {
                s_m: 0.005,
                s_c: 0.05,
                beta: 3.0,
            },
            refine_zones: zones.clone(),
            ..Default::default()
        })
        .unwrap();
        let mut rnd = uniform_in_pm1(5);
        let u: Vec<P2> = m
            .positions()
            .iter()
            .map(|x| [0.004 * x[0] + 0.03 * rnd(), 0.002 * x[1] + 0.03 * rnd()])
            .collect();
        m.set_displacements(&u).unwrap();
        m.commit_history();
        let f = m.internal_forces();
        let v = m.grid().volume;
        let bonds = m.bonds().clone();
        let (mut err, mut scale, mut total) = (0.0f64, 0.0f64, [0.0f64; 2]);
        for (i, fi) in f.iter().enumerate() {
            let mut sum = [0.0; 2];
            for b in bonds.row(i) {
                let p = m.pair_force(i, b);
                sum = [sum[0] + p[0] * v, sum[1] + p[1] * v];
            }
            err = err.max((fi[0] - sum[0]).hypot(fi[1] - sum[1]));
            scale = scale.max(fi[0].hypot(fi[1]));
            total = [total[0] + fi[0], total[1] + fi[1]];
        }
        let degraded = m.s_hist.iter().filter(|&&s| s > 0.005 && s < 0.05).count();
        // Measured: 2.9e-16 (uniform) and 4.6e-16 (mixed) of the largest force, the
        // order of the sums; the total force, 3.6e-16 and 1.5e-15 of it.
        eprintln!(
            "zones {}: pass vs pairs {:e}, total {:e}, {degraded} degraded, {} broken bonds",
            zones.len(),
            err / scale,
            total[0].hypot(total[1]) / scale,
            m.broken_bonds()
        );
        assert!(m.broken_bonds() > 0 && (degraded > 0 || !zones.is_empty()));
        assert!(err < 1e-12 * scale, "{err:e} of {scale:e}");
        assert!(total[0].hypot(total[1]) < 1e-12 * scale, "{total:?}");
    }
}
