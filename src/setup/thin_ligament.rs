//! Thin ligaments: a crack whose flank runs close along another boundary (an outline
//! edge, a hole, another crack), leaving a strip of material between them.
//!
//! A strip of thickness $w$ and length $\ell$ between a crack face and another boundary
//! bends like a beam. The BEM crack faces (constant elements, the traction equation
//! deciding the opening) converge on it only at elements far below $w$, and the error
//! estimate from two levels sees little of the error before that; ordinary boundaries
//! converge far sooner (a polygon body with the same strip and no crack: within a few
//! per cent at elements of w / 8). Measured on an edge crack 0.03 m under the free top
//! edge of a 2 m x 1 m plate, 0.5 m long ($\ell / w = 17$), the plate pulled by 1 Pa on
//! its top and bottom edges (E = 1e4 Pa); Euler-Bernoulli with a rigid root puts the
//! strip's end at least $q \ell^4 / 8EI$ = 0.347 m above the bulk (the root's compliance
//! and shear only add). The default sizes (w / 3 along the strip) give a CMOD of 0.028 m
//! with an estimate of 0.0016 m: more than 92 % low, exit 0. Uniform crack elements
//! (`bem.group_sizes.<crack>`) of w / 16, w / 32, w / 64 and w / 128 give 0.190, 0.303,
//! 0.383 and 0.431 m with estimates of 0.153, 0.206, 0.164 and 0.066 m, $K_I$ 9.8, 25, 37
//! and 45 Pa m^0.5 with estimates of 7, 26, 34 and 35: from w / 32 within their estimates
//! as far as the bound tells, converging at about $h^{0.6}$. At $\ell / w = 50$ (0.01 m
//! under the edge, bound 9.4 m) w / 16, w / 32 and w / 64 (7000 elements) give 0.18,
//! 0.38 and 0.72 m and $K_I$ of either sign: no affordable mesh resolves it. At
//! $\ell / w = 5$ (0.1 m under the edge) the default sizes give $K_I$ and CMOD about 6 %
//! and 5 % below their values at w / 64, with estimates of 7 % and 5 %: covered, narrowly.
//!
//! So the scene is solved as it is, and every K and CMOD of a crack with a ligament more
//! than [`SLENDERNESS_LIMIT`] times as long as it is thick gets a note ([`note`]; `pdbem
//! check` prints it too) with what helps: up to [`RESOLVED_SLENDERNESS`], crack elements
//! of [`RESOLVING_FRACTION`] w, with which the note goes ([`resolved`]).
//!
//! Each crack is sampled along its length (every half gap, at least every 1/1000 of its
//! length); at a sample $p$ the gap $w(p)$ is the distance to the nearest point $q$ of
//! another boundary, leaving out points $q$ no farther from a mouth $m$ of the crack than
//! $p$ is ($|q - m| \le |p - m|$: the wedge between an inclined edge crack and its edge is
//! a corner, not a ligament). A ligament is a run of consecutive samples whose gaps lie
//! within a factor [`RUN_RATIO`]: its thickness is the smallest gap, its length the run's
//! length along the crack. A tip that approaches a boundary ahead of it has gaps that
//! grow along the flank, a ligament about as long as it is thick (the tip sizes resolve
//! it, [`super::sizing::LocalSizes`]).

use pdbem_bem::mesh::LoopSpec;

use crate::geometry::{point_segment_distance, polyline_length, P2};
use crate::scene::shapes::SceneGeometry;
use crate::scene::Scene;

/// Largest length / thickness of a ligament that passes without a note (module docs:
/// 5 is at the edge of the estimate, 17 far beyond it).
pub const SLENDERNESS_LIMIT: f64 = 4.0;
/// Crack elements of at most this fraction of a ligament's thickness resolve it, up to
/// [`RESOLVED_SLENDERNESS`] (module docs: from w / 32 within the estimates at 17).
pub const RESOLVING_FRACTION: f64 = 1.0 / 64.0;
/// Most slender ligament crack elements of [`RESOLVING_FRACTION`] are known to resolve.
pub const RESOLVED_SLENDERNESS: f64 = 17.0;
/// Consecutive samples whose gaps lie within this ratio belong to one ligament.
pub const RUN_RATIO: f64 = 2.0;
/// Finest sampling along a crack, as a fraction of its length.
const FINEST_STEP: f64 = 1e-3;

/// A thin strip between a crack's flank and another boundary.
#[derive(Debug, Clone, PartialEq)]
pub struct Ligament {
    /// Crack index in scene order.
    pub crack: usize,
    /// The other boundary at the thinnest point: an edge group, a hole or `crack '<name>'`.
    pub other: String,
    /// Thickness: the smallest gap along the run (m).
    pub width: f64,
    /// Length along the crack (m).
    pub length: f64,
    /// First and last sample of the run on the crack (m).
    pub from: P2,
    /// See `from`.
    pub to: P2,
}

impl Ligament {
    /// Length over thickness.
    pub fn slenderness(&self) -> f64 {
        self.length / self.width
    }

    /// Which crack runs along what, how far and how close: "cracks.i ('name') runs L m
    /// alongside X at w m, from (x, y) to (x, y) m".
    pub fn describe(&self, scene: &Scene) -> String {
        format!(
            "cracks.{} ('{}') runs {:.3e} m alongside {} at {:.3e} m, from ({:.4}, {:.4}) to \
             ({:.4}, {:.4}) m",
            self.crack,
            scene.cracks[self.crack].name,
            self.length,
            self.other,
            self.width,
            self.from.x,
            self.from.y,
            self.to.x,
            self.to.y,
        )
    }
}

/// One sample of a crack: where, the gap there (m) and the nearest other boundary.
#[derive(Debug, Clone, PartialEq)]
struct Sample {
    at: P2,
    gap: f64,
    other: String,
}

/// The ligaments of `scene`'s cracks more slender than [`SLENDERNESS_LIMIT`], on the
/// static BEM loops at refinement 1, leaving out those the crack's own elements
/// (`bem.group_sizes.<crack>`) resolve ([`resolved`]).
pub fn of_scene(scene: &Scene) -> Vec<Ligament> {
    let geo = SceneGeometry::of(scene);
    if geo.cracks.is_empty() {
        return Vec::new();
    }
    let loops = super::bem::loops(scene, &geo, 1.0);
    find(&geo, &loops)
        .into_iter()
        .filter(|l| l.slenderness() > SLENDERNESS_LIMIT && !resolved(scene, l))
        .collect()
}

/// Whether the scene's elements on the ligament's crack resolve it: at most
/// [`RESOLVING_FRACTION`] of its thickness (`bem.group_sizes.<crack>`), and the ligament
/// no more slender than [`RESOLVED_SLENDERNESS`].
pub fn resolved(scene: &Scene, l: &Ligament) -> bool {
    let name = &scene.cracks[l.crack].name;
    let fine = scene
        .bem
        .group_sizes
        .get(name)
        .is_some_and(|&h| h <= RESOLVING_FRACTION * l.width * (1.0 + 1e-9));
    fine && l.slenderness() <= RESOLVED_SLENDERNESS
}

/// The note of a ligament (module docs).
pub fn note(scene: &Scene, l: &Ligament) -> String {
    let name = &scene.cracks[l.crack].name;
    format!(
        "thin ligament: {} (a strip {:.0} times as long as it is thick, more than \
         {SLENDERNESS_LIMIT}): BEM crack faces resolve such a strip only with elements far \
         below its thickness, and the error estimates do not see it (an edge crack 0.03 m \
         under a free edge over 0.5 m: CMOD more than 92 % low with an estimate of 6 %); the \
         K at the tips of '{name}' and its CMOD may be off by more than their estimates. Up to \
         {RESOLVED_SLENDERNESS} times, crack elements of 1/64 of the thickness \
         (bem.group_sizes.{name}: {:.3e}) bring them within their estimates; beyond, move the \
         crack away from {}",
        l.describe(scene),
        l.slenderness(),
        RESOLVING_FRACTION * l.width,
        l.other,
    )
}

/// The notes of `ligaments` (of `scene`): one per crack and other boundary, on its
/// thinnest stretch, saying how many more stretches along the same boundary it stands
/// for. A crack passing a hole makes several (the gap doubles every few samples away from
/// the closest point, and a polygon's vertices and chords alternate): 9 notes for one
/// crack 12 m long passing 1e-3 m above a hole of radius 1 m got 4 notes (5 with 2048
/// elements on the hole) before.
pub fn grouped_notes(scene: &Scene, ligaments: &[Ligament]) -> Vec<String> {
    let mut groups: Vec<Vec<&Ligament>> = Vec::new();
    for l in ligaments {
        let same = |g: &&mut Vec<&Ligament>| g[0].crack == l.crack && g[0].other == l.other;
        match groups.iter_mut().find(same) {
            Some(g) => g.push(l),
            None => groups.push(vec![l]),
        }
    }
    groups
        .iter()
        .map(|g| {
            let thinnest = g
                .iter()
                .min_by(|a, b| a.width.total_cmp(&b.width))
                .unwrap_or(&g[0]);
            let mut text = note(scene, thinnest);
            if g.len() > 1 {
                text.push_str(&format!(
                    " ({} more stretches of the crack run alongside {}, up to {:.0} times as \
                     long as they are thick)",
                    g.len() - 1,
                    thinnest.other,
                    g.iter().map(|l| l.slenderness()).fold(0.0, f64::max)
                ));
            }
            text
        })
        .collect()
}

/// Every ligament of the cracks of `geo` against `loops` and the other cracks, slender
/// or not.
pub fn find(geo: &SceneGeometry, loops: &[LoopSpec]) -> Vec<Ligament> {
    let mut out = Vec::new();
    for ci in 0..geo.cracks.len() {
        let samples = samples(geo, loops, ci);
        for run in runs(&samples) {
            let thinnest = run
                .iter()
                .min_by(|a, b| a.gap.total_cmp(&b.gap))
                .unwrap_or(&run[0]);
            let length = run.windows(2).map(|w| (w[1].at - w[0].at).norm()).sum();
            out.push(Ligament {
                crack: ci,
                other: thinnest.other.clone(),
                width: thinnest.gap,
                length,
                from: run[0].at,
                to: run[run.len() - 1].at,
            });
        }
    }
    out
}

/// Samples of crack `ci` every half gap, at least every [`FINEST_STEP`] of its length.
fn samples(geo: &SceneGeometry, loops: &[LoopSpec], ci: usize) -> Vec<Sample> {
    let crack = &geo.cracks[ci];
    let len = polyline_length(&crack.points);
    let floor = FINEST_STEP * len;
    let mouths = mouths(loops, &crack.points, len);
    let mut out = Vec::new();
    for w in crack.points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let seg = (b - a).norm();
        if seg == 0.0 {
            continue;
        }
        let mut t: f64 = 0.0;
        loop {
            let at = a + (b - a) * (t / seg).min(1.0);
            let (gap, other) = gap_at(geo, loops, ci, &mouths, at);
            out.push(Sample { at, gap, other });
            if t >= seg {
                break;
            }
            t = (t + (0.5 * gap).max(floor)).min(seg);
        }
    }
    out
}

/// The crack's ends on a loop (its mouths).
fn mouths(loops: &[LoopSpec], points: &[P2], len: f64) -> Vec<P2> {
    let tol = 1e-9 * len;
    [points[0], *points.last().unwrap_or(&points[0])]
        .into_iter()
        .filter(|p| loop_segments(loops).any(|(a, b, _)| point_segment_distance(p, &a, &b) <= tol))
        .collect()
}

/// Every edge of the loops as (start, end, group).
fn loop_segments(loops: &[LoopSpec]) -> impl Iterator<Item = (P2, P2, String)> + '_ {
    loops.iter().flat_map(|l| {
        let n = l.points.len();
        (0..n).map(move |i| {
            (
                l.points[i],
                l.points[(i + 1) % n],
                format!("'{}'", l.edge_groups[i]),
            )
        })
    })
}

/// The gap at `p` on crack `ci` and the boundary it reaches: the distance to the nearest
/// point of a loop or another crack that is farther from every mouth than `p` (infinite
/// when there is none).
fn gap_at(
    geo: &SceneGeometry,
    loops: &[LoopSpec],
    ci: usize,
    mouths: &[P2],
    p: P2,
) -> (f64, String) {
    let tol = 1e-9 * polyline_length(&geo.cracks[ci].points);
    let others = geo
        .cracks
        .iter()
        .enumerate()
        .filter(|(j, _)| *j != ci)
        .flat_map(|(_, c)| {
            c.points
                .windows(2)
                .map(move |w| (w[0], w[1], format!("crack '{}'", c.name)))
        });
    let mut best = (f64::INFINITY, String::new());
    for (a, b, name) in loop_segments(loops).chain(others) {
        let q = nearest_point(&p, &a, &b);
        let behind = mouths
            .iter()
            .any(|m| (q - m).norm() <= (p - m).norm() + tol);
        let d = (q - p).norm();
        if !behind && d < best.0 {
            best = (d, name);
        }
    }
    best
}

/// The point of segment `a`-`b` nearest to `p`.
fn nearest_point(p: &P2, a: &P2, b: &P2) -> P2 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    if l2 == 0.0 {
        return *a;
    }
    a + ab * ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
}

/// Runs of consecutive samples with a finite gap, split where the gaps of a run would
/// span more than [`RUN_RATIO`].
fn runs(samples: &[Sample]) -> Vec<Vec<Sample>> {
    let mut out: Vec<Vec<Sample>> = Vec::new();
    let mut current: Vec<Sample> = Vec::new();
    let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
    for s in samples {
        let finite = s.gap.is_finite() && s.gap > 0.0;
        let fits = finite && s.gap.max(hi) <= RUN_RATIO * s.gap.min(lo);
        if !fits && !current.is_empty() {
            out.push(std::mem::take(&mut current));
            (lo, hi) = (f64::INFINITY, 0.0);
        }
        if finite {
            current.push(s.clone());
            lo = lo.min(s.gap);
            hi = hi.max(s.gap);
        }
    }
    if !current.is_empty() {
        out.push(current);
    }
    out
}
