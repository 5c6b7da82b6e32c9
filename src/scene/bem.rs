//! `bem`: discretisation and post-processing settings of the boundary element
//! solver. Absent = all defaults.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use super::body::Pt;
use super::shapes::{HoleShape, SceneGeometry};

/// BEM settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BemSettings {
    /// Target element length (m), > 0. Default: automatic, the smaller side of
    /// the outline's bounding box / 100, or for an infinite plate its largest feature
    /// (longest crack, largest hole diameter) / 80; cracks default to the smaller of this
    /// and a fraction of their tip length scale ([`crate::setup::sizing`]).
    pub element_size: Option<f64>,
    /// Element length per edge group (m), overriding `element_size`. Default: none.
    pub group_sizes: BTreeMap<String, f64>,
    /// Uniform refinement around every crack tip. Default: none (REFERENCES.md:
    /// keep elements near the tip uniform; geometric grading biases COD SIFs).
    pub tip_refinement: Option<TipRefinement>,
    /// Elements on each circular hole. Default 128 ([`crate::setup::sizing`]).
    pub elements_per_circle: Option<usize>,
    /// Solve on h and h/2 and Richardson-extrapolate SIF and CMOD (O(h)
    /// convergence of constant elements). Default false.
    pub richardson: bool,
    /// Relative tolerance on every K (against K_eq) and CMOD, in [4e-4, 0.5]
    /// ([`MIN_TOLERANCE`]): the solver
    /// halves every element size until the error estimate meets it, within the memory
    /// budget ([`crate::refine`]). Default: none (one level and its estimate).
    pub tolerance: Option<f64>,
    /// Fit range of the crack-opening SIF fit, as a fraction of L = a (or
    /// min(a, W - a) for edge cracks), in (0, 1]. Default 0.3 (REFERENCES.md).
    pub cod_fit_fraction: f64,
    /// J / interaction integral contour. Default: a circle of radius 0.25 a with 64 points.
    pub j_contour: JContour,
    /// Report a condition-number estimate of the system. Default false.
    pub condition_estimate: bool,
    /// Extra interior points (m) where displacement and stress are reported. Default: none.
    pub interior_points: Vec<Pt>,
}

/// Relative floor of every error estimate ([`crate::refine`]).
pub const ESTIMATE_FLOOR: f64 = 2e-4;
/// Smallest `bem.tolerance`: twice the floor (the tolerance test's safety factor 2,
/// [`crate::refine`]); a tolerance below it could never be certified.
pub const MIN_TOLERANCE: f64 = 4e-4;

/// Default outline size as a fraction of the smaller body extent
/// ([`crate::setup::sizing`]).
pub const DEFAULT_OUTLINE_FRACTION: f64 = 0.01;
/// Default crack element size as a fraction of the tip length scale L (and of the
/// largest feature of an infinite plate) ([`crate::setup::sizing`]).
pub const DEFAULT_CRACK_FRACTION: f64 = 1.0 / 80.0;

impl BemSettings {
    /// Element size where no group size applies, before refinement (m): `element_size`,
    /// or the default rule of [`crate::setup::sizing`].
    pub fn base_size(&self, geo: &SceneGeometry) -> f64 {
        if let Some(h) = self.element_size {
            return h;
        }
        if let Some(o) = &geo.outline {
            let (lo, hi) = crate::geometry::bounding_box(&o.points);
            let ext = (hi - lo).min();
            return DEFAULT_OUTLINE_FRACTION * ext;
        }
        // Infinite body: from the largest feature.
        let mut feature: f64 = 0.0;
        for c in &geo.cracks {
            feature = feature.max(crate::geometry::polyline_length(&c.points));
        }
        for (_, h) in &geo.holes {
            if let HoleShape::Circle { radius, .. } = h {
                feature = feature.max(2.0 * radius);
            }
        }
        feature.max(1e-300) * DEFAULT_CRACK_FRACTION
    }
}

impl Default for BemSettings {
    fn default() -> Self {
        BemSettings {
            element_size: None,
            group_sizes: BTreeMap::new(),
            tip_refinement: None,
            elements_per_circle: None,
            richardson: false,
            tolerance: None,
            cod_fit_fraction: 0.3,
            j_contour: JContour::default(),
            condition_estimate: false,
            interior_points: Vec::new(),
        }
    }
}

/// Uniform small elements within `radius` of each crack tip.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TipRefinement {
    /// Element length near the tip (m), > 0.
    pub element_size: f64,
    /// Radius of the refined zone around the tip (m), > 0.
    pub radius: f64,
}

/// Circular contour of interior points around each tip for the J and
/// interaction integrals.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct JContour {
    /// Contour radius as a fraction of the crack length a (edge crack) or
    /// half-length (interior crack), in (0, 1). Default 0.25.
    pub radius_fraction: f64,
    /// Number of interior points on the contour, >= 8. Default 64.
    pub points: usize,
}

impl Default for JContour {
    fn default() -> Self {
        JContour {
            radius_fraction: 0.25,
            points: 64,
        }
    }
}
