//! The PD model of a window (seed 002 section 2.3, Fig. 6).
//!
//! The region is the window rectangle with its grid aligned to the window (nodes at cell
//! centres, `grid_origin` = lower-left corner, `grid_angle` = window angle), so every
//! boundary node row faces exactly one interface element. Interface sides get a
//! fictitious layer of depth delta (3 rows for m = 3.015) whose displacements come from
//! BEM each iteration; outer sides take the scene's conditions ([`EdgeCondition`]):
//! tractions as boundary-layer body forces, displacements on their own fictitious layer.
//!
//! Stiffness calibration: the bond-based micromodulus $c = 9E/(\pi t \delta^3)$
//! (seed 002 Eq. 5) is exact only for the continuous horizon; the discrete horizon sum
//! with partial volumes is 14 % soft for m = 3.015. [`bulk_stiffness_factor`] measures that
//! factor on a bulk node under uniform strain (Madenci & Oterkus energy method, the same
//! quantity `pd::surface` uses) and the window is built with $E\,g_{bulk}$, which removes
//! the bulk error without the surface correction's stiffening of the bonds that reach the
//! outermost virtual nodes (they lack neighbours beyond the layer, so their correction
//! factor would be about 2).

use pdbem_bem::V2;
use pdbem_pd::mixed::RefineZone;
use pdbem_pd::{
    BoundaryCondition, Failure, Layer, PdMaterial, PdModel, PdProblem, Plane, Region, Selection,
};

use crate::window::{SideKind, Window};

/// PD material and modelling options of the windows.
#[derive(Debug, Clone, PartialEq)]
pub struct PdSettings {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Thickness (m); PD forces are in N for this thickness.
    pub thickness: f64,
    /// Plane stress or plane strain (PMB: nu = 1/3 or 1/4; the state-based model takes
    /// its own nu).
    pub plane: Plane,
    /// Constitutive model: PMB, or state-based PD with the BEM body's Poisson ratio.
    pub material: PdMaterial,
    /// Bond failure law (static coupled solves normally use `Failure::None`).
    pub failure: Failure,
    /// Madenci-Oterkus surface correction (useful on outer free sides; it stiffens the
    /// bonds to the outermost virtual nodes, see the module docs).
    pub surface_correction: bool,
    /// Scale E by [`bulk_stiffness_factor`] (PMB only: the state-based constants are
    /// calibrated on the lattice). Leave it off with `surface_correction`, which already
    /// contains the bulk factor.
    pub bulk_correction: bool,
    /// Stiffen the bonds around pre-crack faces (`pdbem_pd::surface`): the crack faces of
    /// a PD window then match the traction-free LEFM faces of the BEM crack.
    pub crack_face_correction: bool,
    /// A refinement zone at the crack tip each window serves ([`WindowRefine`]); `None`:
    /// uniform windows.
    pub refine: Option<WindowRefine>,
}

/// A square zone of finer cells centred on a window's crack tip (`pdbem_pd::mixed`):
/// the window is coarse at its interface and fine at the tip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowRefine {
    /// Half the zone's side (m): coarse cells whose centres lie within it are split.
    pub half_size: f64,
    /// Splits per cell: 1 (4 children) or 2 (16).
    pub levels: u32,
}

/// A scene condition on a piece of a window's outer side.
#[derive(Debug, Clone, PartialEq)]
pub struct EdgeCondition {
    /// Start of the piece (m).
    pub from: V2,
    /// End of the piece (m).
    pub to: V2,
    /// Traction (Pa), global x and y; None where a component is not a traction.
    pub traction: [Option<f64>; 2],
    /// Prescribed displacement (m), global x and y.
    pub displacement: [Option<f64>; 2],
    /// Whether the scene's condition goes on past `from` and past `to` (its outline edge
    /// runs on beyond the window's corner, or turns at a corner of the outline): the
    /// fictitious layer of a displacement then runs a horizon past that end. Where the
    /// scene's piece ends inside an edge (a free surface or another condition follows)
    /// the layer ends there too ([`outer_strip`]).
    pub continues: [bool; 2],
}

fn p2(v: V2) -> [f64; 2] {
    [v.x, v.y]
}

/// The bulk stiffness factor g = W_CM / W_PD of the discrete horizon sum (dimensionless),
/// measured on the centre node of a small grid under a uniform unit strain along x.
pub fn bulk_stiffness_factor(dx: f64, horizon_factor: f64, plane: Plane) -> f64 {
    let half = (horizon_factor.ceil() as usize + 2) as f64 * dx;
    let n = 2.0 * half + dx;
    let p = PdProblem {
        region: Region::rectangle([0.0, 0.0], [n, n]),
        dx,
        horizon_factor,
        youngs_modulus: 1.0,
        plane,
        ..Default::default()
    };
    let Ok(model) = PdModel::new(&p) else {
        return 1.0;
    };
    let centre = [0.5 * n, 0.5 * n];
    let pos = model.positions();
    let i = (0..model.n_real())
        .min_by(|&a, &b| {
            let d = |k: usize| (pos[k][0] - centre[0]).hypot(pos[k][1] - centre[1]);
            d(a).total_cmp(&d(b))
        })
        .unwrap_or(0);
    let b = model.bonds();
    let w_pd: f64 = b
        .row(i)
        .map(|k| {
            let nx = b.xi[k][0] * b.inv_len[k];
            0.25 * b.k[k] / b.inv_len[k] * nx.powi(4)
        })
        .sum();
    // W_CM = E' / 2 for unit strain; E' = 9E/8 (plane stress) or 6E/5 (plane strain),
    // the bond-based constants of pd::surface.
    let e_eff = match plane {
        Plane::Stress => 9.0 / 8.0,
        Plane::Strain => 6.0 / 5.0,
    };
    if w_pd > 0.0 {
        0.5 * e_eff / w_pd
    } else {
        1.0
    }
}

/// The strip of virtual nodes outside side `k`, grown along the side by delta at ends
/// whose neighbour side is `grow_kind`: an axis-aligned box for an axis-aligned window
/// (its nodes lie half a spacing or more from every face, so both forms select the same
/// nodes), else the strip's own turned box (a turned window against a turned outline).
fn side_box(w: &Window, k: usize, grow_kind: SideKind) -> Selection {
    let (a, b) = w.side(k);
    let t = (b - a).normalize();
    let out = V2::new(t.y, -t.x);
    let d = w.delta() * (1.0 + 1e-6);
    let grow = |side: usize| if w.sides[side] == grow_kind { d } else { 0.0 };
    let (ga, gb) = (grow((k + 3) % 4), grow((k + 1) % 4));
    if !w.axis_aligned() {
        return Selection::OrientedBox {
            origin: p2(a - ga * t),
            axes: [p2(t), p2(out)],
            extent: [(b - a).norm() + ga + gb, d],
        };
    }
    let pts = [
        a - ga * t,
        b + gb * t,
        a - ga * t + d * out,
        b + gb * t + d * out,
    ];
    let (lo, hi) = pdbem_geometry::bounding_box(&pts);
    Selection::Box {
        min: p2(lo),
        max: p2(hi),
    }
}

/// The fictitious strip of the outer condition `c` of window `w`: the nodes within a
/// horizon outward of the piece whose projection on its line falls on the piece, or
/// within a horizon past an end the condition goes on past (`c.continues`). Where the
/// scene's piece ends inside an edge the strip ends there: a layer of every node within
/// a horizon of the piece held the free surface beyond its end too (the shear plate's
/// bottom clamp, which ends at x = 10 m, reached x = 10.3 m in a window against it, and
/// PD-BEM started its second crack at (10.225, 0.025) m).
pub fn outer_strip(w: &Window, c: &EdgeCondition) -> Selection {
    let t = (c.to - c.from).normalize();
    let mut out = V2::new(t.y, -t.x);
    if out.dot(&(c.from - w.spec.center)) < 0.0 {
        out = -out;
    }
    let d = w.delta() * (1.0 + 1e-6);
    let past = |k: usize| if c.continues[k] { d } else { 0.0 };
    Selection::OrientedBox {
        origin: p2(c.from - past(0) * t),
        axes: [p2(t), p2(out)],
        extent: [(c.to - c.from).norm() + past(0) + past(1), d],
    }
}

/// Builds the PD problem of window `w` with pre-cracks `cracks` and outer conditions.
pub fn build_problem(
    w: &Window,
    s: &PdSettings,
    cracks: &[Vec<V2>],
    outer: &[EdgeCondition],
) -> PdProblem {
    let (lx, ly) = w.size();
    let e = if s.bulk_correction && s.material == PdMaterial::Pmb {
        s.youngs_modulus * bulk_stiffness_factor(w.spec.dx, w.spec.horizon_factor, s.plane)
    } else {
        s.youngs_modulus
    };
    let mut boundary = Vec::new();
    if w.sides.iter().all(|k| *k == SideKind::Interface) {
        boundary.push(BoundaryCondition::Displacement {
            on: Selection::All,
            ux: Some(0.0),
            uy: Some(0.0),
            layer: Layer::Fictitious,
        });
    } else {
        for k in 0..4 {
            if w.sides[k] == SideKind::Interface {
                boundary.push(BoundaryCondition::Displacement {
                    on: side_box(w, k, SideKind::Interface),
                    ux: Some(0.0),
                    uy: Some(0.0),
                    layer: Layer::Fictitious,
                });
            }
        }
    }
    for c in outer {
        let edge = vec![p2(c.from), p2(c.to)];
        if c.traction.iter().any(|t| t.is_some_and(|v| v != 0.0)) {
            boundary.push(BoundaryCondition::Traction {
                edge: edge.clone(),
                traction: [c.traction[0].unwrap_or(0.0), c.traction[1].unwrap_or(0.0)],
                depth: None,
            });
        }
        if c.displacement.iter().any(Option::is_some) {
            boundary.push(BoundaryCondition::Displacement {
                on: outer_strip(w, c),
                ux: c.displacement[0],
                uy: c.displacement[1],
                layer: Layer::Fictitious,
            });
        }
    }
    let refine_zones = s
        .refine
        .map(|r| {
            let open = open_sides(w, &boundary);
            refine_zones(p2(zone_centre(w, tip_of(w, cracks), r, open)), r)
        })
        .unwrap_or_default();
    PdProblem {
        region: Region::rotated_rectangle(p2(w.spec.center), lx, ly, w.spec.angle),
        dx: w.spec.dx,
        horizon_factor: w.spec.horizon_factor,
        thickness: s.thickness,
        youngs_modulus: e,
        plane: s.plane,
        failure: s.failure,
        cracks: cracks
            .iter()
            .map(|c| c.iter().map(|p| p2(*p)).collect())
            .collect(),
        boundary,
        surface_correction: s.surface_correction,
        crack_face_correction: s.crack_face_correction,
        grid_angle: w.spec.angle,
        grid_origin: Some(p2(w.corners()[0])),
        material: s.material,
        // Windows carry no scene tractions (the BEM loads them by displacement).
        traction: pdbem_pd::TractionLoad::BodyForceLayer,
        refine_zones,
    }
}

/// The nested zones of `r` at `centre`: level `l` (1..=levels) over the half side
/// `half_size (levels - l + 1) / levels`, so that every size jump is a factor 2 (a
/// factor-4 jump was measured to add about 1 % to the SENT CMOD, see
/// docs/coupled_refined.md).
pub fn refine_zones(centre: [f64; 2], r: WindowRefine) -> Vec<RefineZone> {
    (1..=r.levels)
        .map(|l| RefineZone {
            centre,
            half_size: r.half_size * f64::from(r.levels - l + 1) / f64::from(r.levels),
            levels: l,
        })
        .collect()
}

/// Extent of the split cells of a zone of half side `half_size` from its centre along
/// window `w`'s axes (m): the zone's sides run along the window lattice
/// ([`RefineZone`]), and cells reach dx/2 past their centres.
fn zone_reach(w: &Window, half_size: f64) -> f64 {
    half_size + 0.5 * w.spec.dx
}

/// How far (m) the refinement zone of window `w` (setting `r`) may sit off the window
/// centre along both axes while it keeps two horizons from every side
/// ([`zone_centre`], all sides closed): zero when the zone takes the whole room.
pub fn zone_room(w: &Window, r: WindowRefine) -> f64 {
    let m = zone_reach(w, r.half_size) + 2.0 * w.delta();
    let dx = w.spec.dx;
    let (lx, ly) = w.size();
    let lo = (m / dx - 1e-9).ceil() * dx;
    (0.5 * lx.min(ly) - lo).max(0.0)
}

/// Centre of the refinement zone of window `w` for the tip `tip`: the cell corner nearest
/// the tip, moved along the window's axes (if needed) so that the zone keeps two horizons
/// from every side but the `open` ones ([`open_sides`]; a window pushed against the
/// outline holds its tip off centre).
pub fn zone_centre(w: &Window, tip: V2, r: WindowRefine, open: [bool; 4]) -> V2 {
    let m = zone_reach(w, r.half_size) + 2.0 * w.delta();
    let (lx, ly) = w.size();
    // Snapped to the nearest cell corner: the split cells are then symmetric about the
    // lattice lines through it, so a crack running along one (a symmetric problem) meets a
    // symmetric grid; a zone centred off the line by the tracked tip's scatter was
    // measured to pull the PD-BEM path of growth_tension_edge 0.26 m aside.
    let q = w.to_local(tip) / w.spec.dx;
    let q = V2::new(q.x.round(), q.y.round()) * w.spec.dx;
    // Held two horizons inside on the cell-corner lattice (a clamped centre off the
    // lattice splits the cells asymmetrically about it and shifts the zone's end by a
    // cell; measured on the tension plate); up to an open side itself.
    let dx = w.spec.dx;
    let clamp = |v: f64, l: f64, (open_lo, open_hi): (bool, bool)| {
        let lo = if open_lo {
            0.0
        } else {
            (m / dx - 1e-9).ceil() * dx
        };
        let hi = if open_hi {
            l
        } else {
            ((l - m) / dx + 1e-9).floor() * dx
        };
        if lo > hi {
            0.5 * l
        } else {
            v.clamp(lo, hi)
        }
    };
    let (e1, e2) = w.axes();
    // Sides: 0 bottom (local y = 0), 1 right, 2 top, 3 left ([`Window::corners`]).
    w.corners()[0]
        + clamp(q.x, lx, (open[3], open[1])) * e1
        + clamp(q.y, ly, (open[0], open[2])) * e2
}

/// The outer sides of window `w` that carry none of the scene's conditions in `boundary`
/// (the window problem's conditions, [`build_problem`]): free surfaces. A refinement zone
/// may reach them ([`zone_centre`]): a free side has no fictitious layer and no loaded
/// boundary layer, nothing that needs the coarse spacing there. Interface sides, and outer sides with a traction or a displacement
/// condition, are not open; a condition of a kind `build_problem` does not make for an
/// outer side closes them all.
pub fn open_sides(w: &Window, boundary: &[BoundaryCondition]) -> [bool; 4] {
    let mut open = w.sides.map(|k| k == SideKind::Outer);
    for c in boundary {
        let pts: Vec<[f64; 2]> = match c {
            BoundaryCondition::Traction { edge, .. } => edge.clone(),
            BoundaryCondition::Displacement {
                on: Selection::NearPolyline { points, .. },
                ..
            } => points.clone(),
            // An outer strip ([`outer_strip`]) or an interface strip of a turned window:
            // its inner edge lies on the side.
            BoundaryCondition::Displacement {
                on:
                    Selection::OrientedBox {
                        origin,
                        axes,
                        extent,
                    },
                ..
            } => vec![
                *origin,
                [
                    origin[0] + extent[0] * axes[0][0],
                    origin[1] + extent[0] * axes[0][1],
                ],
            ],
            // The interface layers: their sides are not open anyway.
            BoundaryCondition::Displacement {
                on: Selection::All | Selection::Box { .. },
                ..
            } => continue,
            _ => return [false; 4],
        };
        for (k, o) in open.iter_mut().enumerate() {
            *o &= !on_side(w, &pts, k);
        }
    }
    open
}

/// Whether a segment of the polyline `pts` lies along side `k` of `w`: both its ends on
/// the side's line, overlapping the side by more than a round-off.
fn on_side(w: &Window, pts: &[[f64; 2]], k: usize) -> bool {
    let (a, b) = w.side(k);
    let t = (b - a).normalize();
    let tol = 1e-6 * w.spec.dx;
    let across = |p: V2| ((p - a) - (p - a).dot(&t) * t).norm();
    pts.windows(2).any(|s| {
        let (p, q) = (V2::new(s[0][0], s[0][1]), V2::new(s[1][0], s[1][1]));
        let (sp, sq) = ((p - a).dot(&t), (q - a).dot(&t));
        let overlap = sp.max(sq).min((b - a).norm()) - sp.min(sq).max(0.0);
        across(p) < tol && across(q) < tol && overlap > tol
    })
}

/// The crack tip window `w` serves: the end of its PD pre-cracks deepest inside the window
/// (the other ends reach beyond its boundary); the window centre without a pre-crack.
pub fn tip_of(w: &Window, cracks: &[Vec<V2>]) -> V2 {
    // Signed: the far ends of pre-cracks reach past the window's sides, and a tip near an
    // outer side is closer to it than they are.
    let depth = |p: V2| {
        let d = (0..4)
            .map(|k| {
                let (a, b) = w.side(k);
                pdbem_geometry::point_segment_projection(&p, &a, &b).0
            })
            .fold(f64::INFINITY, f64::min);
        if w.contains(p, 0.0) {
            d
        } else {
            -d
        }
    };
    cracks
        .iter()
        .flat_map(|c| [c.first(), c.last()])
        .flatten()
        .copied()
        .max_by(|a, b| depth(*a).total_cmp(&depth(*b)))
        .unwrap_or(w.spec.center)
}

/// Check that the refinement zone of `problem` (window `w`) keeps two coarse horizons
/// from every window side but the open ones ([`open_sides`]), so the interface layers,
/// the layers of outer conditions and the nodes their bonds and dilatations reach stay
/// on the uniform coarse grid and the interface maps are those of the uniform window.
/// The message names the setting and the room there is.
pub fn check_refine_zone(w: &Window, problem: &PdProblem) -> Result<(), String> {
    let Some(z) = problem.refine_zones.first() else {
        return Ok(());
    };
    let reach = zone_reach(w, z.half_size);
    let need = reach + 2.0 * w.delta();
    let c = V2::new(z.centre[0], z.centre[1]);
    let open = open_sides(w, &problem.boundary);
    let room = (0..4)
        .filter(|&k| !open[k])
        .map(|k| {
            let (a, b) = w.side(k);
            pdbem_geometry::point_segment_projection(&c, &a, &b).0
        })
        .fold(f64::INFINITY, f64::min);
    if room + 1e-9 * w.spec.dx < need {
        return Err(format!(
            "the zone at ({:.4}, {:.4}) reaches {reach:.4} m from its centre, which is {room:.4} m from the nearest window side with an interface or a condition; it must stay two horizons (2 delta = {:.4} m) inside: half_size at most {:.4} m for this window",
            c.x,
            c.y,
            2.0 * w.delta(),
            (room - 2.0 * w.delta() - 0.5 * w.spec.dx).max(0.0)
        ));
    }
    Ok(())
}

/// Number of interface displacement conditions [`build_problem`] puts first in
/// `boundary`: one for a window with interface sides only, else one per interface side.
pub fn interface_condition_count(w: &Window) -> usize {
    if w.sides.iter().all(|k| *k == SideKind::Interface) {
        1
    } else {
        w.sides
            .iter()
            .filter(|k| **k == SideKind::Interface)
            .count()
    }
}

/// The problem of window `w` for the traction ordering ([`crate::traction_window`]):
/// `problem` (from [`build_problem`]) without the fictitious layers of the interface
/// sides, so those sides are free surfaces loaded through seed 001's transfer
/// functions, and with `pins` (real nodes pinned against the rigid motions, global
/// components). The material constants stay those of the window (bulk-corrected
/// modulus): the Madenci-Oterkus surface correction on the now free interface sides
/// was measured worse on the uniform-tension patch of
/// `tests/verification_coupling_ordering.rs` (interface tractions off by up to 28 % of
/// sigma at the corners and the window 7 % too stiff, against 8 % and 1 % without).
pub fn traction_problem(
    w: &Window,
    problem: &PdProblem,
    pins: &[([f64; 2], [Option<f64>; 2])],
) -> PdProblem {
    let mut p = problem.clone();
    p.boundary
        .drain(..interface_condition_count(w).min(p.boundary.len()));
    for (at, c) in pins {
        p.boundary.push(BoundaryCondition::Displacement {
            on: Selection::Circle {
                centre: *at,
                radius: 0.25 * w.spec.dx,
            },
            ux: c[0],
            uy: c[1],
            layer: Layer::Real,
        });
    }
    p.traction = pdbem_pd::TractionLoad::TransferFunction;
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refine_zone_follows_the_tip_and_keeps_two_horizons_inside() {
        let w = crate::growth::fixtures::window(10.0, 5.0);
        let r = WindowRefine {
            half_size: 0.1,
            levels: 2,
        };
        // dx = 0.05, delta = 0.15075: the zone's cells reach 0.125 from its centre, which
        // must stay 0.4265 from every side of [9.5, 10.5]^2.
        // Snapped to the cell corner (10.05, 5.05) nearest the tip.
        let c = zone_centre(&w, V2::new(10.06, 5.04), r, [false; 4]);
        assert!((c - V2::new(10.05, 5.05)).norm() < 1e-12);
        // Held 0.4265 inside, on the lattice: the corner 0.45 from the side.
        let c = zone_centre(&w, V2::new(9.6, 5.0), r, [false; 4]);
        assert!((c.x - (9.5 + 0.45)).abs() < 1e-9 && (c.y - 5.0).abs() < 1e-12);
        let zones = refine_zones([c.x, c.y], r);
        assert_eq!(zones.len(), 2);
        assert_eq!((zones[0].levels, zones[1].levels), (1, 2));
        assert!((zones[1].half_size - 0.05).abs() < 1e-15);
        let mut p = PdProblem {
            refine_zones: zones,
            ..Default::default()
        };
        assert!(check_refine_zone(&w, &p).is_ok());
        p.refine_zones[0].centre = [9.6, 5.0];
        let e = check_refine_zone(&w, &p).unwrap_err();
        assert!(e.contains("half_size at most"), "{e}");
    }

    /// A clamp under the bottom side of the 1 m window [9.5, 10.5] x [0, 1] (dx 0.05 m,
    /// delta 0.151 m) from its corner to x = 10 m, where the scene's clamp ends: the
    /// fictitious layer lies beneath the clamp, a horizon past the corner where it goes on,
    /// and stops at x = 10 m.
    #[test]
    fn an_outer_layer_ends_where_the_clamp_ends() {
        let w = crate::growth::fixtures::window(10.0, 0.5);
        assert_eq!(w.sides[0], SideKind::Outer);
        let clamp = EdgeCondition {
            from: V2::new(9.5, 0.0),
            to: V2::new(10.0, 0.0),
            traction: [None; 2],
            displacement: [Some(0.0), Some(0.0)],
            continues: [true, false],
        };
        let settings = PdSettings {
            youngs_modulus: 1e9,
            thickness: 1.0,
            plane: Plane::Stress,
            material: PdMaterial::Pmb,
            failure: Failure::None,
            surface_correction: false,
            bulk_correction: false,
            crack_face_correction: false,
            refine: None,
        };
        let p = build_problem(&w, &settings, &[], std::slice::from_ref(&clamp));
        let m = PdModel::new(&p).unwrap();
        let pos = &m.grid().pos[m.n_real()..];
        let below: Vec<[f64; 2]> = pos.iter().copied().filter(|q| q[1] < 0.0).collect();
        // Columns x = 9.375-9.975 (0.125 m past the corner is within the horizon, 0.175
        // m is not), three rows, less (9.375, -0.125), 0.177 m from the window's corner
        // (the grid makes fictitious nodes within a horizon of the region only).
        assert_eq!(below.len(), 13 * 3 - 1, "{below:?}");
        let xs = below.iter().map(|q| q[0]);
        let (lo, hi) = (
            xs.clone().fold(f64::INFINITY, f64::min),
            xs.fold(0.0, f64::max),
        );
        assert!(
            (lo - 9.375).abs() < 1e-9 && (hi - 9.975).abs() < 1e-9,
            "{lo} {hi}"
        );
        // Within a horizon of the piece, as before, the layer held the free surface
        // beyond x = 10 m too: (10.075, -0.025) m.
        let near = Selection::NearPolyline {
            points: vec![p2(clamp.from), p2(clamp.to)],
            distance: None,
        };
        assert!(near.contains([10.075, -0.025], w.delta()));
        assert!(!outer_strip(&w, &clamp).contains([10.075, -0.025], w.delta()));
        // The outer side is held, not open.
        assert_eq!(open_sides(&w, &p.boundary), [false; 4]);
    }

    #[test]
    fn bulk_factor_measures_the_discrete_horizon_sum() {
        let g = bulk_stiffness_factor(0.1, 3.015, Plane::Stress);
        // Measured 1.1616: the discrete horizon sum with the partial volumes of pd::bonds
        // (m = 3.015) is 14 % softer than the continuum value.
        assert!((g - 1.1616).abs() < 1e-3, "g = {g}");
    }
}
