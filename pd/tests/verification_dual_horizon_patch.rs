//! Dual-horizon state-based PD (seed 004 section 2.2, Eq. 13) on a patch of mixed
//! particle sizes: the left half of a 32 x 32 square has spacing 1, the right half 0.5
//! (horizons 3.015 and 1.5075). Under a homogeneous strain prescribed on the outer layer
//! (two coarse horizons deep), the interior should take the homogeneous field: the force
//! at the exact field is the spurious ("ghost") force, measured at the size jump and away
//! from it, and the solved field is compared with the exact one. Also: the forces are
//! minus the energy gradient and balance (Newton's third law across sizes, what dual
//! horizons are for).

use pdbem_pd::state_based::dual_horizon::DualHorizon;
use pdbem_pd::Plane;

const L: f64 = 32.0;
/// Depth of the prescribed layer: two coarse horizons, so that every particle whose
/// constants or dilatation reach a free particle has its whole family.
const LAYER: f64 = 6.03;
const EPS: [f64; 3] = [1e-6, -0.4e-6, 0.3e-6];

fn patch(nu: f64, plane: Plane) -> DualHorizon {
    let (mut pos, mut dx) = (Vec::new(), Vec::new());
    for j in 0..32 {
        for i in 0..16 {
            pos.push([i as f64 + 0.5, j as f64 + 0.5]);
            dx.push(1.0);
        }
    }
    for j in 0..64 {
        for i in 0..32 {
            pos.push([16.0 + 0.5 * (i as f64 + 0.5), 0.5 * (j as f64 + 0.5)]);
            dx.push(0.5);
        }
    }
    DualHorizon::new(&pos, &dx, 1.0, 3.015, plane, 1.0, nu).expect("constants")
}

fn exact(p: [f64; 2]) -> [f64; 2] {
    [EPS[0] * p[0] + EPS[2] * p[1], EPS[2] * p[0] + EPS[1] * p[1]]
}

/// Free particles: deeper than the prescribed layer.
fn free(p: [f64; 2]) -> bool {
    let d = p[0].min(p[1]).min(L - p[0]).min(L - p[1]);
    d > LAYER
}

/// Largest spurious force over the free particles near the jump and away from it, in
/// units of E |eps| dx_k h (the force a cell face of the particle carries).
fn spurious(m: &DualHorizon) -> (f64, f64) {
    let u: Vec<[f64; 2]> = m.pos.iter().map(|&p| exact(p)).collect();
    let f = m.forces(&u);
    let (mut jump, mut away) = (0.0f64, 0.0f64);
    for (k, &p) in m.pos.iter().enumerate().filter(|(_, p)| free(**p)) {
        let dxk = m.volume[k].sqrt();
        let r = f[k][0].hypot(f[k][1]) / (1e-6 * dxk);
        // Near the jump: within two coarse horizons of x = 16 (a particle there sees a
        // neighbour whose family holds both sizes).
        if (p[0] - 16.0).abs() < 6.03 {
            jump = jump.max(r);
        } else {
            away = away.max(r);
        }
    }
    (jump, away)
}

/// Solve K du = F(u_exact) on the free particles by matrix-free conjugate gradients (K
/// applied as a directional difference of the forces); returns the largest distance
/// from the exact field relative to the largest exact displacement, the largest strain
/// error (difference of du over particle pairs closer than 1.5 coarse spacings, over
/// |eps|), and the CG iterations.
fn solved_error(m: &DualHorizon) -> (f64, f64, usize) {
    let n = m.pos.len();
    let mask: Vec<bool> = m.pos.iter().map(|&p| free(p)).collect();
    let u0: Vec<[f64; 2]> = m.pos.iter().map(|&p| exact(p)).collect();
    let f0 = m.forces(&u0);
    // K v as a directional difference with a step of 1e-9 m in the largest component
    // (the field is linear in the load up to geometric terms of order eps = 1e-6).
    let apply = |v: &[[f64; 2]]| -> Vec<[f64; 2]> {
        let vmax = v
            .iter()
            .fold(0.0f64, |a, x| a.max(x[0].abs()).max(x[1].abs()));
        let scale = 1e-9 / vmax.max(f64::MIN_POSITIVE);
        let up: Vec<[f64; 2]> = (0..n)
            .map(|i| [u0[i][0] + scale * v[i][0], u0[i][1] + scale * v[i][1]])
            .collect();
        let fp = m.forces(&up);
        (0..n)
            .map(|i| {
                if mask[i] {
                    [(f0[i][0] - fp[i][0]) / scale, (f0[i][1] - fp[i][1]) / scale]
                } else {
                    [0.0; 2]
                }
            })
            .collect()
    };
    let dot = |a: &[[f64; 2]], b: &[[f64; 2]]| -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| x[0] * y[0] + x[1] * y[1])
            .sum()
    };
    let mut x = vec![[0.0; 2]; n];
    let mut r: Vec<[f64; 2]> = (0..n)
        .map(|i| if mask[i] { f0[i] } else { [0.0; 2] })
        .collect();
    let mut p = r.clone();
    let r0 = dot(&r, &r).sqrt();
    let mut rr = dot(&r, &r);
    let mut iters = 0;
    while rr.sqrt() > 1e-8 * r0 && iters < 2000 {
        iters += 1;
        let ap = apply(&p);
        let alpha = rr / dot(&p, &ap);
        for i in 0..n {
            for c in 0..2 {
                x[i][c] += alpha * p[i][c];
                r[i][c] -= alpha * ap[i][c];
            }
        }
        let rr_new = dot(&r, &r);
        let beta = rr_new / rr;
        rr = rr_new;
        for i in 0..n {
            for c in 0..2 {
                p[i][c] = r[i][c] + beta * p[i][c];
            }
        }
    }
    let umax = u0.iter().fold(0.0f64, |a, v| a.max(v[0].hypot(v[1])));
    let mut strain = 0.0f64;
    for i in 0..n {
        for b in m.bonds.row(i) {
            let j = m.bonds.nbr[b] as usize;
            let l = 1.0 / m.bonds.inv_len[b];
            if l < 1.5 && mask[i] && mask[j] {
                strain = strain.max((x[i][0] - x[j][0]).hypot(x[i][1] - x[j][1]) / l);
            }
        }
    }
    let eps = EPS[0].hypot(EPS[1]).hypot(EPS[2]);
    let du = x.iter().fold(0.0f64, |a, v| a.max(v[0].hypot(v[1]))) / umax;
    (du, strain / eps, iters)
}

#[test]
fn mixed_spacing_patch_spurious_force_is_confined_to_the_size_jump() {
    for (nu, plane) in [(0.3, Plane::Stress), (0.2, Plane::Strain)] {
        let m = patch(nu, plane);
        let (jump, away) = spurious(&m);
        let (err, strain, iters) = solved_error(&m);
        println!(
            "{plane:?} nu {nu}: spurious force at the jump {jump:.2e}, away {away:.2e} (E eps dx h); solved field off by {err:.2e} of the largest displacement, strain error {strain:.2e} of |eps| ({iters} CG iterations)"
        );
        // Measured (both materials): away from the jump 1.2e-10 (round-off: the
        // homogeneous field is an exact equilibrium there); within two coarse horizons
        // of it 0.26-0.27 E |eps| dx h. Solved: the field is 0.97 % of the largest
        // displacement off the homogeneous one, the strain locally 41 % of |eps| off, at
        // the jump; 76 CG iterations. Dual horizons make the forces balance (the test
        // below) but do not pass the patch test at a 2:1 size jump: the odd moments of a
        // mixed family and of a mixed dual horizon do not vanish.
        assert!(away < 1e-9, "{away}");
        assert!(jump < 0.35, "{jump}");
        assert!(err < 0.015 && strain < 0.5, "{err} {strain}");
    }
}

#[test]
fn forces_are_minus_the_energy_gradient_and_balance() {
    let m = patch(0.3, Plane::Stress);
    let u: Vec<[f64; 2]> = m
        .pos
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let e = exact(p);
            let w = ((i * 7919) % 17) as f64 / 17.0 - 0.5;
            [1e3 * e[0] + 1e-3 * w, 1e3 * e[1] - 2e-3 * w]
        })
        .collect();
    let f = m.forces(&u);
    let fmax = f.iter().fold(0.0f64, |a, v| a.max(v[0].hypot(v[1])));
    let sum = f.iter().fold([0.0; 2], |a, v| [a[0] + v[0], a[1] + v[1]]);
    let h = 1e-7;
    let mut err = 0.0f64;
    for k in (0..u.len()).step_by(23) {
        for c in 0..2 {
            let mut up = u.clone();
            up[k][c] += h;
            let ep = m.energy(&up);
            up[k][c] -= 2.0 * h;
            let em = m.energy(&up);
            err = err.max((f[k][c] + (ep - em) / (2.0 * h)).abs());
        }
    }
    println!(
        "energy gradient {:.2e}, balance {:.2e}",
        err / fmax,
        sum[0].hypot(sum[1]) / fmax
    );
    // Measured: 9.5e-10 and 2.4e-14 of the largest force.
    assert!(err < 1e-6 * fmax, "{}", err / fmax);
    assert!(sum[0].hypot(sum[1]) < 1e-10 * fmax * u.len() as f64);
}
