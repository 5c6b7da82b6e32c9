#![allow(dead_code)]
//! The uniform-strain window shared by the traction-map and traction-window tests: a
//! 20 x 20 PMB window (dx = 0.025 m) at the centre of a 2 m square, rotated by a given
//! angle, with every node (real and virtual) displaced by the strain `EPS`.

use pdbem_bem::mesh::LoopSpec;
use pdbem_bem::V2;
use pdbem_coupling::pd_window::PdSettings;
use pdbem_coupling::setup::{build, Layout};
use pdbem_coupling::{WindowModel, WindowSpec};
use pdbem_pd::{Failure, Plane};

pub const E: f64 = 2e9;
pub const NU: f64 = 1.0 / 3.0;
pub const THICKNESS: f64 = 0.01;
/// Uniform strain (exx, eyy, gamma_xy / 2).
pub const EPS: [f64; 3] = [1e-3, 4e-4, 3e-4];

fn square(side: f64, size: f64) -> LoopSpec {
    LoopSpec {
        points: vec![
            V2::new(0.0, 0.0),
            V2::new(side, 0.0),
            V2::new(side, side),
            V2::new(0.0, side),
        ],
        edge_groups: ["bottom", "right", "top", "left"]
            .map(String::from)
            .to_vec(),
        edge_sizes: vec![size; 4],
        is_hole: false,
    }
}

/// Plane-stress stress of the uniform strain (bond-based PD: nu = 1/3).
pub fn stress() -> [f64; 3] {
    let f = E / (1.0 - NU * NU);
    [
        f * (EPS[0] + NU * EPS[1]),
        f * (EPS[1] + NU * EPS[0]),
        E / (1.0 + NU) * EPS[2],
    ]
}

pub fn window(angle_deg: f64) -> (pdbem_bem::Mesh, WindowModel) {
    let layout = Layout {
        outline: square(2.0, 0.05),
        holes: Vec::new(),
        cracks: Vec::new(),
        windows: vec![WindowSpec {
            center: V2::new(1.0, 1.0),
            angle: angle_deg.to_radians(),
            dx: 0.025,
            nx: 20,
            ny: 20,
            horizon_factor: 3.015,
        }],
        pd: PdSettings {
            youngs_modulus: E,
            thickness: THICKNESS,
            plane: Plane::Stress,
            failure: Failure::None,
            surface_correction: false,
            bulk_correction: true,
            material: pdbem_pd::PdMaterial::Pmb,
            crack_face_correction: false,
            refine: None,
        },
    };
    let built = build(&layout, |_, _| Vec::new()).unwrap();
    let mut w = built.windows.into_iter().next().unwrap();
    let u: Vec<[f64; 2]> = w
        .model
        .positions()
        .iter()
        .map(|p| [EPS[0] * p[0] + EPS[2] * p[1], EPS[2] * p[0] + EPS[1] * p[1]])
        .collect();
    let virt = w.model.virtual_nodes();
    w.model.set_prescribed_displacements(&u[virt]).unwrap();
    w.model.set_displacements(&u).unwrap();
    (built.mesh, w)
}

pub fn exact_traction(n: V2) -> V2 {
    let s = stress();
    V2::new(s[0] * n.x + s[2] * n.y, s[2] * n.x + s[1] * n.y)
}
