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
        /// Angle between crack line and load (degrees).
        beta_deg: f64,
    },
    /// Circular hole (first hole) under remote uniaxial tension: hoop stress
    /// sigma (1 - 2 cos 2 theta), peak 3 sigma.
    Kirsch {
        /// Remote uniaxial tension (Pa).
        sigma: f64,
    },
}
