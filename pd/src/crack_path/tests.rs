//! Tests of the tip tracker ([`super`]).

use super::*;
use crate::problem::{PdProblem, Region};

/// Unit grid `nx x ny` (dx = 1, nodes at cell centres) with damage 0.5
/// on the nodes for which `band` holds.
fn field(nx: usize, ny: usize, band: impl Fn(f64, f64) -> bool) -> (Vec<P2>, Vec<f64>) {
    let mut pos = Vec::new();
    let mut phi = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let p = [i as f64 + 0.5, j as f64 + 0.5];
            phi.push(if band(p[0], p[1]) { 0.5 } else { 0.1 });
            pos.push(p);
        }
    }
    (pos, phi)
}

/// Coarse cells (spacing 1) over [0, 10] x [0, 20] and fine cells (0.5) over [10, 20] x
/// [5, 15] (a refined zone): positions, the damage `phi(x, y, spacing)` and the spacings.
fn mixed_field(phi: impl Fn(f64, f64, f64) -> f64) -> (Vec<P2>, Vec<f64>, Vec<f64>) {
    let (mut pos, mut damage, mut h) = (Vec::new(), Vec::new(), Vec::new());
    for (x0, x1, y0, y1, dh) in [(0.0, 10.0, 0.0, 20.0, 1.0), (10.0, 20.0, 5.0, 15.0, 0.5)] {
        let (nx, ny) = (((x1 - x0) / dh) as usize, ((y1 - y0) / dh) as usize);
        for j in 0..ny {
            for i in 0..nx {
                let p = [x0 + (i as f64 + 0.5) * dh, y0 + (j as f64 + 0.5) * dh];
                damage.push(phi(p[0], p[1], dh));
                pos.push(p);
                h.push(dh);
            }
        }
    }
    (pos, damage, h)
}

fn max_offset_from_line(points: &[P2], y: f64) -> f64 {
    points.iter().map(|p| (p[1] - y).abs()).fold(0.0, f64::max)
}

#[test]
fn straight_two_row_band_is_centred_and_reaches_the_tip() {
    // A crack along y = 10 from x = 0 to x = 12: the rows y = 9.5 and
    // 10.5 are damaged. Centred path: on y = 10 within 1e-12 except the
    // entry, tip at the farthest node x = 11.5.
    let (pos, phi) = field(30, 20, |x, y| x < 12.0 && (y - 10.0).abs() < 1.0);
    let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 10.0], &PathParams::default()).unwrap();
    // Measured: 0.034 dx next to the entry (the band starts there), 1e-9
    // from x = 4 on.
    assert!(
        max_offset_from_line(&p.points, 10.0) < 0.05,
        "{:?}",
        p.points
    );
    assert!((p.tip()[0] - 11.5).abs() < 1e-12, "tip {:?}", p.tip());
    assert_eq!(p.nodes.len(), 24);
    assert!((p.length - 11.5).abs() < 0.01, "length {}", p.length);
    let d = p.tip_direction(3.0).unwrap();
    assert!((d[0] - 1.0).abs() < 1e-12);
}

#[test]
fn mixed_spacing_links_coarse_into_fine_cells_and_stops_at_a_fine_gap() {
    // Coarse cells (spacing 1) for x < 10, fine cells (0.5) for 10 <= x < 20 (a
    // refined zone); a crack along y = 10: two coarse rows to x = 10, then two fine
    // rows to x = 14 and again from x = 15 to 18, with an intact ligament of two fine
    // cells between (nodes 1.5 apart: more than the fine link of 0.75, less than the
    // coarse link of 1.5).
    let band =
        |x: f64, y: f64, h: f64| (y - 10.0).abs() < h && (x < 14.0 || (15.0..18.0).contains(&x));
    let (pos, phi, h) = mixed_field(|x, y, dh| if band(x, y, dh) { 0.5 } else { 0.1 });
    let prm = PathParams::default();
    let p = trace_crack_spaced(&pos, &phi, &h, [0.0, 10.0], &prm).unwrap();
    // The coarse band links into the fine one (0.79 apart), the gap stops the
    // path at the last fine node before it.
    assert!((p.tip()[0] - 13.75).abs() < 1e-12, "tip {:?}", p.tip());
    assert_eq!(p.nodes.len(), 20 + 16);
    // Resampled at the fine spacing and centred on the band's centre line: measured
    // 0.099 of a coarse spacing next to the entry (0.034 at one point per coarse
    // spacing, the uniform test above), 0.065 of a fine spacing at the size jump and
    // below 1e-9 from 4.5 fine spacings past it (the smoothing radius of 2 spacings
    // reaches the coarse rows before that).
    let fine: Vec<P2> = p.points.iter().copied().filter(|q| q[0] > 10.0).collect();
    assert!(fine.len() >= 8, "{:?}", p.points);
    assert!(
        max_offset_from_line(&p.points, 10.0) < 0.11,
        "{:?}",
        p.points
    );
    assert!(
        max_offset_from_line(&fine, 10.0) < 0.1 * 0.5,
        "{:?}",
        p.points
    );
    let past = fine.iter().position(|q| q[0] > 12.25).unwrap();
    assert!(
        max_offset_from_line(&fine[past..], 10.0) < 1e-8,
        "{:?}",
        p.points
    );
    // Taken at the coarse spacing everywhere, the link bridges the ligament.
    let coarse = trace_crack_in(&pos, &phi, 1.0, [0.0, 10.0], &prm).unwrap();
    assert!(
        (coarse.tip()[0] - 17.75).abs() < 1e-12,
        "tip {:?}",
        coarse.tip()
    );
    // One spacing for every node: the uniform trace, bit for bit.
    let ones = vec![1.0; pos.len()];
    let same = trace_crack_spaced(&pos, &phi, &ones, [0.0, 10.0], &prm).unwrap();
    assert_eq!(same, coarse);
}

#[test]
fn a_lower_threshold_in_the_finest_cells_follows_the_crack_there_only() {
    // Coarse cells (spacing 1) for x < 10, fine cells (0.5) for 10 <= x < 20; a crack
    // along y = 10: two coarse rows of damage 0.5 to x = 10, two fine rows of 0.5 to
    // x = 13, then two fine rows of 0.34 to x = 16 (a fresh crack between node rows,
    // under the threshold 0.38), and a coarse column of 0.34 beside the size jump
    // (x = 9.5, y = 10 to 19: the damage that spreads along the jump where the crack
    // meets coarse cells that cannot break).
    let phi_at = |x: f64, y: f64, h: f64| {
        let on_line = (y - 10.0).abs() < h;
        if on_line && (x < 13.0) {
            0.5
        } else if (on_line && x < 16.0) || (h > 0.75 && x > 9.0 && (10.0..19.0).contains(&y)) {
            0.34
        } else {
            0.1
        }
    };
    let (pos, phi, h) = mixed_field(phi_at);
    let prm = PathParams::default();
    let entry = [0.0, 10.0];
    // At 0.38 the tip stops where the fine damage drops under it.
    let plain = trace_crack_spaced(&pos, &phi, &h, entry, &prm).unwrap();
    assert!((plain.tip()[0] - 12.75).abs() < 1e-12, "{:?}", plain.tip());
    // At 0.304 in the fine cells: to the end of the 0.34 rows, on the line.
    let fine = trace_crack_finest_in(&pos, &phi, &h, entry, &prm, 0.304).unwrap();
    assert!((fine.tip()[0] - 15.75).abs() < 1e-12, "{:?}", fine.tip());
    assert!((fine.tip()[1] - 10.0).abs() < 1e-9, "{:?}", fine.tip());
    assert!(fine.nodes.iter().all(|&i| h[i] < 0.75 || phi[i] > 0.38));
    // At 0.304 everywhere the coarse column beside the jump takes the tip (its far end is
    // farther along the crack).
    let low = PathParams {
        threshold: 0.304,
        ..prm
    };
    let all = trace_crack_spaced(&pos, &phi, &h, entry, &low).unwrap();
    assert!(all.tip()[1] > 18.0, "{:?}", all.tip());
    // One spacing for every node: the trace at the lower threshold.
    let ones = vec![1.0; pos.len()];
    assert_eq!(
        trace_crack_finest_in(&pos, &phi, &ones, entry, &prm, 0.304).unwrap(),
        trace_crack_spaced(&pos, &phi, &ones, entry, &low).unwrap()
    );
    // A lower threshold outside (0, 1) is refused with the field named.
    let e = trace_crack_finest_in(&pos, &phi, &h, entry, &prm, 1.2).unwrap_err();
    assert!(e.to_string().contains("path.threshold"), "{e}");
}

#[test]
fn kinked_band_is_followed_to_its_far_end() {
    // Horizontal to x = 10, then up at 45 degrees (one-node-wide band
    // along y = 10 + (x - 10), two rows wide on the flat part).
    let (pos, phi) = field(30, 30, |x, y| {
        (x < 10.0 && (y - 10.0).abs() < 1.0) || ((10.0..20.0).contains(&x) && (y - x).abs() < 1.0)
    });
    let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 10.0], &PathParams::default()).unwrap();
    let t = p.tip();
    assert!(t[0] > 19.0 && (t[1] - t[0]).abs() < 1.0, "tip {t:?}");
    let d = p.tip_direction(4.0).unwrap();
    let ang = d[1].atan2(d[0]).to_degrees();
    assert!((ang - 45.0).abs() < 5.0, "tip direction {ang} deg");
}

#[test]
fn crack_not_connected_to_the_entry_is_ignored() {
    // A damaged blob far from the entry; the entry has no crack near it.
    let (pos, phi) = field(20, 20, |x, y| {
        (x - 15.0).abs() < 2.0 && (y - 15.0).abs() < 2.0
    });
    let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 5.0], &PathParams::default()).unwrap();
    assert!(p.is_empty());
    assert_eq!(p.points, vec![[0.0, 5.0]]);
    assert_eq!(p.length, 0.0);
}

#[test]
fn gap_of_two_cells_stops_the_path() {
    // Band broken between x = 8 and x = 10: two cells, more than the
    // 1.5 dx link, so the tip stays at x = 7.5.
    let (pos, phi) = field(30, 20, |x, y| {
        (x < 8.0 || (10.0..20.0).contains(&x)) && (y - 10.0).abs() < 1.0
    });
    let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 10.0], &PathParams::default()).unwrap();
    assert!((p.tip()[0] - 7.5).abs() < 1e-12);
}

#[test]
fn branch_longest_along_the_crack_wins() {
    // Main band to x = 15; a short branch down at x = 5 (6 long). The
    // farthest point along the crack is the end of the main band.
    let (pos, phi) = field(30, 30, |x, y| {
        (x < 15.0 && (y - 20.0).abs() < 1.0) || ((x - 5.0).abs() < 1.0 && y > 13.0 && y < 20.0)
    });
    let p = trace_crack_in(&pos, &phi, 1.0, [0.0, 20.0], &PathParams::default()).unwrap();
    assert!((p.tip()[0] - 14.5).abs() < 1e-12, "tip {:?}", p.tip());
}

#[test]
fn a_crack_joining_behind_the_previous_tip_does_not_take_the_tip_over() {
    // Main band along y = 20 to x = 15 (entry at x = 0); a second crack
    // joins it at x = 3 and runs down to y = 0, 22 dx along the crack
    // from the entry against the main band's 14.5. Traced from scratch
    // its end is the farthest point; traced beyond the previous tip at
    // x = 10 the tip stays on the main band, at its end.
    let (pos, phi) = field(30, 30, |x, y| {
        (x < 15.0 && (y - 20.0).abs() < 1.0) || ((x - 3.0).abs() < 1.0 && y < 20.0)
    });
    let prm = PathParams::default();
    let free = trace_crack_in(&pos, &phi, 1.0, [0.0, 20.0], &prm).unwrap();
    assert!(free.tip()[1] < 1.0, "from scratch: tip {:?}", free.tip());
    let on = trace_crack_beyond(&pos, &phi, 1.0, [0.0, 20.0], [10.0, 20.0], &prm).unwrap();
    assert!((on.tip()[0] - 14.5).abs() < 1e-12, "tip {:?}", on.tip());
    assert!(
        max_offset_from_line(&on.points, 20.0) < 0.6,
        "{:?}",
        on.points
    );
    // A previous tip at the end of the band: the tip stays there, and
    // one at the entry gives the trace from scratch.
    let end = trace_crack_beyond(&pos, &phi, 1.0, [0.0, 20.0], [14.5, 20.0], &prm).unwrap();
    assert!((end.tip()[0] - 14.5).abs() < 1e-12, "tip {:?}", end.tip());
    let entry = trace_crack_beyond(&pos, &phi, 1.0, [0.0, 20.0], [0.0, 20.0], &prm).unwrap();
    assert_eq!(entry, free);
}

#[test]
fn a_fork_just_behind_the_previous_tip_still_continues_it() {
    // The band forks 1 dx behind the previous tip (x = 9, tip at x = 10):
    // both arms are beyond it within BEYOND_DX, and the longer one (down,
    // 12 dx against 5 along y = 20) is the tip.
    let (pos, phi) = field(30, 30, |x, y| {
        (x < 15.0 && (y - 20.0).abs() < 1.0) || ((x - 9.0).abs() < 1.0 && y < 20.0 && y > 7.0)
    });
    let prm = PathParams::default();
    let on = trace_crack_beyond(&pos, &phi, 1.0, [0.0, 20.0], [10.0, 20.0], &prm).unwrap();
    assert!(on.tip()[1] < 8.0, "tip {:?}", on.tip());
}

#[test]
fn clusters_are_the_connected_cracks() {
    // Two bands two cells apart (more than the 1.5 dx link) and a band
    // touching the first diagonally (linked): two clusters.
    let (pos, phi) = field(20, 20, |x, y| {
        (x < 8.0 && (y - 10.0).abs() < 1.0)
            || ((10.0..16.0).contains(&x) && (y - 10.0).abs() < 1.0)
            || ((x - 8.5).abs() < 0.6 && (y - 11.5).abs() < 0.6)
    });
    let c = crack_clusters(&pos, &phi, 1.0, &PathParams::default()).unwrap();
    assert_eq!(c.len(), 2, "{c:?}");
    assert_eq!((c[0].len(), c[1].len()), (17, 12));
    assert!(c[0].contains(&(11 * 20 + 8)));
}

#[test]
fn bad_input_is_reported_with_numbers() {
    let (pos, phi) = field(4, 4, |_, _| false);
    let e = trace_crack_in(&pos, &phi[..3], 1.0, [0.0, 0.0], &PathParams::default());
    assert!(matches!(
        e,
        Err(PdError::LengthMismatch {
            expected: 16,
            got: 3,
            ..
        })
    ));
    let bad = PathParams {
        threshold: 1.5,
        ..Default::default()
    };
    assert!(trace_crack_in(&pos, &phi, 1.0, [0.0, 0.0], &bad).is_err());
}

#[test]
fn model_pre_crack_is_traced_along_its_line() {
    // 20 x 10 cells, dx = 1, pre-crack along y = 5 from the left edge to
    // x = 8 (between node rows): the pre-cut damage is about 0.39 next
    // to the line, above the 0.38 threshold; the traced tip lies within
    // 1.5 dx of the pre-crack tip and the path on the line.
    let p = PdProblem {
        region: Region::rectangle([0.0, 0.0], [20.0, 10.0]),
        dx: 1.0,
        youngs_modulus: 1.0,
        cracks: vec![vec![[-1.0, 5.0], [8.0, 5.0]]],
        ..Default::default()
    };
    let m = PdModel::new(&p).unwrap();
    let path = trace_crack(&m, [0.0, 5.0], &PathParams::default()).unwrap();
    assert!(!path.is_empty());
    // Measured: tip node at x = 6.5 (the nodes at x = 7.5 beside the
    // pre-crack tip lose fewer than 0.38 of their bonds).
    assert!((path.tip()[0] - 8.0).abs() <= 1.5, "tip {:?}", path.tip());
    assert!(
        max_offset_from_line(&path.points, 5.0) < 0.05,
        "{:?}",
        path.points
    );
}

#[test]
fn mixed_model_is_traced_at_its_fine_spacing_in_the_zone() {
    // The plate above with the pre-crack to x = 12 and the cells within 3 of (12, 5)
    // split once (spacing 0.5): the trace runs from the coarse cells into the fine ones,
    // is resampled at the fine spacing there and stays on the line.
    let p = PdProblem {
        region: Region::rectangle([0.0, 0.0], [20.0, 10.0]),
        dx: 1.0,
        youngs_modulus: 1.0,
        cracks: vec![vec![[-1.0, 5.0], [12.0, 5.0]]],
        refine_zones: vec![crate::refine_zone::RefineZone {
            centre: [12.0, 5.0],
            half_size: 3.0,
            levels: 1,
        }],
        ..Default::default()
    };
    let m = PdModel::new(&p).unwrap();
    assert!(m.grid().is_mixed());
    let path = trace_crack(&m, [0.0, 5.0], &PathParams::default()).unwrap();
    // Measured: tip at x = 11.25 (the fine nodes at x = 11.75 beside the pre-crack's end
    // lose fewer than 0.38 of their bonds, as the coarse ones do in the test above).
    assert!(
        (path.tip()[0] - 12.0).abs() <= 1.5 * 0.5 + 1e-9,
        "tip {:?}",
        path.tip()
    );
    // Measured: 0.099 next to the entry, where the band starts (the path is resampled at
    // the finest spacing, so a point lies half a coarse cell from the entry), under 1e-3 from
    // x = 9.5 on (2e-4).
    assert!(
        max_offset_from_line(&path.points, 5.0) < 0.11,
        "{:?}",
        path.points
    );
    let zone: Vec<P2> = path.points.iter().copied().filter(|q| q[0] > 9.5).collect();
    assert!(max_offset_from_line(&zone, 5.0) < 1e-3, "{:?}", path.points);
    let steps: Vec<f64> = zone.windows(2).map(|w| (w[1][0] - w[0][0]).abs()).collect();
    assert!(steps.iter().all(|&d| (d - 0.5).abs() < 0.05), "{steps:?}");
}
