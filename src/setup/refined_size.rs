//! What `pd.refinement`'s static regions add to a stand-alone PD grid, estimated from
//! the scene alone ([`super::estimate`] checks it against the memory budget before
//! anything is built; [`crate::run_dynamic::check`] counts its bonds in the run's work).

use crate::geometry::polyline_length;
use crate::scene::shapes::SceneGeometry;
use crate::scene::PdRefinement;

/// The particles and directed bonds the static regions of `r` add to a stand-alone PD
/// grid of spacing `dx` and horizon factor `m`: every circle (its part in the bounding
/// box) and the band of `near_cracks` about each crack (at most the bounding box), its
/// area over dx^2 parents each adding 4^L - 1 particles at level L, with pi m^2 bonds
/// each, 4^L times as many with `keep_horizon` (the parent's horizon over spacings 2^L
/// finer). Overlaps count twice; the criteria's splits during a run are not counted (a
/// split refuses a body over the budget before allocating it).
pub fn refined_children(r: &PdRefinement, geo: &SceneGeometry, dx: f64, m: f64) -> (f64, f64) {
    // Stand-alone PD has an outline: its box holds the holes and cracks too.
    let (lo, hi) = geo.bounds();
    let (lo, hi) = ([lo.x, lo.y], [hi.x, hi.y]);
    let boxed = |area: f64| area.min((hi[0] - lo[0]) * (hi[1] - lo[1]));
    let mut regions: Vec<(f64, u8)> = r
        .circles
        .iter()
        .map(|c| {
            let area = disc_in_box(c.centre, c.radius, (lo, hi));
            (area, c.level.unwrap_or(r.max_level).min(r.max_level))
        })
        .collect();
    if let Some(d) = r.near_cracks {
        for cr in &geo.cracks {
            let area = (polyline_length(&cr.points) + 2.0 * d) * 2.0 * d;
            regions.push((boxed(area), r.max_level));
        }
    }
    let (mut nodes, mut bonds) = (0.0, 0.0);
    for (area, level) in regions {
        let split = 4f64.powi(i32::from(level));
        let children = area / (dx * dx) * (split - 1.0);
        nodes += children;
        bonds += children * std::f64::consts::PI * m * m * if r.keep_horizon { split } else { 1.0 };
    }
    (nodes, bonds)
}

/// Area of the disc of `centre` and `radius` inside the box `(lo, hi)`, by the midpoint
/// rule over 256 strips (a size estimate).
fn disc_in_box(centre: (f64, f64), radius: f64, (lo, hi): ([f64; 2], [f64; 2])) -> f64 {
    let (a, b) = (
        (centre.0 - radius).max(lo[0]),
        (centre.0 + radius).min(hi[0]),
    );
    // Also 0 for a non-finite radius or box (NaN fails every comparison).
    if b.partial_cmp(&a) != Some(std::cmp::Ordering::Greater) {
        return 0.0;
    }
    let n = 256;
    let w = (b - a) / f64::from(n);
    (0..n)
        .map(|i| {
            let x = a + (f64::from(i) + 0.5) * w;
            let half = (radius * radius - (x - centre.0).powi(2)).max(0.0).sqrt();
            ((centre.1 + half).min(hi[1]) - (centre.1 - half).max(lo[1])).max(0.0) * w
        })
        .sum()
}

/// The nodes `pd.refine_zones` add to a stand-alone grid of spacing `dx` over a body of
/// bounding box `(w, h)`: per zone its cells (at most the body's) times `4^levels - 1`,
/// overlapping zones counted in each (an upper bound; 0 for values validation refuses).
pub fn zone_children(zones: &[crate::scene::PdZone], (w, h): (f64, f64), dx: f64) -> f64 {
    let cells = |side: f64, body: f64| (side / dx + 1.0).floor().min(body / dx + 1.0).max(0.0);
    let extra: f64 = zones
        .iter()
        .map(|z| {
            let per_cell = 4f64.powi(z.levels.min(8) as i32) - 1.0;
            cells(2.0 * z.half_size, w) * cells(2.0 * z.half_size, h) * per_cell
        })
        .sum();
    if extra.is_nan() {
        0.0
    } else {
        extra
    }
}
