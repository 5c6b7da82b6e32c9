//! Refusal of finite bodies whose loads nothing balances (issue 17).
//!
//! A finite BEM body (or a piece of it cut off by cracks) that the scene's displacement
//! conditions do not hold against a rigid motion is solved by removing that motion
//! ([`pdbem_bem::system`], bordering). If the prescribed tractions have a resultant along
//! the free motion, the solve still returns: the solution of some other, balanced load,
//! with SIFs off by any amount (a SENT plate pulled on one side only: K_I -50 %). Such a
//! scene is an error, in `pdbem check` and in every mode of `pdbem run`, that gives the
//! resultant $F_x, F_y$ and the moment $M$ about the outline's area centroid (about the
//! piece's mean collocation point when cracks cut the body apart), with the test and
//! tolerance of [`pdbem_bem::system::balance`] (relative 1e-6 of
//! $\sum_e h_e (|t_x| + |t_y|)$).
//!
//! Infinite plates are not checked: a remote stress is balanced by construction (the holes
//! and crack faces carry minus its traction, whose resultant over a closed loop or a pair
//! of faces vanishes), and a net force on a hole of an infinite plate is carried to
//! infinity (Kelvin's solution), which is a valid problem.
//!
//! Entry points: [`check`] (a built mesh and its conditions), run by
//! [`super::bem::build`]; [`super::bem::check_balance`] checks the scene's whole body for
//! the coupled and growth modes whose BEM mesh has windows cut out.

use anyhow::{bail, Result};
use pdbem_bem::system::balance::{load_imbalance, Imbalance, BALANCE_TOLERANCE};
use pdbem_bem::{Bc, Mesh, V2};

use crate::scene::Scene;

/// An error when a piece of the finite body `mesh` under `bcs` has prescribed tractions
/// out of balance along a rigid motion no displacement condition holds.
pub fn check(scene: &Scene, mesh: &Mesh, bcs: &[[Bc; 2]]) -> Result<()> {
    let out = load_imbalance(mesh, bcs, BALANCE_TOLERANCE);
    let Some(first) = out.first() else {
        return Ok(());
    };
    let pieces = mesh_pieces(mesh);
    let mut shown = first.clone();
    if pieces == 1 {
        if let Some(c) = outline_centroid(scene) {
            shown = about(&shown, c);
        }
    }
    bail!(
        "{}: boundary: {}. The solution would be that of another load: balance the loads or \
         add a support (a displacement condition)",
        scene.file_label().display(),
        describe(mesh, &shown, pieces > 1)
    )
}

/// The note of an explicit-dynamics scene (no pins, so a free body is solved as it is)
/// whose prescribed tractions on the whole body `mesh` under `bcs` are out of balance
/// along a rigid motion no displacement condition holds: the body accelerates as a whole,
/// besides its waves and cracks. Gives the resultant and the largest rigid acceleration
/// |F| / (rho A) of the body's mass per metre of thickness (`density` rho, area `area`)
/// with the rigid displacement it makes by `end_time`. `None` when the loads balance.
pub fn dynamic_note(
    scene: &Scene,
    (mesh, bcs): (&Mesh, &[[Bc; 2]]),
    area: f64,
    density: f64,
    end_time: f64,
) -> Option<String> {
    let first = load_imbalance(mesh, bcs, BALANCE_TOLERANCE)
        .into_iter()
        .next()?;
    let pieces = mesh_pieces(mesh);
    let shown = match outline_centroid(scene) {
        Some(c) if pieces == 1 => about(&first, c),
        _ => first,
    };
    let mass = density * area;
    let a = shown.force[0].hypot(shown.force[1]) / mass;
    let motion = if a > 0.0 {
        format!(
            "; the resultant accelerates the body's {mass:.4e} kg/m (rho A) at up to {a:.3e} m/s^2, a rigid displacement of up to {:.3e} m by end_time",
            0.5 * a * end_time * end_time
        )
    } else {
        String::new()
    };
    Some(format!(
        "{}{motion}. Explicit dynamics runs the body as it is: it accelerates as a whole, besides its waves and cracks, and the crack measures are those of a body in flight; balance the loads or add a support if that is not the intent",
        describe(mesh, &shown, pieces > 1)
    ))
}

/// The number of pieces of `mesh` (one when they cannot be told).
fn mesh_pieces(mesh: &Mesh) -> usize {
    pdbem_bem::mesh::pieces(mesh).map_or(1, |p| p.iter().max().map_or(1, |m| m + 1))
}

/// Area centroid of the scene's outline (None for an infinite plate).
fn outline_centroid(scene: &Scene) -> Option<V2> {
    let geo = crate::scene::shapes::SceneGeometry::of(scene);
    crate::geometry::polygon_centroid(&geo.outline?.points)
}

/// The same resultant with the moment taken about `p`:
/// $M_p = M_c + (c - p) \times F$.
fn about(i: &Imbalance, p: V2) -> Imbalance {
    let d = i.centroid - p;
    Imbalance {
        centroid: p,
        moment: i.moment + d.x * i.force[1] - d.y * i.force[0],
        ..i.clone()
    }
}

fn describe(mesh: &Mesh, i: &Imbalance, several: bool) -> String {
    let groups: Vec<&str> = i.groups.iter().map(|&g| mesh.groups[g].as_str()).collect();
    let body = if several {
        format!("piece {} of the body (cut apart by cracks)", i.piece)
    } else {
        "the body".to_string()
    };
    let held = if i.free_motions == 3 {
        format!("no displacement condition holds {body}")
    } else {
        format!(
            "the displacement conditions leave {} rigid motion(s) of {body} free",
            i.free_motions
        )
    };
    format!(
        "the prescribed tractions (on {}) are out of balance and {held}: resultant \
         Fx = {:.6e} N/m, Fy = {:.6e} N/m, M = {:.6e} N m/m about ({:.6}, {:.6}) m (per metre \
         of thickness; {:.2e} of the summed |traction| x length, tolerance {:.0e})",
        groups.join(", "),
        i.force[0],
        i.force[1],
        i.moment,
        i.centroid.x,
        i.centroid.y,
        i.relative,
        BALANCE_TOLERANCE
    )
}
