//! Probe (research, not used by the engine): can a variational correction remove the
//! patch-test error of dual horizons at a size jump (issue 20; docs/coupled_refined.md)?
//!
//! On the 24 x 24 patch of `tests/verification_mixed_spacing.rs` (or SIDE x SIDE; a zone of 8 x 8 cells
//! split `LEVELS` times, the fictitious layer prescribed), it adds to the model's
//! symmetric stiffness `K` the correction
//! $$C = \sum_{k\in B} \frac{V_k}{V_{ref}}\, D_k^T H_k D_k,$$
//! $D_k$ the shape-tensor strain of node k's own family ($\varepsilon_k =
//! \mathrm{sym}(\sum_j V_j (u_j - u_k)\otimes\xi\, M_k^{-1})$, exact on linear fields,
//! zero on rigid motions), $H_k$ a symmetric 3 x 3 matrix per node of the band $B$ (real
//! nodes within `REACH` coarse horizons of a node of another size), chosen as the
//! least-squares solution of $C u_m = -K u_m$ on the real DOFs for the three uniform
//! strains $u_m$. `C` is the Hessian of $\tfrac12\sum_k V_k \varepsilon_k:H_k:\varepsilon_k$,
//! so `K + C` stays symmetric and translation-invariant. Printed: the residual of the
//! uniform strains before and after, the smallest eigenvalue of the free block of `K` and
//! `K + C`, and the patch test (a mixed homogeneous strain on the layer) solved with each.
//! Dense matrices: a few seconds per run.
//!
//! `cargo run --release -p pdbem-pd --example jump_correction_probe -- LEVELS [pmb|sb] [REACH]
//! [SIDE]` (SIDE: the patch's side in cells, 24 by default; the zone stays 8 x 8).

use nalgebra::{DMatrix, DVector, SymmetricEigen};
use pdbem_pd::mixed::RefineZone;
use pdbem_pd::{BoundaryCondition, Layer, PdMaterial, PdModel, PdProblem, Region, Selection};

type Entry = (usize, [f64; 3]);

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let levels: u32 = args.get(1).map_or(Ok(1), |s| s.parse())?;
    let state_based = args.get(2).is_some_and(|s| s == "sb");
    let reach: f64 = args.get(3).map_or(Ok(3.0), |s| s.parse())?;
    let side: f64 = args.get(4).map_or(Ok(24.0), |s| s.parse())?;
    let material = if state_based {
        PdMaterial::StateBased { poisson_ratio: 0.3 }
    } else {
        PdMaterial::Pmb
    };
    let p = PdProblem {
        region: Region::rectangle([0.0, 0.0], [side, side]),
        dx: 1.0,
        youngs_modulus: 1.0,
        material,
        boundary: vec![BoundaryCondition::Displacement {
            on: Selection::All,
            ux: Some(0.0),
            uy: Some(0.0),
            layer: Layer::Fictitious,
        }],
        refine_zones: vec![RefineZone {
            centre: [0.5 * side, 0.5 * side],
            half_size: 4.0,
            levels,
        }],
        ..Default::default()
    };
    let m = PdModel::new(&p)?;
    let (nn, nr) = (m.n_nodes(), m.n_real());
    let x = m.positions().to_vec();
    let dxs: Vec<f64> = (0..nn).map(|i| m.grid().node_dx(i)).collect();
    let dense = m.tangent_dense();
    let k = DMatrix::from_fn(2 * nn, 2 * nn, |i, j| dense[i][j]);
    let modes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let field = |e: [f64; 3]| {
        DVector::from_fn(2 * nn, |d, _| {
            let q = x[d / 2];
            if d % 2 == 0 {
                e[0] * q[0] + e[2] * q[1]
            } else {
                e[2] * q[0] + e[1] * q[1]
            }
        })
    };
    let worst = |mat: &DMatrix<f64>| {
        modes
            .iter()
            .map(|&e| (mat * field(e)).rows(0, 2 * nr).abs().max())
            .fold(0.0, f64::max)
    };
    let dist = |a: usize, b: usize| (x[a][0] - x[b][0]).hypot(x[a][1] - x[b][1]);
    let band: Vec<usize> = (0..nr)
        .filter(|&i| (0..nr).any(|j| (dxs[j] - dxs[i]).abs() > 1e-9 && dist(i, j) <= reach * 3.015))
        .collect();
    let ops: Vec<Vec<Entry>> = band.iter().map(|&q| strain_operator(q, &x, &dxs)).collect();
    let h = fit(&k, &band, &ops, &dxs, nr, &field)?;
    let c = correction(&band, &ops, &dxs, &h, nn);
    let kc = &k + &c;
    println!(
        "levels {levels}, {}, band {} of {nr} real nodes ({reach} coarse horizons): max |H| {:.3e} E",
        if state_based { "state-based" } else { "PMB" },
        band.len(),
        h.abs().max()
    );
    println!(
        "residual of the uniform strains (E eps dx h): K {:.3e}, K + C {:.3e}",
        worst(&k),
        worst(&kc)
    );
    let free = |mat: &DMatrix<f64>| mat.view((0, 0), (2 * nr, 2 * nr)).into_owned();
    println!(
        "smallest eigenvalue of the free block: K {:.4e}, K + C {:.4e}",
        SymmetricEigen::new(free(&k)).eigenvalues.min(),
        SymmetricEigen::new(free(&kc)).eigenvalues.min()
    );
    let ue = field([1e-4, -0.4e-4, 0.3e-4]);
    for (name, mat) in [("K", &k), ("K + C", &kc)] {
        let kfp = mat.view((0, 2 * nr), (2 * nr, 2 * (nn - nr))).into_owned();
        let rhs = -(kfp * ue.rows(2 * nr, 2 * (nn - nr)));
        let uf = free(mat).lu().solve(&rhs).ok_or("singular free block")?;
        let off = (&uf - ue.rows(0, 2 * nr)).abs().max() / ue.abs().max();
        println!(
            "patch test with {name}: solved field off by {off:.3e} of the largest displacement"
        );
    }
    Ok(())
}

/// The shape-tensor strain of node `q` as `(dof, [d exx, d eyy, d exy])` entries.
fn strain_operator(q: usize, x: &[[f64; 2]], dxs: &[f64]) -> Vec<Entry> {
    let family: Vec<usize> = (0..x.len())
        .filter(|&j| {
            j != q && (x[j][0] - x[q][0]).hypot(x[j][1] - x[q][1]) <= 3.015 * dxs[q] + 1e-9
        })
        .collect();
    let xi = |j: usize| [x[j][0] - x[q][0], x[j][1] - x[q][1]];
    let mut mm = [[0.0; 2]; 2];
    for &j in &family {
        let (v, e) = (dxs[j] * dxs[j], xi(j));
        for a in 0..2 {
            for b in 0..2 {
                mm[a][b] += v * e[a] * e[b];
            }
        }
    }
    let det = mm[0][0] * mm[1][1] - mm[0][1] * mm[1][0];
    let inv = [
        [mm[1][1] / det, -mm[0][1] / det],
        [-mm[1][0] / det, mm[0][0] / det],
    ];
    let mut out = Vec::with_capacity(2 * family.len() + 2);
    let mut own = [[0.0f64; 3]; 2];
    for &j in &family {
        let (v, e) = (dxs[j] * dxs[j], xi(j));
        let g = [
            v * (e[0] * inv[0][0] + e[1] * inv[1][0]),
            v * (e[0] * inv[0][1] + e[1] * inv[1][1]),
        ];
        let cx = [g[0], 0.0, 0.5 * g[1]];
        let cy = [0.0, g[1], 0.5 * g[0]];
        out.push((2 * j, cx));
        out.push((2 * j + 1, cy));
        for c in 0..3 {
            own[0][c] -= cx[c];
            own[1][c] -= cy[c];
        }
    }
    out.push((2 * q, own[0]));
    out.push((2 * q + 1, own[1]));
    out
}

/// Index of `H[a][b]` among a node's six unknowns.
fn slot(a: usize, b: usize) -> usize {
    match (a.min(b), a.max(b)) {
        (0, 0) => 0,
        (1, 1) => 1,
        (2, 2) => 2,
        (0, 1) => 3,
        (0, 2) => 4,
        _ => 5,
    }
}

/// Least-squares `H` (six per band node) with `C u_m = -K u_m` on the real DOFs.
fn fit(
    k: &DMatrix<f64>,
    band: &[usize],
    ops: &[Vec<Entry>],
    dxs: &[f64],
    nr: usize,
    field: &dyn Fn([f64; 3]) -> DVector<f64>,
) -> Result<DVector<f64>, Box<dyn std::error::Error>> {
    let rows = 6 * nr;
    let mut a = DMatrix::<f64>::zeros(rows, 6 * band.len());
    let mut b = DVector::<f64>::zeros(rows);
    for (m, e) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
        .iter()
        .enumerate()
    {
        let r = k * field(*e);
        for d in 0..2 * nr {
            b[m * 2 * nr + d] = -r[d];
        }
    }
    for (bi, (&q, op)) in band.iter().zip(ops).enumerate() {
        let w = dxs[q] * dxs[q];
        for &(dof, c) in op.iter().filter(|(dof, _)| *dof < 2 * nr) {
            for m in 0..3 {
                for (s, cs) in c.iter().enumerate() {
                    a[(m * 2 * nr + dof, 6 * bi + slot(s, m))] += w * cs;
                }
            }
        }
    }
    let ata = a.transpose() * &a;
    let shift = 1e-12 * ata.diagonal().max();
    let n = ata.nrows();
    let chol = (ata + DMatrix::identity(n, n) * shift)
        .cholesky()
        .ok_or("normal equations not positive definite")?;
    Ok(chol.solve(&(a.transpose() * b)))
}

/// `C = sum_k V_k D_k^T H_k D_k` on all DOFs.
fn correction(
    band: &[usize],
    ops: &[Vec<Entry>],
    dxs: &[f64],
    h: &DVector<f64>,
    nn: usize,
) -> DMatrix<f64> {
    let mut c = DMatrix::<f64>::zeros(2 * nn, 2 * nn);
    for (bi, (&q, op)) in band.iter().zip(ops).enumerate() {
        let w = dxs[q] * dxs[q];
        for &(p1, c1) in op {
            for &(p2, c2) in op {
                let mut s = 0.0;
                for a in 0..3 {
                    for b in 0..3 {
                        s += c1[a] * h[6 * bi + slot(a, b)] * c2[b];
                    }
                }
                c[(p1, p2)] += w * s;
            }
        }
    }
    c
}
