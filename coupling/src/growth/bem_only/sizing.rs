//! Local-feature sizing of the geometries BEM-only growth re-meshes: the rule of the
//! static BEM mesh (`pdbem::setup::sizing::LocalSizes`, issue 17) applied to the crack
//! front as it has grown, so that K stays right while a ligament shrinks.
//!
//! Every growing tip $t$ has a length scale
//! $$L_t = \min\big(\ell_t,\ \operatorname{dist}(t, \text{loops}),\ \operatorname{dist}(t, \text{other cracks})\big),$$
//! $\ell_t$ the crack's arc length (half of it for a crack with two tips), and is the
//! source of the size field ([`pdbem_bem::mesh::size_field`])
//! $$S_1:\quad h_t = \min(h_{base},\ f L_t),\quad \text{uniform within } z L_t,\quad
//!   \text{grading } g,$$
//! with $f = 1/80$, $z = 1$, $g = 0.05$ ([`TipSizing`], given by the setup layer from
//! the static rule). The outline and hole elements next to a tip are refined by the same
//! source, so a ligament of length $L$ keeps about $80$ elements however short it gets.
//!
//! A grown crack is straight only over its last increments: the crack-opening fit
//! ([`pdbem_bem::post::sif::cod_sif`]) must not reach across a kink. The fit radius is
//! $r_t = \min(\phi L_t, s_t)$, $\phi$ the scene's `bem.cod_fit_fraction` and $s_t$ the
//! straight run behind the tip ([`straight_run`]: the arc length over which the crack
//! stays within [`STRAIGHT_ANGLE`] of the tip's line). When $s_t$ limits it, a second
//! source $S_2$ of size $\min(h_t, r_t/8)$, uniform within $r_t$, keeps at least eight
//! crack-opening stations in the fit (the fit has four terms).
//!
//! Before meshing, the crack polylines are simplified (Douglas-Peucker,
//! [`simplify`]) to within [`SIMPLIFY_FRACTION`] of the increment: every segment of a
//! polyline is meshed with at least one element, and a crack grown by 300 straight
//! increments would otherwise keep 300 elements per face far from its tip.

use pdbem_bem::mesh::{LoopSpec, SizeSource, SourceShape};
use pdbem_geometry::{point_segment_distance, polyline_length, P2};

use crate::growth::front::Front;

/// A crack is straight behind its tip while every point lies within this angle (rad) of
/// the tip's line, seen from the tip. Faces beyond a kink of phi are turned by phi, so a
/// fit reaching across it reads about phi K_I of spurious K_II and the next kink is off
/// by about 2 phi: with 0.5 degree the mode-I crack of `growth_tension_edge` zig-zagged
/// (kinks of 0.3, 0.9, then -7 degrees, and K_I 10 % low every third increment). At
/// 1e-4 rad the error is far below the kinks MCS asks for.
pub const STRAIGHT_ANGLE: f64 = 1e-4;

/// Crack-opening stations wanted within a fit radius limited by a kink.
pub const STATIONS_PER_FIT: f64 = 8.0;

/// Tolerance of the polyline simplification as a fraction of the increment: 1e-3 da
/// moves the crack by 0.1 mm at da = 0.1 m, a fifth of the smallest tip element of a
/// ligament of 0.04 m.
pub const SIMPLIFY_FRACTION: f64 = 1e-3;

/// The local-feature rule of the tip sources (module docs); the setup layer gives the
/// static mesh's constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipSizing {
    /// Tip element size over the tip length scale (f = 1/80).
    pub fraction: f64,
    /// Radius of the uniform tip zone in tip length scales (z = 1).
    pub zone: f64,
    /// Grading outside the zone (g = 0.05).
    pub grading: f64,
    /// Largest element size (m): the base size of the body.
    pub base: f64,
}

/// Length scale and fit radius of one tip of the front.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipScale {
    /// Index into [`Front::tips`].
    pub tip: usize,
    /// Tip length scale L (m).
    pub scale: f64,
    /// Crack-opening fit radius (m).
    pub fit: f64,
    /// The straight run behind the tip limits the fit (`fit` is the run's length).
    pub run_limited: bool,
}

/// Length scales and fit radii of every tip of `front` that is a tip of the mesh (not
/// stopped on the outline, not joined to a hole or a loop; `fit_fraction`: the fit radius over L; `grown`: restrict the fit to the straight
/// run).
pub fn tip_scales(
    front: &Front,
    loops: &[LoopSpec],
    fit_fraction: f64,
    grown: bool,
) -> Vec<TipScale> {
    let (lo, hi) = front.bounds();
    let on_boundary = 1e-9 * (hi - lo).norm();
    (0..front.tips.len())
        .filter(|&t| front.tips[t].ended.as_deref() != Some("outline"))
        .map(|t| (t, tip_scale(front, t, loops)))
        .filter(|&(_, scale)| scale > on_boundary)
        .map(|(t, scale)| {
            let run = if grown {
                straight_run(front, t)
            } else {
                f64::INFINITY
            };
            let fit = fit_fraction * scale;
            TipScale {
                tip: t,
                scale,
                fit: fit.min(run),
                run_limited: run < fit,
            }
        })
        .collect()
}

/// The sources of the tips (module docs) at refinement `refine` (sizes and gradings
/// divided by it).
pub fn tip_sources(
    front: &Front,
    scales: &[TipScale],
    rule: &TipSizing,
    refine: f64,
) -> Vec<SizeSource> {
    let mut out = Vec::new();
    for s in scales {
        let at = front.tip_position(s.tip);
        let h = rule.base.min(rule.fraction * s.scale);
        out.push(SizeSource {
            shape: SourceShape::Point(at),
            size: h / refine,
            radius: rule.zone * s.scale,
            grading: rule.grading / refine,
        });
        if s.run_limited {
            // A whole number of elements on the run, which is one segment of the mesh
            // ([`simplify_crack`]): uniform up to the run's start.
            let n = STATIONS_PER_FIT.max((s.fit / h).ceil());
            out.push(SizeSource {
                shape: SourceShape::Point(at),
                size: s.fit / n / refine,
                radius: s.fit,
                grading: rule.grading / refine,
            });
        }
    }
    out
}

/// Tip length scale of tip `t` (module docs).
pub fn tip_scale(front: &Front, t: usize, loops: &[LoopSpec]) -> f64 {
    let tip = &front.tips[t];
    let c = &front.cracks[tip.crack];
    let len = polyline_length(&c.points);
    let mut l = if c.mouth { len } else { 0.5 * len };
    let p = front.tip_position(t);
    for lp in loops {
        let n = lp.points.len();
        for i in 0..n {
            l = l.min(point_segment_distance(
                &p,
                &lp.points[i],
                &lp.points[(i + 1) % n],
            ));
        }
    }
    for (j, other) in front.cracks.iter().enumerate() {
        if j == tip.crack {
            continue;
        }
        for w in other.points.windows(2) {
            l = l.min(point_segment_distance(&p, &w[0], &w[1]));
        }
    }
    l
}

/// Arc length behind tip `t` over which its crack is straight: every point within
/// [`STRAIGHT_ANGLE`] of the line of the last segment, seen from the tip.
pub fn straight_run(front: &Front, t: usize) -> f64 {
    straight_points(front, t).1
}

/// The number of polyline points behind tip `t` on its straight run (at least one) and
/// the run's length (m).
fn straight_points(front: &Front, t: usize) -> (usize, f64) {
    let tip = &front.tips[t];
    let pts = &front.cracks[tip.crack].points;
    let behind: Vec<P2> = if tip.at_end {
        pts.iter().rev().copied().collect()
    } else {
        pts.clone()
    };
    let p = behind[0];
    let d = front.tip_direction(t);
    let tol = STRAIGHT_ANGLE.tan();
    let (mut run, mut count) = ((behind[1] - p).norm(), 1);
    for q in &behind[2..] {
        let r = q - p;
        let along = -r.dot(&d);
        let off = (r.x * d.y - r.y * d.x).abs();
        if along <= 0.0 || off > tol * along {
            break;
        }
        run = r.norm();
        count += 1;
    }
    (count, run)
}

/// The polyline of crack `c` of `front` simplified to within `tol` ([`simplify`]), with
/// the straight run behind each tip as one segment: the mesher splits a segment whose
/// length is not a whole number of elements by halving its last two elements, and a
/// vertex inside the fit zone put such a pair among the fit's stations (measured on the
/// mode-I crack of `growth_tension_edge`: K_I 9.5 % low whenever the run was two
/// increments long). The run's points lie within [`STRAIGHT_ANGLE`] of its chord.
pub fn simplify_crack(front: &Front, c: usize, tol: f64) -> Vec<P2> {
    let pts = &front.cracks[c].points;
    let n = pts.len();
    let (mut lo, mut hi) = (0, n - 1);
    for (t, tip) in front.tips.iter().enumerate() {
        if tip.crack != c {
            continue;
        }
        let (k, _) = straight_points(front, t);
        if tip.at_end {
            hi = hi.min(n - 1 - k);
        } else {
            lo = lo.max(k);
        }
    }
    if lo >= hi {
        return pts.clone();
    }
    let mut out = if lo > 0 { vec![pts[0]] } else { Vec::new() };
    out.extend(simplify(&pts[lo..=hi], tol));
    if hi < n - 1 {
        out.push(pts[n - 1]);
    }
    out
}

/// Douglas-Peucker simplification of an open polyline to within `tol` (m); the end
/// points are kept.
pub fn simplify(points: &[P2], tol: f64) -> Vec<P2> {
    if points.len() <= 2 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    keep[0] = true;
    keep[points.len() - 1] = true;
    let mut stack = vec![(0, points.len() - 1)];
    while let Some((a, b)) = stack.pop() {
        let (mut far, mut worst) = (a, -1.0);
        for i in a + 1..b {
            let d = point_segment_distance(&points[i], &points[a], &points[b]);
            if d > worst {
                worst = d;
                far = i;
            }
        }
        if worst > tol {
            keep[far] = true;
            stack.push((a, far));
            stack.push((far, b));
        }
    }
    points
        .iter()
        .zip(&keep)
        .filter(|(_, &k)| k)
        .map(|(p, _)| *p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::front::FrontCrack;

    fn square() -> Vec<P2> {
        vec![
            P2::new(0.0, 0.0),
            P2::new(10.0, 0.0),
            P2::new(10.0, 10.0),
            P2::new(0.0, 10.0),
        ]
    }

    fn loops() -> Vec<LoopSpec> {
        vec![LoopSpec {
            points: square(),
            edge_groups: vec!["e".into(); 4],
            edge_sizes: vec![0.5; 4],
            is_hole: false,
        }]
    }

    /// An edge crack from (5, 10) down to (5, 10 - a), then along `tail`.
    fn front(a: f64, tail: &[P2]) -> Front {
        let mut points = vec![P2::new(5.0, 10.0), P2::new(5.0, 10.0 - a)];
        points.extend_from_slice(tail);
        Front::new(
            Some(square()),
            Vec::new(),
            vec![FrontCrack {
                name: "c".into(),
                points,
                mouth: true,
            }],
        )
    }

    #[test]
    fn the_length_scale_is_the_shorter_of_the_crack_and_the_ligament() {
        let f = front(2.0, &[]);
        assert!((tip_scale(&f, 0, &loops()) - 2.0).abs() < 1e-12);
        let f = front(9.9, &[]);
        assert!((tip_scale(&f, 0, &loops()) - 0.1).abs() < 1e-12);
    }

    #[test]
    fn the_straight_run_stops_at_a_kink_and_the_fit_follows_it() {
        // 2 m down, then 0.3 m at 45 degrees in three increments.
        let s = std::f64::consts::FRAC_1_SQRT_2 * 0.1;
        let tail: Vec<P2> = (1..=3)
            .map(|k| P2::new(5.0 + s * k as f64, 8.0 - s * k as f64))
            .collect();
        let f = front(2.0, &tail);
        let run = straight_run(&f, 0);
        assert!((run - 0.3).abs() < 1e-12, "{run}");
        let sc = tip_scales(&f, &loops(), 0.3, true);
        assert!((sc[0].fit - 0.3).abs() < 1e-12);
        let rule = TipSizing {
            fraction: 1.0 / 80.0,
            zone: 1.0,
            grading: 0.05,
            base: 0.5,
        };
        // L = 2.21 m (to the top edge), 0.3 L = 0.66 m: the run of 0.3 m limits the fit;
        // S2 of 0.3 / 11 m (a whole number of elements at most L/80 = 0.028 m).
        let src = tip_sources(&f, &sc, &rule, 1.0);
        assert_eq!(src.len(), 2);
        assert!((src[1].size - 0.3 / 11.0).abs() < 1e-12, "{}", src[1].size);
        // Without the straight run the static fit 0.3 L and S1 alone.
        let sc = tip_scales(&f, &loops(), 0.3, false);
        assert!((sc[0].fit - 0.3 * sc[0].scale).abs() < 1e-12);
        assert_eq!(tip_sources(&f, &sc, &rule, 1.0).len(), 1);
        // The run is one segment of the meshed polyline: mouth, kink, tip.
        assert_eq!(simplify_crack(&f, 0, 1e-6).len(), 3);
        // A single kinked increment of 0.1 m: S2 of 0.0125 m within 0.1 m.
        let f = front(2.0, &tail[..1]);
        let sc = tip_scales(&f, &loops(), 0.3, true);
        let src = tip_sources(&f, &sc, &rule, 2.0);
        assert_eq!(src.len(), 2);
        assert!((src[1].size - 0.1 / 8.0 / 2.0).abs() < 1e-12);
        assert!((src[1].radius - 0.1).abs() < 1e-12);
    }

    #[test]
    fn simplification_keeps_corners_and_drops_collinear_points() {
        let mut pts: Vec<P2> = (0..=10).map(|k| P2::new(0.0, -0.1 * k as f64)).collect();
        pts.extend((1..=5).map(|k| P2::new(0.1 * k as f64, -1.0)));
        let s = simplify(&pts, 1e-6);
        assert_eq!(s, vec![pts[0], pts[10], pts[15]]);
        // A drift below the tolerance is straightened.
        let drift: Vec<P2> = (0..=10)
            .map(|k| P2::new(1e-7 * (k % 2) as f64, -0.1 * k as f64))
            .collect();
        assert_eq!(simplify(&drift, 1e-6).len(), 2);
    }
}
