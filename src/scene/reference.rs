//! `reference`: an analytic solution the run is compared with (REFERENCES.md).
//! Absent = no comparison.

use serde::{Deserialize, Serialize};

/// Analytic reference of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Reference {
    /// Single edge-cracked strip: K_I by Tada's F(a/W) (and the FEM table),
    /// CMOD by the V(a/W) formula, for the first crack (an edge crack, a = its length).
    SentTada {
        /// Strip width W along the crack (m), > 0.
        width: f64,
        /// Remote tension sigma (Pa).
        sigma: f64,
    },
    /// Central crack in an infinite plate (first crack, half-length a =
    /// length / 2): K_I = sigma sqrt(pi a) sin^2 beta, K_II = sigma sqrt(pi a)
    /// sin beta cos beta, kink by maximum circumferential stress.
    InclinedCrackInfinite {
        /// Remote uniaxial tension (Pa).
        sigma: f64,
        /// Angle between crack line and load (degrees, counter-clockwise from the line of
        /// cracks.0 to the tension). Default: from the loads (the direction of their
        /// uniform tension), so that a sweep over the crack's angle keeps its reference.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        beta_deg: Option<f64>,
    },
    /// Circular hole (first hole) under remote uniaxial tension: hoop stress
    /// sigma (1 - 2 cos 2 theta), peak 3 sigma.
    Kirsch {
        /// Remote uniaxial tension (Pa).
        sigma: f64,
    },
}

impl Reference {
    /// A note when the scene's body is not the reference's: the inclined-crack and Kirsch
    /// closed forms are the infinite plate's with one crack or one hole, so on a finite
    /// outline, or with other holes or cracks, `k1_err`, `k2_err` and `hoop_peak_err` hold
    /// the body's difference besides the run's own error (which the error estimates
    /// bound). A 4 m crack in a 20 m square plate, its edges 5 half-lengths from its
    /// centre, opens 5.1 % more in mode I than the closed form (the BEM of that plate);
    /// 10 half-lengths, 1.35 %. A hole of radius 1 m in a 10 m square plate under uniaxial
    /// tension: hoop peak +12.0 %. The 2 m crack of `inclined_crack_45_finite` with a hole
    /// of radius 1 m 1.41 m from its tip: k1_err +45 % (no word before).
    pub fn scope_note(&self, scene: &super::Scene) -> Option<String> {
        let geo = super::shapes::SceneGeometry::of(scene);
        let (what, centre, size, unit, errs) = match self {
            Reference::InclinedCrackInfinite { .. } => {
                let crack = geo.cracks.first()?;
                let (first, last) = (crack.points.first()?, crack.points.last()?);
                let a = 0.5 * crate::geometry::polyline_length(&crack.points);
                (
                    "InclinedCrackInfinite is the infinite plate's closed form for one crack",
                    first + (last - first) * 0.5,
                    a,
                    "half crack lengths from the crack's centre",
                    "k1_err and k2_err",
                )
            }
            Reference::Kirsch { .. } => {
                let Some((_, crate::geometry::HoleShape::Circle { center, radius })) =
                    geo.holes.first()
                else {
                    return None;
                };
                (
                    "Kirsch is the infinite plate's closed form for one hole",
                    *center,
                    *radius,
                    "hole radii from its centre",
                    "hoop_peak_err",
                )
            }
            Reference::SentTada { .. } => return None,
        };
        let mut departs = Vec::new();
        if let Some(outline) = &geo.outline {
            let n = outline.points.len();
            let nearest = (0..n)
                .map(|i| {
                    let (p, q) = (&outline.points[i], &outline.points[(i + 1) % n]);
                    crate::geometry::point_segment_distance(&centre, p, q)
                })
                .fold(f64::INFINITY, f64::min);
            departs.push(format!(
                "this body is finite (its nearest edge is {:.1} {unit})",
                nearest / size
            ));
        }
        let (holes, cracks) = match self {
            Reference::Kirsch { .. } => (geo.holes.len() - 1, geo.cracks.len()),
            _ => (geo.holes.len(), geo.cracks.len() - 1),
        };
        if holes + cracks > 0 {
            departs.push(format!(
                "it holds {holes} other hole(s) and {cracks} other crack(s)"
            ));
        }
        (!departs.is_empty()).then(|| {
            format!(
                "reference: {what}, and {}: {errs} include what that adds to the closed form (the body's finite size, its other holes and cracks); the error estimates bound the run's own error",
                departs.join(" and ")
            )
        })
    }
}
