//! A crack that runs from the outline into a hole (both ends mouths: the crack of a growth
//! run joined to the hole it ran into, issue 18 item 5), against the same body meshed as
//! one outline (the crack opened into a slot 1e-3 m wide whose faces run into the hole).
//!
//! Plate [0, 2] x [0, 1] m, hole of radius 0.2 m at (1, 0.5) as a 64-gon with a flat edge
//! at its bottom, a straight crack up from (1, 0) to the middle of that edge. Left edge
//! clamped, right edge pulled by p along x (the crack opens). Checked:
//! - the mesher splits the hole edge at the junction and marks neither crack end a tip;
//! - interior displacements at points 0.1 m or more from the crack, the hole and the clamp
//!   agree with the slot model within 1 % of the largest displacement, and the crack
//!   opening (upper minus lower face) with the slot's face separation within 2 %;
//! - equilibrium: the boundary tractions' resultant and moment within 1e-2 of p x height
//!   (constant elements do not balance exactly: measured 4.8e-3 and 4.2e-3, the same to
//!   5 digits as the slot model's), and no larger than twice the slot model's;
//! - rigid motion: with the loops given a rigid displacement the crack faces follow it
//!   within 1e-5 of its size (measured 1.1e-6 near the junction) and the tractions vanish within 1e-6 E a beyond 0.1 m of
//!   the junction; nearer, on the hole, within 1e-4 E a, and 5e-3 E a on the two hole
//!   elements that meet the crack (measured 1.19e-3), where the traction-free crack face
//!   meets the hole at a right angle;
//! - where that error comes from: a rigid translation is reproduced exactly (1e-9 E a);
//!   the error is the rotation's, and it is the constant-element collocation error next to
//!   a kink of the boundary. Beside a kink of angle theta, the piecewise-constant
//!   displacement of a linear field misses it by O(w h) at distances O(h), so the
//!   traction error is O(E w theta) whatever h: on the hole's polygon edges split into
//!   several elements it sits on the elements beside the vertices, halves with the kink
//!   angle (64-gon against 128-gon) and does not fall with h; with one element per edge
//!   (as circular holes are meshed) the two kinks of each element cancel to 1e-12. The
//!   junction splits one hole edge into two elements, each beside one vertex: that is the
//!   1.19e-3 above, and it falls with the element size at the junction (below 5e-5 E a
//!   at h = 3.125 mm, measured 1.2e-5).

mod common;

use common::{rect_loop, steel};
use pdbem_bem::mesh::{CrackSpec, FaceMode, LoopSpec};
use pdbem_bem::post::{Background, FieldEvaluator};
use pdbem_bem::{Bc, BemSystem, Mesh, MeshBuilder, SolveParams, V2};

const N: usize = 64;
const R: f64 = 0.2;
const H: f64 = 0.025;
const P: f64 = 1.0;
const SLOT: f64 = 1e-3;

/// The 64-gon of the hole, clockwise, its first edge flat at the bottom (centred on x = 1).
fn hole_points() -> Vec<V2> {
    polygon_points(N)
}

/// The `n`-gon of the hole, clockwise, its first edge flat at the bottom.
fn polygon_points(n: usize) -> Vec<V2> {
    let c = V2::new(1.0, 0.5);
    (0..n)
        .map(|k| {
            let a =
                -std::f64::consts::FRAC_PI_2 - (k as f64 - 0.5) * std::f64::consts::TAU / n as f64;
            c + R * V2::new(a.cos(), a.sin())
        })
        .collect()
}

/// Height of the hole's flat bottom edge.
fn bottom_y() -> f64 {
    0.5 - R * (std::f64::consts::PI / N as f64).cos()
}

fn joined_mesh() -> Mesh {
    plate_mesh(H, N, true)
}

/// The plate with its `n`-gon hole at element size `h`, with the crack joined to the hole
/// or without it.
fn plate_mesh(h: f64, n: usize, crack: bool) -> Mesh {
    let mut b = MeshBuilder::new();
    b.add_loop(rect_loop(0.0, 0.0, 2.0, 1.0, h));
    b.add_loop(LoopSpec {
        edge_groups: vec!["hole".into(); n],
        edge_sizes: vec![h; n],
        points: polygon_points(n),
        is_hole: true,
    });
    if crack {
        b.add_crack(CrackSpec {
            name: "crack".into(),
            points: vec![V2::new(1.0, 0.0), V2::new(1.0, bottom_y())],
            faces: FaceMode::Coincident,
            element_size: h,
            tip: None,
        });
    }
    b.build().unwrap()
}

/// The same body as one outline: the crack opened into a slot of width `SLOT` running
/// into the hole, traversed counter-clockwise (body on the left).
fn slot_mesh() -> Mesh {
    let g = 0.5 * SLOT;
    let yb = bottom_y();
    let hole = hole_points();
    let mut pts = vec![
        V2::new(0.0, 0.0),
        V2::new(1.0 - g, 0.0),
        V2::new(1.0 - g, yb),
    ];
    let mut groups: Vec<String> = ["bottom", "slot", "hole"].map(String::from).to_vec();
    // Around the hole from the left end of its bottom edge (clockwise, the body outside),
    // back to the right end of that edge.
    pts.extend(hole.iter().skip(1).copied());
    groups.extend(std::iter::repeat_n("hole".to_string(), N - 1));
    pts.push(hole[0]);
    groups.push("hole".into());
    pts.extend([
        V2::new(1.0 + g, yb),
        V2::new(1.0 + g, 0.0),
        V2::new(2.0, 0.0),
        V2::new(2.0, 1.0),
        V2::new(0.0, 1.0),
    ]);
    groups.extend(["slot", "bottom", "right", "top", "left"].map(String::from));
    let n = pts.len();
    assert_eq!(groups.len(), n);
    let mut b = MeshBuilder::new();
    b.add_loop(LoopSpec {
        points: pts,
        edge_groups: groups,
        edge_sizes: vec![H; n],
        is_hole: false,
    });
    b.build().unwrap()
}

/// Left edge clamped, right edge pulled by `P` along x, the rest free.
fn tension(mesh: &Mesh) -> Vec<[Bc; 2]> {
    mesh.elements
        .iter()
        .map(|e| match mesh.groups[e.group].as_str() {
            "left" => [Bc::Displacement(0.0), Bc::Displacement(0.0)],
            "right" => [Bc::Traction(P), Bc::Traction(0.0)],
            _ => [Bc::Traction(0.0), Bc::Traction(0.0)],
        })
        .collect()
}

fn solve(mesh: &Mesh, bcs: &[[Bc; 2]]) -> pdbem_bem::Solution {
    BemSystem::new(mesh, &steel(), bcs, &SolveParams::default())
        .unwrap()
        .solve()
        .unwrap()
}

#[test]
fn a_crack_joined_to_a_hole_meshes_as_a_cut_with_two_mouths() {
    let mesh = joined_mesh();
    let c = &mesh.cracks[0];
    assert!(!c.start_is_tip && !c.end_is_tip);
    assert!(mesh.tips().is_empty());
    let rim = V2::new(1.0, bottom_y());
    let hole = mesh.group("hole").unwrap();
    let ends: Vec<V2> = mesh
        .group_elements(hole)
        .flat_map(|e| [mesh.elements[e].a, mesh.elements[e].b])
        .collect();
    assert!(
        ends.iter().any(|p| (p - rim).norm() < 1e-12),
        "the hole edge is split at the junction"
    );
    let last = &mesh.elements[*c.upper.last().unwrap()];
    assert!((last.b - rim).norm() < 1e-12, "{:?}", last.b);
}

#[test]
fn a_crack_joined_to_a_hole_agrees_with_the_slotted_outline() {
    let joined = joined_mesh();
    let slot = slot_mesh();
    let (sj, ss) = (
        solve(&joined, &tension(&joined)),
        solve(&slot, &tension(&slot)),
    );
    let mat = steel();
    let ej = FieldEvaluator::new(&joined, &mat, &sj, Background::default());
    let es = FieldEvaluator::new(&slot, &mat, &ss, Background::default());
    let centre = V2::new(1.0, 0.5);
    let pts: Vec<V2> = (1..20)
        .flat_map(|i| (1..10).map(move |j| V2::new(0.1 * i as f64, 0.1 * j as f64)))
        .filter(|p| (p.x - 1.0).abs() >= 0.1 && (p - centre).norm() >= R + 0.1 && p.x >= 0.1)
        .collect();
    assert!(pts.len() > 100);
    let (uj, us) = (ej.displacements(&pts), es.displacements(&pts));
    let scale = us.iter().map(|u| u[0].hypot(u[1])).fold(0.0, f64::max);
    let worst = uj
        .iter()
        .zip(&us)
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-2 * scale,
        "interior displacements differ by {worst:.3e}, largest {scale:.3e}"
    );
    // Crack opening against the slot's face separation at the same height, away from the
    // mouth and the junction (0.05 m).
    let c = &joined.cracks[0];
    let sg = slot.group("slot").unwrap();
    // The slot face element on the side `left` nearest to height y: its x displacement.
    let face = |left: bool, y: f64| {
        slot.group_elements(sg)
            .filter(|&e| (slot.elements[e].mid.x < 1.0) == left)
            .min_by(|&a, &b| {
                (slot.elements[a].mid.y - y)
                    .abs()
                    .total_cmp(&(slot.elements[b].mid.y - y).abs())
            })
            .map(|e| ss.u[e][0])
            .unwrap()
    };
    let mut checked = 0;
    for (&up, &lo) in c.upper.iter().zip(&c.lower) {
        let y = joined.elements[up].mid.y;
        if y < 0.05 || y > bottom_y() - 0.05 {
            continue;
        }
        // The upper face lies left of the upward crack (x < 1).
        let cod = sj.u[lo][0] - sj.u[up][0];
        let gap = face(false, y) - face(true, y);
        assert!(
            (cod - gap).abs() < 2e-2 * gap.abs(),
            "y = {y:.3}: opening {cod:.4e}, slot {gap:.4e}"
        );
        checked += 1;
    }
    assert!(checked > 5, "{checked} stations");
    // Equilibrium: the joined body's boundary tractions against the slot model's (the
    // constant-element BEM does not balance exactly; the join must not make it worse).
    let (fj, mj) = resultant(&joined, &sj);
    let (fs, ms) = resultant(&slot, &ss);
    eprintln!("resultant joined {fj:?} {mj:.3e}, slot {fs:?} {ms:.3e}");
    assert!(fj.norm() < 1e-2 * P, "resultant {fj:?}");
    assert!(mj.abs() < 1e-2 * P * 2.0, "moment {mj:.3e}");
    assert!(
        fj.norm() < 2.0 * fs.norm().max(1e-6 * P),
        "{fj:?} vs slot {fs:?}"
    );
}

/// Resultant force (N/m) and moment about the origin of the boundary tractions.
fn resultant(mesh: &Mesh, s: &pdbem_bem::Solution) -> (V2, f64) {
    let (mut f, mut m) = (V2::zeros(), 0.0);
    for (e, t) in mesh.elements.iter().zip(&s.t) {
        let t = V2::new(t[0], t[1]) * e.h;
        f += t;
        m += e.mid.x * t.y - e.mid.y * t.x;
    }
    (f, m)
}

#[test]
fn a_crack_joined_to_a_hole_follows_a_rigid_motion() {
    let mesh = joined_mesh();
    let (a, w) = (V2::new(1e-3, -2e-3), 5e-4);
    let rigid = |p: V2| a + w * V2::new(-p.y, p.x);
    let sol = solve(&mesh, &rigid_bcs(&mesh, a, w));
    let scale = a.norm();
    let rim = V2::new(1.0, bottom_y());
    let e_a = steel().e * scale;
    for (e, (u, t)) in mesh.elements.iter().zip(sol.u.iter().zip(&sol.t)) {
        let r = rigid(e.mid);
        let what = &mesh.groups[e.group];
        assert!(
            (u[0] - r.x).hypot(u[1] - r.y) < 1e-5 * scale,
            "{what} at {:?}: u {u:?} vs {r:?}",
            e.mid
        );
        // Measured: 6.6e-7 E a at most, except on the hole elements near the junction,
        // where a traction-free crack face meets a loop under displacement at a right
        // angle (elements of 0.025 and 0.0098 m): 1.19e-3 E a on the two that meet it,
        // then 4.8e-5, 1.1e-5 and 4.9e-6 at 0.02, 0.04 and 0.06 m on one side.
        let d = (e.mid - rim).norm();
        let tol = if d < 0.01 {
            5e-3
        } else if d < 0.1 {
            1e-4
        } else {
            1e-6
        };
        assert!(
            t[0].hypot(t[1]) < tol * e_a,
            "{what} at {:?}: t {t:?}",
            e.mid
        );
    }
}

/// The rigid motion `a + w e_z x p` prescribed on the loops, the crack faces
/// traction-free.
fn rigid_bcs(mesh: &Mesh, a: V2, w: f64) -> Vec<[Bc; 2]> {
    mesh.elements
        .iter()
        .map(|e| {
            if mesh.groups[e.group].starts_with("crack") {
                [Bc::Traction(0.0), Bc::Traction(0.0)]
            } else {
                let u = a + w * V2::new(-e.mid.y, e.mid.x);
                [Bc::Displacement(u.x), Bc::Displacement(u.y)]
            }
        })
        .collect()
}

/// Largest traction (in E times the motion's scale) on the hole elements, split into
/// (elements with an end on a polygon vertex, the other hole elements, the elements
/// within `junction` of the junction), under the rigid motion `a + w e_z x p` prescribed on
/// the loops (crack faces traction-free).
fn rigid_errors(mesh: &Mesh, n: usize, a: V2, w: f64, junction: f64) -> (f64, f64, f64) {
    let sol = solve(mesh, &rigid_bcs(mesh, a, w));
    // The motion's scale: the translation, or the rotation times the 1 m plate height.
    let e_scale = steel().e * a.norm().max(w * 1.0);
    let verts = polygon_points(n);
    let rim = V2::new(1.0, bottom_y());
    let (mut at_vertex, mut other, mut at_junction) = (0.0f64, 0.0f64, 0.0f64);
    for (e, t) in mesh.elements.iter().zip(&sol.t) {
        let err = t[0].hypot(t[1]) / e_scale;
        if mesh.groups[e.group] != "hole" {
            continue;
        }
        if (e.mid - rim).norm() < junction {
            at_junction = at_junction.max(err);
        } else if verts
            .iter()
            .any(|v| (e.a - v).norm() < 1e-9 || (e.b - v).norm() < 1e-9)
        {
            at_vertex = at_vertex.max(err);
        } else {
            other = other.max(err);
        }
    }
    (at_vertex, other, at_junction)
}

#[test]
fn rigid_motion_errors_are_the_rotation_at_kinks_and_fall_at_the_junction_with_h() {
    let (a, w) = (V2::new(1e-3, -2e-3), 5e-4);
    // Translation: exact on every hole element, split edges and junction included.
    let fine = plate_mesh(0.003125, N, true);
    let (v, o, j) = rigid_errors(&fine, N, a, 0.0, 0.01);
    assert!(
        v.max(o).max(j) < 1e-9,
        "translation: {v:.2e} {o:.2e} {j:.2e}"
    );
    // Rotation, one element per polygon edge (h above the edge length 0.0196 m): the two
    // kinks of each element cancel.
    let (v, o, _) = rigid_errors(&plate_mesh(H, N, false), N, V2::zeros(), w, 0.0);
    assert!(v.max(o) < 1e-9, "one element per edge: {v:.2e} {o:.2e}");
    // Split edges: the error beside a vertex is O(kink angle), whatever h. Measured
    // 1.83e-3 (h = 12.5 mm) and 1.54e-3 (3.125 mm) on the 64-gon, 7.9e-4 on the 128-gon.
    let h = 0.003125;
    let (v64, _, _) = rigid_errors(&plate_mesh(h, N, false), N, V2::zeros(), w, 0.0);
    let (v64c, _, _) = rigid_errors(&plate_mesh(0.0125, N, false), N, V2::zeros(), w, 0.0);
    let (v128, _, _) = rigid_errors(&plate_mesh(h, 2 * N, false), 2 * N, V2::zeros(), w, 0.0);
    assert!(
        (1.0e-3..2.5e-3).contains(&v64) && (v64c / v64 - 1.0).abs() < 0.3,
        "64-gon beside vertices: {v64:.3e} (h = {h}), {v64c:.3e} (h = 0.0125)"
    );
    let ratio = v64 / v128;
    assert!((1.7..2.3).contains(&ratio), "64-gon / 128-gon: {ratio:.3}");
    // The junction: 1.19e-3 at h = 25 mm (the test above), 1.2e-5 at 3.125 mm.
    let (_, _, j) = rigid_errors(&fine, N, a, w, 0.002);
    assert!(j < 5e-5, "junction at h = {h}: {j:.3e}");
}
