//! The ligaments a stand-alone PD grid must resolve: the material between each pre-crack's
//! tip and the nearest other boundary (the outline, a hole, another pre-crack).
//!
//! A grid of spacing $h$ cuts every bond that crosses a pre-crack. Where the material
//! left between a tip and another boundary is narrower than two spacings, fewer than two
//! node columns fit across it: the bonds the grid keeps there form a hinge, or none are
//! left. Measured on a 50 x 100 mm state-based plate with an edge crack (the top's
//! opening per load at 1 kPa): at $h$ = 2 mm a 1.5 mm ligament opens 5.6 times as much
//! as at $h$ = 1 mm and 6.6 times as much as at 0.5 mm, and fails to converge from 1 MPa;
//! 1.0 and 1.2 mm ones fail to converge at any load ("implicit did not converge", no
//! reason given) and a 2.0 mm one opens 2.8 times as much as at 0.5 mm; at $h$ = 1 mm a
//! 1.2 mm ligament opens 2.6 times as much as at 0.5 mm. Such a scene is refused with the ligament named
//! ([`refuse_unresolved`], fewer than [`MIN_SPACINGS`]). From two spacings up the grid has
//! its columns (a 2 mm ligament at $h$ = 1 mm opens 1.33 times as much as at 0.5 mm), but
//! the horizon $\delta = m h$ spans it: a ligament under the horizon is noted ([`notes`]).
//!
//! A node that lies on a pre-crack loses every bond (the grid's rows through a crack):
//! [`refuse_loaded_loose_nodes`] refuses a model where the loads reach such nodes.
//!
//! The width is the distance from the tip to the nearest point of the other boundaries,
//! leaving out what the crack starts from: the outline edge its mouth lies on (with the
//! edges that continue it within [`MOUTH_TURN_DEG`], a curved outline's pieces) and a hole
//! its first point lies on. The spacing is the grid's at the tip: `dx` halved for each
//! level of a `pd.refine_zones` zone over the tip (not for the cells `pd.refinement`
//! splits as it sets up: the rule is the coarse grid's there, on the safe side).

use anyhow::{bail, Result};

use crate::geometry::{point_segment_distance, polyline_distance_hypot, P2};
use crate::scene::shapes::{CrackLine, SceneGeometry};
use crate::scene::Scene;

/// Grid spacings a ligament must span ([`refuse_unresolved`]): two node columns.
pub const MIN_SPACINGS: f64 = 2.0;

/// Turn (degrees) up to which outline edges next to the mouth's edge count as the same
/// side of the body (the pieces of a curved outline), left out of the ligament.
pub const MOUTH_TURN_DEG: f64 = 30.0;

/// The material ahead of a tip: its width and what bounds it.
#[derive(Clone, Debug, PartialEq)]
pub struct Ligament {
    /// Index of the crack in `cracks`.
    pub crack: usize,
    /// Tip name (`<crack>.end`, `<crack>.start`).
    pub tip: String,
    /// Tip position (m).
    pub at: P2,
    /// Width (m): distance from the tip to `other`.
    pub width: f64,
    /// The nearest other boundary, as a scene reader names it.
    pub other: String,
}

/// The narrowest ligament of each tip of the pre-cracks `cut` (names; all cracks when
/// `None`), one per tip; tips with no other boundary (an infinite plate with one crack)
/// have none.
pub fn ligaments(scene: &Scene, geo: &SceneGeometry, cut: Option<&[String]>) -> Vec<Ligament> {
    let tol = 1e-9 * body_size(geo);
    let cracks: Vec<(usize, &CrackLine)> = geo
        .cracks
        .iter()
        .enumerate()
        .filter(|(_, c)| cut.is_none_or(|w| w.contains(&c.name)))
        .collect();
    let mut out = Vec::new();
    for &(i, crack) in &cracks {
        let skipped_edges = mouth_edges(geo, crack, tol);
        let skipped_hole = geo
            .holes
            .iter()
            .position(|(_, h)| h.boundary_distance(&crack.points[0]) <= tol);
        for (tip, at) in crack.tips() {
            if skipped_hole.is_some() && tip.ends_with(".start") {
                continue;
            }
            let mut best: Option<(f64, String)> = None;
            let mut offer = |d: f64, what: String| {
                if best.as_ref().is_none_or(|(b, _)| d < *b) {
                    best = Some((d, what));
                }
            };
            if let Some(o) = &geo.outline {
                let n = o.points.len();
                for e in (0..n).filter(|e| !skipped_edges.contains(e)) {
                    let d = point_segment_distance(&at, &o.points[e], &o.points[(e + 1) % n]);
                    offer(d, format!("the outline (edge '{}')", o.groups[e]));
                }
            }
            for (k, (name, h)) in geo.holes.iter().enumerate() {
                if Some(k) != skipped_hole {
                    offer(
                        h.boundary_distance(&at),
                        format!("body.holes.{k} ('{name}')"),
                    );
                }
            }
            for &(j, other) in cracks.iter().filter(|(j, _)| *j != i) {
                let d = polyline_distance_hypot(&at, &other.points);
                let index = scene_index(scene, &other.name).unwrap_or(j);
                offer(d, format!("cracks.{index} ('{}')", other.name));
            }
            if let Some((width, other)) = best {
                out.push(Ligament {
                    crack: scene_index(scene, &crack.name).unwrap_or(i),
                    tip,
                    at,
                    width,
                    other,
                });
            }
        }
    }
    out
}

/// Error on the first ligament narrower than [`MIN_SPACINGS`] grid spacings at its tip:
/// `dx` the grid's coarse spacing, `spacing_field` the scene field that sets it and
/// `zones` whether `pd.refine_zones` may refine the grid (for the advice); `geo` the
/// scene's geometry.
pub fn refuse_unresolved(
    scene: &Scene,
    geo: &SceneGeometry,
    dx: f64,
    spacing_field: &str,
    zones: bool,
) -> Result<()> {
    let cut = scene.pd.as_ref().and_then(|p| p.pre_cracks.as_deref());
    for l in ligaments(scene, geo, cut) {
        let h = spacing_at(scene, dx, l.at);
        if l.width < MIN_SPACINGS * h {
            bail!(
                "{}: cracks.{}: the ligament between tip {} at ({:.6}, {:.6}) m and {} is {:.4e} m wide, {:.2} PD grid spacings ({:.4e} m there): fewer than two node columns fit across it, the bonds the grid keeps there form a hinge or none are left, so the body is far too compliant there or its solves cannot converge; use {spacing_field} of at most {:.4e} m{}, or a crack that stops short of it",
                scene.file_label().display(),
                l.crack,
                l.tip,
                l.at.x,
                l.at.y,
                l.other,
                l.width,
                l.width / h,
                h,
                l.width / MIN_SPACINGS,
                if zones {
                    ", a pd.refine_zones zone over the tip"
                } else {
                    ""
                }
            );
        }
    }
    Ok(())
}

/// Notes on the ligaments the grid resolves but narrower than the horizon at their tip.
pub fn notes(scene: &Scene, dx: f64) -> Vec<String> {
    let geo = SceneGeometry::of(scene);
    let Some(pd) = &scene.pd else {
        return Vec::new();
    };
    let m = pd.horizon_factor;
    ligaments(scene, &geo, pd.pre_cracks.as_deref())
        .into_iter()
        .filter_map(|l| {
            let h = spacing_at(scene, dx, l.at);
            (l.width >= MIN_SPACINGS * h && l.width < m * h).then(|| {
                format!(
                    "cracks.{}: the ligament between tip {} and {} is {:.4e} m wide, {:.2} grid spacings, under the horizon {:.4e} m: the horizon spans the ligament, so its stiffness and strength depend on the grid (a finer grid resolves it)",
                    l.crack,
                    l.tip,
                    l.other,
                    l.width,
                    l.width / h,
                    m * h
                )
            })
        })
        .collect()
}

/// Refuses a quasi-static model whose pre-cracks cut real nodes off the body while the
/// loads reach them: a node on a crack line loses every bond (`pdbem_pd::bonds::cut_cracks`
/// cuts the bonds along the crack too, so that it is not left hanging on them), and a
/// loaded piece nothing holds has no equilibrium. Seed 001's two parallel cracks at
/// nx = 10 (their lines through node rows) with transfer-function tractions, which reach
/// a horizon into the body: 4 such nodes carrying 1.6 kN, and the solves stalled with
/// "implicit did not converge" and no reason. Unloaded loose nodes are left (the shipped
/// 45-degree cracks of seed 001 run through 28 to 50 nodes of their 40 000).
pub fn refuse_loaded_loose_nodes(scene: &Scene, model: &pdbem_pd::PdModel) -> Result<()> {
    let pieces = model.pieces_at(1.0);
    let Some(main) = (0..pieces.len()).max_by_key(|&k| pieces[k].nodes.len()) else {
        return Ok(());
    };
    let n_real = model.n_real();
    let total: f64 = pieces.iter().map(|p| p.load).sum();
    let loaded: Vec<&pdbem_pd::pieces::Piece> = pieces
        .iter()
        .enumerate()
        .filter(|(k, p)| *k != main && p.nodes.iter().any(|&i| i < n_real))
        .map(|(_, p)| p)
        .filter(|p| p.unbalanced() > 1e-9 * total)
        .collect();
    let Some(first) = loaded.first() else {
        return Ok(());
    };
    let nodes: usize = loaded.iter().map(|p| p.nodes.len()).sum();
    let unbalanced: f64 = loaded.iter().map(|p| p.unbalanced()).sum();
    let x = model.positions()[first.nodes[0]];
    let geo = SceneGeometry::of(scene);
    let on = geo
        .cracks
        .iter()
        .map(|c| {
            (
                polyline_distance_hypot(&P2::new(x[0], x[1]), &c.points),
                &c.name,
            )
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .filter(|(d, _)| *d <= 1e-6 * model.grid().dx)
        .map(|(_, name)| format!(", on crack '{name}'"))
        .unwrap_or_default();
    bail!(
        "{}: pd: {nodes} loaded node(s) in {} piece(s) have no intact bond to the body (the first at ({:.6}, {:.6}) m{on}; a pre-crack through a row of nodes cuts every bond of the nodes on it), and nothing holds the {unbalanced:.3e} N the loads put on them at load factor 1, so the solves have no equilibrium; change pd.dx (or pd.nx) so that the cracks run between node rows",
        scene.file_label().display(),
        loaded.len(),
        x[0],
        x[1]
    )
}

/// The grid spacing at `p`: `dx` halved for each level of the deepest `pd.refine_zones`
/// zone whose coarse cells reach `p`.
pub fn spacing_at(scene: &Scene, dx: f64, p: P2) -> f64 {
    let levels = scene
        .pd
        .iter()
        .flat_map(|pd| &pd.refine_zones)
        .filter(|z| {
            let reach = z.half_size + 0.5 * dx;
            (p.x - z.centre.0).abs() <= reach && (p.y - z.centre.1).abs() <= reach
        })
        .map(|z| z.levels)
        .max()
        .unwrap_or(0);
    dx / 2f64.powi(levels as i32)
}

/// The outline edges a crack's mouth lies on, with the edges continuing them within
/// [`MOUTH_TURN_DEG`] (total turn from the mouth's edge) on either side.
fn mouth_edges(geo: &SceneGeometry, crack: &CrackLine, tol: f64) -> Vec<usize> {
    let (Some(o), true) = (&geo.outline, crack.mouth) else {
        return Vec::new();
    };
    let n = o.points.len();
    let mouth = crack.points[0];
    let edge = |e: usize| (o.points[e % n], o.points[(e + 1) % n]);
    let touched: Vec<usize> = (0..n)
        .filter(|&e| {
            let (a, b) = edge(e);
            point_segment_distance(&mouth, &a, &b) <= tol
        })
        .collect();
    let heading = |e: usize| {
        let (a, b) = edge(e);
        (b.y - a.y).atan2(b.x - a.x)
    };
    let turn = |from: usize, to: usize| {
        let mut t = heading(to) - heading(from);
        while t > std::f64::consts::PI {
            t -= 2.0 * std::f64::consts::PI;
        }
        while t < -std::f64::consts::PI {
            t += 2.0 * std::f64::consts::PI;
        }
        t
    };
    let limit = MOUTH_TURN_DEG.to_radians();
    let mut out = touched.clone();
    for &e0 in &touched {
        for step in [1, n - 1] {
            let (mut prev, mut total) = (e0, 0.0);
            for k in 1..n {
                let e = (e0 + k * step) % n;
                // Walking backwards turns every step the other way: |total| is the same.
                total += turn(prev, e);
                if total.abs() >= limit || out.contains(&e) {
                    break;
                }
                out.push(e);
                prev = e;
            }
        }
    }
    out
}

fn scene_index(scene: &Scene, name: &str) -> Option<usize> {
    scene.cracks.iter().position(|c| c.name == name)
}

fn body_size(geo: &SceneGeometry) -> f64 {
    let mut pts: Vec<P2> = geo
        .outline
        .as_ref()
        .map(|o| o.points.clone())
        .unwrap_or_default();
    for c in &geo.cracks {
        pts.extend(c.points.iter().copied());
    }
    if pts.is_empty() {
        return 1.0;
    }
    let (lo, hi) = crate::geometry::bounding_box(&pts);
    (hi - lo).norm().max(1e-300)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A disk of radius 50 mm as a 64-gon with an edge crack of 3 mm, radial, from the
    /// middle of an edge: the edges that continue the mouth's (within 30 degrees) are left
    /// out, so the ligament is the 25 mm to the outline 30 degrees round, not the 3.9 mm to
    /// the piece next to the mouth's, and the 2 mm grid resolves it.
    #[test]
    fn a_curved_outline_next_to_the_mouth_is_not_a_ligament() {
        let n = 64;
        let r = 0.05;
        let pts: Vec<String> = (0..n)
            .map(|k| {
                let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                format!("({}, {})", r * t.cos(), r * t.sin())
            })
            .collect();
        // The middle of edge 0 (points 0 and 1), and the crack along the inward normal.
        let half = std::f64::consts::PI / n as f64;
        let (m, dir) = (r * half.cos(), 180.0 + half.to_degrees());
        let text = format!(
            r#"(name: "disk", material: (E: 1e9, nu: 0.3, plane: Stress),
            body: (outline: Polygon(points: [{}])),
            cracks: [(name: "c", start: ({}, {}), angle_deg: {dir}, length: 0.003)],
            boundary: [(on: "outline", normal: 1e6)],
            pd: (dx: 0.002))"#,
            pts.join(", "),
            m * half.cos(),
            m * half.sin()
        );
        let scene = Scene::from_ron_str(&text, "disk.ron").expect("valid");
        let geo = SceneGeometry::of(&scene);
        let l = ligaments(&scene, &geo, None);
        assert_eq!(l.len(), 1);
        // The tip at radius 47 mm to the polygon's edges 30 degrees or more round.
        let want = {
            let (a, b) = (0.047f64, r * (std::f64::consts::PI / n as f64).cos());
            (a * a + b * b - 2.0 * a * b * (30f64.to_radians()).cos()).sqrt()
        };
        assert!(
            l[0].width > 0.9 * want && l[0].width < 1.2 * want,
            "{l:?} vs {want}"
        );
        assert!(l[0].other.starts_with("the outline"), "{l:?}");
        refuse_unresolved(&scene, &geo, 0.002, "pd.dx", true).expect("resolved");
        // With every edge counted, the 3.9 mm to the mouth's next edge would be the
        // ligament and the 2 mm grid refused.
        let tip = l[0].at;
        let o = geo.outline.as_ref().unwrap();
        let next = point_segment_distance(&tip, &o.points[1], &o.points[2]);
        assert!(next < MIN_SPACINGS * 0.002, "{next}");
    }

    /// `dx` is halved per level of the deepest zone whose coarse cells reach the point.
    #[test]
    fn the_spacing_at_a_point_follows_the_refine_zones() {
        let text = r#"(name: "z", material: (E: 1e9, nu: 0.3, plane: Stress),
            body: (outline: Rectangle(x0: 0, y0: 0, width: 0.1, height: 0.1)),
            boundary: [(on: "top", y: Traction(1e6)), (on: "bottom", y: Traction(-1e6))],
            pd: (dx: 0.002, refine_zones: [(centre: (0.05, 0.05), half_size: 0.01),
                 (centre: (0.05, 0.05), half_size: 0.004, levels: 2)]))"#;
        let scene = Scene::from_ron_str(text, "z.ron").expect("valid");
        let at = |x: f64| spacing_at(&scene, 0.002, P2::new(x, 0.05));
        assert_eq!(at(0.05), 0.0005);
        assert_eq!(at(0.056), 0.001);
        assert_eq!(at(0.08), 0.002);
    }
}
