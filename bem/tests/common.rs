//! Shared builders for the BEM verification tests.
#![allow(dead_code)]

use pdbem_bem::mesh::{CrackSpec, FaceMode, LoopSpec};
use pdbem_bem::{Bc, Material, Mesh, MeshBuilder, Plane, V2};

/// Axis-aligned rectangle loop with edges bottom, right, top, left.
pub fn rect_loop(x0: f64, y0: f64, w: f64, h: f64, size: f64) -> LoopSpec {
    LoopSpec::rectangle(x0, y0, w, h, size)
}

/// Circle as n single-element sides (a hole when `hole`).
pub fn circle_loop(c: V2, r: f64, n: usize, hole: bool) -> LoopSpec {
    let pts: Vec<V2> = (0..n)
        .map(|i| {
            let t = 2.0 * std::f64::consts::PI * i as f64 / n as f64;
            c + r * V2::new(t.cos(), t.sin())
        })
        .collect();
    LoopSpec {
        points: pts,
        edge_groups: vec!["hole".into(); n],
        edge_sizes: vec![f64::INFINITY; n],
        is_hole: hole,
    }
}

/// The seed-002 plate material: E = 1e4 Pa, nu = 1/3, plane stress.
pub fn steel() -> Material {
    Material::new(1e4, 1.0 / 3.0, Plane::Stress).unwrap()
}

/// Traction conditions t = sigma . n on every element (remote-stress superposition uses -sigma).
pub fn traction_from_stress(mesh: &Mesh, s: [f64; 3], sign: f64) -> Vec<[Bc; 2]> {
    mesh.elements
        .iter()
        .map(|e| {
            let n = e.normal;
            [
                Bc::Traction(sign * (s[0] * n.x + s[2] * n.y)),
                Bc::Traction(sign * (s[2] * n.x + s[1] * n.y)),
            ]
        })
        .collect()
}

/// A straight crack spec.
pub fn crack(name: &str, a: V2, b: V2, size: f64, faces: FaceMode) -> CrackSpec {
    CrackSpec {
        name: name.into(),
        points: vec![a, b],
        faces,
        element_size: size,
        tip: None,
    }
}

/// Builds a mesh from loops and cracks.
pub fn build(loops: Vec<LoopSpec>, cracks: Vec<CrackSpec>) -> Mesh {
    let mut b = MeshBuilder::new();
    for l in loops {
        b.add_loop(l);
    }
    for c in cracks {
        b.add_crack(c);
    }
    b.build().unwrap()
}
