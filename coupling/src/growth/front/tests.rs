//! Tests of the crack front: separation, stops at cracks and holes, paths, rays.
use super::*;

/// A 10 m x 10 m plate with `cracks` (name, start, direction angle in degrees,
/// length) and `holes`.
pub(super) fn plate(cracks: &[(&str, (f64, f64), f64, f64)], holes: Vec<HoleShape>) -> Front {
    let outline = vec![
        P2::new(0.0, 0.0),
        P2::new(10.0, 0.0),
        P2::new(10.0, 10.0),
        P2::new(0.0, 10.0),
    ];
    let on_outline = |p: P2| p.x == 0.0 || p.x == 10.0 || p.y == 0.0 || p.y == 10.0;
    let cracks = cracks
        .iter()
        .map(|&(name, start, angle, length)| {
            let a = P2::new(start.0, start.1);
            let b = a + length * pdbem_geometry::direction(angle);
            FrontCrack {
                name: name.into(),
                points: vec![a, b],
                mouth: on_outline(a),
            }
        })
        .collect();
    let holes = holes
        .into_iter()
        .enumerate()
        .map(|(i, h)| (format!("hole{i}"), h))
        .collect();
    Front::new(Some(outline), holes, cracks)
}

#[test]
fn edge_crack_reaching_the_far_side_separates_the_body() {
    let mut f = plate(&[("c", (0.0, 5.0), 0.0, 2.0)], vec![]);
    assert_eq!(f.tips.len(), 1);
    assert_eq!(f.tips[0].name, "c.end");
    let mut hits = Vec::new();
    for _ in 0..20 {
        if f.active().is_empty() {
            break;
        }
        hits.push(f.step_ahead(0, P2::new(1.0, 0.0), 1.0, 0.25));
    }
    // 2 -> 3 ... 9, then 9 -> 10 within 1.25: clipped onto x = 10.
    assert_eq!(hits.last(), Some(&Obstacle::Outline));
    assert!((f.tip_position(0).x - 10.0).abs() < 1e-12);
    assert!(f.separated());
    assert!((f.extension(0) - 8.0).abs() < 1e-12);
}

#[test]
fn interior_crack_needs_both_tips_on_the_outline() {
    let mut f = plate(&[("c", (4.0, 5.0), 0.0, 2.0)], vec![]);
    assert_eq!(f.tips[0].name, "c.start");
    let d0 = f.tip_direction(0);
    assert!((d0.x + 1.0).abs() < 1e-12);
    while f.tips[1].ended.is_none() {
        f.step_ahead(1, P2::new(1.0, 0.0), 1.5, 0.1);
    }
    assert!(!f.separated());
    while f.tips[0].ended.is_none() {
        f.step_ahead(0, d0, 1.5, 0.1);
    }
    assert!(f.separated());
    assert!((f.tip_position(0).x).abs() < 1e-12);
}

#[test]
fn a_crack_stops_a_tip_before_it_and_a_hole_takes_it_in() {
    let mut f = plate(
        &[("a", (0.0, 5.0), 0.0, 2.0), ("b", (10.0, 5.0), 180.0, 2.0)],
        vec![],
    );
    let hit = loop {
        let h = f.step_ahead(0, P2::new(1.0, 0.0), 1.0, 0.5);
        if h != Obstacle::None {
            break h;
        }
    };
    assert_eq!(hit, Obstacle::Crack("b".into()));
    assert_eq!(f.tips[0].ended.as_deref(), Some("coalescence:b"));
    // Both edge cracks joined: mouths on both sides.
    assert!(f.separated());
    let circle = HoleShape::Circle {
        center: P2::new(6.0, 5.0),
        radius: 1.0,
    };
    let mut f = plate(&[("a", (0.0, 5.0), 0.0, 2.0)], vec![circle]);
    let hit = loop {
        let h = f.step_ahead(0, P2::new(1.0, 0.0), 1.0, 0.5);
        if h != Obstacle::None {
            break h;
        }
    };
    assert_eq!(hit, Obstacle::Hole("hole0".into()));
    // Clipped onto the hole (its left point at x = 5): the crack joins it, and a crack
    // from the outline into a hole does not cut the body.
    assert!((f.tip_position(0) - P2::new(5.0, 5.0)).norm() < 1e-12);
    assert!(!f.separated());
}

#[test]
fn set_path_replaces_the_grown_part_at_either_end() {
    let mut f = plate(&[("c", (4.0, 5.0), 0.0, 2.0)], vec![]);
    f.set_path(
        1,
        &[P2::new(6.0, 5.0), P2::new(7.0, 5.0), P2::new(8.0, 5.5)],
    );
    f.set_path(1, &[P2::new(6.0, 5.0), P2::new(7.0, 5.2)]);
    f.set_path(0, &[P2::new(4.0, 5.0), P2::new(3.0, 5.0)]);
    let pts = &f.cracks[0].points;
    assert_eq!(pts.len(), 4);
    assert_eq!(f.tip_position(1), P2::new(7.0, 5.2));
    assert_eq!(f.tip_position(0), P2::new(3.0, 5.0));
    assert!((f.extension(0) - 1.0).abs() < 1e-12);
}

#[test]
fn ray_hits() {
    let o = P2::new(0.0, 0.0);
    let d = P2::new(1.0, 0.0);
    let s = ray_segment(&o, &d, &P2::new(2.0, -1.0), &P2::new(2.0, 1.0));
    assert_eq!(s, Some(2.0));
    assert_eq!(
        ray_segment(&o, &-d, &P2::new(2.0, -1.0), &P2::new(2.0, 1.0)),
        None
    );
    let c = HoleShape::Circle {
        center: P2::new(5.0, 0.0),
        radius: 1.0,
    };
    assert!((ray_hole(&o, &d, &c).unwrap() - 4.0).abs() < 1e-12);
}

#[test]
fn room_ahead_is_the_distance_to_the_first_obstacle_on_the_ray() {
    // Edge crack from (0, 5) to (2, 5); a circular hole of radius 1 at (6, 5); a crack
    // across the ray at x = 8 beyond it.
    let hole = HoleShape::Circle {
        center: P2::new(6.0, 5.0),
        radius: 1.0,
    };
    let f = plate(
        &[("c", (0.0, 5.0), 0.0, 2.0), ("d", (8.0, 2.0), 90.0, 6.0)],
        vec![hole],
    );
    let t = f.tips.iter().position(|t| t.name == "c.end").unwrap();
    let ahead = f.room_ahead(t, P2::new(1.0, 0.0)).unwrap();
    assert!((ahead - 3.0).abs() < 1e-12, "{ahead}");
    // Upwards: the top edge, 5 m away; downwards the bottom edge.
    assert!((f.room_ahead(t, P2::new(0.0, 1.0)).unwrap() - 5.0).abs() < 1e-12);
    assert!((f.room_ahead(t, P2::new(0.0, -1.0)).unwrap() - 5.0).abs() < 1e-12);
}
