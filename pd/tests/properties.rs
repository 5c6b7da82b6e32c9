//! Property tests of the bond model (STYLE.md item 9): rigid-body motion
//! gives zero force, the analytic tangent matches a finite-difference
//! Jacobian and is symmetric, the force is minus the energy gradient.

use pdbem_pd::{BoundaryCondition, Failure, Layer, PdModel, PdProblem, Region, Selection};

fn problem(failure: Failure) -> PdProblem {
    PdProblem {
        region: Region::rectangle([0.0, 0.0], [0.01, 0.008]),
        dx: 0.001,
        youngs_modulus: 200e9,
        thickness: 0.001,
        failure,
        cracks: vec![vec![[0.003, 0.004], [0.0065, 0.0043]]],
        surface_correction: true,
        boundary: vec![BoundaryCondition::Displacement {
            on: Selection::Box {
                min: [-1.0, -1.0],
                max: [0.0, 1.0],
            },
            ux: Some(0.0),
            uy: None,
            layer: Layer::Fictitious,
        }],
        ..Default::default()
    }
}

/// Deterministic pseudo-random numbers in [-1, 1).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}

fn max_abs(v: &[[f64; 2]]) -> f64 {
    v.iter()
        .flat_map(|x| x.iter())
        .fold(0.0f64, |a, &b| a.max(b.abs()))
}

#[test]
fn rigid_translation_and_large_rotation_give_zero_force() {
    let mut m = PdModel::new(&problem(Failure::None)).unwrap();
    let x = m.positions().to_vec();
    // Reference scale: force of a 1e-3 uniform strain.
    let strain: Vec<[f64; 2]> = x.iter().map(|p| [1e-3 * p[0], 0.0]).collect();
    let scale = max_abs(&m.force_density_at(&strain));
    let theta: f64 = 0.7; // 40 degrees: the stretch is fully nonlinear
    let (s, c) = theta.sin_cos();
    let rigid: Vec<[f64; 2]> = x
        .iter()
        .map(|p| {
            [
                c * p[0] - s * p[1] - p[0] + 0.3,
                s * p[0] + c * p[1] - p[1] - 0.2,
            ]
        })
        .collect();
    let f = m.force_density_at(&rigid);
    eprintln!("rigid: {:e}", max_abs(&f) / scale);
    // Measured: 2.4e-11 of the strain force (round-off of the stretch).
    assert!(
        max_abs(&f) < 1e-9 * scale,
        "rigid force {} vs scale {}",
        max_abs(&f),
        scale
    );
}

fn fd_check(failure: Failure, amp: f64, commit_amp: Option<f64>) {
    let mut m = PdModel::new(&problem(failure)).unwrap();
    let x = m.positions().to_vec();
    let mut seed = 7u64;
    let field = |a: f64, seed: &mut u64| -> Vec<[f64; 2]> {
        x.iter()
            .map(|p| {
                [
                    a * (p[0] + 0.3 * p[1]) + 0.2 * a * 0.001 * lcg(seed),
                    a * 0.5 * p[1] + 0.2 * a * 0.001 * lcg(seed),
                ]
            })
            .collect()
    };
    if let Some(ca) = commit_amp {
        let u = field(ca, &mut seed.clone());
        m.set_displacements(&u).unwrap();
        m.commit_history();
    }
    let u = field(amp, &mut seed);
    m.set_displacements(&u).unwrap();
    let u = m.displacements().to_vec();
    let k = m.tangent_dense();
    let n = u.len();
    let h = 1e-9;
    let mut kmax = 0.0f64;
    let mut err = 0.0f64;
    for j in 0..n {
        for c in 0..2 {
            let mut up = u.clone();
            let mut um = u.clone();
            up[j][c] += h;
            um[j][c] -= h;
            let fp = m.force_density_at(&up);
            let fm = m.force_density_at(&um);
            for i in 0..n {
                for r in 0..2 {
                    let fd = -(fp[i][r] - fm[i][r]) / (2.0 * h);
                    let an = k[2 * i + r][2 * j + c];
                    kmax = kmax.max(an.abs());
                    err = err.max((fd - an).abs());
                }
            }
        }
    }
    eprintln!("FD Jacobian: err/max|K| = {:e}", err / kmax);
    // Measured: 1.3e-10 (elastic), 1.4e-10 (degrading) relative to max |K|.
    assert!(
        err < 1e-6 * kmax,
        "FD Jacobian error {err:e} vs max |K| {kmax:e}"
    );
    let mut asym = 0.0f64;
    for a in 0..2 * n {
        for b in 0..2 * n {
            asym = asym.max((k[a][b] - k[b][a]).abs());
        }
    }
    eprintln!("asymmetry/max|K| = {:e}", asym / kmax);
    // Symmetric to round-off (measured 0: both directions are bitwise equal).
    assert!(asym <= 1e-12 * kmax, "asymmetry {asym:e}");
    let _ = &mut seed;
}

#[test]
fn tangent_matches_finite_differences_elastic_large_strain() {
    fd_check(Failure::None, 0.05, None);
}

#[test]
fn tangent_matches_finite_differences_with_degradation_and_history() {
    // Stretches of the field spread over (0, ~0.03): many bonds in the tanh
    // range (s_m, s_c) on the loading branch, and, after committing a larger
    // field, on the unloading (secant) branch.
    fd_check(
        Failure::Degradation {
            s_m: 0.011,
            s_c: 0.05,
            beta: 3.0,
        },
        0.02,
        Some(0.025),
    );
}

#[test]
fn force_is_minus_energy_gradient() {
    let mut m = PdModel::new(&problem(Failure::None)).unwrap();
    let x = m.positions().to_vec();
    let mut seed = 3u64;
    let u: Vec<[f64; 2]> = x
        .iter()
        .map(|p| {
            [
                0.01 * p[1] + 1e-5 * lcg(&mut seed),
                -0.02 * p[0] + 1e-5 * lcg(&mut seed),
            ]
        })
        .collect();
    m.set_displacements(&u).unwrap();
    let u = m.displacements().to_vec();
    let fixed = m.boundary().fixed.clone();
    let f = m.internal_forces();
    let h = 1e-9;
    let mut err = 0.0f64;
    let fmax = max_abs(&f);
    for j in (0..u.len()).step_by(7) {
        for c in 0..2 {
            if fixed[j][c] {
                continue;
            }
            let mut up = u.clone();
            up[j][c] += h;
            m.set_displacements(&up).unwrap();
            let ep = m.energy();
            up[j][c] -= 2.0 * h;
            m.set_displacements(&up).unwrap();
            let em = m.energy();
            let grad = (ep - em) / (2.0 * h);
            err = err.max((f[j][c] + grad).abs());
        }
    }
    eprintln!("energy gradient: {:e}", err / fmax);
    // Measured: 1.2e-10 of the largest nodal force.
    assert!(
        err < 1e-4 * fmax,
        "force vs -dPi/du: {err:e} (max force {fmax:e})"
    );
}

/// `PdProblem::bond_law` (the law before any model is built, for `pdbem check` and the
/// run's first lines) equals the built model's, bit for bit: PMB and state-based with a
/// fracture energy, a critical stretch, the tanh law and elastic bonds, plane stress and
/// strain.
#[test]
fn the_problems_bond_law_is_the_models() {
    use pdbem_pd::problem::{Failure, PdMaterial, Plane};
    let failures = [
        Failure::None,
        Failure::CriticalStretch { s0: 1e-3 },
        Failure::FractureEnergy { g_c: 3.0 },
        Failure::Degradation {
            s_m: 1e-3,
            s_c: 2e-3,
            beta: 3.0,
        },
    ];
    for material in [
        PdMaterial::Pmb,
        PdMaterial::StateBased { poisson_ratio: 0.2 },
    ] {
        for plane in [Plane::Stress, Plane::Strain] {
            for failure in failures {
                let p = pdbem_pd::PdProblem {
                    region: pdbem_pd::Region::rectangle([0.0, 0.0], [0.05, 0.02]),
                    dx: 0.002,
                    thickness: 1e-3,
                    youngs_modulus: 32e9,
                    plane,
                    material,
                    failure,
                    ..Default::default()
                };
                let model = pdbem_pd::PdModel::new(&p).expect("model");
                assert_eq!(
                    p.bond_law(),
                    model.law(),
                    "{material:?} {plane:?} {failure:?}"
                );
            }
        }
    }
}
