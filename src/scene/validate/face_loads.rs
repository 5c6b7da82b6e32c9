//! Conditions on crack faces where PD models the crack. PD pre-cracks are traction-free:
//! the PD bodies (stand-alone, full-PD growth, PD-BEM windows) carry no crack-face loads.
//! A face condition on a crack a window covers was dropped inside the window, and the
//! coupled K was that of another load: `coupled_sent_a5` with a face pressure of 0.2 Pa
//! besides its 0.5 Pa tension gave K_I 7.336 against the BEM's 7.827 (6.3 % low) and a
//! CMOD 1.4 % low, exit 0. So such a condition is refused, naming the crack and the way
//! out (the BEM alone, or BEM-only growth, carries face loads: a pressurised Griffith
//! crack's K within 0.03 %, `tests/verification_face_tractions.rs`).

use super::pd::square_corners;
use super::Checker;
use crate::geometry::{p2, point_in_polygon, polyline_polygon_hit, P2};
use crate::scene::shapes::SceneGeometry;
use crate::scene::{GrowthMode, Placement, Scene};

/// Where PD models crack faces: everywhere, at the tips, or inside one window.
enum PdCover {
    Everywhere(&'static str),
    Tips,
    Window(Vec<P2>),
}

/// Refuses conditions on the faces of cracks that PD models (module docs).
pub fn check(c: &mut Checker, scene: &Scene) {
    let Some(cover) = pd_cover(scene) else {
        return;
    };
    let geo = SceneGeometry::of(scene);
    for (k, bc) in scene.boundary.iter().enumerate() {
        let Some(ci) = scene
            .cracks
            .iter()
            .position(|cr| cr.name == bc.on || cr.face_names().contains(&bc.on))
        else {
            continue;
        };
        let Some(line) = geo.cracks.get(ci) else {
            continue;
        };
        let why = match &cover {
            PdCover::Everywhere(mode) => format!("{mode} models every crack in PD"),
            PdCover::Tips if !line.tips().is_empty() => {
                "a PD window covers its tips (coupling.placement: AtTips)".to_string()
            }
            PdCover::Window(corners) if covers(corners, &line.points) => {
                "the PD window (coupling.placement) covers part of it".to_string()
            }
            _ => continue,
        };
        c.fail(
            format!("boundary.{k}.on"),
            format!("{:?}", bc.on),
            format!(
                "a condition on the faces of crack '{}', and {why}: PD pre-cracks are \
                 traction-free, so the load would be dropped there and K would be that of \
                 another load (a face pressure on coupled_sent_a5: K_I 6.3 % low); solve the \
                 scene with the BEM alone (drop `pd` and `coupling`, or growth.mode: BemOnly), \
                 which carries crack-face loads",
                scene.cracks[ci].name
            ),
        );
    }
}

/// Where the scene's PD models crack faces; `None` when the BEM models them all.
fn pd_cover(scene: &Scene) -> Option<PdCover> {
    let growth = scene.growth.as_ref().map(|g| g.mode);
    if growth == Some(GrowthMode::BemOnly) || scene.pd.is_none() {
        return None;
    }
    let Some(co) = &scene.coupling else {
        return Some(PdCover::Everywhere("stand-alone PD"));
    };
    if growth == Some(GrowthMode::FullPd) {
        return Some(PdCover::Everywhere("full-PD growth"));
    }
    Some(match &co.placement {
        Placement::AtTips => PdCover::Tips,
        Placement::Centered { center, angle_deg } => {
            PdCover::Window(square_corners(p2(*center), co.side, *angle_deg))
        }
        Placement::Region {
            x0,
            y0,
            width,
            height,
        } => PdCover::Window(vec![
            P2::new(*x0, *y0),
            P2::new(x0 + width, *y0),
            P2::new(x0 + width, y0 + height),
            P2::new(*x0, y0 + height),
        ]),
    })
}

/// Whether the crack polyline enters the window polygon.
fn covers(corners: &[P2], line: &[P2]) -> bool {
    line.iter().any(|p| point_in_polygon(p, corners))
        || polyline_polygon_hit(line, corners).is_some()
}
