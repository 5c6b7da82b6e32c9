//! A body cut in two by cracks (from the outline through a hole to the outline): each
//! piece keeps its own rigid modes. The left piece is held and unloaded, the right piece
//! floats under a self-equilibrated uniaxial stress: the left piece must not move, and
//! the right one must carry the uniform stress exactly as a body of its own would.

mod common;

use common::{build, crack, rect_loop, steel, traction_from_stress};
use pdbem_bem::mesh::{FaceMode, LoopSpec};
use pdbem_bem::{Bc, BemSystem, SolveParams, V2};

fn hole() -> LoopSpec {
    let mut l = rect_loop(0.8, 0.4, 0.4, 0.2, 0.05);
    l.edge_groups = vec!["hole".into(); 4];
    l.is_hole = true;
    l
}

#[test]
fn a_floating_piece_carries_its_own_equilibrated_load() {
    for faces in [FaceMode::Coincident, FaceMode::Gap(1e-4)] {
        let mesh = build(
            vec![rect_loop(0.0, 0.0, 2.0, 1.0, 0.05), hole()],
            vec![
                crack("top", V2::new(1.0, 1.0), V2::new(1.0, 0.6), 0.05, faces),
                crack("bottom", V2::new(1.0, 0.4), V2::new(1.0, 0.0), 0.05, faces),
            ],
        );
        let p = 3.0;
        let stress = traction_from_stress(&mesh, [0.0, p, 0.0], 1.0);
        let left = mesh.group("left").unwrap();
        let bcs: Vec<[Bc; 2]> = mesh
            .elements
            .iter()
            .zip(&stress)
            .map(|(e, t)| {
                if e.group == left {
                    [Bc::Displacement(0.0), Bc::Displacement(0.0)]
                } else if e.mid.x > 1.0 {
                    *t
                } else {
                    [Bc::Traction(0.0), Bc::Traction(0.0)]
                }
            })
            .collect();
        let sys = BemSystem::new(&mesh, &steel(), &bcs, &SolveParams::default()).unwrap();
        assert_eq!(sys.free_modes_per_piece(), &[0, 3], "{faces:?}");
        let sol = sys.solve().unwrap();
        let strain = p / 1e4;
        let mut left_max: f64 = 0.0;
        for (e, u) in mesh.elements.iter().zip(&sol.u) {
            if e.mid.x < 1.0 - 1e-3 {
                left_max = left_max.max(u[0].hypot(u[1]));
            }
        }
        assert!(
            left_max < 1e-6 * strain,
            "{faces:?}: left piece moved {left_max:e}"
        );
        // Right piece: u_y(top) - u_y(bottom) = strain x height at every x.
        let top = mesh.group("top").unwrap();
        let bottom = mesh.group("bottom").unwrap();
        let at = |g: usize, x: f64| {
            mesh.elements
                .iter()
                .zip(&sol.u)
                .find(|(e, _)| e.group == g && (e.mid.x - x).abs() < 0.026)
                .map(|(_, u)| u[1])
                .unwrap()
        };
        for x in [1.125, 1.525, 1.975] {
            let stretch = at(top, x) - at(bottom, x);
            assert!(
                (stretch / strain - 1.0).abs() < 1e-2,
                "{faces:?} x = {x}: stretch {stretch:e}, uniform stress gives {strain:e}"
            );
        }
    }
}
