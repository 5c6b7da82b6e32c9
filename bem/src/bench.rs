//! Benchmark of assembly, factorization and further right-hand sides (issue: `pdbem bench bem`).
//!
//! The mesh is the seed-002 edge-cracked plate (20 m x 10 m, a/W = 0.8, uniform elements), at
//! sizes chosen to give the requested element counts. A further right-hand side is timed two
//! ways on the same factorization: a substitution through the whole LU factor, and new
//! tractions on the loaded edges (a variable group, as coupling interfaces are) through the
//! precomputed response R = A^{-1} B_var.

use crate::mesh::{CrackSpec, FaceMode, LoopSpec};
use crate::{Bc, BemError, BemSystem, Material, MeshBuilder, Plane, SolveParams, V2};
use serde::Serialize;
use std::time::Instant;

/// One measured mesh.
#[derive(Debug, Clone, Serialize)]
pub struct BenchEntry {
    /// Number of elements.
    pub elements: usize,
    /// Number of unknowns.
    pub unknowns: usize,
    /// Assembly wall time (s).
    pub assembly_s: f64,
    /// LU factorization wall time (s).
    pub factor_s: f64,
    /// Median wall time of one further right-hand side by substitution (s).
    pub solve_s: f64,
    /// Wall time of the precomputed interface response R = A^{-1} B_var (s).
    pub response_s: f64,
    /// Median wall time of one further right-hand side through R (s).
    pub solve_response_s: f64,
    /// Bytes held by the factorization and kept columns.
    pub memory_bytes: usize,
}

/// A mesh, its per-element conditions and the groups whose values may change.
pub type LoadedMesh = (crate::Mesh, Vec<[Bc; 2]>, Vec<usize>);

/// The plate mesh with about `target` elements and its loaded-edge conditions.
pub fn sent_plate(target: usize) -> Result<LoadedMesh, BemError> {
    // Perimeter 60 m plus two faces of 8 m: 76 m of boundary.
    let h = 76.0 / target as f64;
    let mut b = MeshBuilder::new();
    b.add_loop(LoopSpec::rectangle(0.0, 0.0, 20.0, 10.0, h));
    b.add_crack(CrackSpec {
        name: "c".into(),
        points: vec![V2::new(10.0, 10.0), V2::new(10.0, 2.0)],
        faces: FaceMode::Coincident,
        element_size: h,
        tip: None,
    });
    let mesh = b.build()?;
    let (left, right) = (
        mesh.group("left").unwrap_or(usize::MAX),
        mesh.group("right").unwrap_or(usize::MAX),
    );
    let bcs = mesh
        .elements
        .iter()
        .map(|e| {
            let tx = if e.group == left {
                -0.5
            } else if e.group == right {
                0.5
            } else {
                0.0
            };
            [Bc::Traction(tx), Bc::Traction(0.0)]
        })
        .collect();
    Ok((mesh, bcs, vec![left, right]))
}

/// Measures every size in `targets` (element counts).
pub fn run(targets: &[usize], rhs_repeats: usize) -> Result<Vec<BenchEntry>, BemError> {
    let mat = Material::new(1e4, 1.0 / 3.0, Plane::Stress)?;
    let mut out = Vec::new();
    for &t in targets {
        let (mesh, bcs, loaded) = sent_plate(t)?;
        let params = SolveParams {
            variable_groups: loaded,
            estimate_condition: false,
            precompute_response: true,
            ..Default::default()
        };
        let sys = BemSystem::new(&mesh, &mat, &bcs, &params)?;
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let mut subst = Vec::new();
        for _ in 0..rhs_repeats.max(1) {
            let t0 = Instant::now();
            std::hint::black_box(sys.solve()?);
            subst.push(t0.elapsed().as_secs_f64());
        }
        let mut times = Vec::new();
        for r in 0..rhs_repeats.max(1) {
            let scale = 1.0 + 0.1 * (r + 1) as f64;
            let new: Vec<[Bc; 2]> = bcs
                .iter()
                .map(|b| [Bc::Traction(b[0].value() * scale), b[1]])
                .collect();
            let t0 = Instant::now();
            let sol = sys.solve_with(&new)?;
            times.push(t0.elapsed().as_secs_f64());
            std::hint::black_box(&sol);
        }
        let info = sys.info();
        out.push(BenchEntry {
            elements: info.elements,
            unknowns: info.unknowns,
            assembly_s: info.assembly_s,
            factor_s: info.factor_s,
            solve_s: median(subst),
            response_s: info.response_s,
            solve_response_s: median(times),
            memory_bytes: info.memory_bytes,
        });
    }
    Ok(out)
}

/// Least-squares exponent p of t = c n^p over the entries (None with fewer than 2).
pub fn fit_exponent(points: &[(f64, f64)]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(n, t)| *n > 0.0 && *t > 0.0)
        .map(|(n, t)| (n.ln(), t.ln()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let k = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / k, sy / k);
    let (num, den) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    (den > 0.0).then(|| num / den)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponent_fit_recovers_a_power_law() {
        let pts: Vec<(f64, f64)> = [500.0, 1000.0, 2000.0]
            .iter()
            .map(|n: &f64| (*n, 3e-9 * n.powf(2.7)))
            .collect();
        assert!((fit_exponent(&pts).unwrap() - 2.7).abs() < 1e-12);
    }

    #[test]
    fn small_bench_runs_and_further_rhs_changes_the_solution() {
        let r = run(&[120], 2).unwrap();
        assert_eq!(r.len(), 1);
        assert!(r[0].elements >= 100 && r[0].solve_s >= 0.0);
    }
}
