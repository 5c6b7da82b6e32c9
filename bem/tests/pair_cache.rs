//! Reusing element-pair blocks from an earlier assembly ([`PairCache`]) gives the same
//! system as a fresh assembly, bit for bit, and integrates only the pairs with a new
//! element: the edge crack of a plate grows as in a growth run's relocation.
mod common;

use common::*;
use pdbem_bem::mesh::FaceMode;
use pdbem_bem::{Bc, BemSystem, Material, Mesh, PairCache, Plane, Solution, SolveParams, V2};

/// A 2 m x 1 m plate with an edge crack from the middle of the top edge down to `tip_y`
/// (coincident faces), elements of 0.05 m.
fn plate(tip_y: f64) -> Mesh {
    build(
        vec![rect_loop(0.0, 0.0, 2.0, 1.0, 0.05)],
        vec![crack(
            "c",
            V2::new(1.0, 1.0),
            V2::new(1.0, tip_y),
            0.05,
            FaceMode::Coincident,
        )],
    )
}

/// Left edge clamped, unit tension on the right edge, the rest free.
fn conditions(mesh: &Mesh) -> Vec<[Bc; 2]> {
    let (left, right) = (mesh.group("left").unwrap(), mesh.group("right").unwrap());
    mesh.elements
        .iter()
        .map(|e| {
            if e.group == left {
                [Bc::Displacement(0.0), Bc::Displacement(0.0)]
            } else if e.group == right {
                [Bc::Traction(1.0), Bc::Traction(0.0)]
            } else {
                [Bc::Traction(0.0), Bc::Traction(0.0)]
            }
        })
        .collect()
}

/// Solution of `mesh` with the cache (and the pairs it reused) or without.
fn solve(mesh: &Mesh, mat: &Material, cache: Option<&mut PairCache>) -> (Solution, usize) {
    let bcs = conditions(mesh);
    let params = SolveParams::default();
    let sys = BemSystem::new_with_cache(mesh, mat, &bcs, &params, cache).unwrap();
    (sys.solve().unwrap(), sys.info().reused_pairs)
}

#[test]
fn a_grown_crack_reuses_the_old_pairs_and_solves_bit_for_bit_as_a_fresh_assembly() {
    let mat = steel();
    let (short, long) = (plate(0.7), plate(0.6));
    let mut cache = PairCache::default();
    let (_, reused) = solve(&short, &mat, Some(&mut cache));
    assert_eq!(reused, 0, "an empty cache reuses nothing");
    assert_eq!(cache.elements(), short.len());

    let (cached, reused) = solve(&long, &mat, Some(&mut cache));
    let (fresh, _) = solve(&long, &mat, None);
    assert_eq!(
        cached, fresh,
        "copied blocks must equal integrated ones exactly"
    );
    // The outline (120 elements) is the same in both meshes, so at least its pairs are
    // copied; the crack faces' new elements (0.1 m of growth, 2 per face) are not.
    let outline = 120;
    let new = long.len() - short.len();
    assert_eq!(new, 4, "two elements more per face");
    assert!(
        reused >= outline * outline && reused <= (long.len() - new).pow(2),
        "reused {reused} of {} pairs",
        long.len().pow(2)
    );
    assert_eq!(
        cache.elements(),
        long.len(),
        "the cache now holds the new mesh"
    );

    // Other constants (here nu) make the blocks different: nothing is reused and the
    // solution is that of the other material.
    let other = Material::new(1e4, 0.25, Plane::Stress).unwrap();
    let (with_other, reused) = solve(&long, &other, Some(&mut cache));
    assert_eq!(reused, 0);
    assert_eq!(with_other, solve(&long, &other, None).0);
}

#[test]
fn storage_recycled_from_earlier_assemblies_leaves_no_trace() {
    // The cache hands the storage of the assembly before last (pair blocks, first-moment
    // matrix) to the next assembly with stale entries; meshes that grow, shrink and grow
    // again must still solve bit for bit as fresh assemblies.
    let mat = steel();
    let mut cache = PairCache::default();
    for a in [0.7, 0.6, 0.7, 0.55, 0.6] {
        let mesh = plate(a);
        let (cached, _) = solve(&mesh, &mat, Some(&mut cache));
        assert_eq!(
            cached,
            solve(&mesh, &mat, None).0,
            "crack tip parameter {a}"
        );
    }
}
